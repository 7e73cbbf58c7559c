//! Every vector of `testdata/aok-frames.json`, both directions.

use crate::events;
use events::feed_byte;

use aok_proto::{
    Ack, Action, ActionWord, Command, CommandDecoder, DebugValue, ExternalControl, FirmwareVersion,
    Message, Motor, MotorTest, ParameterValue, ReplyForm, Stick, Waypoint, WaypointNumber,
    WaypointSlot,
};
use aok_proto::{Expect, MessageDecoder};

const VECTORS: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../testdata/aok-frames.json"
));

fn unhex(s: &str) -> Vec<u8> {
    (0..s.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(&s[i..i + 2], 16).unwrap())
        .collect()
}

fn vectors() -> Vec<(String, Vec<u8>, String)> {
    let v: serde_json::Value = serde_json::from_str(VECTORS).unwrap();
    v["vectors"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| {
            (
                e["name"].as_str().unwrap().to_owned(),
                unhex(e["bytes"].as_str().unwrap()),
                e["direction"].as_str().unwrap().to_owned(),
            )
        })
        .collect()
}

/// What each vector means, typed.
enum Expected {
    ToDevice(Command),
    FromDevice(Message, Expect, FirmwareVersion),
}

fn expected(name: &str) -> Expected {
    let latest = FirmwareVersion::LATEST;
    match name {
        "seed-example-external-control" => {
            Expected::ToDevice(Command::ExternalControl(ExternalControl {
                roll: Stick::new(32).unwrap(),
                nick: Stick::new(-32).unwrap(),
                yaw: Stick::new(0).unwrap(),
                pitch: 0,
                expiry_ms: 500,
            }))
        }
        "debug-value-flightstatus" => Expected::FromDevice(
            Message::Debug(DebugValue {
                number: 86,
                value: -2,
            }),
            Expect::Nothing,
            latest,
        ),
        "debug-value-large" => Expected::FromDevice(
            Message::Debug(DebugValue {
                number: 3,
                value: 305_419_896,
            }),
            Expect::Nothing,
            latest,
        ),
        "set-parameter" => Expected::ToDevice(Command::SetParameter(ParameterValue {
            number: 12,
            value: 1500,
        })),
        "get-parameter" => Expected::ToDevice(Command::ReadParameter(12)),
        "parameter-reply-v031" => Expected::FromDevice(
            Message::Parameter(ParameterValue {
                number: 12,
                value: 1500,
            }),
            Expect::Parameter(12),
            FirmwareVersion::new(0, 31),
        ),
        "parameter-reply-v030" => Expected::FromDevice(
            Message::Parameter(ParameterValue {
                number: 12,
                value: 1500,
            }),
            Expect::Parameter(12),
            FirmwareVersion::new(0, 30),
        ),
        "motor-test-3" => Expected::ToDevice(Command::MotorTest(MotorTest {
            motor: Motor::new(3).unwrap(),
            value: 40,
        })),
        "set-waypoint-1" => Expected::ToDevice(Command::SetWaypoint(Waypoint {
            slot: WaypointSlot::Waypoint(WaypointNumber::new(1).unwrap()),
            longitude: 237_512_345,
            latitude: 480_012_345,
            action1: ActionWord::new(Action::HoldAndClimb, 15),
            action2: ActionWord::new(Action::SetFlySpeed, 250),
        })),
        "ack-ok" => Expected::FromDevice(Message::Ack(Ack::Ok), Expect::Ack, latest),
        other => panic!("vector {other} has no expectation in this test"),
    }
}

#[test]
fn every_vector_is_covered() {
    let v = vectors();
    assert_eq!(v.len(), 10);
    for (name, _, direction) in &v {
        match (expected(name), direction.as_str()) {
            (Expected::ToDevice(_), "to-device") | (Expected::FromDevice(..), "from-device") => {}
            _ => panic!("{name}: direction {direction} disagrees"),
        }
    }
}

