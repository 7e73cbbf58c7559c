//! Literal wire bytes: the ICD's own example, a real ForeFlight ID capture, and frames worked
//! out by hand from the layout tables (field by field in the comments). The CRC bytes were
//! computed outside this crate (an independent script of the ICD's CRC) and are pinned here.

use gdl90_proto::message::{
    AddressType, Ahrs, AltitudeDatum, CallSign, Emergency, ForeFlightId, GeoAltitude, Heading,
    Heartbeat, LatLon, Message, Report, StratuxAhrs, Track,
};
use gdl90_proto::{Decode, Decoder, Error, MAX_ENCODED_LEN, TYPED_FRAME};

/// Decodes `wire` byte by byte and returns the one message it must hold, owned.
fn decode_one(wire: &[u8]) -> Message<'static> {
    let mut d = Decoder::<TYPED_FRAME>::new();
    let mut got = Vec::new();
    for b in wire {
        d.feed(core::slice::from_ref(b), |ev| {
            let msg = ev.expect("a good frame");
            // Leak the raw data of unknown messages so the value outlives the decoder.
            got.push(match msg {
                Message::Unknown { id, data } => Message::Unknown {
                    id,
                    data: Vec::leak(data.to_vec()),
                },
                Message::Heartbeat(m) => Message::Heartbeat(m),
                Message::Ownship(m) => Message::Ownship(m),
                Message::GeoAltitude(m) => Message::GeoAltitude(m),
                Message::Traffic(m) => Message::Traffic(m),
                Message::ForeFlightId(m) => Message::ForeFlightId(m),
                Message::Ahrs(m) => Message::Ahrs(m),
                Message::StratuxAhrs(m) => Message::StratuxAhrs(m),
            });
        });
    }
    assert_eq!(got.len(), 1, "{wire:02X?}");
    assert_eq!(d.stats().frames_ok, 1);
    got.remove(0)
}

/// ICD section 2.2.4: the heartbeat example and its CRC, `B3 8B` (0x8BB3 LSB first).
const ICD_HEARTBEAT: [u8; 11] = [
    0x7E, 0x00, 0x81, 0x41, 0xDB, 0xD0, 0x08, 0x02, 0xB3, 0x8B, 0x7E,
];

fn icd_heartbeat() -> Heartbeat {
    Heartbeat {
        gps_position_valid: true,       // 0x81 bit 7
        uat_initialized: true,          // 0x81 bit 0
        csa_requested: true,            // 0x41 bit 6
        utc_ok: true,                   // 0x41 bit 0
        seconds_since_midnight: 0xD0DB, // DB D0 LSB first, bit 16 (0x41 bit 7) clear
        uplink_messages: 1,             // 0x08 >> 3
        basic_long_messages: 2,         // (0x08 & 3) << 8 | 0x02
        ..Heartbeat::default()
    }
}

#[test]
fn icd_heartbeat_example_decodes_and_encodes_bit_for_bit() {
    assert_eq!(
        decode_one(&ICD_HEARTBEAT),
        Message::Heartbeat(icd_heartbeat())
    );
    let mut wire = [0u8; MAX_ENCODED_LEN];
    let n = Message::Heartbeat(icd_heartbeat())
        .encode(&mut wire)
        .unwrap();
    assert_eq!(&wire[..n], &ICD_HEARTBEAT);
}

/// A heartbeat (status 81 01, 74 s after midnight) whose CRC 0x7EBB has its high byte
/// escaped: `BB 7D 5E`.
const HEARTBEAT_CRC_ESCAPED: [u8; 12] = [
    0x7E, 0x00, 0x81, 0x01, 0x4A, 0x00, 0x00, 0x00, 0xBB, 0x7D, 0x5E, 0x7E,
];
/// The same at 2604 s: CRC 0x7E7D, both bytes escaped: `7D 5D 7D 5E`.
const HEARTBEAT_CRC_BOTH_ESCAPED: [u8; 13] = [
    0x7E, 0x00, 0x81, 0x01, 0x2C, 0x0A, 0x00, 0x00, 0x7D, 0x5D, 0x7D, 0x5E, 0x7E,
];

