//! `record`, `replay` and `decode` of captures, with the real binary on 127.0.0.1.

use std::borrow::Cow;
use std::net::UdpSocket;
use std::path::PathBuf;
use std::time::Duration;

use crate::common::*;
use pcap_file::DataLink;
use pcap_file::pcap::{PcapHeader, PcapPacket, PcapWriter};
use pcap_file::pcapng::PcapNgReader;
use pcap_file::pcapng::blocks::Block;
use protolink::capture::ethernet_udp;
use serde_json::Value;

fn temp(tag: &str) -> PathBuf {
    std::env::temp_dir().join(format!("protolink-cap-{}-{tag}", std::process::id()))
}

/// TOAST "hi" with a good CRC, then GYRO-less TOAST "hj" carrying hi's CRC (bad), then a
/// frame without CRC (TOAST "ok" whose last two bytes are read as text).
const GOOD: [u8; 8] = [0x7E, 0x52, b'h', b'i', 0, 0x73, 0xEC, 0x7E];
const BAD: [u8; 8] = [0x7E, 0x52, b'h', b'j', 0, 0x73, 0xEC, 0x7E];

fn blocks(path: &PathBuf) -> Vec<Block<'static>> {
    let mut r = PcapNgReader::new(std::fs::File::open(path).unwrap()).unwrap();
    let mut v = Vec::new();
    while let Some(b) = r.next_block() {
        v.push(b.unwrap().into_owned());
    }
    v
}

#[test]
fn record_udp_writes_ethernet_ipv4_udp_with_the_real_ports() {
    let port = free_udp_port();
    let out = temp("udp.pcapng");
    let from = format!("udp:{port}");
    let child = spawn(&[
        "record",
        "--from",
        &from,
        "--out",
        out.to_str().unwrap(),
        "--seconds",
        "1.5",
    ]);
    std::thread::sleep(Duration::from_millis(400));
    let tx = UdpSocket::bind("127.0.0.1:0").unwrap();
    let src_port = tx.local_addr().unwrap().port();
    let mut both = GOOD.to_vec();
    both.extend_from_slice(&BAD);
    tx.send_to(&GOOD, ("127.0.0.1", port)).unwrap();
    tx.send_to(&both, ("127.0.0.1", port)).unwrap();
    let o = finish(child);
    ok(&o);
    assert!(
        stderr(&o).contains("recorded 2 packets, 24 bytes"),
        "{}",
        stderr(&o)
    );

    let b = blocks(&out);
    let Block::InterfaceDescription(idb) = &b[0] else {
        panic!("first block {:?}", b[0])
    };
    assert_eq!(idb.linktype, DataLink::ETHERNET);
    let packets: Vec<_> = b
        .iter()
        .filter_map(|b| match b {
            Block::EnhancedPacket(p) => Some(p.data.to_vec()),
            _ => None,
        })
        .collect();
    assert_eq!(packets.len(), 2);
    let src = format!("127.0.0.1:{src_port}").parse().unwrap();
    let dst = format!("127.0.0.1:{port}").parse().unwrap();
    assert_eq!(packets[0], ethernet_udp(src, dst, &GOOD));
    assert_eq!(packets[1], ethernet_udp(src, dst, &both));
    // MACs zero, IPv4, UDP, the real ports.
    assert_eq!(&packets[0][..12], &[0; 12]);
    assert_eq!(packets[0][14], 0x45);
    assert_eq!(packets[0][23], 17);
    assert_eq!(&packets[0][34..36], &src_port.to_be_bytes());
    assert_eq!(&packets[0][36..38], &port.to_be_bytes());

    // Decoded by --proto (the port is not one of ours): datagram boundaries and frame numbers.
    let o = run(&[
        "decode",
        "--from",
        out.to_str().unwrap(),
        "--proto",
        "aeolus",
        "--json",
    ]);
    let lines = json_lines(&ok(&o));
    let events: Vec<&Value> = lines.iter().filter(|v| v["frame"].is_u64()).collect();
    assert_eq!(events.len(), 3, "{lines:?}");
    assert_eq!(events[0]["frame"], 1);
    assert_eq!(events[0]["name"], "TOAST");
    assert_eq!(events[0]["crc"], "ok");
    assert_eq!(events[0]["fields"]["text"], "hi");
    assert_eq!(events[1]["frame"], 2);
    assert_eq!(events[1]["offset"], 8);
    assert_eq!(events[2]["frame"], 2);
    assert_eq!(events[2]["kind"], "error");
    assert_eq!(events[2]["offset"], 16);
    assert!(
        events[1]["capture_time"].as_f64().unwrap() >= events[0]["capture_time"].as_f64().unwrap()
    );
    assert!(events[0]["capture_time"].as_f64().unwrap() > 1.7e9);
    let _ = std::fs::remove_file(out);
}