#[test]
fn to_device_vectors_encode_and_decode() {
    for (name, bytes, _) in vectors() {
        let Expected::ToDevice(cmd) = expected(&name) else {
            continue;
        };
        // Encode.
        let mut buf = [0u8; 19];
        let n = cmd.emit(&mut buf).unwrap();
        assert_eq!(&buf[..n], &bytes[..], "{name}: encoding");
        assert_eq!(cmd.buffer_len(), bytes.len(), "{name}: buffer_len");
        // Parse.
        assert_eq!(
            Command::parse(&bytes),
            Ok((cmd, bytes.len())),
            "{name}: parse"
        );
        // Byte-at-a-time device decoder: exactly one item, on the last byte.
        let mut dec = CommandDecoder::new();
        for (i, &b) in bytes.iter().enumerate() {
            let items: Vec<_> = feed_byte(&mut dec, b);
            if i + 1 < bytes.len() {
                assert!(items.is_empty(), "{name}: early item at byte {i}");
            } else {
                assert_eq!(items, vec![Ok(cmd)], "{name}: decoder");
            }
        }
        assert_eq!(dec.stats().frames_ok, 1);
        assert_eq!(dec.stats().bytes_discarded, 0);
    }
}

#[test]
fn from_device_vectors_encode_and_decode() {
    for (name, bytes, _) in vectors() {
        let Expected::FromDevice(msg, expect, fw) = expected(&name) else {
            continue;
        };
        let mut buf = [0u8; 19];
        let n = msg.emit(&mut buf, fw.reply_form()).unwrap();
        assert_eq!(&buf[..n], &bytes[..], "{name}: encoding");
        let mut dec = MessageDecoder::new(fw);
        dec.expect(expect);
        let mut got = Vec::new();
        for (i, &b) in bytes.iter().enumerate() {
            let items: Vec<_> = feed_byte(&mut dec, b);
            assert!(i + 1 == bytes.len() || items.is_empty(), "{name}: early");
            got.extend(items);
        }
        assert_eq!(got, vec![Ok(msg)], "{name}: decoder");
        assert_eq!(dec.expecting(), Expect::Nothing, "{name}: pending cleared");
    }
}

#[test]
fn headerless_reply_is_not_a_message_without_a_pending_read() {
    let bytes = unhex("000005dcd9");
    let mut dec = MessageDecoder::new(FirmwareVersion::new(0, 30));
    let got: Vec<_> = bytes.iter().flat_map(|&b| feed_byte(&mut dec, b)).collect();
    assert!(got.is_empty());
    assert_eq!(dec.stats().unknown_bytes, 5);
}

#[test]
fn headed_reply_vector_parses_standalone_and_headerless_too() {
    let headed = unhex("ff0c000005dcd9");
    let p = ParameterValue {
        number: 12,
        value: 1500,
    };
    assert_eq!(Message::parse(&headed), Ok((Message::Parameter(p), 7)));
    let headerless = unhex("000005dcd9");
    assert_eq!(ParameterValue::parse_headerless(&headerless, 12), Ok(p));
    // The same value in both forms: the headerless frame is the headed one minus FF NUM.
    assert_eq!(&headed[2..], &headerless[..]);
    let mut buf = [0u8; 7];
    assert_eq!(
        Message::Parameter(p).emit(&mut buf, ReplyForm::Headerless),
        Ok(5)
    );
    assert_eq!(&buf[..5], &headerless[..]);
}

#[test]
fn external_control_vector_is_little_endian() {
    let bytes = unhex("532000e0ff00000000f401ca");
    let (Command::ExternalControl(e), 12) = Command::parse(&bytes).unwrap() else {
        panic!("not external control");
    };
    assert_eq!(
        (
            e.roll.get(),
            e.nick.get(),
            e.yaw.get(),
            e.pitch,
            e.expiry_ms
        ),
        (32, -32, 0, 0, 500)
    );
}
