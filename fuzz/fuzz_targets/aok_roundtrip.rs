//! emit(parse(x)) == x wherever parse succeeds, for AOK commands (PC -> device) and for the
//! self-describing device messages.
#![no_main]
use aok_proto::{Command, Message, ReplyForm};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok((cmd, used)) = Command::parse(data) {
        let mut out = [0u8; 32];
        let n = cmd.emit(&mut out).unwrap();
        assert_eq!(&out[..n], &data[..used]);
    }
    if let Ok((msg, used)) = Message::parse(data) {
        let mut out = [0u8; 32];
        let n = msg.emit(&mut out, ReplyForm::Headed).unwrap();
        assert_eq!(&out[..n], &data[..used]);
    }
});