#[test]
fn record_byte_streams_on_the_link_type_of_their_protocol() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../testdata");
    for (file, extra, link) in [
        ("qemu-uart0-aeolus.bin", &["--proto", "aeolus"][..], 147u32),
        ("qemu-uart1-aydp.bin", &["--proto", "aydp"][..], 148),
        (
            "qemu-uart1-aydp.bin",
            &["--proto", "aydp", "--profile", "reference"][..],
            149,
        ),
        (
            "qemu-uart2-aok.bin",
            &["--proto", "aok", "--side", "pc"][..],
            150,
        ),
        ("qemu-uart2-aok.bin", &["--proto", "aok"][..], 151),
    ] {
        let input = root.join(file);
        let out = temp(&format!("{link}.pcapng"));
        let mut args = vec![
            "record",
            "--from",
            input.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        ok(&run(&args));
        let b = blocks(&out);
        let Block::InterfaceDescription(idb) = &b[0] else {
            panic!("first block {:?}", b[0])
        };
        assert_eq!(u32::from(idb.linktype), link, "{file} {extra:?}");
        let stored: Vec<u8> = b
            .iter()
            .filter_map(|b| match b {
                Block::EnhancedPacket(p) => Some(p.data.to_vec()),
                _ => None,
            })
            .flatten()
            .collect();
        assert_eq!(
            stored,
            std::fs::read(&input).unwrap(),
            "{file}: every byte kept"
        );
        let _ = std::fs::remove_file(out);
    }
}

#[test]
fn decode_of_a_stream_capture_equals_decode_of_the_raw_bytes() {
    let input = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../testdata/qemu-uart0-aeolus.bin");
    let out = temp("uart0.pcapng");
    ok(&run(&[
        "record",
        "--from",
        input.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]));
    let live = json_lines(&ok(&run(&[
        "decode",
        "--proto",
        "aeolus",
        "--from",
        input.to_str().unwrap(),
        "--json",
    ])));
    // No --proto: the link type (USER0) names AEOLUS.
    let cap = json_lines(&ok(&run(&[
        "decode",
        "--from",
        out.to_str().unwrap(),
        "--json",
    ])));
    let strip = |v: &Value| {
        let mut v = v.clone();
        if let Value::Object(m) = &mut v {
            for k in ["frame", "capture_time", "flow", "proto"] {
                m.remove(k);
            }
        }
        v
    };
    let live_msgs: Vec<Value> = live
        .iter()
        .filter(|v| v["kind"] == "message")
        .cloned()
        .collect();
    let cap_msgs: Vec<Value> = cap
        .iter()
        .filter(|v| v["kind"] == "message")
        .map(strip)
        .collect();
    assert!(live_msgs.len() > 1000);
    assert_eq!(live_msgs, cap_msgs);
    assert!(
        cap.iter()
            .all(|v| v["kind"] != "message" || v["proto"] == "aeolus")
    );
    let _ = std::fs::remove_file(out);
}

