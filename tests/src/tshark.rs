//! The tshark comparison of the Wireshark dissector with `protolink decode --json`: every
//! AEOLUS message of every frame, and every field tshark shows, equal to what decode prints.
//! Used by `host-tool/tests/all/wireshark.rs` (sim and crafted frames) and
//! `tests/tests/all/capture_qemu.rs` (the firmware in QEMU).

use std::path::Path;
use std::process::Command;

use aeolus_proto::message::CalibrationStatus;
use serde_json::Value;

/// tshark, or `None` when it is missing: the caller's test is then skipped through
/// [`crate::skip::skip`] (which fails it under CI, so the comparison never skips there).
pub fn tshark() -> Option<&'static str> {
    let found = Command::new("tshark")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    if found {
        return Some("tshark");
    }
    crate::skip::skip("tshark is not installed (scripts/setup.sh tshark installs it)");
    None
}

fn tshark_messages(
    tshark: &str,
    dissector: &Path,
    cap: &Path,
    decode_as: Option<u16>,
) -> Vec<Vec<Value>> {
    tshark_layer(tshark, dissector, cap, decode_as, "aeolus")
}

/// Each packet's `layer` entries (one per message) as tshark shows them with the dissector.
fn tshark_layer(
    tshark: &str,
    dissector: &Path,
    cap: &Path,
    decode_as: Option<u16>,
    layer: &str,
) -> Vec<Vec<Value>> {
    let mut cmd = Command::new(tshark);
    cmd.arg("-r")
        .arg(cap)
        .arg("-X")
        .arg(format!("lua_script:{}", dissector.display()));
    if let Some(port) = decode_as {
        cmd.arg("-d").arg(format!("udp.port=={port},{layer}"));
    }
    cmd.args(["-T", "json", "--no-duplicate-keys", "-j", layer]);
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
        .map(|p| match &p["_source"]["layers"][layer] {
            Value::Array(a) => a.clone(),
            Value::Null => Vec::new(),
            one => vec![one.clone()],
        })
        .collect()
}

/// `decode --json` events per frame (1-based frame n at index n-1): messages and CRC errors.
fn decode_messages(protolink: &Path, cap: &Path, frames: usize) -> Vec<Vec<Value>> {
    decode_proto(protolink, cap, frames, "aeolus")
}

/// `decode --proto PROTO --json` events per frame.
fn decode_proto(protolink: &Path, cap: &Path, frames: usize, proto: &str) -> Vec<Vec<Value>> {
    decode_proto_with(protolink, cap, frames, proto, &[])
}

fn decode_proto_with(
    protolink: &Path,
    cap: &Path,
    frames: usize,
    proto: &str,
    extra: &[&str],
) -> Vec<Vec<Value>> {
    let out = Command::new(protolink)
        .args(["decode", "--proto", proto, "--json"])
        .args(extra)
        .arg("--from")
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

/// A tshark value that may be one string or an array of them, as a list.
fn list(v: &Value) -> Vec<Value> {
    match v {
        Value::Array(a) => a.clone(),
        Value::Null => Vec::new(),
        one => vec![one.clone()],
    }
}

fn hex_of(v: &Value) -> Value {
    Value::String(v.as_str().unwrap_or("").replace(':', ""))
}

/// Counts of an AYDP or AOK comparison.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Compared {
    /// Messages (and failed candidates) compared.
    pub messages: usize,
    /// Fields compared in them.
    pub fields: usize,
    /// Checksum failures both flagged.
    pub checksum_errors: usize,
    /// Other failures (bad length, malformed data) both flagged.
    pub other_errors: usize,
}

/// AYDP: every message and failed candidate of every frame, as `protolink decode --proto aydp
/// --json` prints it and as tshark shows it with the dissector: the same events in the same
/// frames, the header (type, expedited, wire length, time) and every typed field equal.
pub fn compare_aydp(tshark: &str, protolink: &Path, dissector: &Path, cap: &Path) -> Compared {
    compare_aydp_profile(tshark, protolink, dissector, cap, Some("spec"))
}

