//! Property tests: every message type round-trips through emit, framing, deframing and parse
//! for arbitrary field values, NaN bit patterns included.

use crate::common;
use aeolus_proto::Decode;
use aeolus_proto::{message::*, *};
use common::{arb_message, same_bits};
use proptest::prelude::*;

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]

    #[test]
    fn data_round_trip(msg in arb_message()) {
        let mut data = [0u8; 256];
        let n = msg.emit(&mut data).unwrap();
        prop_assert_eq!(n, msg.buffer_len());
        let back = Message::parse(msg.id(), &data[..n]).unwrap();
        prop_assert!(same_bits(&msg, &back), "{:?} != {:?}", msg, back);
    }

    #[test]
    fn frame_round_trip_through_deframer_and_byte_iterator(msg in arb_message(), omit in any::<bool>()) {
        let mode = if omit { CrcMode::Omit } else { CrcMode::Compute };
        let mut wire = [0u8; max_encoded_len(256)];
        let n = msg.encode(&mut wire, mode).unwrap();
        prop_assert!(n <= max_encoded_len(msg.buffer_len()));
        // Only the two flags may be 0x7E on the wire.
        prop_assert_eq!(wire[..n].iter().filter(|&&b| b == FLAG).count(), 2);
        // The iterator yields the same bytes.
        let mut data = [0u8; 256];
        let len = msg.emit(&mut data).unwrap();
        let streamed: Vec<u8> = FrameBytes::new(msg.id(), &data[..len], mode).collect();
        prop_assert_eq!(&streamed[..], &wire[..n]);

        let mut d = Decoder::<512>::new();
        let mut got = Vec::new();
        d.feed(&wire[..n], |ev| got.push(ev.map(|f| (f.has_crc(), f.raw().to_vec()))));
        prop_assert_eq!(got.len(), 1);
        let (has_crc, raw) = got.pop().unwrap().unwrap();
        let frame = Frame::new_checked(&raw, false).unwrap();
        // A frame whose real CRC is 0x0000 counts as checked either way.
        prop_assert!(has_crc || frame.crc() == 0);
        prop_assert_eq!(has_crc, !omit || aeolus_proto::crc::checksum(&raw[..raw.len() - 2]) == 0);
        let back = frame.message().unwrap();
        prop_assert!(same_bits(&msg, &back));
    }

    #[test]
    fn datagram_of_several_messages(msgs in prop::collection::vec(arb_message(), 1..6)) {
        let mut datagram = Vec::new();
        for m in &msgs {
            let mut buf = [0u8; max_encoded_len(256)];
            let n = m.encode(&mut buf, CrcMode::Compute).unwrap();
            datagram.extend_from_slice(&buf[..n]);
        }
        let got: Vec<Message<'_>> =
            decode_datagram(&mut datagram, true).map(|f| f.unwrap().message().unwrap()).collect();
        prop_assert_eq!(got.len(), msgs.len());
        for (a, b) in msgs.iter().zip(&got) {
            prop_assert!(same_bits(a, b));
        }
    }
}

#[test]
fn nan_payloads_survive() {
    let nan = f32::from_bits(0x7FC0_1234);
    let snan = f32::from_bits(0xFF80_0001);
    let dnan = f64::from_bits(0x7FF8_0000_DEAD_BEEF);
    let g = Gyro {
        valid: true,
        timestamp_ms: dnan,
        x: nan,
        y: snan,
        z: -0.0,
    };
    let mut data = [0u8; Gyro::LEN];
    g.emit(&mut data).unwrap();
    let back = Gyro::parse(&data).unwrap();
    assert_eq!(back.x.to_bits(), 0x7FC0_1234);
    assert_eq!(back.y.to_bits(), 0xFF80_0001);
    assert_eq!(back.z.to_bits(), 0x8000_0000);
    assert_eq!(back.timestamp_ms.to_bits(), 0x7FF8_0000_DEAD_BEEF);
}

