//! The device's bulk reply: 16 headed parameter replies, numbered on from `first` (wrapping
//! past 255), 112 bytes, and nothing written into a buffer one byte short.

use aok_proto::{Decode, Expect, MessageDecoder};
use aok_proto::{Error, FirmwareVersion, Message, ParameterValue};

#[test]
fn sixteen_replies_numbered_on_from_first_in_112_bytes() {
    let values: [i32; 16] = core::array::from_fn(|i| i as i32 * 1000 - 3);
    let mut buf = [0xAAu8; 120];
    assert_eq!(
        aok_proto::BulkReply { first: 250, values }.emit(&mut buf),
        Ok(112)
    );
    assert_eq!(&buf[112..], &[0xAA; 8]);
    let mut d = MessageDecoder::new(FirmwareVersion::LATEST);
    d.expect(Expect::Bulk(250));
    let mut got = Vec::new();
    d.feed(&buf[..112], |ev| got.push(ev));
    let want: Vec<Result<Message, Error>> = (0..16)
        .map(|i| {
            Ok(Message::Parameter(ParameterValue {
                number: 250u8.wrapping_add(i as u8),
                value: values[i],
            }))
        })
        .collect();
    assert_eq!(got, want);
}

#[test]
fn a_buffer_one_byte_short_is_refused_untouched() {
    let mut buf = [0xAAu8; 111];
    assert_eq!(
        aok_proto::BulkReply {
            first: 0,
            values: [1; 16]
        }
        .emit(&mut buf),
        Err(aok_proto::EncodeError::BufferTooSmall { needed: 112 })
    );
    assert_eq!(buf, [0xAA; 111]);
}
