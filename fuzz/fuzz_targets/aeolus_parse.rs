//! Every typed parse on any ID and data: no panic; what parses emits exactly `buffer_len`
//! bytes.
#![no_main]
use aeolus_proto::message::Message;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Some((&id, rest)) = data.split_first() else { return };
    if let Ok(msg) = Message::parse(id, rest) {
        let mut out = [0u8; 512];
        let n = msg.emit(&mut out).unwrap();
        assert_eq!(n, msg.buffer_len());
        assert_eq!(msg.id(), id);
    }
});