#[test]
fn escaped_crc_bytes_are_accepted_and_produced() {
    for (wire, seconds) in [
        (&HEARTBEAT_CRC_ESCAPED[..], 74),
        (&HEARTBEAT_CRC_BOTH_ESCAPED[..], 2604),
    ] {
        let hb = Heartbeat {
            gps_position_valid: true,
            uat_initialized: true,
            utc_ok: true,
            seconds_since_midnight: seconds,
            ..Heartbeat::default()
        };
        assert_eq!(decode_one(wire), Message::Heartbeat(hb));
        let mut out = [0u8; MAX_ENCODED_LEN];
        let n = Message::Heartbeat(hb).encode(&mut out).unwrap();
        assert_eq!(&out[..n], wire);
    }
}

/// An all-zero heartbeat: its genuine CRC is 0x0000. It is a checked CRC, not "no CRC".
const HEARTBEAT_ZERO_CRC: [u8; 11] = [0x7E, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0x7E];

#[test]
fn a_genuine_crc_of_zero_is_accepted() {
    assert_eq!(
        decode_one(&HEARTBEAT_ZERO_CRC),
        Message::Heartbeat(Heartbeat::default())
    );
}

#[test]
fn a_zeroed_crc_field_is_a_crc_error_not_an_unchecked_frame() {
    // The ICD heartbeat with its CRC replaced by 00 00 (AEOLUS would accept it unchecked).
    let mut wire = ICD_HEARTBEAT;
    wire[8] = 0;
    wire[9] = 0;
    let mut d = Decoder::<TYPED_FRAME>::new();
    let mut events = Vec::new();
    for b in &wire {
        d.feed(core::slice::from_ref(b), |ev| {
            events.push(ev.map(|m| m.id()))
        });
    }
    assert_eq!(
        events,
        [Err(Error::ChecksumMismatch {
            id: 0,
            computed: 0x8BB3,
            received: 0
        })]
    );
    let s = d.stats();
    assert_eq!((s.frames_ok, s.checksum_errors), (0, 1));
    assert_eq!((s.bytes_discarded, s.frame_bytes, s.flags), (9, 0, 2));
}

/// An Ownship Report worked out by hand from `layout::report` (data offsets):
/// - 0: `s`=0 no alert, `t`=0 ADS-B ICAO: `00`
/// - 1..4: address 0xA1B2C3: `A1 B2 C3`
/// - 4..7: latitude 45.0 = 45 x 2^23/180 = 0x200000: `20 00 00`
/// - 7..10: longitude -90.0 = -0x400000, 24-bit two's complement 0xC00000: `C0 00 00`
/// - 10..12: altitude 2500 ft = (2500 + 1000) / 25 = 140 = 0x08C; misc 0b1001 (airborne,
///   updated, true track): `08 C9`
/// - 12: NIC 9, NACp 10: `9A`
/// - 13..16: 120 kt = 0x078; -128 fpm = -2 steps = 0xFFE: `07 8F FE`
/// - 16: track 90 degrees = 64 x 360/256: `40`
/// - 17: emitter category 1 (light): `01`
/// - 18..26: "N12345" space padded: `4E 31 32 33 34 35 20 20`
/// - 26: no emergency: `00`
///
/// CRC 0x4B58, LSB first: `58 4B`.
const OWNSHIP: [u8; 32] = [
    0x7E, 0x0A, 0x00, 0xA1, 0xB2, 0xC3, 0x20, 0x00, 0x00, 0xC0, 0x00, 0x00, 0x08, 0xC9, 0x9A, 0x07,
    0x8F, 0xFE, 0x40, 0x01, 0x4E, 0x31, 0x32, 0x33, 0x34, 0x35, 0x20, 0x20, 0x00, 0x58, 0x4B, 0x7E,
];

