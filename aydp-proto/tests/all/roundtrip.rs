//! Property tests: every typed message round-trips through the encoder (buffer and iterator)
//! and the decoder, in both profiles, normal and expedited. Fixed seeds via proptest's
//! deterministic runner configuration.

use aydp_proto::{
    Decode, Decoder, DirectOutputBuilder, Encoder, FixDetailBuilder, FixQuality, Message,
    OutputEntry, Position, Profile, Raw, Satellite, SystemControl, SystemValueUpdate, Timestamp,
    UpdateMode, VesselData, WindDirection, WindSpeed, uflt16,
};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};

/// A value representable as uflt16 (so it survives the round trip exactly).
fn uf() -> impl Strategy<Value = f32> {
    (0u16..0x7C00).prop_map(uflt16::f16_bits_to_f32)
}

#[derive(Debug, Clone)]
enum Spec {
    Empty,
    Position(Position),
    FixQuality(FixQuality),
    FixDetail(Vec<Satellite>),
    DirectOutput(Vec<OutputEntry>),
    Svu(u16, UpdateMode, Vec<u8>),
    Control(SystemControl),
    Wind(f32),
    WindDir(f32),
    Vessel(VesselData),
    User(u8, Vec<u8>),
    Unknown(u8, Vec<u8>),
}

fn finite() -> impl Strategy<Value = f32> {
    -1.0e6f32..1.0e6
}

fn spec_strategy() -> impl Strategy<Value = Spec> {
    prop_oneof![
        Just(Spec::Empty),
        (any::<f64>(), any::<f64>(), finite()).prop_map(|(a, b, c)| Spec::Position(Position {
            latitude: a,
            longitude: b,
            altitude: c
        })),
        (any::<u8>(), uf(), uf(), uf(), any::<u8>()).prop_map(|(t, m, h, v, s)| Spec::FixQuality(
            FixQuality {
                fix_type: t,
                mean_dop: m,
                hdop: h,
                vdop: v,
                satellites: s
            }
        )),
        prop::collection::vec(
            (any::<u8>(), uf(), uf(), uf()).prop_map(|(id, a, e, s)| Satellite {
                id,
                azimuth: a,
                elevation: e,
                snr: s
            }),
            0..20
        )
        .prop_map(Spec::FixDetail),
        prop::collection::vec(
            (any::<u8>(), any::<u8>(), finite()).prop_map(|(d, c, v)| OutputEntry {
                device: d,
                channel: c,
                value: v
            }),
            0..20
        )
        .prop_map(Spec::DirectOutput),
        (
            any::<u16>(),
            prop_oneof![
                Just(UpdateMode::Single),
                any::<u32>().prop_map(|count| UpdateMode::Array { count }),
                any::<u32>().prop_map(|index| UpdateMode::Element { index }),
            ],
            prop::collection::vec(any::<u8>(), 0..64)
        )
            .prop_map(|(a, m, d)| Spec::Svu(a, m, d)),
        prop_oneof![
            Just(SystemControl::StoreConfiguration),
            any::<u16>().prop_map(|address| SystemControl::RequestData { address }),
        ]
        .prop_map(Spec::Control),
        finite().prop_map(Spec::Wind),
        finite().prop_map(Spec::WindDir),
        (finite(), finite(), any::<f64>(), any::<i32>(), finite()).prop_map(|(r, h, lat, s, d)| {
            Spec::Vessel(VesselData {
                roll: r,
                heading: h,
                latitude: lat,
                satellites: s,
                hdop: d,
                ..Default::default()
            })
        }),
        (100u8..=126, prop::collection::vec(any::<u8>(), 0..64))
            .prop_map(|(t, d)| Spec::User(t, d)),
        (10u8..=99, prop::collection::vec(any::<u8>(), 0..64))
            .prop_filter("17 is typed in Reference", |(t, _)| *t != 17)
            .prop_map(|(t, d)| Spec::Unknown(t, d)),
    ]
}

