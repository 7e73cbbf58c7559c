//! Round trips: typed values on the wire grid survive emit and parse exactly and a whole
//! encode and decode; arbitrary values (NaN, infinities, out of range) are clamped or marked,
//! never wrapped; parse then emit is the identity on canonical data.

use gdl90_proto::message::{
    AddressType, Ahrs, CallSign, Emergency, ForeFlightId, GeoAltitude, Heading, Heartbeat, LatLon,
    Message, Name, Report, StratuxAhrs, Track,
};
use gdl90_proto::{Decode, Decoder, EncodeError, MAX_ENCODED_LEN, TYPED_FRAME, max_encoded_len};
use proptest::prelude::*;

const DEG_PER_LSB: f64 = 180.0 / 8_388_608.0;

fn heartbeat() -> impl Strategy<Value = Heartbeat> {
    (any::<[bool; 10]>(), 0u32..=0x1FFFF, 0u8..=31, 0u16..=1023).prop_map(|(f, s, u, b)| {
        Heartbeat {
            gps_position_valid: f[0],
            maintenance_required: f[1],
            ident: f[2],
            address_talkback: f[3],
            gps_battery_low: f[4],
            atc_services: f[5],
            uat_initialized: f[6],
            csa_requested: f[7],
            csa_not_available: f[8],
            utc_ok: f[9],
            seconds_since_midnight: s,
            uplink_messages: u,
            basic_long_messages: b,
        }
    })
}

fn report() -> impl Strategy<Value = Report> {
    let position = prop_oneof![
        Just(None),
        (-(1i64 << 22)..=(1 << 22), -(1i64 << 23)..(1 << 23)).prop_map(|(la, lo)| Some(LatLon {
            lat_deg: la as f64 * DEG_PER_LSB,
            lon_deg: lo as f64 * DEG_PER_LSB,
        })),
    ];
    let track = prop_oneof![
        Just(None),
        (0u8..3, any::<u8>()).prop_map(|(k, t)| {
            let d = t as f32 * 360.0 / 256.0;
            Some(
                [
                    Track::TrueTrack(d),
                    Track::MagneticHeading(d),
                    Track::TrueHeading(d),
                ][k as usize],
            )
        }),
    ];
    (
        (
            any::<bool>(),
            0u8..16,
            0u32..=0xFF_FFFF,
            position,
            proptest::option::of(0i32..=0xFFE),
        ),
        (
            any::<[bool; 2]>(),
            track,
            1u8..16,
            0u8..16,
            proptest::option::of(0u16..=0xFFE),
        ),
        (
            proptest::option::of(-510i32..=510),
            any::<u8>(),
            "[A-Z0-9 ]{0,8}",
            0u8..16,
        ),
    )
        .prop_map(
            |((alert, t, address, position, alt), (m, track, nic, nacp, gs), (vr, e, cs, p))| {
                Report {
                    traffic_alert: alert,
                    address_type: AddressType::from_nibble(t),
                    address,
                    position,
                    pressure_altitude_ft: alt.map(|a| a * 25 - 1000),
                    airborne: m[0],
                    extrapolated: m[1],
                    track,
                    // NIC 0 with no position, so the "no position" reading is unambiguous.
                    nic: if position.is_some() { nic } else { 0 },
                    nacp,
                    ground_speed_kt: gs,
                    vertical_rate_fpm: vr.map(|v| v * 64),
                    emitter: e,
                    call_sign: CallSign::new(&cs).unwrap(),
                    emergency: Emergency::from_nibble(p),
                }
            },
        )
}

fn geo() -> impl Strategy<Value = GeoAltitude> {
    (
        any::<i16>(),
        any::<bool>(),
        proptest::option::of(0u16..0x7FFF),
    )
        .prop_map(|(a, w, v)| GeoAltitude {
            altitude_ft: a as i32 * 5,
            vertical_warning: w,
            vfom_m: v,
        })
}

fn tenths(limit: i32) -> impl Strategy<Value = Option<f32>> {
    proptest::option::of((-limit..=limit).prop_map(|v| v as f32 / 10.0))
}

fn ahrs() -> impl Strategy<Value = Ahrs> {
    let heading = prop_oneof![
        Just(None),
        (any::<bool>(), -3600i32..=3600).prop_filter_map(
            "magnetic -0.1 is the invalid word",
            |(m, v)| {
                let d = v as f32 / 10.0;
                match (m, v) {
                    (true, -1) => None,
                    (true, _) => Some(Some(Heading::Magnetic(d))),
                    (false, _) => Some(Some(Heading::True(d))),
                }
            }
        ),
    ];
    (
        tenths(1800),
        tenths(1800),
        heading,
        proptest::option::of(0u16..0xFFFF),
        proptest::option::of(0u16..0xFFFF),
    )
        .prop_map(|(roll_deg, pitch_deg, heading, ias, tas)| Ahrs {
            roll_deg,
            pitch_deg,
            heading,
            indicated_airspeed_kt: ias,
            true_airspeed_kt: tas,
        })
}