fn ownship() -> Report {
    Report {
        traffic_alert: false,
        address_type: AddressType::AdsbIcao,
        address: 0xA1B2C3,
        position: Some(LatLon {
            lat_deg: 45.0,
            lon_deg: -90.0,
        }),
        pressure_altitude_ft: Some(2500),
        airborne: true,
        extrapolated: false,
        track: Some(Track::TrueTrack(90.0)),
        nic: 9,
        nacp: 10,
        ground_speed_kt: Some(120),
        vertical_rate_fpm: Some(-128),
        emitter: 1,
        call_sign: CallSign::new("N12345").unwrap(),
        emergency: Emergency::None,
    }
}

#[test]
fn ownship_report_worked_by_hand() {
    assert_eq!(decode_one(&OWNSHIP), Message::Ownship(ownship()));
    let mut wire = [0u8; MAX_ENCODED_LEN];
    let n = Message::Ownship(ownship()).encode(&mut wire).unwrap();
    assert_eq!(&wire[..n], &OWNSHIP);
}

/// The ICD's traffic report example (section 3.5.4): N825V at 44.90708 N 122.99488 W,
/// 5000 ft, airborne, true track 45 degrees, 123 kt, climbing 64 fpm, NIC 10, NACp 9, light
/// aircraft, ICAO address 52642511 (octal). CRC 0xD657: `57 D6`.
const ICD_TRAFFIC: [u8; 32] = [
    0x7E, 0x14, 0x00, 0xAB, 0x45, 0x49, 0x1F, 0xEF, 0x15, 0xA8, 0x89, 0x78, 0x0F, 0x09, 0xA9, 0x07,
    0xB0, 0x01, 0x20, 0x01, 0x4E, 0x38, 0x32, 0x35, 0x56, 0x20, 0x20, 0x20, 0x00, 0x57, 0xD6, 0x7E,
];

#[test]
fn icd_traffic_example() {
    let Message::Traffic(t) = decode_one(&ICD_TRAFFIC) else {
        panic!("not a traffic report")
    };
    assert_eq!(t.address, 0o52642511);
    let p = t.position.unwrap();
    assert!((p.lat_deg - 44.90708).abs() < 1e-4, "{}", p.lat_deg);
    assert!((p.lon_deg + 122.99488).abs() < 1e-4, "{}", p.lon_deg);
    assert_eq!(t.pressure_altitude_ft, Some(5000));
    assert!(t.airborne && !t.extrapolated);
    assert_eq!(t.track, Some(Track::TrueTrack(45.0)));
    assert_eq!((t.nic, t.nacp), (10, 9));
    assert_eq!(t.ground_speed_kt, Some(123));
    assert_eq!(t.vertical_rate_fpm, Some(64));
    assert_eq!(t.emitter, 1);
    assert_eq!(t.call_sign.as_str(), Some("N825V"));
    let mut wire = [0u8; MAX_ENCODED_LEN];
    let n = Message::Traffic(t).encode(&mut wire).unwrap();
    assert_eq!(&wire[..n], &ICD_TRAFFIC);
}

/// ForeFlight AHRS worked out by hand from `layout::ahrs`:
/// - 0: sub-ID `01`
/// - 1..3: roll 10.0 = 100 = `00 64`
/// - 3..5: pitch -5.0 = -50 = `FF CE`
/// - 5..7: true heading (bit 15 clear) 180.0 = 1800 = `07 08`
/// - 7..9: IAS 120 kt = `00 78`
/// - 9..11: TAS 126 kt = `00 7E`, the flag byte, escaped on the wire as `7D 5E`
///
/// CRC 0xBF5A: `5A BF`.
const AHRS: [u8; 17] = [
    0x7E, 0x65, 0x01, 0x00, 0x64, 0xFF, 0xCE, 0x07, 0x08, 0x00, 0x78, 0x00, 0x7D, 0x5E, 0x5A, 0xBF,
    0x7E,
];

fn ahrs() -> Ahrs {
    Ahrs {
        roll_deg: Some(10.0),
        pitch_deg: Some(-5.0),
        heading: Some(Heading::True(180.0)),
        indicated_airspeed_kt: Some(120),
        true_airspeed_kt: Some(126),
    }
}