/// [`compare_aydp`] with decode's `--profile` given, or (`None`) left to decode's default:
/// `--profile` applies to TCP and UDP port 6321 (the link types carry their own profile), which
/// decode reads as `reference` by default, as the dissector does.
pub fn compare_aydp_profile(
    tshark: &str,
    protolink: &Path,
    dissector: &Path,
    cap: &Path,
    profile: Option<&str>,
) -> Compared {
    let shown = tshark_layer(tshark, dissector, cap, None, "aydp");
    let flag = match profile {
        Some(p) => vec!["--profile", p],
        None => Vec::new(),
    };
    let decoded = decode_proto_with(protolink, cap, shown.len(), "aydp", &flag);
    let mut c = Compared::default();
    for (i, (t, d)) in shown.iter().zip(&decoded).enumerate() {
        let frame = i + 1;
        assert_eq!(
            t.len(),
            d.len(),
            "frame {frame}: tshark {t:?}\ndecode {d:?}"
        );
        for (t, d) in t.iter().zip(d) {
            c.messages += 1;
            let status = t["aydp.status"].as_str().unwrap_or("");
            if d["kind"] == "error" {
                let e = d["error"].as_str().unwrap();
                if e == "checksum mismatch" {
                    assert_eq!(status, "bad_checksum", "frame {frame}: {t}");
                    assert_eq!(t["aydp.checksum_status"], "bad", "frame {frame}");
                    c.checksum_errors += 1;
                } else if let Some(n) = e.strip_prefix("bad length field ") {
                    assert_eq!(status, "bad_length", "frame {frame}: {t}");
                    assert_eq!(t["aydp.length"], n, "frame {frame}");
                    c.other_errors += 1;
                } else if e.contains("message is malformed") {
                    assert_eq!(status, "malformed", "frame {frame}: {e} / {t}");
                    let ty = e.split(' ').nth(1).unwrap();
                    assert_eq!(t["aydp.type"], ty, "frame {frame}");
                    c.other_errors += 1;
                } else {
                    panic!("frame {frame}: an error the comparison does not know: {e}");
                }
                continue;
            }
            assert_eq!(status, "ok", "frame {frame}: {t}\n{d}");
            let name = d["name"].as_str().unwrap();
            assert_eq!(t["aydp.name"], name, "frame {frame}");
            assert_eq!(t["aydp.type"], d["type"].to_string(), "frame {frame}");
            assert_eq!(t["aydp.len"], d["len"].to_string(), "frame {frame}");
            let expedited = d["expedited"].as_bool().unwrap();
            assert_eq!(t["aydp.expedited"], if expedited { "1" } else { "0" });
            assert_eq!(t["aydp.checksum_status"], "ok");
            c.fields += 4;
            if !expedited {
                assert_eq!(t["aydp.seconds"], d["time"]["seconds"].to_string());
                assert_eq!(t["aydp.subsec"], d["time"]["subsec"].to_string());
                c.fields += 2;
            } else {
                assert!(t.get("aydp.seconds").is_none(), "frame {frame}");
            }
            let df = d["fields"].as_object().unwrap();
            let prefix = format!("aydp.{}.", name.to_lowercase());
            let tf: Vec<(&String, &Value)> = t
                .as_object()
                .unwrap()
                .iter()
                .filter(|(k, _)| k.starts_with(&prefix))
                .collect();
            let what = format!("frame {frame} {name}");
            if df.contains_key("msg_type") {
                assert_eq!(t["aydp.msg_type"], df["msg_type"].to_string(), "{what}");
                assert_eq!(hex_of(&t["aydp.data"]), df["data"], "{what}");
                c.fields += 2;
                continue;
            }
            match name {
                "SYSTEM_VALUE_UPDATE" => {
                    let (mode, field) = match &df["mode"] {
                        Value::String(s) if s == "Single" => (1, 0),
                        m if m.get("Array").is_some() => (2, m["Array"]["count"].as_u64().unwrap()),
                        m => (3, m["Element"]["index"].as_u64().unwrap()),
                    };
                    assert_eq!(t[format!("{prefix}mode")], mode.to_string(), "{what}");
                    assert_eq!(t[format!("{prefix}field")], field.to_string(), "{what}");
                    assert_eq!(
                        t[format!("{prefix}address")],
                        df["address"].to_string(),
                        "{what}"
                    );
                    assert_eq!(hex_of(&t[format!("{prefix}data")]), df["data"], "{what}");
                    c.fields += 4;
                }
                "SYSTEM_CONTROL" => {
                    let code = match df["command"].as_str().unwrap() {
                        "RequestData" => "1",
                        "StoreConfiguration" => "2",
                        other => panic!("{what}: command {other}"),
                    };
                    assert_eq!(t[format!("{prefix}command")], code, "{what}");
                    c.fields += 1;
                    if let Some(a) = df.get("address") {
                        assert_eq!(t[format!("{prefix}address")], a.to_string(), "{what}");
                        c.fields += 1;
                    }
                    assert_eq!(tf.len(), df.len(), "{what}");
                }
                "FIX_DETAIL" | "DIRECT_OUTPUT" => {
                    let entries = df.values().next().unwrap().as_array().unwrap();
                    assert_eq!(
                        t[format!("{prefix}count")],
                        entries.len().to_string(),
                        "{what}"
                    );
                    c.fields += 1;
                    let keys: Vec<&String> = entries
                        .first()
                        .map(|e| e.as_object().unwrap().keys().collect())
                        .unwrap_or_default();
                    for k in &keys {
                        let values = list(&t[format!("{prefix}{k}")]);
                        assert_eq!(values.len(), entries.len(), "{what}.{k}");
                        for (j, (e, v)) in entries.iter().zip(&values).enumerate() {
                            same_value(&e[k.as_str()], v, &format!("{what}[{j}].{k}"));
                            c.fields += 1;
                        }
                    }
                    let expected = if entries.is_empty() {
                        1
                    } else {
                        keys.len() + 1
                    };
                    assert_eq!(tf.len(), expected, "{what}: {t}");
                }
                _ => {
                    assert_eq!(tf.len(), df.len(), "{what}: {t}\n{d}");
                    for (k, v) in df {
                        same_value(v, &t[format!("{prefix}{k}")], &format!("{what}.{k}"));
                        c.fields += 1;
                    }
                }
            }
        }
    }
    c
}

