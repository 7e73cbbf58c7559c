//! Typed parsing errors, uflt16 and the system-value registry.

use aydp_proto::registry::{Cell, Registry, RegistryError, Slot};
use aydp_proto::{
    Decode, DirectOutput, Encoder, Error, FixDetail, FixQuality, Message, Position, Profile, Raw,
    SystemControl, SystemValueUpdate, Timestamp, UpdateMode, VesselData, uflt16,
};

#[test]
fn wrong_payload_sizes_are_typed_errors() {
    let big = [0u8; 80];
    for (t, len) in [(3u8, 20usize), (4, 8)] {
        for p in [Profile::Spec, Profile::Reference] {
            assert_eq!(
                Message::parse(t, false, &big[..len - 1], p),
                Err(Error::PayloadTooShort {
                    msg_type: t,
                    expected: len,
                    actual: len - 1
                })
            );
            assert_eq!(
                Message::parse(t, false, &big[..len + 1], p),
                Err(Error::PayloadTooLong {
                    msg_type: t,
                    expected: len,
                    actual: len + 1
                })
            );
        }
    }
    assert!(matches!(
        Message::parse(17, false, &big[..67], Profile::Reference),
        Err(Error::PayloadTooShort {
            msg_type: 17,
            expected: 68,
            ..
        })
    ));
    assert!(matches!(
        Message::parse(17, false, &big[..67], Profile::Spec),
        Ok(Message::Unknown(_))
    ));
    assert!(matches!(
        Message::parse(1, false, &big[..5], Profile::Reference),
        Err(Error::PayloadTooLong { .. })
    ));
    assert_eq!(
        Message::parse(0, false, &[1], Profile::Spec),
        Err(Error::PayloadTooLong {
            msg_type: 0,
            expected: 0,
            actual: 1
        })
    );
    assert_eq!(
        Message::parse(0, true, &[], Profile::Reference),
        Ok(Message::NoOp)
    );
    assert!(matches!(
        Message::parse(6, false, &[1], Profile::Spec),
        Ok(Message::Tbd(_))
    ));
    assert!(matches!(
        Message::parse(6, false, &[1], Profile::Reference),
        Ok(Message::Unknown(_))
    ));
    assert!(matches!(
        Message::parse(126, false, &[1], Profile::Spec),
        Ok(Message::UserDefined(_))
    ));
    assert!(matches!(
        Message::parse(127, false, &[], Profile::Spec),
        Err(aydp_proto::Error::BadType(127))
    ));
}

#[test]
fn count_fields_must_match() {
    assert_eq!(
        FixDetail::parse(&[1, 0, 0, 0, 0, 0, 0]),
        Err(Error::CountMismatch {
            msg_type: 5,
            count: 1
        })
    );
    assert_eq!(
        FixDetail::parse(&[]),
        Err(Error::PayloadTooShort {
            msg_type: 5,
            expected: 1,
            actual: 0
        })
    );
    assert!(FixDetail::parse(&[0]).unwrap().is_empty());
    // Negative uflt16 (sign bit) in a satellite.
    assert_eq!(
        FixDetail::parse(&[1, 9, 0, 0x80, 0, 0, 0, 0]),
        Err(Error::NegativeUflt16)
    );
    assert_eq!(
        DirectOutput::parse(&[2, 0, 1, 2, 0, 0, 0x20, 0x41]),
        Err(Error::CountMismatch {
            msg_type: 7,
            count: 2
        })
    );
    assert_eq!(
        DirectOutput::parse(&[0]),
        Err(Error::PayloadTooShort {
            msg_type: 7,
            expected: 2,
            actual: 1
        })
    );
    assert!(DirectOutput::parse(&[0, 0]).unwrap().is_empty());
    let mut q = [0u8; 8];
    q[4] = 0x80; // hdop sign bit
    assert_eq!(FixQuality::parse(&q), Err(Error::NegativeUflt16));
}