#[test]
fn wrong_length_is_typed_and_raw_frame_stays() {
    let mut wire = [0u8; 64];
    // A GYRO ID with 31 data bytes.
    let n = encode_frame(Gyro::ID, &[0u8; 31], &[], CrcMode::Compute, &mut wire).unwrap();
    let mut d = Decoder::<64>::strict();
    let mut seen = 0;
    d.feed(&wire[..n], |ev| {
        let frame = ev.unwrap();
        assert_eq!(
            frame.message(),
            Err(Error::WrongLength {
                id: 62,
                expected: 32,
                actual: 31
            })
        );
        assert_eq!(frame.raw().len(), 1 + 31 + 2);
        assert_eq!(frame.data(), &[0u8; 31]);
        seen += 1;
    });
    assert_eq!(seen, 1);
    for (id, len) in [
        (51, 32),
        (63, 40),
        (71, 52),
        (72, 80),
        (75, 32),
        (76, 208),
        (12, 32),
    ] {
        assert_eq!(
            Message::parse(id, &[0u8; 33]),
            Err(Error::WrongLength {
                id,
                expected: len,
                actual: 33
            })
        );
    }
}

#[test]
fn unknown_ids_are_kept_raw() {
    assert_eq!(
        Message::parse(200, &[1, 2, 3]),
        Ok(Message::Unknown {
            id: 200,
            data: &[1, 2, 3]
        })
    );
    assert_eq!(Message::parse(81, &[9; 5]), Ok(Message::Log(&[9; 5])));
}

#[test]
fn texts_follow_a6() {
    // Missing NUL: the string is all the data.
    let Ok(Message::Command(t)) = Message::parse(11, b"a reboot") else {
        panic!()
    };
    assert_eq!(t.as_str(), Some("a reboot"));
    // Bytes after the NUL are ignored by the typed view.
    let Ok(Message::Toast(t)) = Message::parse(82, b"on\0junk") else {
        panic!()
    };
    assert_eq!(t.as_bytes(), b"on");
    // Not UTF-8: raw bytes kept.
    let Ok(Message::Toast(t)) = Message::parse(82, &[0xC3, 0x28, 0]) else {
        panic!()
    };
    assert_eq!(t.as_str(), None);
    assert_eq!(t.as_bytes(), &[0xC3, 0x28]);
    // Too long for the bounded text.
    let long = [b'x'; TEXT_CAPACITY + 1];
    assert_eq!(
        Message::parse(82, &long),
        Err(Error::TextTooLong { id: 82, len: 121 })
    );
    assert!(Message::parse(82, &long[..TEXT_CAPACITY]).is_ok());
}

#[test]
fn compass_keeps_unknown_calibration_status() {
    let c = Compass {
        valid: true,
        calibration: CalibrationStatus::Other(-7),
        has_value: true,
        calibration_percent: 55,
        calibration_remaining: 12,
        timestamp_ms: 42.0,
        heading_deg: 271.5,
        soft_iron: [1.0, 2.0, 3.0],
        hard_iron: [4.0, 5.0, 6.0, 7.0, 8.0, 9.0, 10.0, 11.0, 12.0],
    };
    let mut data = [0u8; Compass::LEN];
    c.emit(&mut data).unwrap();
    assert_eq!(data[1], 0xF9);
    assert_eq!(&data[3..5], &[55, 12]);
    assert_eq!(&data[32..36], &1.0f32.to_le_bytes());
    assert_eq!(&data[76..80], &12.0f32.to_le_bytes());
    assert_eq!(Compass::parse(&data), Ok(c));
}

#[test]
fn encode_reports_buffer_too_small() {
    let msg = Message::Toast(Text::new("AEOLUS on").unwrap());
    for len in 0..15 {
        let mut out = vec![0u8; len];
        assert_eq!(
            msg.encode(&mut out, CrcMode::Compute),
            Err(EncodeError::BufferTooSmall {
                needed: max_encoded_len(10)
            }),
            "len {len}"
        );
    }
    let mut out = [0u8; 15];
    assert_eq!(msg.encode(&mut out, CrcMode::Compute), Ok(15));
    assert_eq!(
        Gyro::default().emit(&mut [0u8; 31]),
        Err(EncodeError::BufferTooSmall { needed: Gyro::LEN })
    );
    // A text's data is the text and its NUL.
    assert_eq!(
        Text::new("AEOLUS on").unwrap().emit(&mut [0u8; 9]),
        Err(EncodeError::BufferTooSmall { needed: 10 })
    );
}
