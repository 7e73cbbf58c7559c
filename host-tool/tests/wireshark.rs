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

use aeolus_proto::message::{Message, Text};
use aeolus_proto::{CrcMode, encode_frame};
use common::*;
use protolink::capture::CaptureWriter;
use protolink_tests::tshark::{compare, tshark};

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
    let (messages, fields) = compare(
        tshark,
        Path::new(env!("CARGO_BIN_EXE_protolink")),
        &dissector(),
        &cap,
        None,
    );
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
    let (messages, fields) = compare(
        tshark,
        Path::new(env!("CARGO_BIN_EXE_protolink")),
        &dissector(),
        &cap,
        Some(port),
    );
    println!("sim capture: {messages} messages, {fields} fields equal in tshark and decode");
    assert!(messages > 800, "{messages}");
    let _ = std::fs::remove_file(cap);
}

#[test]
fn tshark_joins_frames_split_across_uart_chunks_as_decode_does() {
    let Some(tshark) = tshark() else { return };
    // The firmware's UART0 in QEMU, cut into 100-byte chunks on link type USER0.
    let uart = std::fs::read(root().join("testdata/qemu-uart0-aeolus.bin")).unwrap();
    let cap = temp("uart0.pcapng");
    let mut w = CaptureWriter::create(&cap, 147, "uart0").unwrap();
    let t0 = Duration::from_secs(1_700_000_000);
    for (i, chunk) in uart.chunks(100).enumerate() {
        w.chunk(t0 + Duration::from_millis(i as u64), chunk)
            .unwrap();
    }
    w.flush().unwrap();
    drop(w);
    let (messages, fields) = compare(
        tshark,
        Path::new(env!("CARGO_BIN_EXE_protolink")),
        &dissector(),
        &cap,
        None,
    );
    println!("UART capture: {messages} messages, {fields} fields equal in tshark and decode");
    // README: the sample holds 1614 frames, all with a good CRC.
    assert_eq!(messages, 1614);
    let _ = std::fs::remove_file(cap);
}
