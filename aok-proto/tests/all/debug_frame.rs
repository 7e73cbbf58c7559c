//! The device's debug frame is 7 bytes, and a PC decoder reads it back as the same value.

use aok_proto::{DebugValue, FirmwareVersion, Message};
use aok_proto::{Decode, MessageDecoder};

#[test]
fn a_debug_value_is_seven_bytes_that_read_back() {
    let v = DebugValue {
        number: 86,
        value: -2,
    };
    let mut buf = [0xAAu8; 9];
    assert_eq!(
        Message::Debug(v).emit(&mut buf, aok_proto::ReplyForm::Headed),
        Ok(7)
    );
    assert_eq!(buf[0], 0x1C);
    assert_eq!(buf[7..], [0xAA; 2]);
    let mut d = MessageDecoder::new(FirmwareVersion::LATEST);
    let mut got = Vec::new();
    d.feed(&buf[..7], |ev| got.push(ev));
    assert_eq!(got, [Ok(Message::Debug(v))]);
}