/// Build the message, encode it both ways, decode it, parse it and compare.
fn check(s: &Spec, profile: Profile, ts: Option<Timestamp>) -> Result<(), TestCaseError> {
    let mut scratch = [0u8; 512];
    let msg: Message<'_> = match s {
        Spec::Empty => match (profile, ts) {
            (Profile::Reference, _) => Message::NoOp,
            (Profile::Spec, Some(_)) => Message::TimeSync,
            (Profile::Spec, None) => Message::Heartbeat,
        },
        Spec::Position(p) => Message::Position(*p),
        Spec::FixQuality(q) => Message::FixQuality(*q),
        Spec::FixDetail(sats) => {
            let mut b = FixDetailBuilder::new(&mut scratch);
            for s in sats {
                b.push(*s).unwrap();
            }
            Message::FixDetail(b.finish())
        }
        Spec::DirectOutput(es) => {
            let mut b = DirectOutputBuilder::new(&mut scratch);
            for e in es {
                b.push(*e).unwrap();
            }
            Message::DirectOutput(b.finish())
        }
        Spec::Svu(a, m, d) => {
            let mode = match m {
                UpdateMode::Single => UpdateMode::Single,
                m => *m,
            };
            Message::SystemValueUpdate(SystemValueUpdate {
                address: *a,
                mode,
                data: d,
            })
        }
        Spec::Control(c) => Message::SystemControl(*c),
        Spec::Wind(w) => match profile {
            Profile::Reference => Message::WindSpeed(WindSpeed(*w)),
            Profile::Spec => Message::Tbd(Raw {
                msg_type: 1,
                data: &[],
            }),
        },
        Spec::WindDir(w) => match profile {
            Profile::Reference => Message::WindDirection(WindDirection(*w)),
            Profile::Spec => Message::Tbd(Raw {
                msg_type: 2,
                data: &[1, 2, 3],
            }),
        },
        Spec::Vessel(v) => match profile {
            Profile::Reference => Message::VesselData(*v),
            Profile::Spec => Message::Unknown(Raw {
                msg_type: 17,
                data: &[9; 68],
            }),
        },
        Spec::User(t, d) => Message::UserDefined(Raw {
            msg_type: *t,
            data: d,
        }),
        Spec::Unknown(t, d) => Message::Unknown(Raw {
            msg_type: *t,
            data: d,
        }),
    };
    let enc = Encoder::new(profile);
    let mut buf = [0u8; 1024];
    if ts.is_none() && !profile.has_expedited() {
        // The Reference profile has no expedited header: every encoding path refuses it.
        prop_assert_eq!(
            enc.encode(&msg, ts, &mut buf),
            Err(aydp_proto::EncodeError::ExpeditedInReference)
        );
        prop_assert!(enc.iter(&msg, ts).is_err());
        return Ok(());
    }
    let n = enc.encode(&msg, ts, &mut buf).unwrap();
    let iter: Vec<u8> = enc.iter(&msg, ts).unwrap().collect();
    prop_assert_eq!(&iter[..], &buf[..n]);
    prop_assert_eq!(enc.iter(&msg, ts).unwrap().len(), n);
    // Too small a buffer is an error, never a panic.
    prop_assert!(enc.encode(&msg, ts, &mut buf[..n - 1]).is_err());

    let mut dec = Decoder::<1024>::new(profile);
    let mut got = Vec::new();
    dec.feed(&buf[..n], |e| {
        let f = e.unwrap();
        got.push((f.timestamp(), f.is_expedited(), f.as_bytes().to_vec()));
    });
    prop_assert_eq!(got.len(), 1);
    let (t, exp, bytes) = &got[0];
    prop_assert_eq!(*t, ts);
    prop_assert_eq!(*exp, ts.is_none());
    let frame = aydp_proto::Frame::new_checked(bytes, profile).unwrap();
    let parsed = frame.message().unwrap();
    prop_assert_eq!(parsed, msg);
    Ok(())
}

fn runner(seed: u8) -> TestRunner {
    TestRunner::new_with_rng(
        Config {
            cases: 1500,
            failure_persistence: None,
            ..Config::default()
        },
        TestRng::from_seed(RngAlgorithm::ChaCha, &[seed; 32]),
    )
}

#[test]
fn every_typed_message_round_trips_in_both_profiles_normal_and_expedited() {
    let strategy = (
        spec_strategy(),
        prop_oneof![Just(Profile::Spec), Just(Profile::Reference)],
        prop::option::of((any::<i64>(), any::<i64>()).prop_map(|(s, ss)| Timestamp::new(s, ss))),
    );
    runner(7)
        .run(&strategy, |(s, profile, ts)| check(&s, profile, ts))
        .unwrap();
}

#[test]
fn parsing_arbitrary_data_never_panics() {
    let strategy = (
        any::<u8>(),
        any::<bool>(),
        prop::collection::vec(any::<u8>(), 0..200),
    );
    runner(8)
        .run(&strategy, |(t, exp, data)| {
            for p in [Profile::Spec, Profile::Reference] {
                let _ = Message::parse(t & 0x7F, exp, &data, p);
                let _ = aydp_proto::Frame::new_checked(&data, p).map(|f| f.message());
            }
            Ok(())
        })
        .unwrap();
}
