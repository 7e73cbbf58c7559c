//! The AEOLUS deframer on any byte stream, normal and strict: no panic, and the byte
//! accounting holds after every byte.
#![no_main]
use aeolus_proto::Decoder;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let mut normal = Decoder::<64>::new();
    let mut strict = Decoder::<64>::strict();
    for (i, &b) in data.iter().enumerate() {
        if let Some(Ok(frame)) = normal.push(b) {
            assert!(frame.raw().len() >= 3);
            let _ = frame.message();
        }
        if let Some(Ok(frame)) = strict.push(b) {
            assert!(frame.has_crc());
        }
        for d in [&normal, &strict] {
            let s = d.stats();
            let accounted = s.flags as usize + s.frame_bytes as usize + s.bytes_discarded as usize;
            assert_eq!(accounted + d.held_bytes(), i + 1);
        }
    }
});
