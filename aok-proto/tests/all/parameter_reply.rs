//! The device's parameter reply in both firmware forms (K4): 7 bytes headed, 5 headerless,
//! each read back by a PC decoder of that firmware that waits for that parameter.

use aok_proto::{Decode, Expect, MessageDecoder};
use aok_proto::{FirmwareVersion, Message, ParameterValue, ReplyForm};

#[test]
fn each_form_has_its_length_and_reads_back() {
    let p = ParameterValue {
        number: 12,
        value: -1500,
    };
    for (fw, form, len) in [
        (FirmwareVersion::LATEST, ReplyForm::Headed, 7),
        (FirmwareVersion::new(0, 30), ReplyForm::Headerless, 5),
    ] {
        let mut buf = [0xAAu8; 9];
        assert_eq!(
            Message::Parameter(p).emit(&mut buf, form),
            Ok(len),
            "{form:?}"
        );
        assert_eq!(buf[len..], [0xAA; 9][len..], "{form:?}");
        let mut d = MessageDecoder::new(fw);
        d.expect(Expect::Parameter(12));
        let mut got = Vec::new();
        d.feed(&buf[..len], |ev| got.push(ev));
        assert_eq!(got, [Ok(Message::Parameter(p))], "{form:?}");
    }
    let mut headed = [0u8; 7];
    Message::Parameter(p)
        .emit(&mut headed, ReplyForm::Headed)
        .unwrap();
    assert_eq!(headed[..6], [0xFF, 12, 0xFF, 0xFF, 0xFA, 0x24]);
}