#[test]
fn ahrs_worked_by_hand() {
    assert_eq!(decode_one(&AHRS), Message::Ahrs(ahrs()));
    let mut wire = [0u8; MAX_ENCODED_LEN];
    let n = Message::Ahrs(ahrs()).encode(&mut wire).unwrap();
    assert_eq!(&wire[..n], &AHRS);
}

#[test]
fn ahrs_invalid_markers_and_rejected_attitudes() {
    // Everything invalid: 7FFF 7FFF FFFF FFFF FFFF.
    let data = [
        1, 0x7F, 0xFF, 0x7F, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF,
    ];
    assert_eq!(Ahrs::parse(&data), Ok(Ahrs::default()));
    // Roll 1801 (0x0709): the whole message is rejected.
    let mut bad = data;
    bad[1..3].copy_from_slice(&1801i16.to_be_bytes());
    assert_eq!(
        Ahrs::parse(&bad),
        Err(Error::OutOfRange {
            id: 0x65,
            field: "roll"
        })
    );
    // Pitch -1801.
    let mut bad = data;
    bad[3..5].copy_from_slice(&(-1801i16).to_be_bytes());
    assert_eq!(
        Ahrs::parse(&bad),
        Err(Error::OutOfRange {
            id: 0x65,
            field: "pitch"
        })
    );
    // ±180.0 exactly is accepted.
    let mut edge = data;
    edge[1..3].copy_from_slice(&(-1800i16).to_be_bytes());
    edge[3..5].copy_from_slice(&1800i16.to_be_bytes());
    let a = Ahrs::parse(&edge).unwrap();
    assert_eq!((a.roll_deg, a.pitch_deg), (Some(-180.0), Some(180.0)));
    // Magnetic heading -0.1 would be FFFF (invalid): it goes out as magnetic 359.9.
    let mut out = [0u8; Ahrs::LEN];
    Ahrs {
        heading: Some(Heading::Magnetic(-0.1)),
        ..Ahrs::default()
    }
    .emit(&mut out)
    .unwrap();
    assert_eq!(out[5..7], [0x8E, 0x0F]); // 0x8000 | 3599
    // A heading beyond ±360 is reduced, not clamped; NaN is invalid.
    Ahrs {
        heading: Some(Heading::True(370.0)),
        roll_deg: Some(f32::NAN),
        ..Ahrs::default()
    }
    .emit(&mut out)
    .unwrap();
    assert_eq!(out[1..7], [0x7F, 0xFF, 0x7F, 0xFF, 0x00, 0x64]);
}

/// A Stratux AHRS report (0x4C) from outside this project: the `leAHRS` test frame of a
/// TypeScript GDL90 decoder published on GitHub (found through the code search's exact-string
/// index, which did not name the repository; see the crate README), given there unescaped
/// without flags as `4c 45 01 01`, twenty field bytes, then its CRC `b7 49`. Nothing in it needs
/// escaping. Its CRC checks out with the ICD's CRC (the decoder below verifies it), and it
/// follows Stratux's layout field for field: roll, pitch, heading, slip/skid, yaw rate and G
/// all 0, airspeed `7FFF` (Stratux never measures it), pressure altitude `FFFF` and vertical
/// speed `7FFF` (no pressure sensor), reserved `7FFF`, the bytes `makeAHRSGDL90Report` writes.
const EXTERNAL_STRATUX_AHRS: [u8; 28] = [
    0x7E, 0x4C, 0x45, 0x01, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
    0x00, 0x7F, 0xFF, 0xFF, 0xFF, 0x7F, 0xFF, 0x7F, 0xFF, 0xB7, 0x49, 0x7E,
];

