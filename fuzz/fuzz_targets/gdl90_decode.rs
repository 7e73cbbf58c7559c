//! The GDL90 decoder on any byte stream: no panic; byte by byte and slice by slice (in chunks
//! the input chooses) give the same events and counters; the byte accounting holds after
//! every byte; no frame whose CRC field is `00 00` is accepted unless its CRC really is 0.
#![no_main]
use aeolus_proto::Decode as _;
use gdl90_proto::{Decoder, crc, message::Message};
use libfuzzer_sys::fuzz_target;

fn show(ev: Result<Message<'_>, gdl90_proto::Error>) -> String {
    format!("{ev:?}")
}

fuzz_target!(|data: &[u8]| {
    let Some((&chunk, stream)) = data.split_first() else { return };
    let mut bytewise = Decoder::<64>::new();
    let mut want = Vec::new();
    for (i, &b) in stream.iter().enumerate() {
        bytewise.feed(&[b], |ev| { want.push(show(ev)); });
        let s = bytewise.stats();
        let accounted = s.flags as usize + s.frame_bytes as usize + s.bytes_discarded as usize;
        assert_eq!(accounted + bytewise.held_bytes(), i + 1);
    }
    let mut bulk = Decoder::<64>::new();
    let mut got = Vec::new();
    for piece in stream.chunks(1 + chunk as usize % 61) {
        bulk.feed(piece, |ev| got.push(show(ev)));
    }
    assert_eq!(got, want);
    assert_eq!(bulk.stats(), bytewise.stats());
    // Every frame delivered carried a CRC that checks out: re-check the ones between flags.
    for frame in stream.split(|&b| b == 0x7E) {
        if (3..=64).contains(&frame.len()) && !frame.contains(&0x7D) {
            let (body, tail) = frame.split_at(frame.len() - 2);
            let received = u16::from_le_bytes([tail[0], tail[1]]);
            if received == 0 && crc::checksum(body) != 0 {
                let mut d = Decoder::<64>::new();
                d.feed(&[0x7E], |_| {});
                for &b in frame {
                    d.feed(&[b], |ev| panic!("no event expected, got {:?}", ev.err()));
                }
                let mut events = Vec::new();
                d.feed(&[0x7E], |ev| events.push(ev.is_err()));
                assert_eq!(events, [true]);
            }
        }
    }
});
