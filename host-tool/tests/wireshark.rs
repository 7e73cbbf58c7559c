//! The generated Wireshark dissector: the committed copy is the generator's output, and tshark
//! with it prints exactly what `protolink decode --json` prints, frame by frame and field by
//! field, on captures made by `record` (from `sim`) and on crafted frames (bad CRC, no CRC,
//! escapes, several messages per datagram, raw and text messages).
//!
//! Without tshark the comparison is skipped with a message, except under CI (`CI=true`),
//! where a missing tshark fails the test.

mod common;

use std::net::SocketAddrV4;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

use aeolus_proto::message::{CalibrationStatus, Message, Text};
use aeolus_proto::{CrcMode, encode_frame};
use common::*;
use protolink::capture::CaptureWriter;
use serde_json::Value;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn dissector() -> PathBuf {
    root().join("tools/wireshark/protolink.lua")
}

fn temp(tag: &str) -> PathBuf {
    std::env::temp_dir().join(format!("protolink-ws-{}-{tag}", std::process::id()))
}

#[test]
fn the_committed_dissector_is_the_generators_output() {
    let generated = ok(&run(&["wireshark"]));
    let committed = std::fs::read_to_string(dissector()).expect("tools/wireshark/protolink.lua");
    assert!(
        generated == committed,
        "tools/wireshark/protolink.lua is stale: run `cargo run -q -p protolink -- wireshark > tools/wireshark/protolink.lua`"
    );
    // Every fixed message and every one of its fields is declared.
    for (_, name, _, fields) in protolink::wireshark::FIXED {
        for (field, _, _) in fields {
            let key = format!("\"aeolus.{}.{field}\"", name.to_lowercase());
            assert!(committed.contains(&key), "{key} missing");
        }
    }
}

/// tshark, or `None` (with the reason printed) when it is missing outside CI.
fn tshark() -> Option<&'static str> {
    let found = Command::new("tshark")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    if found {
        return Some("tshark");
    }
    assert!(
        std::env::var("CI").as_deref() != Ok("true"),
        "tshark is missing under CI: scripts/setup.sh tshark installs it"
    );
    eprintln!(
        "SKIPPED: tshark is not installed (apt-get install tshark, or scripts/setup.sh tshark)"
    );
    None
}

fn tshark_messages(tshark: &str, cap: &Path, decode_as: Option<u16>) -> Vec<Vec<Value>> {
    let mut cmd = Command::new(tshark);
    cmd.arg("-r")
        .arg(cap)
        .arg("-X")
        .arg(format!("lua_script:{}", dissector().display()));
    if let Some(port) = decode_as {
        cmd.arg("-d").arg(format!("udp.port=={port},aeolus"));
    }
    cmd.args(["-T", "json", "--no-duplicate-keys", "-j", "aeolus"]);
    let out = cmd.output().expect("tshark runs");
    assert!(
        out.status.success(),
        "tshark: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        !stderr.contains("Lua: Error"),
        "the dissector failed: {stderr}"
    );
    let packets: Vec<Value> = serde_json::from_slice(&out.stdout).expect("tshark's JSON");
    packets
        .iter()
        .map(|p| match &p["_source"]["layers"]["aeolus"] {
            Value::Array(a) => a.clone(),
            Value::Null => Vec::new(),
            one => vec![one.clone()],
        })
        .collect()
}

/// `decode --json` events per frame (1-based frame n at index n-1): messages and CRC errors.
fn decode_messages(cap: &Path, frames: usize) -> Vec<Vec<Value>> {
    let lines = json_lines(&ok(&run(&[
        "decode",
        "--from",
        cap.to_str().unwrap(),
        "--proto",
        "aeolus",
        "--json",
    ])));
    let mut per = vec![Vec::new(); frames];
    for v in lines {
        if let Some(f) = v["frame"].as_u64() {
            per[f as usize - 1].push(v);
        }
    }
    per
}

fn close(a: f64, b: f64) -> bool {
    // tshark prints floats with 6 significant digits.
    a == b || (a - b).abs() <= 1e-5 * a.abs().max(b.abs()) || (a - b).abs() < 1e-35
}