#[test]
fn system_value_update_and_control_checks() {
    assert_eq!(
        SystemValueUpdate::parse(&[4, 0, 0, 0, 0, 0, 0]),
        Err(Error::UnknownUpdateMode(4))
    );
    assert_eq!(
        SystemValueUpdate::parse(&[1, 0, 0, 5, 0, 0, 0, 1]),
        Err(Error::NonZeroSingleIndex(5))
    );
    assert_eq!(
        SystemValueUpdate::parse(&[3, 0x10, 0x00, 2, 0, 0, 0, 7]),
        Ok(SystemValueUpdate {
            address: 0x10,
            mode: UpdateMode::Element { index: 2 },
            data: &[7]
        })
    );
    assert_eq!(
        SystemControl::parse(&[1, 8]),
        Err(Error::PayloadTooShort {
            msg_type: 9,
            expected: 3,
            actual: 2
        })
    );
    assert_eq!(
        SystemControl::parse(&[1, 8, 0, 0]),
        Err(Error::PayloadTooLong {
            msg_type: 9,
            expected: 3,
            actual: 4
        })
    );
    assert_eq!(
        SystemControl::parse(&[2, 0]),
        Err(Error::PayloadTooLong {
            msg_type: 9,
            expected: 1,
            actual: 2
        })
    );
    assert_eq!(SystemControl::parse(&[3]), Err(Error::UnknownCommand(3)));
    assert_eq!(
        SystemControl::parse(&[]),
        Err(Error::PayloadTooShort {
            msg_type: 9,
            expected: 1,
            actual: 0
        })
    );
}

#[test]
fn uflt16_every_value_round_trips_and_rounding_is_nearest_even() {
    for h in 0u16..0x7C00 {
        let f = uflt16::decode(h).unwrap();
        assert_eq!(uflt16::encode(f), h, "{h:#06x}");
        assert_eq!(uflt16::decode(h | 0x8000), Err(Error::NegativeUflt16));
        if h == 0x7BFF {
            continue; // the next value is infinity; checked below
        }
        // Midpoint to the next value rounds to the even one.
        let next = uflt16::f16_bits_to_f32(h + 1);
        let mid = ((f as f64 + next as f64) / 2.0) as f32;
        let want = if h & 1 == 0 { h } else { h + 1 };
        if (mid as f64) == (f as f64 + next as f64) / 2.0 {
            assert_eq!(uflt16::encode(mid), want, "midpoint after {h:#06x}");
        }
        // Just above and below the midpoint.
        assert_eq!(uflt16::encode(f32::from_bits(mid.to_bits() + 1)), h + 1);
        assert_eq!(uflt16::encode(f32::from_bits(mid.to_bits() - 1)), h);
    }
    assert_eq!(uflt16::decode(0x7C00), Ok(f32::INFINITY));
    assert!(uflt16::decode(0x7E00).unwrap().is_nan());
    assert_eq!(uflt16::encode(f32::NAN), 0x7E00);
    assert_eq!(uflt16::encode(-0.0), 0);
    assert_eq!(uflt16::encode(f32::NEG_INFINITY), 0);
    assert_eq!(uflt16::encode(65520.0), 0x7C00); // the tie above 65504 goes to infinity (even)
    assert_eq!(uflt16::encode(65519.996), 0x7BFF);
    assert_eq!(uflt16::encode(2f32.powi(-25)), 0); // tie to even (zero)
    assert_eq!(uflt16::encode(2f32.powi(-25) * 1.5), 1);
    const ONE: u16 = uflt16::encode(1.0);
    assert_eq!(ONE, 0x3C00);
}

#[test]
fn encoder_and_header_errors() {
    let enc = Encoder::new(Profile::Spec);
    let mut small = [0u8; 10];
    let pos = Position::default();
    assert_eq!(
        enc.encode(&pos, Some(Timestamp::default()), &mut small),
        Err(aydp_proto::EncodeError::BufferTooSmall { needed: 43 })
    );
    assert_eq!(
        enc.encode(
            &Raw {
                msg_type: 127,
                data: &[]
            },
            None,
            &mut small
        ),
        Err(aydp_proto::EncodeError::BadType(127))
    );
    assert!(
        enc.iter(
            &Raw {
                msg_type: 200,
                data: &[]
            },
            None
        )
        .is_err()
    );
    // An expedited length field of 6 is below Spec's minimum; in Reference it counts data.
    assert_eq!(Profile::Spec.frame_len(6, true), None);
    assert_eq!(Profile::Reference.frame_len(6, true), Some(6 + 7));
    // Reference vessel data, normal: the length counts data only.
    let v = VesselData::default();
    let n = Encoder::new(Profile::Reference)
        .encode(&v, Some(Timestamp::default()), &mut [0u8; 100])
        .unwrap();
    assert_eq!(n, 68 + 23);
}

