//! `Message::timestamp_ms` is the message's own timestamp field for the nine timestamped
//! telemetry kinds, and `None` for every other kind.

use aeolus_proto::message::*;

#[test]
fn each_timestamped_kind_gives_its_own_timestamp() {
    let got = [
        Message::Gyro(Gyro {
            timestamp_ms: 1.5,
            ..Gyro::default()
        })
        .timestamp_ms(),
        Message::Accel(Accel {
            timestamp_ms: 2.5,
            ..Accel::default()
        })
        .timestamp_ms(),
        Message::Magnet(Magnet {
            timestamp_ms: 3.5,
            ..Magnet::default()
        })
        .timestamp_ms(),
        Message::Pressure(Pressure {
            timestamp_ms: 4.5,
            ..Pressure::default()
        })
        .timestamp_ms(),
        Message::Temp(Temp {
            timestamp_ms: 5.5,
            ..Temp::default()
        })
        .timestamp_ms(),
        Message::Gps(Gps {
            timestamp_ms: 6.5,
            ..Gps::default()
        })
        .timestamp_ms(),
        Message::Attitude(Attitude {
            timestamp_ms: 7.5,
            ..Attitude::default()
        })
        .timestamp_ms(),
        Message::Compass(Compass {
            timestamp_ms: 8.5,
            ..Compass::default()
        })
        .timestamp_ms(),
        Message::Wind(Wind {
            timestamp_ms: 9.5,
            ..Wind::default()
        })
        .timestamp_ms(),
    ];
    let want = [1.5, 2.5, 3.5, 4.5, 5.5, 6.5, 7.5, 8.5, 9.5].map(Some);
    assert_eq!(got, want);
}

#[test]
fn the_other_kinds_have_no_timestamp() {
    let text = Text::new("hi").unwrap();
    let others = [
        Message::AeolusInfo(AeolusInfo::default()),
        Message::CalibInfo(&[0; CALIBINFO_LEN]),
        Message::DebugInfo(&[0; DEBUGINFO_LEN]),
        Message::Log(b"log"),
        Message::Toast(text.clone()),
        Message::Command(text),
        Message::SetTime(SetTime::default()),
        Message::Unknown {
            id: 99,
            data: &[1, 2],
        },
    ];
    for m in others {
        assert_eq!(m.timestamp_ms(), None, "{}", m.name());
    }
}