#[test]
fn external_stratux_ahrs_frame_decodes_and_encodes_byte_for_byte() {
    let want = StratuxAhrs {
        roll_deg: Some(0.0),
        pitch_deg: Some(0.0),
        heading_deg: Some(0.0),
        slip_skid_deg: Some(0.0),
        yaw_rate_dps: Some(0.0),
        g_load: Some(0.0),
        indicated_airspeed_kt: None,
        pressure_altitude_ft: None,
        vertical_speed_fpm: None,
    };
    assert_eq!(
        decode_one(&EXTERNAL_STRATUX_AHRS),
        Message::StratuxAhrs(want)
    );
    let mut wire = [0u8; MAX_ENCODED_LEN];
    let n = Message::StratuxAhrs(want).encode(&mut wire).unwrap();
    assert_eq!(&wire[..n], &EXTERNAL_STRATUX_AHRS);
}

/// Worked by hand from Stratux's layout, big-endian after `4C 45 01 01`: roll 300 (`01 2C`),
/// pitch -25 (`FF E7`), heading 2713 (`0A 99`), slip/skid -15 (`FF F1`), yaw rate 65
/// (`00 41`), G 12 (`00 0C`), IAS 98 kt (`00 62`), pressure altitude 1234 + 5000 = 6234
/// (`18 5A`), vertical speed -500 (`FE 0C`), reserved `7F FF`. CRC 0x705E by the independent
/// script, sent `5E 70`.
const STRATUX_AHRS: [u8; 28] = [
    0x7E, 0x4C, 0x45, 0x01, 0x01, 0x01, 0x2C, 0xFF, 0xE7, 0x0A, 0x99, 0xFF, 0xF1, 0x00, 0x41, 0x00,
    0x0C, 0x00, 0x62, 0x18, 0x5A, 0xFE, 0x0C, 0x7F, 0xFF, 0x5E, 0x70, 0x7E,
];

#[test]
fn stratux_ahrs_worked_by_hand() {
    let want = StratuxAhrs {
        roll_deg: Some(30.0),
        pitch_deg: Some(-2.5),
        heading_deg: Some(271.3),
        slip_skid_deg: Some(-1.5),
        yaw_rate_dps: Some(6.5),
        g_load: Some(1.2),
        indicated_airspeed_kt: Some(98),
        pressure_altitude_ft: Some(1234),
        vertical_speed_fpm: Some(-500),
    };
    assert_eq!(decode_one(&STRATUX_AHRS), Message::StratuxAhrs(want));
    let mut wire = [0u8; MAX_ENCODED_LEN];
    let n = Message::StratuxAhrs(want).encode(&mut wire).unwrap();
    assert_eq!(&wire[..n], &STRATUX_AHRS);
}

#[test]
fn stratux_ahrs_markers_clamps_and_rejections() {
    let mut invalid = vec![0x45, 0x01, 0x01];
    invalid.extend([0x7F, 0xFF].repeat(10));
    invalid[17..19].copy_from_slice(&[0xFF, 0xFF]);
    assert_eq!(StratuxAhrs::parse(&invalid), Ok(StratuxAhrs::default()));
    let mut out = [0u8; StratuxAhrs::LEN];
    StratuxAhrs::default().emit(&mut out).unwrap();
    assert_eq!(&out[..], &invalid[..], "None is the marker, field by field");
    // Rejected: attitude beyond ±180, heading beyond ±360, another header.
    for (at, value, field) in [
        (3, 1801i16, "roll"),
        (5, -1801, "pitch"),
        (7, 3601, "heading"),
    ] {
        let mut bad = invalid.clone();
        bad[at..at + 2].copy_from_slice(&value.to_be_bytes());
        assert_eq!(
            StratuxAhrs::parse(&bad),
            Err(Error::OutOfRange { id: 0x4C, field })
        );
    }
    let mut bad = invalid.clone();
    bad[2] = 0x02;
    assert_eq!(
        StratuxAhrs::parse(&bad),
        Err(Error::OutOfRange {
            id: 0x4C,
            field: "header"
        })
    );
    assert_eq!(
        StratuxAhrs::parse(&invalid[..22]),
        Err(Error::WrongLength {
            id: 0x4C,
            expected: 23,
            actual: 22
        })
    );
    // Clamps never land on a marker; NaN is invalid; a heading is reduced into 0..360.
    StratuxAhrs {
        roll_deg: Some(500.0),
        pitch_deg: Some(f32::NAN),
        heading_deg: Some(725.0),
        g_load: Some(1e9),
        indicated_airspeed_kt: Some(i16::MAX),
        pressure_altitude_ft: Some(i32::MAX),
        vertical_speed_fpm: Some(i16::MAX),
        ..StratuxAhrs::default()
    }
    .emit(&mut out)
    .unwrap();
    assert_eq!(&out[3..9], &[0x07, 0x08, 0x7F, 0xFF, 0x00, 0x32]); // 1800, invalid, 50
    assert_eq!(&out[13..15], &[0x7F, 0xFE]);
    assert_eq!(&out[15..21], &[0x7F, 0xFE, 0xFF, 0xFE, 0x7F, 0xFE]);
    // A 0x4C frame without the 0x45 byte is some other message: raw.
    let mut wire = [0u8; 32];
    let n = gdl90_proto::encode_frame(0x4C, &[0x46, 1, 1], &mut wire).unwrap();
    assert_eq!(
        decode_one(&wire[..n]),
        Message::Unknown {
            id: 0x4C,
            data: &[0x46, 1, 1]
        }
    );
}