fn same_value(decoded: &Value, shown: &Value, what: &str) {
    match (decoded, shown) {
        (Value::Bool(b), Value::String(s)) => {
            assert_eq!(s, if *b { "1" } else { "0" }, "{what}")
        }
        (Value::Number(n), Value::String(s)) => {
            let (a, b) = (n.as_f64().unwrap(), s.parse::<f64>().expect(what));
            assert!(close(a, b), "{what}: decode {a}, tshark {b}");
        }
        (Value::Array(a), Value::Array(b)) => {
            assert_eq!(a.len(), b.len(), "{what}");
            for (i, (x, y)) in a.iter().zip(b).enumerate() {
                same_value(x, y, &format!("{what}[{i}]"));
            }
        }
        (Value::String(name), Value::String(s)) => {
            // CalibrationStatus: tshark prints the raw value, decode its name.
            let v: i8 = s.parse().expect(what);
            let expected = serde_json::to_value(CalibrationStatus::from_i8(v)).unwrap();
            assert_eq!(&expected, &Value::String(name.clone()), "{what}");
        }
        other => panic!("{what}: cannot compare {other:?}"),
    }
}

/// Every message of every frame: the same messages, and every field tshark shows equal to
/// decode's. Returns how many messages and fields were compared.
fn compare(tshark: &str, cap: &Path, decode_as: Option<u16>) -> (usize, usize) {
    let shown = tshark_messages(tshark, cap, decode_as);
    let decoded = decode_messages(cap, shown.len());
    let (mut messages, mut fields) = (0, 0);
    for (i, (t, d)) in shown.iter().zip(&decoded).enumerate() {
        let frame = i + 1;
        assert_eq!(
            t.len(),
            d.len(),
            "frame {frame}: tshark {t:?}\ndecode {d:?}"
        );
        for (t, d) in t.iter().zip(d) {
            messages += 1;
            let status = t["aeolus.crc_status"].as_str().unwrap();
            if d["kind"] == "error" {
                assert!(d["error"].as_str().unwrap().contains("CRC mismatch"), "{d}");
                assert_eq!(status, "bad", "frame {frame}");
                continue;
            }
            let name = d["name"].as_str().unwrap();
            assert_eq!(t["aeolus.name"], name, "frame {frame}");
            assert_eq!(t["aeolus.id"], d["id"].to_string(), "frame {frame}");
            assert_eq!(t["aeolus.len"], d["len"].to_string(), "frame {frame}");
            assert_eq!(status, d["crc"].as_str().unwrap(), "frame {frame} {name}");
            let lower = name.to_lowercase();
            let df = d["fields"].as_object().unwrap();
            if let Some(text) = df.get("text") {
                assert_eq!(&t["aeolus.text"], text, "frame {frame}");
                fields += 1;
                continue;
            }
            if let Some(data) = df.get("data") {
                let hex = t["aeolus.data"].as_str().unwrap_or("").replace(':', "");
                assert_eq!(Value::String(hex), *data, "frame {frame}");
                assert_eq!(t["aeolus.data_len"], df["len"].to_string(), "frame {frame}");
                fields += 2;
                continue;
            }
            // Every field tshark shows is one decode has, with the same value, and none is missing.
            let prefix = format!("aeolus.{lower}.");
            let shown_keys: Vec<&String> = t
                .as_object()
                .unwrap()
                .keys()
                .filter(|k| k.starts_with(&prefix))
                .collect();
            assert_eq!(shown_keys.len(), df.len(), "frame {frame} {name}: {t}\n{d}");
            for (k, v) in df {
                let what = format!("frame {frame} {name}.{k}");
                same_value(v, &t[format!("{prefix}{k}")], &what);
                fields += 1;
            }
        }
    }
    (messages, fields)
}

fn frame(id: u8, data: &[u8], crc: CrcMode) -> Vec<u8> {
    let mut out = vec![0u8; 1024];
    let n = encode_frame(id, data, &[], crc, &mut out).unwrap();
    out.truncate(n);
    out
}