#[test]
fn decode_reads_classic_pcap_by_its_magic_and_finds_aeolus_by_port() {
    // Named .bin on purpose: the magic number decides, not the name.
    let path = temp("classic.bin");
    let mut w = PcapWriter::with_header(
        std::fs::File::create(&path).unwrap(),
        PcapHeader {
            datalink: DataLink::ETHERNET,
            ..Default::default()
        },
    )
    .unwrap();
    let box_addr = "127.0.0.1:40000".parse().unwrap();
    let app = "127.0.0.1:5001".parse().unwrap();
    let other = "127.0.0.1:53".parse().unwrap();
    for (t, src, dst, payload) in [
        (1.5, box_addr, app, &GOOD[..]),
        (2.25, box_addr, other, &GOOD[..]),
        (3.0, box_addr, app, &BAD[..]),
    ] {
        let f = ethernet_udp(src, dst, payload);
        w.write_packet(&PcapPacket {
            timestamp: Duration::from_secs_f64(1_700_000_000.0 + t),
            orig_len: f.len() as u32,
            data: Cow::Borrowed(&f),
        })
        .unwrap();
    }
    drop(w);
    let lines = json_lines(&ok(&run(&[
        "decode",
        "--from",
        path.to_str().unwrap(),
        "--json",
    ])));
    assert_eq!(lines[0]["frame"], 1);
    assert_eq!(lines[0]["capture_time"], 1_700_000_001.5);
    assert_eq!(lines[0]["name"], "TOAST");
    assert_eq!(lines[0]["flow"], "udp 127.0.0.1:40000 > 127.0.0.1:5001");
    assert_eq!(lines[1]["frame"], 3);
    assert_eq!(lines[1]["capture_time"], 1_700_000_003.0);
    assert_eq!(lines[1]["kind"], "error");
    assert!(lines[1]["error"].as_str().unwrap().contains("CRC"));
    let cap = lines.iter().find(|v| v["kind"] == "capture").unwrap();
    assert_eq!(cap["frames"], 3);
    assert_eq!(cap["skipped"], 1);
    assert_eq!(cap["flows"], 1);

    // A raw stream named .pcapng is no capture: --proto is then needed (a usage error).
    let raw = temp("raw.pcapng");
    std::fs::write(&raw, GOOD).unwrap();
    let err = usage_failed(&run(&["decode", "--from", raw.to_str().unwrap()]));
    assert!(err.contains("--proto is needed"), "{err}");
    let _ = std::fs::remove_file(path);
    let _ = std::fs::remove_file(raw);
}

#[test]
fn replay_rejects_bad_speeds_and_non_captures_in_one_sentence() {
    for s in ["0", "-1", "NaN", "inf", "1001", "fast"] {
        let speed = format!("--speed={s}");
        let err = usage_failed(&run(&[
            "replay",
            "x.pcapng",
            "--to",
            "udp:127.0.0.1:9",
            &speed,
        ]));
        assert!(err.contains("0.01 to 1000"), "{s}: {err}");
    }
    let raw = temp("notcap");
    std::fs::write(&raw, GOOD).unwrap();
    let err = failed(&run(&[
        "replay",
        raw.to_str().unwrap(),
        "--to",
        "udp:127.0.0.1:9",
    ]));
    assert!(err.contains("neither a pcapng nor a pcap"), "{err}");
    let err = failed(&run(&[
        "replay",
        "/nonexistent/x.pcapng",
        "--to",
        "udp:127.0.0.1:9",
    ]));
    assert!(err.contains("cannot open"), "{err}");
    let _ = std::fs::remove_file(raw);
}

fn messages(lines: &[Value]) -> Vec<(String, Value)> {
    lines
        .iter()
        .filter(|v| v["kind"] == "message")
        .map(|v| (v["name"].as_str().unwrap().to_owned(), v["fields"].clone()))
        .collect()
}

#[test]
fn sim_recorded_then_replayed_into_decode_gives_the_same_messages() {
    // Record 2 s of `sim`.
    let rec_port = free_udp_port();
    let cap = temp("sim.pcapng");
    let from = format!("udp:{rec_port}");
    let recorder = spawn(&[
        "record",
        "--from",
        &from,
        "--out",
        cap.to_str().unwrap(),
        "--seconds",
        "3",
    ]);
    std::thread::sleep(Duration::from_millis(300));
    let to = format!("127.0.0.1:{rec_port}");
    let in_port = free_udp_port().to_string();
    ok(&run(&[
        "sim",
        "--udp-out",
        &to,
        "--udp-in",
        &in_port,
        "--pack",
        "4",
        "--seconds",
        "2",
    ]));
    ok(&finish(recorder));
    let recorded = messages(&json_lines(&ok(&run(&[
        "decode",
        "--from",
        cap.to_str().unwrap(),
        "--proto",
        "aeolus",
        "--json",
    ]))));
    assert!(recorded.len() > 500, "{} messages", recorded.len());
    assert_eq!(recorded[0].0, "TOAST");

    // Replay it twice as fast into a live `decode` on another port.
    let dec_port = free_udp_port();
    let listen = format!("udp:{dec_port}");
    // Its output goes to a file: a pipe nobody reads yet would fill and stall it.
    let dec_out = temp("replayed.json");
    let mut decoder = std::process::Command::new(env!("CARGO_BIN_EXE_protolink"))
        .args([
            "decode",
            "--from",
            &listen,
            "--proto",
            "aeolus",
            "--json",
            "--seconds",
            "4",
        ])
        .stdout(std::fs::File::create(&dec_out).unwrap())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(300));
    let dest = format!("udp:127.0.0.1:{dec_port}");
    let started = std::time::Instant::now();
    let o = run(&[
        "replay",
        cap.to_str().unwrap(),
        "--to",
        &dest,
        "--speed",
        "2",
    ]);
    let took = started.elapsed();
    ok(&o);
    // 2 s recorded at twice the speed: about 1 s, the timing kept.
    assert!(took >= Duration::from_millis(800), "{took:?}");
    assert!(took < Duration::from_millis(2500), "{took:?}");
    assert!(decoder.wait().unwrap().success());
    let replayed = messages(&json_lines(&std::fs::read_to_string(&dec_out).unwrap()));
    let _ = std::fs::remove_file(dec_out);
    let first_diff = recorded.iter().zip(&replayed).position(|(a, b)| a != b);
    assert_eq!(
        (replayed.len(), first_diff),
        (recorded.len(), None),
        "replayed vs recorded messages: counts and the first difference"
    );
    let _ = std::fs::remove_file(cap);
}