/// A real ForeFlight ID frame captured from a SkyEcho (published in the repository
/// jakkaj/skyecho-controller-app, in its file docs/research/foreflight-extensions.md): serial 0x270FAE2D, name and long name
/// "SkyEcho", no capabilities. Its CRC `2D F0` checks out with the ICD's CRC.
const SKYECHO_ID: [u8; 43] = [
    0x7E, 0x65, 0x00, 0x01, 0x00, 0x00, 0x00, 0x00, 0x27, 0x0F, 0xAE, 0x2D, 0x53, 0x6B, 0x79, 0x45,
    0x63, 0x68, 0x6F, 0x00, 0x53, 0x6B, 0x79, 0x45, 0x63, 0x68, 0x6F, 0x00, 0x00, 0x00, 0x00, 0x00,
    0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x2D, 0xF0, 0x7E,
];

#[test]
fn foreflight_id_capture() {
    let id = ForeFlightId {
        version: 1,
        serial: Some(0x270F_AE2D),
        name: gdl90_proto::message::Name::new("SkyEcho").unwrap(),
        long_name: gdl90_proto::message::Name::new("SkyEcho").unwrap(),
        altitude_datum: AltitudeDatum::Wgs84Ellipsoid,
        other_capabilities: 0,
    };
    assert_eq!(decode_one(&SKYECHO_ID), Message::ForeFlightId(id));
    let mut wire = [0u8; MAX_ENCODED_LEN];
    let n = Message::ForeFlightId(id).encode(&mut wire).unwrap();
    assert_eq!(&wire[..n], &SKYECHO_ID);
    // Capabilities bit 0 set: MSL.
    let mut data = [0u8; ForeFlightId::LEN];
    id.emit(&mut data).unwrap();
    data[37] = 0x01;
    assert_eq!(
        ForeFlightId::parse(&data).unwrap().altitude_datum,
        AltitudeDatum::Msl
    );
    data[2..10].fill(0xFF);
    assert_eq!(ForeFlightId::parse(&data).unwrap().serial, None);
}

/// Geometric altitude 1500 ft (300 = `01 2C`), VFOM 10 m (`00 0A`); CRC 0x2624: `24 26`.
const GEO_ALTITUDE: [u8; 9] = [0x7E, 0x0B, 0x01, 0x2C, 0x00, 0x0A, 0x24, 0x26, 0x7E];

#[test]
fn geo_altitude_by_hand() {
    let alt = GeoAltitude {
        altitude_ft: 1500,
        vertical_warning: false,
        vfom_m: Some(10),
    };
    assert_eq!(decode_one(&GEO_ALTITUDE), Message::GeoAltitude(alt));
    let mut wire = [0u8; MAX_ENCODED_LEN];
    let n = Message::GeoAltitude(alt).encode(&mut wire).unwrap();
    assert_eq!(&wire[..n], &GEO_ALTITUDE);
}

