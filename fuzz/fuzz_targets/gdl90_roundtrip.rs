//! Every typed GDL90 parse on any ID and data: no panic; what parses emits `buffer_len`
//! bytes, refuses a buffer one byte short, parses back to the same message, and emits the
//! same bytes again (emit . parse is the identity on canonical data); the whole frame goes
//! through encode and the decoder unchanged.
#![no_main]
use aeolus_proto::Decode as _;
use gdl90_proto::{Decoder, max_encoded_len, message::Message};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Some((&id, rest)) = data.split_first() else { return };
    let Ok(msg) = Message::parse(id, rest) else { return };
    assert_eq!(msg.id(), id);
    let mut canon = vec![0u8; msg.buffer_len()];
    let n = msg.emit(&mut canon).unwrap();
    assert_eq!(n, msg.buffer_len());
    if n > 0 {
        assert!(msg.emit(&mut canon.clone()[..n - 1]).is_err());
    }
    let again = Message::parse(id, &canon).unwrap();
    assert_eq!(again, msg);
    let mut twice = vec![0u8; n];
    again.emit(&mut twice).unwrap();
    assert_eq!(twice, canon);
    // Through the wire, with a decoder large enough for the longest input (-max_len=4096).
    let mut wire = vec![0u8; max_encoded_len(n)];
    let w = msg.encode(&mut wire).unwrap();
    let mut d = Decoder::<4100>::new();
    let mut seen = 0;
    for b in &wire[..w] {
        d.feed(core::slice::from_ref(b), |ev| {
            assert_eq!(ev.unwrap(), msg);
            seen += 1;
        });
    }
    assert_eq!(seen, 1);
});
