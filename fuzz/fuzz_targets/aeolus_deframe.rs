//! The AEOLUS decoder on any byte stream, normal and strict: no panic, and the byte
//! accounting holds after every byte; `next_event`, called on the rest until it finds nothing,
//! gives the frames and errors of `feed` one byte a call, and the same counters.
#![no_main]
use aeolus_proto::{Decode, Decoder};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let mut normal = Decoder::<64>::new();
    let mut strict = Decoder::<64>::strict();
    let mut want = Vec::new();
    for (i, &b) in data.iter().enumerate() {
        normal.feed(&[b], |ev| match ev {
            Ok(frame) => {
                assert!(frame.raw().len() >= 3);
                let _ = frame.message();
                want.push(Ok(frame.raw().to_vec()));
            }
            Err(e) => want.push(Err(e)),
        });
        strict.feed(&[b], |ev| {
            if let Ok(frame) = ev {
                assert!(frame.has_crc());
            }
        });
        for d in [&normal, &strict] {
            let s = d.stats();
            let accounted = s.flags as usize + s.frame_bytes as usize + s.bytes_discarded as usize;
            assert_eq!(accounted + d.held_bytes(), i + 1);
        }
    }
    let mut until = Decoder::<64>::new();
    let (mut got, mut rest) = (Vec::new(), data);
    loop {
        let (n, ev) = until.next_event(rest);
        assert!(n <= rest.len());
        let found = ev.is_some();
        assert!(found || n == rest.len());
        got.extend(ev.map(|e| e.map(|f| f.raw().to_vec())));
        rest = &rest[n..];
        if !found && rest.is_empty() {
            break;
        }
    }
    assert_eq!(got, want);
    assert_eq!(until.stats(), normal.stats());
});