#[test]
fn report_markers_and_clamps() {
    // Everything "not available": position 0/0 with NIC 0, altitude FFF, speed FFF,
    // vertical rate 800, track type 0.
    let none = Report::default();
    let mut data = [0u8; Report::LEN];
    none.emit(&mut data).unwrap();
    assert_eq!(data[10..16], [0xFF, 0xF0, 0x00, 0xFF, 0xF8, 0x00]);
    assert_eq!(Report::parse(10, &data), Ok(none));
    // Out-of-range values clamp to the largest valid code, never to a marker.
    let big = Report {
        pressure_altitude_ft: Some(200_000),
        ground_speed_kt: Some(5000),
        vertical_rate_fpm: Some(-1_000_000),
        nic: 99,
        address: u32::MAX,
        position: Some(LatLon {
            lat_deg: 95.0,
            lon_deg: 190.0,
        }),
        ..Report::default()
    };
    big.emit(&mut data).unwrap();
    let back = Report::parse(10, &data).unwrap();
    assert_eq!(back.pressure_altitude_ft, Some(101_350));
    assert_eq!(back.ground_speed_kt, Some(4094));
    assert_eq!(back.vertical_rate_fpm, Some(-32_640));
    assert_eq!((back.nic, back.address), (15, 0xFF_FFFF));
    let p = back.position.unwrap();
    assert_eq!(p.lat_deg, 90.0);
    assert!((p.lon_deg + 170.0).abs() < 1e-4, "{}", p.lon_deg);
    // A NaN position is sent as "no position", NIC 0.
    let nan = Report {
        position: Some(LatLon {
            lat_deg: f64::NAN,
            lon_deg: 1.0,
        }),
        nic: 8,
        ..Report::default()
    };
    nan.emit(&mut data).unwrap();
    assert_eq!(data[4..10], [0; 6]);
    assert_eq!(data[12] >> 4, 0);
    // The reserved vertical-rate codes read as "not available".
    data[14] = (data[14] & 0xF0) | 0x1;
    data[15] = 0xFF; // 0x1FF = 511 steps
    assert_eq!(Report::parse(10, &data).unwrap().vertical_rate_fpm, None);
}

#[test]
fn unknown_ids_and_foreflight_sub_ids_are_delivered_raw() {
    // ID 7 (uplink), 3 data bytes; CRC computed by the encoder (framing is tested above).
    for (id, data) in [
        (7u8, &[1u8, 2, 3][..]),
        (0x65, &[0x02, 0xAA][..]),
        (0x65, &[][..]),
    ] {
        let mut wire = [0u8; 32];
        let n = gdl90_proto::encode_frame(id, data, &mut wire).unwrap();
        assert_eq!(
            decode_one(&wire[..n]),
            Message::Unknown {
                id,
                data: Vec::leak(data.to_vec())
            }
        );
    }
}

#[test]
fn wrong_lengths_are_errors_carrying_the_id() {
    assert_eq!(
        Message::parse(10, &[0; 26]),
        Err(Error::WrongLength {
            id: 10,
            expected: 27,
            actual: 26
        })
    );
    assert_eq!(
        Message::parse(0x65, &[1, 0, 0]),
        Err(Error::WrongLength {
            id: 0x65,
            expected: 11,
            actual: 3
        })
    );
}

#[cfg(feature = "serde")]
#[test]
fn messages_serialise_to_readable_json() {
    let json = serde_json::to_string(&Message::Ownship(ownship())).unwrap();
    assert!(json.contains("\"call_sign\":\"N12345\""), "{json}");
    assert!(json.contains("\"pressure_altitude_ft\":2500"), "{json}");
    let json = serde_json::to_string(&Message::Ahrs(Ahrs::default())).unwrap();
    assert!(json.contains("\"roll_deg\":null"), "{json}");
}