/// The AYDP reference software has no expedited header: in the `Reference` profile every way
/// of encoding one is refused with the same error, before the buffer is looked at, and nothing
/// is written. Decoders still read one (a `Spec` peer may send it).
#[test]
fn reference_profile_refuses_expedited_headers() {
    let enc = Encoder::new(Profile::Reference);
    let refused = Err(aydp_proto::EncodeError::ExpeditedInReference);
    let mut b = [0xAAu8; 100];
    assert_eq!(enc.encode(&Message::NoOp, None, &mut b), refused);
    assert_eq!(enc.encode(&VesselData::default(), None, &mut b), refused);
    // Checked first: a short buffer does not hide it.
    assert_eq!(enc.encode(&Message::NoOp, None, &mut [0u8; 2]), refused);
    assert!(b.iter().all(|&x| x == 0xAA), "nothing written");
    assert_eq!(
        enc.iter(&Message::NoOp, None).err(),
        Some(aydp_proto::EncodeError::ExpeditedInReference)
    );
    assert_eq!(
        enc.iter(&Message::NoOp, None).err(),
        Some(aydp_proto::EncodeError::ExpeditedInReference)
    );
    assert!(!Profile::Reference.has_expedited() && Profile::Spec.has_expedited());
    // The same message, normal, encodes; and Spec still encodes the expedited form.
    assert_eq!(
        enc.encode(&Message::NoOp, Some(Timestamp::new(1, 2)), &mut b),
        Ok(23)
    );
    assert_eq!(
        Encoder::new(Profile::Spec).encode(&Message::NoOp, None, &mut b),
        Ok(7)
    );
    assert_eq!(&b[..7], &[0xFF, 0x80, 7, 0, 0, 0, 0x78]);
    // A Reference decoder still reads an expedited no-op (length 0 counts data only).
    let mut d = aydp_proto::Decoder::<64>::new(Profile::Reference);
    let mut got = Vec::new();
    for x in &[0xFF, 0x80, 0, 0, 0, 0, 0x7F] {
        d.feed(core::slice::from_ref(x), |e| {
            if let Ok(f) = e {
                got.push((f.base_type(), f.timestamp()));
            }
        });
    }
    assert_eq!(got, [(0, None)]);
    // The error reads as one sentence.
    assert!(
        aydp_proto::EncodeError::ExpeditedInReference
            .to_string()
            .contains("no expedited header")
    );
}

fn registry_fixture<R>(
    f: impl FnOnce(&mut Registry<'_, '_>) -> R,
) -> (R, u8, [u8; 40], [f32; 4], f64) {
    let mut direct = 0u8;
    let mut name = [0u8; 40];
    name[..4].copy_from_slice(b"boat");
    let mut gains = [1.0f32, 2.0, 3.0, 4.0];
    let mut rate = 10.0f64;
    let r = {
        let mut slots = [
            Slot::value(0x0000, Cell::u8(&mut direct)).with_range(0.0, 1.0),
            Slot::value(0x0001, Cell::Chars(&mut name)).read_only(),
            Slot::array(0x0010, Cell::F32(&mut gains)).with_range(-100.0, 100.0),
            Slot::value(0x0020, Cell::f64(&mut rate)),
        ];
        let mut reg = Registry::new(&mut slots);
        f(&mut reg)
    };
    (r, direct, name, gains, rate)
}

#[test]
fn registry_read_only_never_changes() {
    let payloads: [&[u8]; 4] = [b"", b"x", &[0u8; 40], &[0u8; 41]];
    for data in payloads {
        for mode in [
            UpdateMode::Single,
            UpdateMode::Array { count: 40 },
            UpdateMode::Element { index: 0 },
        ] {
            let (r, _, name, _, _) = registry_fixture(|reg| {
                reg.apply(&SystemValueUpdate {
                    address: 1,
                    mode,
                    data,
                })
            });
            assert_eq!(r, Err(RegistryError::ReadOnly(1)));
            assert_eq!(&name[..5], b"boat\0");
        }
    }
}

