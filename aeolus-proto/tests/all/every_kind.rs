//! Every message kind of the spec arrives as itself: encoded, framed, decoded and parsed, each
//! of the 16 kinds (and an unknown ID) gives back the same variant and values, under its name.

use aeolus_proto::Decode;
use aeolus_proto::message::*;
use aeolus_proto::{CrcMode, Decoder};

#[test]
fn each_kind_is_parsed_back_into_its_own_variant() {
    let text = Text::new("hi").unwrap();
    let calib = [3u8; CALIBINFO_LEN];
    let debug = [4u8; DEBUGINFO_LEN];
    let kinds = [
        (Message::AeolusInfo(AeolusInfo::default()), "AEOLUSINFO"),
        (
            Message::Pressure(Pressure {
                timestamp_ms: 1.0,
                ..Pressure::default()
            }),
            "PRESSURE",
        ),
        (
            Message::Gyro(Gyro {
                timestamp_ms: 2.0,
                ..Gyro::default()
            }),
            "GYRO",
        ),
        (
            Message::Accel(Accel {
                timestamp_ms: 3.0,
                ..Accel::default()
            }),
            "ACCEL",
        ),
        (
            Message::Magnet(Magnet {
                timestamp_ms: 4.0,
                ..Magnet::default()
            }),
            "MAGNET",
        ),
        (
            Message::Temp(Temp {
                timestamp_ms: 5.0,
                ..Temp::default()
            }),
            "TEMP",
        ),
        (
            Message::Gps(Gps {
                timestamp_ms: 6.0,
                ..Gps::default()
            }),
            "GPS",
        ),
        (
            Message::Attitude(Attitude {
                timestamp_ms: 7.0,
                ..Attitude::default()
            }),
            "ATTITUDE",
        ),
        (
            Message::Compass(Compass {
                timestamp_ms: 8.0,
                ..Compass::default()
            }),
            "COMPASS",
        ),
        (
            Message::Wind(Wind {
                timestamp_ms: 9.0,
                ..Wind::default()
            }),
            "WIND",
        ),
        (
            Message::SetTime(SetTime {
                day: 21,
                ..SetTime::default()
            }),
            "SETTIME",
        ),
        (Message::CalibInfo(&calib), "CALIBINFO"),
        (Message::DebugInfo(&debug), "DEBUGINFO"),
        (Message::Log(b"log line"), "LOG"),
        (Message::Toast(text.clone()), "TOAST"),
        (Message::Command(text), "COMMAND"),
        (
            Message::Unknown {
                id: 99,
                data: &[1, 2],
            },
            "UNKNOWN",
        ),
    ];
    for (m, name) in kinds {
        let mut wire = [0u8; 600];
        let n = m.encode(&mut wire, CrcMode::Compute).unwrap();
        let mut d = Decoder::<256>::strict();
        let mut got = Vec::new();
        d.feed(&wire[..n], |ev| {
            let frame = ev.unwrap();
            got.push((frame.id(), frame.message().map(|p| (p.name(), p == m))));
        });
        assert_eq!(got, [(m.id(), Ok((name, true)))], "{name}");
    }
}
