//! `protolink decode` end to end: the real binary on every vector file, on random bytes, and
//! over file, stdin, TCP and UDP endpoints.

use std::io::Write;
use std::net::UdpSocket;
use std::time::Duration;

use crate::common::*;
use serde_json::{Value, json};

fn decode_json(proto: &[&str], input: &[u8]) -> (Vec<Value>, Value) {
    let file = TempFile::new("decode", input);
    let ep = file.endpoint();
    let mut args = vec!["decode"];
    args.extend_from_slice(proto);
    args.extend(["--from", ep.as_str(), "--json"]);
    let mut lines = json_lines(&ok(&run(&args)));
    let summary = lines.pop().expect("a summary line");
    assert_eq!(summary["kind"], "summary");
    assert_eq!(summary["bytes"], input.len());
    (lines, summary["counters"].clone())
}

#[test]
fn aeolus_vectors_decode_to_their_fields() {
    for v in vectors("aeolus") {
        let bytes = vector_bytes(&v);
        let (lines, counters) = decode_json(&["--proto", "aeolus"], &bytes);
        let name = v["name"].as_str().unwrap();
        match name {
            "bad-crc" => {
                assert_eq!(lines.len(), 1, "{name}: {lines:?}");
                assert_eq!(lines[0]["kind"], "error");
                assert_eq!(lines[0]["offset"], 0, "at the bad frame's opening flag");
                assert!(
                    lines[0]["error"]
                        .as_str()
                        .unwrap()
                        .starts_with("CRC mismatch on message 82")
                );
                assert_eq!(counters["checksum_errors"], 1);
            }
            "datagram-two-messages" => {
                let names: Vec<_> = lines.iter().map(|l| l["name"].clone()).collect();
                assert_eq!(names, [json!("GYRO"), json!("TOAST")]);
                assert_eq!(lines[1]["fields"]["text"], "hi");
                assert_eq!(counters["frames_ok"], 2);
            }
            _ => {
                assert_eq!(lines.len(), 1, "{name}: {lines:?}");
                let l = &lines[0];
                assert_eq!(l["kind"], "message", "{name}");
                assert_eq!(l["id"], v["id"], "{name}");
                assert_eq!(l["len"], bytes.len(), "{name}");
                assert_eq!(l["offset"], 0, "{name}: the frame starts the input");
                let expected_crc = if name == "toast-no-crc" { "none" } else { "ok" };
                assert_eq!(l["crc"], expected_crc, "{name}");
                // Every field of the vector comes back with its value.
                for (key, want) in v["fields"].as_object().unwrap() {
                    let got = &l["fields"][key];
                    match (want.as_f64(), got.as_f64()) {
                        (Some(w), Some(g)) => assert_eq!(w, g, "{name}.{key}"),
                        _ => assert_eq!(got, want, "{name}.{key}"),
                    }
                }
            }
        }
    }
}

#[test]
fn aeolus_text_lines_are_readable_and_offsets_are_exact() {
    let mut stream = vec![0x13, 0x37];
    let mut last_start = 0;
    for v in vectors("aeolus") {
        last_start = stream.len();
        stream.extend(vector_bytes(&v));
    }
    let file = TempFile::new("text", &stream);
    let text = ok(&run(&[
        "decode",
        "--proto",
        "aeolus",
        "--from",
        &file.endpoint(),
    ]));
    let lines: Vec<&str> = text.lines().collect();
    // 2 noise bytes, then the 37-byte GYRO frame at offsets 2..39.
    assert_eq!(
        lines[0],
        "@2 GYRO id=62 len=37 crc=ok valid=true timestamp_ms=123456.5 x=0.5 y=-1.25 z=0.0078125"
    );
    assert!(text.contains("TOAST id=82 len=15 crc=ok text=\"AEOLUS on\""));
    assert!(text.contains(
        "AEOLUSINFO id=51 len=39 crc=ok model=83 firmware=[3,8,0] mac=[124,221,144,126,125,10]"
    ));
    assert!(text.contains("text=\"no crc\""));
    let last = lines.last().unwrap();
    assert!(
        last.starts_with(&format!(
            "summary: bytes={} frames_ok=9 frames_no_crc=1 checksum_errors=1",
            stream.len()
        )),
        "{last}"
    );
    assert!(last.contains("bytes_discarded=9"), "{last}");
    let errors: Vec<_> = lines.iter().filter(|l| l.contains(" error: ")).collect();
    assert_eq!(errors.len(), 1);
    // The bad-CRC vector is the last one: its error is at its opening flag.
    assert!(errors[0].starts_with(&format!("@{last_start} error: CRC mismatch")));
}

