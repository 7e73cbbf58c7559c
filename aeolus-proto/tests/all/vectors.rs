//! Every vector of testdata/aeolus-frames.json: decoding gives exactly the listed fields,
//! emitting those fields gives exactly the listed bytes, and the datagram and bad-CRC vectors
//! behave as their notes say.

use crate::common;
use aeolus_proto::Decode;
use aeolus_proto::{message::*, *};
use common::hex;
use serde_json::Value;

const VECTORS: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../testdata/aeolus-frames.json"
));

fn vectors() -> Vec<Value> {
    let doc: Value = serde_json::from_str(VECTORS).unwrap();
    doc["vectors"].as_array().unwrap().clone()
}

fn vector(name: &str) -> Value {
    vectors()
        .into_iter()
        .find(|v| v["name"] == name)
        .unwrap_or_else(|| panic!("no vector {name}"))
}

fn f(v: &Value, k: &str) -> f64 {
    v[k].as_f64().unwrap_or_else(|| panic!("field {k}"))
}

fn bytes_of(v: &Value, k: &str) -> Vec<u8> {
    v[k].as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_u64().unwrap() as u8)
        .collect()
}

/// Builds the message the vector's `fields` describe, independently of the decoder.
fn expected_message(id: u8, v: &Value) -> Message<'static> {
    let b = |k: &str| v[k].as_bool().unwrap();
    match id {
        62 => Message::Gyro(Gyro {
            valid: b("valid"),
            timestamp_ms: f(v, "timestamp_ms"),
            x: f(v, "x") as f32,
            y: f(v, "y") as f32,
            z: f(v, "z") as f32,
        }),
        63 => Message::Accel(Accel {
            valid: b("valid"),
            timestamp_ms: f(v, "timestamp_ms"),
            x: f(v, "x") as f32,
            y: f(v, "y") as f32,
            z: f(v, "z") as f32,
        }),
        66 => Message::Gps(Gps {
            valid: b("valid"),
            has_fix: b("has_fix"),
            satellites: v["satellites"].as_u64().unwrap() as u8,
            timestamp_ms: f(v, "timestamp_ms"),
            latitude_deg: f(v, "latitude_deg") as f32,
            longitude_deg: f(v, "longitude_deg") as f32,
            altitude_m: f(v, "altitude_m") as f32,
            ground_speed_mps: f(v, "ground_speed_mps") as f32,
        }),
        71 => Message::Attitude(Attitude {
            valid: b("valid"),
            timestamp_ms: f(v, "timestamp_ms"),
            roll_rad: f(v, "roll_rad") as f32,
            pitch_rad: f(v, "pitch_rad") as f32,
            yaw_rad: f(v, "yaw_rad") as f32,
            slip_ball: f(v, "slip_ball") as f32,
            turn_coordinator: f(v, "turn_coordinator") as f32,
            qx: f(v, "qx") as f32,
            qy: f(v, "qy") as f32,
            qz: f(v, "qz") as f32,
            qw: f(v, "qw") as f32,
        }),
        82 => Message::Toast(Text::new(v["text"].as_str().unwrap()).unwrap()),
        51 => {
            let fw = bytes_of(v, "firmware");
            let mac = bytes_of(v, "mac");
            Message::AeolusInfo(AeolusInfo {
                model: v["model"].as_u64().unwrap() as u8,
                firmware: fw.try_into().unwrap(),
                mac: mac.try_into().unwrap(),
            })
        }
        other => panic!("no expectation for ID {other}"),
    }
}

fn decode_one(wire: &[u8]) -> (Vec<u8>, bool) {
    let mut d = Decoder::<256>::new();
    let mut got = Vec::new();
    d.feed(wire, |ev| {
        got.push(ev.map(|f| (f.raw().to_vec(), f.has_crc())))
    });
    assert_eq!(got.len(), 1, "exactly one event for {wire:02x?}");
    got.pop().unwrap().expect("a frame")
}