#[test]
fn registry_rejections_change_nothing() {
    let f = |v: f32| v.to_le_bytes();
    let mut four = Vec::new();
    for v in [5.0f32, 6.0, 7.0, 8.0] {
        four.extend(f(v));
    }
    let mut bad_range = four.clone();
    bad_range[12..16].copy_from_slice(&f(1000.0));
    let nan = f(f32::NAN);
    let cases: Vec<(SystemValueUpdate<'_>, RegistryError)> = vec![
        (
            SystemValueUpdate {
                address: 0x99,
                mode: UpdateMode::Single,
                data: &[1],
            },
            RegistryError::UnknownAddress(0x99),
        ),
        (
            SystemValueUpdate {
                address: 0,
                mode: UpdateMode::Single,
                data: &[1, 0],
            },
            RegistryError::WrongSize(0),
        ),
        (
            SystemValueUpdate {
                address: 0,
                mode: UpdateMode::Single,
                data: &[2],
            },
            RegistryError::OutOfRange(0),
        ),
        (
            SystemValueUpdate {
                address: 0,
                mode: UpdateMode::Element { index: 0 },
                data: &[1],
            },
            RegistryError::WrongMode(0),
        ),
        (
            SystemValueUpdate {
                address: 0x10,
                mode: UpdateMode::Single,
                data: &four[..4],
            },
            RegistryError::WrongMode(0x10),
        ),
        (
            SystemValueUpdate {
                address: 0x10,
                mode: UpdateMode::Array { count: 5 },
                data: &four,
            },
            RegistryError::OutOfBounds(0x10),
        ),
        (
            SystemValueUpdate {
                address: 0x10,
                mode: UpdateMode::Array { count: 4 },
                data: &four[..15],
            },
            RegistryError::WrongSize(0x10),
        ),
        (
            SystemValueUpdate {
                address: 0x10,
                mode: UpdateMode::Array { count: 4 },
                data: &bad_range,
            },
            RegistryError::OutOfRange(0x10),
        ),
        (
            SystemValueUpdate {
                address: 0x10,
                mode: UpdateMode::Element { index: 4 },
                data: &four[..4],
            },
            RegistryError::OutOfBounds(0x10),
        ),
        (
            SystemValueUpdate {
                address: 0x10,
                mode: UpdateMode::Element { index: u32::MAX },
                data: &four[..4],
            },
            RegistryError::OutOfBounds(0x10),
        ),
        (
            SystemValueUpdate {
                address: 0x10,
                mode: UpdateMode::Element { index: 1 },
                data: &four[..3],
            },
            RegistryError::WrongSize(0x10),
        ),
        (
            SystemValueUpdate {
                address: 0x10,
                mode: UpdateMode::Element { index: 1 },
                data: &nan,
            },
            RegistryError::OutOfRange(0x10),
        ),
        (
            SystemValueUpdate {
                address: 0x20,
                mode: UpdateMode::Single,
                data: &[0; 4],
            },
            RegistryError::WrongSize(0x20),
        ),
    ];
    for (u, want) in cases {
        let (r, direct, name, gains, rate) = registry_fixture(|reg| reg.apply(&u));
        assert_eq!(r, Err(want), "{u:?}");
        assert_eq!(
            (direct, gains, rate),
            (0, [1.0, 2.0, 3.0, 4.0], 10.0),
            "{u:?} changed something"
        );
        assert_eq!(&name[..4], b"boat");
    }
}