#[test]
fn aydp_vectors_decode_in_their_profile() {
    let expect: &[(&str, Value)] = &[
        (
            "seed-example-enable-direct-control",
            json!({"kind": "error"}),
        ),
        (
            "seed-example-save-config",
            json!({"name": "SYSTEM_CONTROL", "fields": {"command": "StoreConfiguration"}}),
        ),
        (
            "request-data-address-8-corrected",
            json!({"name": "SYSTEM_CONTROL", "fields": {"command": "RequestData", "address": 8}}),
        ),
        (
            "svu-enable-direct-control-table-3.8",
            json!({"name": "SYSTEM_VALUE_UPDATE", "fields": {"address": 0, "mode": "Single", "data": "01"}}),
        ),
        (
            "direct-output-rudder",
            json!({"name": "DIRECT_OUTPUT", "fields": {"entries": [{"device": 1, "channel": 2, "value": 10.0}]}}),
        ),
        (
            "position-timed",
            json!({"name": "POSITION", "time": {"seconds": 1_700_000_000, "subsec": 250}, "fields": {"latitude": 50.5, "longitude": -1.25, "altitude": 12.5}}),
        ),
        (
            "heartbeat",
            json!({"name": "HEARTBEAT", "expedited": true, "len": 7}),
        ),
        (
            "time-sync",
            json!({"name": "TIME_SYNC", "time": {"seconds": 86400, "subsec": 999}}),
        ),
        ("resync-ff-ff", json!({"name": "HEARTBEAT"})),
        (
            "reference-profile-wind-speed",
            json!({"name": "WIND_SPEED", "time": {"seconds": 42, "subsec": 500_000}, "fields": {"value": 3.5}}),
        ),
    ];
    for v in vectors("aydp") {
        let name = v["name"].as_str().unwrap();
        let bytes = vector_bytes(&v);
        let profile = v["profile"].as_str().unwrap();
        let (lines, counters) = decode_json(&["--proto", "aydp", "--profile", profile], &bytes);
        if name == "seed-example-request-data-as-printed" {
            // Y6: rejected; no message comes out of it.
            assert!(lines.iter().all(|l| l["kind"] == "error"), "{lines:?}");
            assert!(!lines.is_empty());
            assert_eq!(counters["frames_ok"], 0);
            continue;
        }
        let (_, want) = expect
            .iter()
            .find(|(n, _)| *n == name)
            .unwrap_or_else(|| panic!("no expectation for {name}"));
        assert_eq!(lines.len(), 1, "{name}: {lines:?}");
        for (key, value) in want.as_object().unwrap() {
            assert_eq!(&lines[0][key], value, "{name}.{key}: {}", lines[0]);
        }
        if lines[0]["kind"] == "error" {
            assert!(
                lines[0]["error"].as_str().unwrap().contains("malformed"),
                "{name}"
            );
            assert_eq!(counters["malformed"], 1);
        } else {
            // A run of 0xFF starts at its last byte (Y5).
            let start = bytes.iter().take_while(|&&b| b == 0xFF).count().max(1) - 1;
            assert_eq!(
                lines[0]["offset"], start,
                "{name}: where the message starts"
            );
        }
    }
}

#[test]
fn aok_vectors_decode_by_side() {
    for v in vectors("aok") {
        let name = v["name"].as_str().unwrap();
        let bytes = vector_bytes(&v);
        let side = if v["direction"] == "to-device" {
            "pc"
        } else {
            "device"
        };
        let (lines, _) = decode_json(&["--proto", "aok", "--side", side], &bytes);
        let want = match name {
            "seed-example-external-control" => Some(
                json!({"name": "EXTERNAL_CONTROL", "fields": {"roll": 32, "nick": -32, "yaw": 0, "pitch": 0, "expiry_ms": 500}}),
            ),
            "debug-value-flightstatus" => {
                Some(json!({"name": "DEBUG", "fields": {"number": 86, "value": -2}}))
            }
            "debug-value-large" => {
                Some(json!({"name": "DEBUG", "fields": {"number": 3, "value": 305_419_896}}))
            }
            "set-parameter" => {
                Some(json!({"name": "SET_PARAMETER", "fields": {"number": 12, "value": 1500}}))
            }
            "get-parameter" => Some(json!({"name": "READ_PARAMETER", "fields": {"number": 12}})),
            "parameter-reply-v031" => {
                Some(json!({"name": "PARAMETER", "fields": {"number": 12, "value": 1500}}))
            }
            "motor-test-3" => {
                Some(json!({"name": "MOTOR_TEST", "fields": {"motor": 3, "value": 40}}))
            }
            "set-waypoint-1" => Some(
                json!({"name": "SET_WAYPOINT", "fields": {"slot": "1", "longitude": 237_512_345, "latitude": 480_012_345, "action1": "hold-and-climb:15", "action2": "set-fly-speed:250"}}),
            ),
            // Only meaningful as the answer to a pending request: a passive decoder skips them.
            "parameter-reply-v030" | "ack-ok" => None,
            other => panic!("no expectation for {other}"),
        };
        match want {
            Some(want) => {
                assert_eq!(lines.len(), 1, "{name}: {lines:?}");
                for (key, value) in want.as_object().unwrap() {
                    assert_eq!(&lines[0][key], value, "{name}.{key}");
                }
                // A run of 0xFF starts at its last byte (Y5).
                let start = bytes.iter().take_while(|&&b| b == 0xFF).count().max(1) - 1;
                assert_eq!(
                    lines[0]["offset"], start,
                    "{name}: where the message starts"
                );
            }
            None => assert!(
                lines.iter().all(|l| l["kind"] != "message"),
                "{name}: {lines:?}"
            ),
        }
    }
}