/// AOK: every frame of every packet, as `protolink decode --proto aok --json` prints it and as
/// tshark shows it: the same events in the same packets, names, lengths and every field equal,
/// checksum failures and out-of-range frames flagged in both.
pub fn compare_aok(tshark: &str, protolink: &Path, dissector: &Path, cap: &Path) -> Compared {
    let shown = tshark_layer(tshark, dissector, cap, None, "aok");
    let decoded = decode_proto(protolink, cap, shown.len(), "aok");
    let mut c = Compared::default();
    for (i, (t, d)) in shown.iter().zip(&decoded).enumerate() {
        let frame = i + 1;
        assert_eq!(
            t.len(),
            d.len(),
            "frame {frame}: tshark {t:?}\ndecode {d:?}"
        );
        for (t, d) in t.iter().zip(d) {
            c.messages += 1;
            let status = t["aok.status"].as_str().unwrap_or("");
            if d["kind"] == "error" {
                let e = d["error"].as_str().unwrap();
                if e == "checksum mismatch" {
                    assert_eq!(status, "bad_checksum", "frame {frame}: {t}");
                    assert_eq!(t["aok.checksum_status"], "bad", "frame {frame}");
                    c.checksum_errors += 1;
                } else {
                    assert_eq!(status, "invalid", "frame {frame}: {e} / {t}");
                    assert_eq!(t["aok.error"], e, "frame {frame}");
                    c.other_errors += 1;
                }
                continue;
            }
            assert_eq!(status, "ok", "frame {frame}: {t}\n{d}");
            let name = d["name"].as_str().unwrap();
            assert_eq!(t["aok.name"], name, "frame {frame}");
            assert_eq!(t["aok.len"], d["len"].to_string(), "frame {frame}");
            assert_ne!(t["aok.checksum_status"], "bad", "frame {frame}");
            c.fields += 2;
            let df = d["fields"].as_object().unwrap();
            let prefix = format!("aok.{}.", name.to_lowercase());
            let shown_keys = t
                .as_object()
                .unwrap()
                .keys()
                .filter(|k| k.starts_with(&prefix))
                .count();
            assert_eq!(shown_keys, df.len(), "frame {frame} {name}: {t}\n{d}");
            for (k, v) in df {
                let s = &t[format!("{prefix}{k}")];
                let what = format!("frame {frame} {name}.{k}");
                match v {
                    Value::String(v) => assert_eq!(s.as_str(), Some(v.as_str()), "{what}"),
                    v => assert_eq!(s.as_str(), Some(v.to_string().as_str()), "{what}"),
                }
                c.fields += 1;
            }
        }
    }
    c
}