#[test]
fn registry_applies_all_three_modes_and_replies() {
    let mut four = Vec::new();
    for v in [5.0f32, 6.0, 7.0, 8.0] {
        four.extend(v.to_le_bytes());
    }
    let (replies, direct, _, gains, rate) = registry_fixture(|reg| {
        reg.apply(&SystemValueUpdate {
            address: 0,
            mode: UpdateMode::Single,
            data: &[1],
        })
        .unwrap();
        reg.apply(&SystemValueUpdate {
            address: 0x10,
            mode: UpdateMode::Array { count: 4 },
            data: &four,
        })
        .unwrap();
        reg.apply(&SystemValueUpdate {
            address: 0x10,
            mode: UpdateMode::Element { index: 2 },
            data: &(-9.5f32).to_le_bytes(),
        })
        .unwrap();
        reg.apply(&SystemValueUpdate {
            address: 0x20,
            mode: UpdateMode::Single,
            data: &2.5f64.to_le_bytes(),
        })
        .unwrap();
        assert_eq!(reg.set(0x20, 0, 4.0f64), Ok(()));
        assert_eq!(reg.set(0x0, 0, 7u8), Err(RegistryError::OutOfRange(0)));
        assert_eq!(reg.get::<f32>(0x10, 2), Some(-9.5));
        assert_eq!(reg.get::<u8>(0x10, 0), None);
        // Reply to "request data" for each address, encoded as a full message.
        let mut out = Vec::new();
        for a in [0u16, 1, 0x10, 0x20] {
            let mut value = [0u8; 64];
            let reply = reg.read(a, &mut value).unwrap();
            let mut frame = [0u8; 128];
            let n = Encoder::new(Profile::Spec)
                .encode(&reply, None, &mut frame)
                .unwrap();
            out.push(frame[..n].to_vec());
        }
        assert_eq!(
            reg.read(0x99, &mut [0u8; 8]),
            Err(RegistryError::UnknownAddress(0x99))
        );
        assert_eq!(
            reg.read(1, &mut [0u8; 8]),
            Err(RegistryError::BufferTooSmall { needed: 40 })
        );
        out
    });
    assert_eq!((direct, gains, rate), (1, [5.0, 6.0, -9.5, 8.0], 4.0));
    // Address 0: single u8 = 1. FF 88 len=15 | 01 0000 00000000 01 | cs
    assert_eq!(
        replies[0],
        [0xFF, 0x88, 15, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 1, 0x78]
    );
    let name = aydp_proto::Frame::new_checked(&replies[1], Profile::Spec).unwrap();
    let Ok(Message::SystemValueUpdate(u)) = name.message() else {
        panic!()
    };
    assert_eq!(u.mode, UpdateMode::Array { count: 40 });
    assert_eq!(&u.data[..5], b"boat\0");
    let gains = aydp_proto::Frame::new_checked(&replies[2], Profile::Spec).unwrap();
    let Ok(Message::SystemValueUpdate(u)) = gains.message() else {
        panic!()
    };
    assert_eq!(u.mode, UpdateMode::Array { count: 4 });
    assert_eq!(&u.data[8..12], &(-9.5f32).to_le_bytes());
}

#[test]
fn registry_text_slot_accepts_shorter_text_nul_padded() {
    let mut name = *b"abcdefgh";
    let mut slots = [Slot::value(0x30, Cell::Chars(&mut name))];
    let mut reg = Registry::new(&mut slots);
    reg.apply(&SystemValueUpdate {
        address: 0x30,
        mode: UpdateMode::Single,
        data: b"xy",
    })
    .unwrap();
    assert_eq!(
        reg.apply(&SystemValueUpdate {
            address: 0x30,
            mode: UpdateMode::Single,
            data: b"123456789"
        }),
        Err(RegistryError::WrongSize(0x30))
    );
    reg.apply(&SystemValueUpdate {
        address: 0x30,
        mode: UpdateMode::Element { index: 7 },
        data: b"z",
    })
    .unwrap();
    assert_eq!(name, *b"xy\0\0\0\0\0z");
}

/// Found by fuzzing (aydp_roundtrip): every non-negative binary16 pattern, NaN payloads and
/// subnormals included, survives decode then encode, so a received frame re-encodes to itself.
#[test]
fn uflt16_decode_then_encode_is_the_identity_on_every_non_negative_pattern() {
    for bits in 0u16..0x8000 {
        let v = uflt16::decode(bits).unwrap();
        assert_eq!(uflt16::encode(v), bits, "pattern {bits:#06x}");
    }
}

/// Found by fuzzing (aydp_parse): base type 127 is not a type (Y3), for parse as for encode.
#[test]
fn base_type_127_is_rejected_by_parse_as_by_the_encoder() {
    for profile in [aydp_proto::Profile::Spec, aydp_proto::Profile::Reference] {
        assert_eq!(
            aydp_proto::Message::parse(127, false, &[], profile),
            Err(aydp_proto::Error::BadType(127))
        );
    }
}