fn stratux_ahrs() -> impl Strategy<Value = StratuxAhrs> {
    let wide = || proptest::option::of(-32768i32..=32766);
    (
        (tenths(1800), tenths(1800), tenths(3600)),
        (wide(), wide(), wide()),
        (wide(), proptest::option::of(-5000i32..=60534), wide()),
    )
        .prop_map(
            |((roll_deg, pitch_deg, heading_deg), (slip, yaw, g), (ias, alt, vs))| StratuxAhrs {
                roll_deg,
                pitch_deg,
                heading_deg,
                slip_skid_deg: slip.map(|v| v as f32 / 10.0),
                yaw_rate_dps: yaw.map(|v| v as f32 / 10.0),
                g_load: g.map(|v| v as f32 / 10.0),
                indicated_airspeed_kt: ias.map(|v| v as i16),
                pressure_altitude_ft: alt,
                vertical_speed_fpm: vs.map(|v| v as i16),
            },
        )
}

fn foreflight_id() -> impl Strategy<Value = ForeFlightId> {
    (
        any::<u8>(),
        proptest::option::of(0..u64::MAX),
        "[a-zA-Z0-9 ]{0,8}",
        "[a-zA-Z0-9 é]{0,7}",
        any::<bool>(),
        any::<u32>(),
    )
        .prop_map(|(version, serial, n, l, msl, caps)| ForeFlightId {
            version,
            serial,
            name: Name::new(&n).unwrap(),
            long_name: Name::new(&l).unwrap(),
            altitude_datum: if msl {
                gdl90_proto::message::AltitudeDatum::Msl
            } else {
                gdl90_proto::message::AltitudeDatum::Wgs84Ellipsoid
            },
            other_capabilities: caps & !1,
        })
}

fn message() -> impl Strategy<Value = Message<'static>> {
    prop_oneof![
        heartbeat().prop_map(Message::Heartbeat),
        report().prop_map(Message::Ownship),
        report().prop_map(Message::Traffic),
        geo().prop_map(Message::GeoAltitude),
        ahrs().prop_map(Message::Ahrs),
        stratux_ahrs().prop_map(Message::StratuxAhrs),
        foreflight_id().prop_map(Message::ForeFlightId),
    ]
}

