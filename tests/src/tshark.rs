//! The tshark comparison of the Wireshark dissector with `protolink decode --json`: every
//! AEOLUS message of every frame, and every field tshark shows, equal to what decode prints.
//! Used by `host-tool/tests/wireshark.rs` (sim and crafted frames) and
//! `tests/tests/capture_qemu.rs` (the firmware in QEMU).

use std::path::Path;
use std::process::Command;

use aeolus_proto::message::CalibrationStatus;
use serde_json::Value;

/// tshark, or `None` (with the reason printed) when it is missing outside CI; under CI
/// (`CI=true`) a missing tshark panics, so the comparison never silently skips there.
pub fn tshark() -> Option<&'static str> {
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

fn tshark_messages(
    tshark: &str,
    dissector: &Path,
    cap: &Path,
    decode_as: Option<u16>,
) -> Vec<Vec<Value>> {
    let mut cmd = Command::new(tshark);
    cmd.arg("-r")
        .arg(cap)
        .arg("-X")
        .arg(format!("lua_script:{}", dissector.display()));
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
fn decode_messages(protolink: &Path, cap: &Path, frames: usize) -> Vec<Vec<Value>> {
    let out = Command::new(protolink)
        .args(["decode", "--proto", "aeolus", "--json", "--from"])
        .arg(cap)
        .output()
        .expect("protolink decode runs");
    assert!(
        out.status.success(),
        "decode: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let lines: Vec<Value> = String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|l| serde_json::from_str(l).expect("a JSON line"))
        .collect();
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
/// decode's (`protolink decode --proto aeolus --json` with the binary `protolink`; tshark with
/// the Lua `dissector`, `decode_as` a UDP port that is not 5001/5002). Returns how many messages and fields were compared.
pub fn compare(
    tshark: &str,
    protolink: &Path,
    dissector: &Path,
    cap: &Path,
    decode_as: Option<u16>,
) -> (usize, usize) {
    let shown = tshark_messages(tshark, dissector, cap, decode_as);
    let decoded = decode_messages(protolink, cap, shown.len());
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