#[test]
fn replay_loop_stops_at_seconds_and_file_output_keeps_every_byte() {
    let input = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../testdata/qemu-uart2-aok.bin");
    let cap = temp("aok.pcapng");
    ok(&run(&[
        "record",
        "--from",
        input.to_str().unwrap(),
        "--proto",
        "aok",
        "--out",
        cap.to_str().unwrap(),
    ]));
    let raw = temp("aok.out");
    let to = format!("file:{}", raw.display());
    let o = run(&[
        "replay",
        cap.to_str().unwrap(),
        "--to",
        &to,
        "--speed",
        "1000",
    ]);
    ok(&o);
    assert_eq!(std::fs::read(&raw).unwrap(), std::fs::read(&input).unwrap());

    // --loop: passes until --seconds.
    let started = std::time::Instant::now();
    let o = run(&[
        "replay",
        cap.to_str().unwrap(),
        "--to",
        &to,
        "--speed",
        "1000",
        "--loop",
        "--seconds",
        "1",
    ]);
    ok(&o);
    let took = started.elapsed();
    assert!(
        took >= Duration::from_millis(900) && took < Duration::from_secs(5),
        "{took:?}"
    );
    let err = stderr(&o);
    let passes: u64 = err
        .split(" in ")
        .nth(1)
        .and_then(|s| s.split(' ').next())
        .and_then(|s| s.parse().ok())
        .unwrap_or(0);
    assert!(passes >= 2, "{err}");
    let _ = std::fs::remove_file(cap);
    let _ = std::fs::remove_file(raw);
}

#[test]
fn decode_udp_json_streams_flat_objects_with_the_capture_time() {
    let rx = UdpSocket::bind("127.0.0.1:0").unwrap();
    rx.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
    let to = rx.local_addr().unwrap().to_string();
    let path = temp("plot.pcap");
    let mut w = PcapWriter::with_header(
        std::fs::File::create(&path).unwrap(),
        PcapHeader {
            datalink: DataLink::ETHERNET,
            ..Default::default()
        },
    )
    .unwrap();
    // A GYRO frame: valid, timestamp 7 ms, x 0.5, y -1.25, z 2.
    let mut data = [0u8; 32];
    data[0] = 1;
    data[8..16].copy_from_slice(&7.0f64.to_le_bytes());
    for (i, v) in [0.5f32, -1.25, 2.0].iter().enumerate() {
        data[16 + 4 * i..20 + 4 * i].copy_from_slice(&v.to_le_bytes());
    }
    let mut frame = vec![0u8; 128];
    let n = aeolus_proto::encode_frame(62, &data, &[], aeolus_proto::CrcMode::Compute, &mut frame)
        .unwrap();
    let mut payload = frame[..n].to_vec();
    payload.extend_from_slice(&GOOD); // a TOAST: no numbers, nothing sent
    let f = ethernet_udp(
        "127.0.0.1:40000".parse().unwrap(),
        "127.0.0.1:5001".parse().unwrap(),
        &payload,
    );
    w.write_packet(&PcapPacket {
        timestamp: Duration::from_millis(1_700_000_000_250),
        orig_len: f.len() as u32,
        data: Cow::Borrowed(&f),
    })
    .unwrap();
    drop(w);
    let o = run(&[
        "decode",
        "--from",
        path.to_str().unwrap(),
        "--udp-json",
        &to,
    ]);
    ok(&o);
    assert!(
        stderr(&o).contains("1 datagrams sent, 0 dropped"),
        "{}",
        stderr(&o)
    );
    let mut buf = [0u8; 2048];
    let n = rx.recv(&mut buf).unwrap();
    assert_eq!(
        std::str::from_utf8(&buf[..n]).unwrap(),
        r#"{"timestamp":1700000000.25,"GYRO/valid":1,"GYRO/timestamp_ms":7.0,"GYRO/x":0.5,"GYRO/y":-1.25,"GYRO/z":2.0}"#
    );
    let err = usage_failed(&run(&[
        "decode",
        "--from",
        path.to_str().unwrap(),
        "--udp-json",
        "nowhere",
    ]));
    assert!(err.contains("nowhere"), "{err}");
    let _ = std::fs::remove_file(path);
}