/// Encodes `msg`, decodes the wire, and returns the debug text of the one message seen.
fn through_the_wire(msg: &Message<'_>) -> String {
    let mut wire = [0u8; MAX_ENCODED_LEN];
    let n = msg.encode(&mut wire).unwrap();
    assert!(n <= max_encoded_len(msg.buffer_len()));
    let mut d = Decoder::<TYPED_FRAME>::new();
    let mut seen = Vec::new();
    d.feed(&wire[..n], |ev| seen.push(format!("{:?}", ev.unwrap())));
    assert_eq!(seen.len(), 1);
    seen.remove(0)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(3000))]

    #[test]
    fn values_on_the_grid_survive_emit_parse_and_the_wire(msg in message()) {
        let mut data = [0u8; 64];
        let n = msg.emit(&mut data).unwrap();
        prop_assert_eq!(n, msg.buffer_len());
        prop_assert_eq!(Message::parse(msg.id(), &data[..n]).unwrap(), msg);
        prop_assert_eq!(through_the_wire(&msg), format!("{msg:?}"));
    }

    #[test]
    fn parse_then_emit_is_the_identity_on_canonical_data(
        which in 0usize..7,
        bytes in proptest::collection::vec(any::<u8>(), 38),
    ) {
        let (id, data): (u8, Vec<u8>) = match which {
            0 => (0, bytes[..Heartbeat::LEN].to_vec()),
            1 => (10, bytes[..Report::LEN].to_vec()),
            2 => (20, bytes[..Report::LEN].to_vec()),
            3 => (11, bytes[..GeoAltitude::LEN].to_vec()),
            4 => (0x65, [&[1u8][..], &bytes[..Ahrs::LEN - 1]].concat()),
            5 => (0x4C, [&[0x45u8, 1, 1][..], &bytes[..StratuxAhrs::LEN - 3]].concat()),
            _ => (0x65, [&[0u8][..], &bytes[..ForeFlightId::LEN - 1]].concat()),
        };
        if let Ok(msg) = Message::parse(id, &data) {
            let mut canon = [0u8; 64];
            let n = msg.emit(&mut canon).unwrap();
            let again = Message::parse(id, &canon[..n]).unwrap();
            prop_assert_eq!(again, msg);
            let mut twice = [0u8; 64];
            let m = again.emit(&mut twice).unwrap();
            prop_assert_eq!(&twice[..m], &canon[..n]);
        }
    }

    #[test]
    fn arbitrary_ahrs_values_are_clamped_or_marked(
        roll in proptest::option::of(any::<f32>()),
        pitch in proptest::option::of(-1000f32..1000.0),
        heading in proptest::option::of(any::<f32>()),
        ias in proptest::option::of(any::<u16>()),
    ) {
        let a = Ahrs {
            roll_deg: roll,
            pitch_deg: pitch,
            heading: heading.map(Heading::Magnetic),
            indicated_airspeed_kt: ias,
            true_airspeed_kt: None,
        };
        let mut data = [0u8; Ahrs::LEN];
        a.emit(&mut data).unwrap();
        // Whatever went in, the receiver accepts it.
        let back = Ahrs::parse(&data).unwrap();
        for (sent, got) in [(roll, back.roll_deg), (pitch, back.pitch_deg)] {
            match sent {
                None => prop_assert_eq!(got, None),
                Some(x) if x.is_nan() => prop_assert_eq!(got, None),
                Some(x) => {
                    let want = x.clamp(-180.0, 180.0);
                    let got = got.unwrap();
                    prop_assert!((got - want).abs() <= 0.05 + want.abs() * 1e-6, "{x} -> {got}");
                }
            }
        }
        match heading {
            None => prop_assert_eq!(back.heading, None),
            Some(x) if x.is_nan() => prop_assert_eq!(back.heading, None),
            Some(_) => prop_assert!(matches!(back.heading, Some(Heading::Magnetic(_)))),
        }
        prop_assert_eq!(back.indicated_airspeed_kt, ias.map(|v| v.min(0xFFFE)));
    }

    #[test]
    fn arbitrary_report_values_are_clamped_or_marked(
        alt in proptest::option::of(any::<i32>()),
        gs in proptest::option::of(any::<u16>()),
        vr in proptest::option::of(any::<i32>()),
        lat in -1e3f64..1e3,
        lon in -1e4f64..1e4,
        track in any::<f32>(),
    ) {
        let r = Report {
            pressure_altitude_ft: alt,
            ground_speed_kt: gs,
            vertical_rate_fpm: vr,
            position: Some(LatLon { lat_deg: lat, lon_deg: lon }),
            nic: 5,
            track: Some(Track::TrueHeading(track)),
            ..Report::default()
        };
        let mut data = [0u8; Report::LEN];
        r.emit(&mut data).unwrap();
        let back = Report::parse(10, &data).unwrap();
        prop_assert_eq!(back.pressure_altitude_ft.is_some(), alt.is_some());
        if let (Some(a), Some(b)) = (alt, back.pressure_altitude_ft) {
            let want = (a as i64).clamp(-1000, 101_350);
            prop_assert!((b as i64 - want).abs() <= 12, "{a} -> {b}");
        }
        prop_assert_eq!(back.ground_speed_kt, gs.map(|v| v.min(4094)));
        prop_assert_eq!(back.vertical_rate_fpm.is_some(), vr.is_some());
        if let (Some(a), Some(b)) = (vr, back.vertical_rate_fpm) {
            let want = (a as i64).clamp(-32_640, 32_640);
            prop_assert!((b as i64 - want).abs() <= 32, "{a} -> {b}");
        }
        let p = back.position.unwrap();
        prop_assert!((p.lat_deg - lat.clamp(-90.0, 90.0)).abs() <= DEG_PER_LSB);
        let dlon = (p.lon_deg - lon).rem_euclid(360.0);
        prop_assert!(dlon <= DEG_PER_LSB || 360.0 - dlon <= DEG_PER_LSB, "{lon} -> {}", p.lon_deg);
        prop_assert!((-180.0..180.0).contains(&p.lon_deg));
        prop_assert!(matches!(back.track, Some(Track::TrueHeading(_))));
    }
}

proptest! {
    /// A buffer short of a message's data is refused with the data's exact length, one short
    /// of its frame with the frame's worst case (`max_encoded_len`), which holds it.
    #[test]
    fn a_short_buffer_is_refused_with_the_length_needed(msg in message(), short_by in 1usize..4) {
        let mut wire = [0u8; MAX_ENCODED_LEN];
        let n = msg.encode(&mut wire).unwrap();
        let mut short = vec![0u8; n.saturating_sub(short_by)];
        let worst = max_encoded_len(msg.buffer_len());
        prop_assert!(n <= worst);
        prop_assert_eq!(msg.encode(&mut short), Err(EncodeError::BufferTooSmall { needed: worst }));
        let len = msg.buffer_len();
        let mut data = vec![0u8; len.saturating_sub(short_by)];
        prop_assert_eq!(msg.emit(&mut data), Err(EncodeError::BufferTooSmall { needed: len }));
    }
}
