//! Every typed parse on any ID and data: no panic; what parses emits exactly `buffer_len`
//! bytes.
#![no_main]
use aeolus_proto::message::Message;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Some((&id, rest)) = data.split_first() else { return };
    if let Ok(msg) = Message::parse(id, rest) {
        let mut out = vec![0u8; msg.buffer_len()];
        let n = msg.emit(&mut out).unwrap();
        // One byte less is refused, not overrun.
        if n > 0 {
            assert!(msg.emit(&mut out[..n - 1]).is_err());
        }
        assert_eq!(n, msg.buffer_len());
        assert_eq!(msg.id(), id);
    }
});
