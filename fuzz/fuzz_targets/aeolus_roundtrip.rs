//! emit(parse(x)) == x wherever parse succeeds, on canonical data (reserved bytes zero, flags
//! 0/1, texts NUL-terminated: what `emit` writes); and parse(emit(m)) == m for every parsed m,
//! bit for bit, through a full frame encode and deframe.
#![no_main]
use aeolus_proto::Decode as _;
use aeolus_proto::{CrcMode, Decoder, max_encoded_len, message::Message};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Some((&id, rest)) = data.split_first() else { return };
    let Ok(msg) = Message::parse(id, rest) else { return };
    let mut canon = vec![0u8; msg.buffer_len()];
    let n = msg.emit(&mut canon).unwrap();
    let canon = &canon[..n];
    // emit(parse(canon)) == canon.
    let again = Message::parse(id, canon).unwrap();
    let mut out = vec![0u8; n];
    let m = again.emit(&mut out).unwrap();
    assert_eq!(&out[..m], canon);
    // The whole frame round-trips through the decoder.
    let mut wire = vec![0u8; max_encoded_len(n)];
    let w = msg.encode(&mut wire, CrcMode::Compute).unwrap();
    // Capacity for the longest input the fuzzer makes (-max_len=4096).
    let mut d = Decoder::<4100>::strict();
    let mut seen = 0;
    for b in &wire[..w] {
        d.feed(core::slice::from_ref(b), |ev| {
            let frame = ev.unwrap();
            assert_eq!(frame.data(), canon);
            seen += 1;
        });
    }
    assert_eq!(seen, 1);
});