#[test]
fn aok_checksum_errors_appear_with_their_offset() {
    // A debug frame with a broken checksum, then a good one.
    let mut stream = unhex("1c56fffffffe58");
    stream.extend(unhex("1c03123456780b"));
    let (lines, counters) = decode_json(&["--proto", "aok"], &stream);
    assert_eq!(lines[0]["kind"], "error");
    // At the first byte of the frame it condemns, not at its last, where it was found, and
    // as long as that frame.
    assert_eq!(
        (&lines[0]["offset"], &lines[0]["len"]),
        (&json!(0), &json!(7))
    );
    assert_eq!(lines[0]["error"], "checksum mismatch");
    assert_eq!(lines.last().unwrap()["fields"]["value"], 305_419_896);
    // The rescan after the false start meets more false starts (FF...): each is reported.
    let errors = lines.iter().filter(|l| l["kind"] == "error").count();
    assert_eq!(counters["checksum_errors"], errors);
    // The device decoder (PC's bytes) reports a bad motor-test checksum the same way.
    let (lines, _) = decode_json(&["--proto", "aok", "--side", "pc"], &unhex("33281c670c"));
    assert_eq!(lines[0]["kind"], "error");
    assert_eq!(lines[0]["offset"], 0);
    assert_eq!(lines.last().unwrap()["name"], "READ_PARAMETER");
}

#[test]
fn one_mebibyte_of_random_bytes_never_panics() {
    let noise = random_bytes(0x5eed_1234, 1 << 20);
    let file = TempFile::new("noise", &noise);
    let ep = file.endpoint();
    for proto in [
        vec!["--proto", "aeolus"],
        vec!["--proto", "aydp", "--profile", "spec"],
        vec!["--proto", "aydp", "--profile", "reference"],
        vec!["--proto", "aok", "--side", "device"],
        vec!["--proto", "aok", "--side", "pc"],
    ] {
        let mut args = vec!["decode", "--from", ep.as_str()];
        args.extend(&proto);
        let out = run(&args);
        let text = ok(&out);
        assert!(!stderr(&out).contains("panicked"));
        let last = text.lines().last().unwrap();
        assert!(
            last.starts_with("summary: bytes=1048576 "),
            "{proto:?}: {last}"
        );
        // Random input produces errors, and they are reported in the stream.
        assert!(text.lines().any(|l| l.contains(" error: ")), "{proto:?}");
    }
}

#[test]
fn stdin_is_an_endpoint() {
    let bytes = vector_bytes(&vectors("aeolus")[0]);
    let out = run_with_stdin(&["decode", "--proto", "aeolus", "--from", "-"], &bytes);
    let text = ok(&out);
    assert!(text.starts_with("@0 GYRO id=62"), "{text}");
}

#[test]
fn tcp_stream_split_into_single_bytes_decodes_the_same() {
    let (listener, ep) = listener();
    let mut stream = Vec::new();
    for v in vectors("aeolus") {
        stream.extend(vector_bytes(&v));
    }
    let sent = stream.clone();
    let server = std::thread::spawn(move || {
        let (mut s, _) = listener.accept().unwrap();
        s.set_nodelay(true).unwrap();
        for b in sent {
            s.write_all(&[b]).unwrap();
        }
    });
    let text = ok(&run(&["decode", "--proto", "aeolus", "--from", &ep]));
    server.join().unwrap();
    let file = TempFile::new("same", &stream);
    let from_file = ok(&run(&[
        "decode",
        "--proto",
        "aeolus",
        "--from",
        &file.endpoint(),
    ]));
    assert_eq!(text, from_file);
}

