//! The generated Wireshark dissector: the committed copy is the generator's output, and tshark
//! with it prints exactly what `protolink decode --json` prints, frame by frame and field by
//! field, on captures made by `record` (from `sim`) and on crafted frames (bad CRC, no CRC,
//! escapes, several messages per datagram, raw and text messages).
//!
//! Without tshark the comparison is skipped with a message, except under CI (`CI=true`),
//! where a missing tshark fails the test.

use std::net::SocketAddrV4;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

use crate::common::*;
use aeolus_proto::message::{Message, Text};
use aeolus_proto::{CrcMode, encode_frame};
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
    for (_, name, _, fields) in protolink::wireshark::aeolus::FIXED {
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

/// An AYDP message on the wire (Y1-Y4): normal with time `(5, 250)`, or expedited.
fn aydp(t: u8, data: &[u8], spec: bool, expedited: bool) -> Vec<u8> {
    let header = if expedited { 6 } else { 22 };
    let len = if spec {
        data.len() + header + 1
    } else {
        data.len()
    };
    let mut f = vec![0xFF, t | if expedited { 0x80 } else { 0 }];
    f.extend((len as u32).to_le_bytes());
    if !expedited {
        f.extend(5i64.to_le_bytes());
        f.extend(250i64.to_le_bytes());
    }
    f.extend(data);
    f.push(f.iter().fold(0, |a, b| a ^ b));
    f
}

fn half(v: f32) -> [u8; 2] {
    // Exact binary16 of the small values used here.
    let bits = v.to_bits();
    let exp = ((bits >> 23) & 0xFF) as i32 - 127 + 15;
    let mant = (bits >> 13) & 0x3FF;
    (((exp as u32) << 10 | mant) as u16).to_le_bytes()
}

/// Every AYDP message `aydp-proto` types, raw ones, a malformed one, a bad checksum and a good
/// message behind a false start, in one profile's byte stream.
fn aydp_stream(spec: bool) -> Vec<u8> {
    let f = |t, d: &[u8]| aydp(t, d, spec, false);
    let mut s = aydp(0, &[], spec, true);
    s.extend(f(0, &[]));
    let mut pos = 48.5f64.to_le_bytes().to_vec();
    pos.extend(11.25f64.to_le_bytes());
    pos.extend(512.5f32.to_le_bytes());
    s.extend(f(3, &pos));
    let mut q = vec![3];
    for v in [1.25, 0.875, 1.5] {
        q.extend(half(v));
    }
    q.push(9);
    s.extend(f(4, &q));
    let mut sats = vec![2];
    for (id, a, e, n) in [(7, 10.0, 20.0, 30.0), (8, 40.0, 50.0, 60.0)] {
        sats.push(id);
        for v in [a, e, n] {
            sats.extend(half(v));
        }
    }
    s.extend(f(5, &sats));
    s.extend(f(5, &[0]));
    let mut out = 2u16.to_le_bytes().to_vec();
    for (d, c, v) in [(1, 2, 0.5f32), (3, 4, -1.5)] {
        out.extend([d, c]);
        out.extend(v.to_le_bytes());
    }
    s.extend(f(7, &out));
    s.extend(f(8, &[1, 0, 0, 0, 0, 0, 0, 1]));
    s.extend(f(8, &[2, 5, 0, 2, 0, 0, 0, 1, 2, 3, 4]));
    s.extend(f(8, &[3, 6, 0, 1, 0, 0, 0, 9]));
    s.extend(aydp(9, &[1, 8, 0], spec, true));
    s.extend(aydp(9, &[2], spec, true));
    s.extend(f(1, &12.5f32.to_le_bytes()));
    s.extend(f(2, &270.0f32.to_le_bytes()));
    let mut vessel = Vec::new();
    for v in [1.0f32, -2.0, 3.0, 4.0, 5.0, 6.0] {
        vessel.extend(v.to_le_bytes());
    }
    vessel.extend(48.1f64.to_le_bytes());
    vessel.extend(11.2f64.to_le_bytes());
    vessel.extend(90.0f32.to_le_bytes());
    vessel.extend(5.5f32.to_le_bytes());
    vessel.extend(3i32.to_le_bytes());
    vessel.extend(11i32.to_le_bytes());
    for v in [1.1f32, 1.2, 1.3] {
        vessel.extend(v.to_le_bytes());
    }
    s.extend(f(17, &vessel));
    s.extend(f(6, &[1, 2]));
    s.extend(f(100, &[0xAA, 0xBB]));
    s.extend(f(50, &[0xCC]));
    // Malformed: a uflt16 with its sign bit set.
    s.extend(f(4, &[3, 0, 0x80, 0, 0, 0, 0, 1]));
    // A bad checksum, after noise and a run of 0xFF.
    let mut bad = f(3, &pos);
    *bad.last_mut().unwrap() ^= 0x55;
    s.extend(b"\x00\x12noise\xff");
    s.extend(bad);
    // A false start (its length field is absurd) in front of a good message.
    s.extend([0xFF, 0x05]);
    s.extend(aydp(9, &[2], spec, true));
    s.extend(f(3, &pos));
    s
}

fn stream_capture(tag: &str, link: u32, bytes: &[u8], chunk: usize) -> PathBuf {
    let cap = temp(tag);
    let mut w = CaptureWriter::create(&cap, link, tag).unwrap();
    let t0 = Duration::from_secs(1_700_000_000);
    for (i, c) in bytes.chunks(chunk).enumerate() {
        w.chunk(t0 + Duration::from_millis(i as u64), c).unwrap();
    }
    w.flush().unwrap();
    cap
}

fn check_aydp(cap: &Path) -> protolink_tests::tshark::Compared {
    let tshark = tshark().expect("checked by the caller");
    protolink_tests::tshark::compare_aydp(
        tshark,
        Path::new(env!("CARGO_BIN_EXE_protolink")),
        &dissector(),
        cap,
    )
}

#[test]
fn tshark_dissects_aydp_streams_of_both_profiles_as_decode_does() {
    if tshark().is_none() {
        return;
    }
    for (spec, link) in [(true, 148), (false, 149)] {
        let bytes = aydp_stream(spec);
        // Whole, and cut into 37-byte chunks (messages span packets).
        for chunk in [bytes.len(), 37] {
            let cap = stream_capture(&format!("aydp-{link}-{chunk}.pcapng"), link, &bytes, chunk);
            let c = check_aydp(&cap);
            println!("AYDP link type {link}, {chunk}-byte chunks: {c:?}");
            assert_eq!(c.messages, 23, "{c:?}");
            assert_eq!(c.checksum_errors, 1);
            // The malformed fix quality and the false start's bad length.
            assert_eq!(c.other_errors, 2);
            assert_eq!(c.fields, if spec { 168 } else { 179 });
            let _ = std::fs::remove_file(cap);
        }
    }
}

#[test]
fn tshark_dissects_a_recorded_aydp_uart_as_decode_does() {
    if tshark().is_none() {
        return;
    }
    let cap = temp("aydp-uart1.pcapng");
    let from = format!(
        "file:{}",
        root().join("testdata/qemu-uart1-aydp.bin").display()
    );
    ok(&run(&[
        "record",
        "--from",
        &from,
        "--proto",
        "aydp",
        "--profile",
        "spec",
        "--out",
        cap.to_str().unwrap(),
    ]));
    let c = check_aydp(&cap);
    println!("AYDP UART capture: {c:?}");
    assert_eq!(c.messages, 15, "{c:?}");
    let _ = std::fs::remove_file(cap);
}

fn xor(bytes: &[u8]) -> u8 {
    bytes.iter().fold(0, |a, b| a ^ b)
}

fn aok_waypoint(slot: u8, lon: i32, lat: i32, a1: u32, a2: u32) -> Vec<u8> {
    let mut b = vec![slot];
    b.extend(lon.to_be_bytes());
    b.extend(lat.to_be_bytes());
    b.extend(a1.to_be_bytes());
    b.extend(a2.to_be_bytes());
    let mut f = vec![0x77];
    f.extend(&b);
    f.push(xor(&b));
    f
}

/// What the device sends: debug values, headed parameter replies, waypoint replies, lone acks
/// (not decodable passively), a bad checksum, a waypoint with a bad slot.
fn aok_device_stream() -> Vec<u8> {
    let debug = |n: u8, v: i32| {
        let mut b = vec![n];
        b.extend(v.to_be_bytes());
        let mut f = vec![0x1C];
        f.extend(&b);
        f.push(xor(&b));
        f
    };
    let reply = |n: u8, v: i32| {
        let v = v.to_be_bytes();
        let mut f = vec![0xFF, n];
        f.extend(v);
        f.push(xor(&v));
        f
    };
    let mut s = debug(86, 3);
    s.extend(debug(1, -123_456));
    s.extend(reply(12, 700));
    s.extend(aok_waypoint(
        0,
        11_786_100,
        48_353_801,
        (2 << 16) | (32768 + 15),
        (9 << 16) | 5,
    ));
    s.push(b'O');
    s.extend(aok_waypoint(31, -1, -1, 32768, 32768));
    let mut bad = debug(5, 99);
    *bad.last_mut().unwrap() ^= 1;
    s.extend(bad);
    s.extend(debug(7, 7));
    s.extend(aok_waypoint(100, 1, 2, 3, 4));
    s.extend(b"E");
    s.extend(aok_waypoint(254, 5, 6, (6 << 16) | (32768 - 100), 32768));
    s.extend(reply(255, -1));
    s
}

/// What the PC sends: every command, a bad checksum, an out-of-range stick, noise.
fn aok_pc_stream() -> Vec<u8> {
    let ext = |v: [i16; 4], e: u16| {
        let mut b = Vec::new();
        for x in v {
            b.extend(x.to_le_bytes());
        }
        b.extend(e.to_le_bytes());
        let mut f = vec![0x53];
        f.extend(&b);
        f.push(xor(&b));
        f
    };
    let mut s = vec![0x63, 0x02, 0x63, 0x01, 0x63, 0x07, 0x63, 0x08, 0x63, 0x09];
    s.extend([0x63, 0x03, 0x02, 0x63, 0x04, 0x01, 0x63, 0x05, 0x03]);
    let p = [12u8, 0xFF, 0xFF, 0xFF, 0xFB];
    s.push(0x73);
    s.extend(p);
    s.push(xor(&p));
    s.extend([
        0x67, 0x0C, 0x47, 0x10, 0x78, 0x00, 0x78, 0x1F, 0x78, 0xFE, 0x78, 0xFF,
    ]);
    s.extend([0x31, 100, 0x31 ^ 100, 0x39, 1, 0x39 ^ 1, 0x43, 5, 0x43 ^ 5]);
    s.extend(aok_waypoint(3, 1000, 2000, (1 << 16) | (32768 + 10), 32768));
    s.extend(ext([10, -200, 0, -300], 500));
    let mut bad = ext([1, 2, 3, 4], 5);
    *bad.last_mut().unwrap() ^= 0xFF;
    s.extend(bad);
    s.extend(ext([300, 0, 0, 0], 1));
    s.extend([0x99, 0x63, 0x02]);
    s
}

#[test]
fn tshark_dissects_aok_in_both_directions_as_decode_does() {
    let Some(tshark) = tshark() else { return };
    for (link, bytes, messages, fields) in [
        (151, aok_device_stream(), 10, 41),
        (150, aok_pc_stream(), 23, 69),
    ] {
        for chunk in [bytes.len(), 5] {
            let cap = stream_capture(&format!("aok-{link}-{chunk}.pcapng"), link, &bytes, chunk);
            let c = protolink_tests::tshark::compare_aok(
                tshark,
                Path::new(env!("CARGO_BIN_EXE_protolink")),
                &dissector(),
                &cap,
            );
            println!("AOK link type {link}, {chunk}-byte chunks: {c:?}");
            assert_eq!(c.checksum_errors, 1, "{c:?}");
            assert_eq!(c.other_errors, 1, "{c:?}");
            assert_eq!((c.messages, c.fields), (messages, fields), "{c:?}");
            let _ = std::fs::remove_file(cap);
        }
    }
}

#[test]
fn tshark_dissects_a_recorded_aok_uart_as_decode_does() {
    let Some(tshark) = tshark() else { return };
    let cap = temp("aok-uart2.pcapng");
    let from = format!(
        "file:{}",
        root().join("testdata/qemu-uart2-aok.bin").display()
    );
    ok(&run(&[
        "record",
        "--from",
        &from,
        "--proto",
        "aok",
        "--side",
        "device",
        "--out",
        cap.to_str().unwrap(),
    ]));
    let c = protolink_tests::tshark::compare_aok(
        tshark,
        Path::new(env!("CARGO_BIN_EXE_protolink")),
        &dissector(),
        &cap,
    );
    println!("AOK UART capture: {c:?}");
    assert_eq!(c.messages, 234, "{c:?}");
    let _ = std::fs::remove_file(cap);
}

/// One Ethernet/IPv4/TCP segment (checksums left 0: Wireshark does not check them by default).
fn tcp_segment(src: SocketAddrV4, dst: SocketAddrV4, seq: u32, payload: &[u8]) -> Vec<u8> {
    let mut f = vec![2, 0, 0, 0, 0, 2, 2, 0, 0, 0, 0, 1, 0x08, 0x00];
    let total = (20 + 20 + payload.len()) as u16;
    f.extend([0x45, 0]);
    f.extend(total.to_be_bytes());
    f.extend([0, 1, 0x40, 0, 64, 6, 0, 0]);
    f.extend(src.ip().octets());
    f.extend(dst.ip().octets());
    f.extend(src.port().to_be_bytes());
    f.extend(dst.port().to_be_bytes());
    f.extend(seq.to_be_bytes());
    f.extend(1u32.to_be_bytes());
    f.extend([0x50, 0x18, 0xFF, 0xFF, 0, 0, 0, 0]);
    f.extend(payload);
    f
}

#[test]
fn tshark_dissects_aydp_over_tcp_6321_as_the_reference_profile() {
    let Some(tshark) = tshark() else { return };
    let cap = temp("aydp-tcp.pcapng");
    let mut w = CaptureWriter::create(&cap, 1, "tcp").unwrap();
    let boat: SocketAddrV4 = "10.0.0.2:6321".parse().unwrap();
    let app: SocketAddrV4 = "10.0.0.1:40000".parse().unwrap();
    let t0 = Duration::from_secs(1_700_000_000);
    let down = aydp_stream(false);
    let up = [aydp(9, &[1, 8, 0], false, true), aydp(9, &[2], false, true)].concat();
    let (mut seq_down, mut seq_up) = (1000u32, 5000u32);
    for (i, c) in down.chunks(50).enumerate() {
        let t = t0 + Duration::from_millis(i as u64 * 10);
        w.chunk(t, &tcp_segment(boat, app, seq_down, c)).unwrap();
        seq_down += c.len() as u32;
        let u = up.get(i * 4..(i * 4 + 4).min(up.len())).unwrap_or(&[]);
        if !u.is_empty() {
            w.chunk(
                t + Duration::from_millis(1),
                &tcp_segment(app, boat, seq_up, u),
            )
            .unwrap();
            seq_up += u.len() as u32;
        }
    }
    w.flush().unwrap();
    drop(w);
    let c = protolink_tests::tshark::compare_aydp_profile(
        tshark,
        Path::new(env!("CARGO_BIN_EXE_protolink")),
        &dissector(),
        &cap,
        None,
    );
    println!("AYDP over TCP 6321: {c:?}");
    assert_eq!(c.messages, 23 + 2, "{c:?}");
    assert_eq!(c.checksum_errors, 1);
    let _ = std::fs::remove_file(cap);
}

#[test]
fn tshark_dissects_aydp_datagrams_on_udp_6321_as_the_reference_profile() {
    let Some(tshark) = tshark() else { return };
    let cap = temp("aydp-udp.pcapng");
    let mut w = CaptureWriter::create(&cap, 1, "udp").unwrap();
    let boat: SocketAddrV4 = "127.0.0.1:6321".parse().unwrap();
    let app: SocketAddrV4 = "127.0.0.1:40001".parse().unwrap();
    let t0 = Duration::from_secs(1_700_000_000);
    let stream = aydp_stream(false);
    // Cut at message boundaries: a UDP datagram ends a message (A9, PL28).
    let mut datagrams: Vec<Vec<u8>> = Vec::new();
    let mut rest = &stream[..];
    let mut one = Vec::new();
    while !rest.is_empty() {
        let expedited = rest[1] & 0x80 != 0;
        let field = u32::from_le_bytes(rest[2..6].try_into().unwrap()) as usize;
        let len = field + if expedited { 7 } else { 23 };
        if rest[0] != 0xFF || len > rest.len() {
            // The noise, bad checksum and false start at the end: one datagram.
            one.extend(rest);
            break;
        }
        one.extend(&rest[..len]);
        rest = &rest[len..];
        if one.len() > 60 {
            datagrams.push(std::mem::take(&mut one));
        }
    }
    datagrams.push(one);
    for (i, d) in datagrams.iter().enumerate() {
        w.udp(t0 + Duration::from_millis(i as u64), boat, app, d)
            .unwrap();
    }
    w.flush().unwrap();
    drop(w);
    let c = protolink_tests::tshark::compare_aydp_profile(
        tshark,
        Path::new(env!("CARGO_BIN_EXE_protolink")),
        &dissector(),
        &cap,
        None,
    );
    println!("AYDP over UDP 6321, {} datagrams: {c:?}", datagrams.len());
    assert_eq!(c.messages, 23, "{c:?}");
    assert_eq!(c.checksum_errors, 1);
    let _ = std::fs::remove_file(cap);
}