#[test]
fn single_frame_vectors_decode_to_fields_and_encode_to_bytes() {
    let mut checked = 0;
    for v in vectors().iter().filter(|v| v.get("frame").is_some()) {
        let name = v["name"].as_str().unwrap();
        let id = v["id"].as_u64().unwrap() as u8;
        let wire = hex(v["frame"].as_str().unwrap());
        let expected = expected_message(id, &v["fields"]);

        // Decode: exactly the listed fields.
        let (raw, has_crc) = decode_one(&wire);
        let frame = Frame::new_checked(&raw, false).unwrap();
        assert_eq!(frame.id(), id, "{name}");
        assert_eq!(frame.message().unwrap(), expected, "{name}");

        // Emit: exactly the listed bytes (with or without CRC as the vector carries it).
        let mode = if has_crc {
            CrcMode::Compute
        } else {
            CrcMode::Omit
        };
        let mut out = [0u8; 300];
        let n = expected.encode(&mut out, mode).unwrap();
        assert_eq!(&out[..n], &wire[..], "{name}: encode");
        let streamed: Vec<u8> = {
            let mut data = [0u8; 256];
            let len = expected.emit(&mut data).unwrap();
            FrameBytes::new(id, &data[..len], mode).collect()
        };
        assert_eq!(streamed, wire, "{name}: byte iterator");
        assert!(
            n <= max_encoded_len(expected.buffer_len()),
            "{name}: worst-case bound"
        );
        checked += 1;
    }
    assert_eq!(checked, 8);
}

#[test]
fn aeolusinfo_vector_escapes_mac_bytes() {
    let wire = hex(vector("aeolusinfo-with-escapes")["frame"].as_str().unwrap());
    // 0x7E and 0x7D in the MAC travel as 7D 5E and 7D 5D.
    let at = wire
        .windows(4)
        .position(|w| w == [0x7D, 0x5E, 0x7D, 0x5D])
        .expect("escaped MAC bytes");
    assert_eq!(at, 13); // flag, ID, 8 data bytes, MAC bytes 0..=2
    let (raw, _) = decode_one(&wire);
    assert_eq!(&raw[1 + 8..1 + 14], &[124, 221, 144, 126, 125, 10]);
}

#[test]
fn toast_crc_escaped_vector() {
    let wire = hex(vector("toast-crc-escaped")["frame"].as_str().unwrap());
    let (raw, has_crc) = decode_one(&wire);
    assert!(has_crc);
    // CRC 0x7D2E, sent LSB first as 2E then 7D escaped.
    assert_eq!(Frame::new_checked(&raw, true).unwrap().crc(), 0x7D2E);
}

#[test]
fn toast_no_crc_vector_is_unchecked_and_rejected_when_strict() {
    let wire = hex(vector("toast-no-crc")["frame"].as_str().unwrap());
    let (_, has_crc) = decode_one(&wire);
    assert!(!has_crc);
    let mut strict = Decoder::<64>::strict();
    let ev = common::events(&mut strict, &wire);
    assert_eq!(ev, [Err(Error::MissingCrc { id: 82 })]);
    assert_eq!(strict.stats().missing_crc, 1);
}

#[test]
fn datagram_vector_holds_two_messages() {
    let v = vector("datagram-two-messages");
    let mut bytes = hex(v["bytes"].as_str().unwrap());
    let stream = bytes.clone();
    let got: Vec<Message<'_>> = decode_datagram(&mut bytes, true)
        .map(|f| f.unwrap().message().unwrap())
        .collect();
    assert_eq!(got.len(), 2);
    assert_eq!(
        got[0],
        Message::Gyro(Gyro {
            valid: true,
            timestamp_ms: 1.0,
            x: 0.0,
            y: 0.0,
            z: 0.0
        })
    );
    assert_eq!(got[1], Message::Toast(Text::new("hi").unwrap()));
    // The same bytes as a UART stream give the same two IDs.
    let mut d = Decoder::<64>::strict();
    let ids: Vec<_> = common::events(&mut d, &stream)
        .into_iter()
        .map(|e| e.unwrap().0)
        .collect();
    assert_eq!(ids, [62, 82]);
}

#[test]
fn bad_crc_vector_is_a_crc_error_carrying_the_id() {
    let v = vector("bad-crc");
    assert_eq!(v["expect"], "crc error");
    let wire = hex(v["bytes"].as_str().unwrap());
    let mut d = Decoder::<64>::new();
    let ev = common::events(&mut d, &wire);
    let [
        Err(Error::ChecksumMismatch {
            id,
            computed,
            received,
        }),
    ] = ev[..]
    else {
        panic!("expected one CRC error, got {ev:?}")
    };
    assert_eq!(id, 82);
    assert_eq!(received, 0x4561);
    assert_ne!(computed, received);
    assert_eq!(d.stats().checksum_errors, 1);
    assert_eq!(d.stats().bytes_discarded, 7);
    let mut datagram = wire.clone();
    let got: Vec<_> = decode_datagram(&mut datagram, false).collect();
    assert!(matches!(
        got[..],
        [Err(Error::ChecksumMismatch { id: 82, .. })]
    ));
}