#[test]
fn udp_datagrams_keep_their_boundaries() {
    let port = free_udp_port();
    let ep = format!("udp:{port}");
    let child = spawn(&[
        "decode",
        "--proto",
        "aeolus",
        "--from",
        &ep,
        "--json",
        "--seconds",
        "3",
    ]);
    let two = vector_bytes(&vectors("aeolus")[8]); // GYRO + TOAST in one datagram
    assert_eq!(vectors("aeolus")[8]["name"], "datagram-two-messages");
    // A datagram cut inside a frame: the frame must not continue into the next datagram.
    let cut = &two[..20];
    let socket = UdpSocket::bind("127.0.0.1:0").unwrap();
    // The child binds its port shortly after it starts; repeat until its time is up.
    for _ in 0..40 {
        socket.send_to(cut, ("127.0.0.1", port)).unwrap();
        socket.send_to(&two, ("127.0.0.1", port)).unwrap();
        std::thread::sleep(Duration::from_millis(25));
    }
    let out = finish(child);
    let lines = json_lines(&ok(&out));
    let messages: Vec<_> = lines.iter().filter(|l| l["kind"] == "message").collect();
    let errors: Vec<_> = lines.iter().filter(|l| l["kind"] == "error").collect();
    assert!(!messages.is_empty(), "nothing arrived");
    // Every whole datagram gives GYRO then TOAST; every cut one a truncation error.
    assert_eq!(messages.len() % 2, 0);
    assert!(
        messages
            .iter()
            .all(|m| m["name"] == "GYRO" || m["name"] == "TOAST")
    );
    assert!(!errors.is_empty());
    assert!(
        errors
            .iter()
            .all(|e| e["error"] == "datagram ends inside a frame"),
        "{errors:?}"
    );
    let summary = lines.last().unwrap();
    assert_eq!(summary["counters"]["checksum_errors"], 0);
    assert_eq!(summary["counters"]["truncated"], errors.len());
}

/// A `Kept` item (what captures and the Python package hold) lends back the item it was made
/// from: the same typed message, placed the same, rendered the same; an error the same kind and
/// sentence. Over the sample streams of every protocol, each read as every side or profile (so
/// that errors come too), and GDL90 frames of several types with one cut short.
#[test]
fn a_kept_item_lends_back_the_item_it_was_made_from() {
    use protolink::decoders::{Decoder, Item, Kept};
    use protolink::proto::{ProfileArg, Proto, Side};
    let testdata = concat!(env!("CARGO_MANIFEST_DIR"), "/../testdata/");
    let read = |name: &str| std::fs::read(format!("{testdata}{name}")).unwrap_or_default();
    let mut gdl90 = Vec::new();
    for m in [
        gdl90_proto::message::Message::Heartbeat(Default::default()),
        gdl90_proto::message::Message::Ownship(Default::default()),
        gdl90_proto::message::Message::GeoAltitude(Default::default()),
        gdl90_proto::message::Message::Ahrs(Default::default()),
        gdl90_proto::message::Message::StratuxAhrs(Default::default()),
        gdl90_proto::message::Message::Unknown {
            id: 7,
            data: &[1, 2, 3],
        },
    ] {
        let mut out = [0u8; 128];
        let n = m.encode(&mut out).unwrap_or(0);
        gdl90.extend_from_slice(&out[..n]);
    }
    gdl90.extend_from_within(..5);
    let streams = [
        (
            read("qemu-uart0-aeolus.bin"),
            Proto::Aeolus,
            ProfileArg::Spec,
            Side::Device,
        ),
        (
            read("qemu-uart1-aydp.bin"),
            Proto::Aydp,
            ProfileArg::Spec,
            Side::Device,
        ),
        (
            read("qemu-uart1-aydp.bin"),
            Proto::Aydp,
            ProfileArg::Reference,
            Side::Device,
        ),
        (
            read("qemu-uart2-aok.bin"),
            Proto::Aok,
            ProfileArg::Spec,
            Side::Device,
        ),
        (
            read("qemu-uart2-aok.bin"),
            Proto::Aok,
            ProfileArg::Spec,
            Side::Pc,
        ),
        (gdl90, Proto::Gdl90, ProfileArg::Spec, Side::Device),
    ];
    let (mut messages, mut errors) = (0, 0);
    for (bytes, proto, profile, side) in streams {
        assert!(!bytes.is_empty(), "{proto:?}: no sample");
        let mut d = Decoder::new(proto, profile, side);
        let mut check = |p: protolink::decoders::Placed<'_>| {
            let kept = Kept::new(&p);
            assert_eq!(kept.with(|q| q.to_event()), p.to_event(), "{proto:?}");
            if let Item::Error(_) = p.item {
                errors += 1;
                assert!(kept.is_error());
            } else {
                messages += 1;
                assert!(kept.with(|q| *q == p), "{proto:?}: {p:?}");
            }
        };
        d.feed(&bytes, 0, &mut check);
        d.finish(&mut check);
    }
    // Both kinds were kept: the other side's and profile's views give errors.
    assert!(
        messages > 1000 && errors > 0,
        "{messages} messages, {errors} errors"
    );
}