/// The field examples printed in the ICD: message counts (3.1.4), latitude/longitude
/// (3.5.1.3), pressure altitude (3.5.1.4), vertical velocity (3.5.1.8), geometric altitude
/// and vertical metrics (3.8).
#[test]
fn icd_field_examples() {
    // 4 uplink and 567 basic/long messages: counts bytes 0x22 0x37.
    let hb = Heartbeat {
        uplink_messages: 4,
        basic_long_messages: 567,
        ..Heartbeat::default()
    };
    let mut data = [0u8; Heartbeat::LEN];
    hb.emit(&mut data).unwrap();
    assert_eq!(data[4..6], [0x22, 0x37]);
    assert_eq!(Heartbeat::parse(&data), Ok(hb));

    let report_with = |bytes: &[(usize, u8)]| {
        let mut d = [0u8; Report::LEN];
        d[12] = 0x10; // NIC 1, so that a 0/0 position still reads as a position
        for &(at, b) in bytes {
            d[at] = b;
        }
        Report::parse(10, &d).unwrap()
    };
    let lat = |b: [u8; 3]| {
        report_with(&[(4, b[0]), (5, b[1]), (6, b[2])])
            .position
            .unwrap()
            .lat_deg
    };
    let lon = |b: [u8; 3]| {
        report_with(&[(7, b[0]), (8, b[1]), (9, b[2])])
            .position
            .unwrap()
            .lon_deg
    };
    let lsb = 180.0 / 8_388_608.0;
    assert_eq!(lat([0x00, 0x00, 0x01]), lsb);
    assert_eq!(lat([0xFF, 0xFF, 0xFF]), -lsb);
    assert_eq!(lat([0x20, 0x00, 0x00]), 45.0);
    assert_eq!(lat([0xE0, 0x00, 0x00]), -45.0);
    assert_eq!(lat([0x40, 0x00, 0x00]), 90.0);
    assert_eq!(lon([0x80, 0x00, 0x00]), -180.0);
    assert_eq!(lon([0x7F, 0xFF, 0xFF]), 180.0 - lsb);

    let alt = |ddd: u16| {
        report_with(&[(10, (ddd >> 4) as u8), (11, (ddd << 4) as u8)]).pressure_altitude_ft
    };
    assert_eq!(alt(0x000), Some(-1000));
    assert_eq!(alt(0x028), Some(0));
    assert_eq!(alt(0x050), Some(1000));
    assert_eq!(alt(0xFFE), Some(101_350));
    assert_eq!(alt(0xFFF), None);

    let vv = |v: u16| report_with(&[(14, (v >> 8) as u8), (15, v as u8)]).vertical_rate_fpm;
    assert_eq!(vv(0x000), Some(0));
    assert_eq!(vv(0x001), Some(64));
    assert_eq!(vv(0xFFF), Some(-64));
    assert_eq!(vv(0x1FD), Some(32_576));
    assert_eq!(vv(0x1FE), Some(32_640));
    assert_eq!(vv(0xE03), Some(-32_576));
    assert_eq!(vv(0xE02), Some(-32_640));
    assert_eq!(vv(0x800), None);
    assert_eq!(vv(0x1FF), None);
    assert_eq!(vv(0xE01), None);

    let geo = |alt: i32, warning: bool, vfom_m: Option<u16>| {
        let mut d = [0u8; GeoAltitude::LEN];
        GeoAltitude {
            altitude_ft: alt,
            vertical_warning: warning,
            vfom_m,
        }
        .emit(&mut d)
        .unwrap();
        d
    };
    assert_eq!(geo(-1000, true, None), [0xFF, 0x38, 0xFF, 0xFF]);
    assert_eq!(geo(0, false, Some(40_000)), [0x00, 0x00, 0x7F, 0xFE]);
    assert_eq!(geo(1000, false, Some(10)), [0x00, 0xC8, 0x00, 0x0A]);
    assert_eq!(geo(0, true, Some(50)), [0x00, 0x00, 0x80, 0x32]);
}