/// Every record of a capture (or the error that stopped the reading), read in-process.
fn read_all_records(path: &std::path::Path) -> Result<usize, String> {
    let mut r = protolink::capture::CaptureReader::open(path).map_err(|e| e.to_string())?;
    let mut n = 0;
    while r.next_record().map_err(|e| e.to_string())?.is_some() {
        n += 1;
    }
    Ok(n)
}

#[test]
fn damaged_captures_end_in_one_sentence_never_a_panic() {
    // A real capture: UDP datagrams, then cut, flipped and overwritten in seeded places.
    let port = free_udp_port();
    let cap = temp("good.pcapng");
    let from = format!("udp:{port}");
    let rec = spawn(&[
        "record",
        "--from",
        &from,
        "--out",
        cap.to_str().unwrap(),
        "--seconds",
        "1",
    ]);
    std::thread::sleep(Duration::from_millis(300));
    let tx = UdpSocket::bind("127.0.0.1:0").unwrap();
    for i in 0..20u8 {
        let mut d = GOOD.to_vec();
        d.extend(std::iter::repeat_n(i, usize::from(i)));
        tx.send_to(&d, ("127.0.0.1", port)).unwrap();
    }
    ok(&finish(rec));
    let good = std::fs::read(&cap).unwrap();
    assert_eq!(read_all_records(&cap), Ok(20));

    let bad = temp("bad.pcapng");
    let noise = random_bytes(12, 4096);
    let mut tried = 0;
    for i in 0..600usize {
        let mut b = good.clone();
        match i % 3 {
            0 => b.truncate(i * 7 % good.len()),
            1 => {
                let at = (i * 131) % b.len();
                b[at] ^= noise[i % noise.len()] | 1;
            }
            _ => {
                let at = (i * 53) % b.len();
                let end = (at + 8).min(b.len());
                b[at..end].copy_from_slice(&noise[i..i + (end - at)]);
            }
        }
        std::fs::write(&bad, &b).unwrap();
        let result = std::panic::catch_unwind(|| read_all_records(&bad));
        let outcome = result.unwrap_or_else(|_| panic!("reading mutation {i} panicked"));
        if let Err(e) = outcome {
            assert!(!e.is_empty() && !e.contains('\n'), "mutation {i}: {e:?}");
        }
        tried += 1;
    }
    assert_eq!(tried, 600);
    // And through the binary: exit 0 or 1, one sentence, no panic.
    let mut b = good.clone();
    b.truncate(good.len() - 5);
    std::fs::write(&bad, &b).unwrap();
    let o = run(&[
        "decode",
        "--from",
        bad.to_str().unwrap(),
        "--proto",
        "aeolus",
    ]);
    let err = failed(&o);
    assert!(err.contains("reading the capture"), "{err}");
    // A cut: the sentence names where the cut block starts (a pcapng block ends with its own
    // length), and the reader has read every record before it.
    let last = u32::from_le_bytes(good[good.len() - 4..].try_into().unwrap()) as usize;
    let start = good.len() - last;
    assert!(
        err.contains(&format!(
            "failed at byte {start}, after frame 19: the file ends inside the block that starts there"
        )),
        "{err}"
    );
    let mut r = protolink::capture::CaptureReader::open(&bad).unwrap();
    for _ in 0..19 {
        assert!(r.next_record().unwrap().is_some());
    }
    assert_eq!(r.offset(), start as u64);
    assert!(matches!(
        r.next_record(),
        Err(protolink::Error::CaptureCut { offset, frames: 19, .. }) if offset == start as u64
    ));
    let _ = std::fs::remove_file(cap);
    let _ = std::fs::remove_file(bad);
}