#[test]
fn tshark_with_the_dissector_prints_what_decode_prints_on_crafted_frames() {
    let Some(tshark) = tshark() else { return };
    let cap = temp("crafted.pcapng");
    let mut w = CaptureWriter::create(&cap, 1, "crafted").unwrap();
    let boxa: SocketAddrV4 = "127.0.0.1:40000".parse().unwrap();
    let app: SocketAddrV4 = "127.0.0.1:5001".parse().unwrap();
    let t0 = Duration::from_secs(1_700_000_000);
    let toast = |s: &str| {
        let mut d = [0u8; 64];
        let n = Message::Toast(Text::new(s).unwrap()).emit(&mut d).unwrap();
        d[..n].to_vec()
    };
    let mut gyro = vec![0u8; 32];
    gyro[0] = 1;
    gyro[8..16].copy_from_slice(&1234.5f64.to_le_bytes());
    gyro[16..20].copy_from_slice(&0.125f32.to_le_bytes());
    // 0x7E and 0x7D inside the data: escaped on the wire.
    gyro[20..24].copy_from_slice(&f32::from_le_bytes([0x7E, 0x7D, 0x20, 0x41]).to_le_bytes());
    gyro[24..28].copy_from_slice(&(-3.5f32).to_le_bytes());
    let mut compass = vec![0u8; 80];
    compass[0] = 1;
    compass[1] = (-2i8) as u8;
    compass[3] = 42;
    for (i, v) in (0..12).map(|i| i as f32 * 0.5 - 1.0).enumerate() {
        compass[32 + 4 * i..36 + 4 * i].copy_from_slice(&v.to_le_bytes());
    }
    let mut bad = frame(82, &toast("hi"), CrcMode::Compute);
    bad[2] ^= 1;
    let mut several = frame(62, &gyro, CrcMode::Compute);
    several.extend(frame(72, &compass, CrcMode::Omit));
    several.extend(frame(82, &toast("AEOLUS on"), CrcMode::Compute));
    let mut info = vec![0u8; 32];
    info[..4].copy_from_slice(&[83, 3, 8, 0]);
    info[8..14].copy_from_slice(&[2, 0x7E, 1, 5, 0, 1]);
    let datagrams: Vec<Vec<u8>> = vec![
        frame(82, &toast("AEOLUS on"), CrcMode::Compute),
        bad,
        frame(82, &toast("no crc"), CrcMode::Omit),
        several,
        frame(51, &info, CrcMode::Compute),
        frame(81, b"log bytes \x7e\x7d", CrcMode::Compute),
        frame(200, &[1, 2, 3], CrcMode::Compute),
    ];
    for (i, d) in datagrams.iter().enumerate() {
        w.udp(t0 + Duration::from_millis(i as u64 * 10), boxa, app, d)
            .unwrap();
    }
    w.flush().unwrap();
    drop(w);
    let (messages, fields) = compare(tshark, &cap, None);
    assert_eq!(messages, 9);
    assert_eq!(fields, 24);
    // The flags tshark raises.
    let out = Command::new(tshark)
        .arg("-r")
        .arg(&cap)
        .arg("-X")
        .arg(format!("lua_script:{}", dissector().display()))
        .args([
            "-T",
            "fields",
            "-e",
            "aeolus.crc_status",
            "-E",
            "occurrence=a",
        ])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(
        text.lines().collect::<Vec<_>>(),
        ["ok", "bad", "none", "ok,none,ok", "ok", "ok", "ok"]
    );
    let _ = std::fs::remove_file(cap);
}

#[test]
fn tshark_with_the_dissector_prints_what_decode_prints_on_a_recorded_sim() {
    let Some(tshark) = tshark() else { return };
    let port = free_udp_port();
    let cap = temp("sim.pcapng");
    let from = format!("udp:{port}");
    let rec = spawn(&[
        "record",
        "--from",
        &from,
        "--out",
        cap.to_str().unwrap(),
        "--seconds",
        "2.5",
    ]);
    std::thread::sleep(Duration::from_millis(300));
    let to = format!("127.0.0.1:{port}");
    let inp = free_udp_port().to_string();
    ok(&run(&[
        "sim",
        "--udp-out",
        &to,
        "--udp-in",
        &inp,
        "--pack",
        "4",
        "--seconds",
        "1.5",
    ]));
    ok(&finish(rec));
    let (messages, fields) = compare(tshark, &cap, Some(port));
    println!("sim capture: {messages} messages, {fields} fields equal in tshark and decode");
    assert!(messages > 800, "{messages}");
    let _ = std::fs::remove_file(cap);
}
