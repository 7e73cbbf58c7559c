//! `protolink sim --bank 30` through `protolink gdl90`, with the GDL90 datagrams decoded here
//! by hand from the ICD's byte layout (not by `gdl90-proto`): AHRS roll, the rates, and the
//! ownship position against the GPS messages that went in.

mod common;

use std::net::UdpSocket;
use std::time::{Duration, Instant};

use aeolus_proto::Decoder;
use aeolus_proto::message::Message;
use common::*;

fn udp() -> (UdpSocket, u16) {
    let s = UdpSocket::bind("127.0.0.1:0").unwrap();
    s.set_nonblocking(true).unwrap();
    let port = s.local_addr().unwrap().port();
    (s, port)
}

/// One GDL90 frame's ID and data, unescaped, with its CRC checked by the AEOLUS CRC (the
/// same algorithm, GDL90 section 2.2.3), or `None` for a bad frame.
fn unframe(datagram: &[u8]) -> Option<(u8, Vec<u8>)> {
    let inner = datagram.strip_prefix(&[0x7E])?.strip_suffix(&[0x7E])?;
    let mut raw = Vec::new();
    let mut escaped = false;
    for &b in inner {
        if escaped {
            raw.push(b ^ 0x20);
            escaped = false;
        } else if b == 0x7D {
            escaped = true;
        } else {
            raw.push(b);
        }
    }
    let (body, crc) = raw.split_at(raw.len().checked_sub(2)?);
    let want = u16::from_le_bytes([crc[0], crc[1]]);
    (aeolus_proto::crc::checksum(body) == want).then(|| (body[0], body[1..].to_vec()))
}

fn i24(b: &[u8]) -> f64 {
    let v = (i32::from(b[0]) << 24 | i32::from(b[1]) << 16 | i32::from(b[2]) << 8) >> 8;
    f64::from(v) * 180.0 / f64::from(1 << 23)
}

#[test]
fn sim_at_30_degrees_of_bank_reaches_an_efb_as_gdl90() {
    let (from_sim, sim_out) = udp();
    let (to_gdl90, _) = udp();
    let (efb, efb_port) = udp();
    let gdl90_in = {
        let s = UdpSocket::bind("127.0.0.1:0").unwrap();
        s.local_addr().unwrap().port()
    };
    let sim = spawn(&[
        "sim",
        "--udp-out",
        &format!("127.0.0.1:{sim_out}"),
        "--udp-in",
        "0",
        "--bank",
        "30",
        "--seconds",
        "8",
    ]);
    let gdl90 = spawn(&[
        "gdl90",
        "--from",
        &format!("udp:{gdl90_in}"),
        "--to",
        &format!("127.0.0.1:{efb_port}"),
        "--seconds",
        "7",
    ]);
    let mut deframer = Box::new(Decoder::<1024>::new());
    let mut fixes: Vec<(f64, f64)> = Vec::new();
    let (mut ahrs_roll, mut heartbeats, mut ownship_checked) = (Vec::new(), 0, 0);
    let mut buf = [0u8; 2048];
    let started = Instant::now();
    // The first 1.5 s let the picture fill; the next 5 s are counted.
    let window = (Duration::from_millis(1500), Duration::from_millis(6500));
    while started.elapsed() < window.1 {
        while let Ok(n) = from_sim.recv(&mut buf) {
            deframer.reset();
            for &b in &buf[..n] {
                if let Some(Ok(f)) = deframer.push(b)
                    && let Ok(Message::Gps(g)) = f.message()
                    && g.has_fix
                {
                    fixes.push((f64::from(g.latitude_deg), f64::from(g.longitude_deg)));
                }
            }
            let _ = to_gdl90.send_to(&buf[..n], ("127.0.0.1", gdl90_in));
        }
        while let Ok(n) = efb.recv(&mut buf) {
            let counted = started.elapsed() >= window.0;
            let (id, data) = unframe(&buf[..n]).expect("every datagram is one good frame");
            match (id, data.first()) {
                (0x00, _) if counted => heartbeats += 1,
                (0x65, Some(0x01)) if counted => {
                    let roll = i16::from_be_bytes([data[1], data[2]]);
                    ahrs_roll.push(f64::from(roll) / 10.0);
                }
                (0x0A, _) if counted => {
                    // Latitude at data bytes 4..7, longitude 7..10: 24-bit semicircles.
                    let (lat, lon) = (i24(&data[4..7]), i24(&data[7..10]));
                    let lsb = 180.0 / f64::from(1 << 23);
                    let near = fixes
                        .iter()
                        .rev()
                        .take(30)
                        .any(|(la, lo)| (la - lat).abs() <= lsb && (lo - lon).abs() <= lsb);
                    assert!(near, "ownship {lat},{lon} is not one of the last GPS fixes");
                    ownship_checked += 1;
                }
                _ => {}
            }
        }
        std::thread::sleep(Duration::from_millis(1));
    }
    let gdl90_out = finish(gdl90);
    let _ = finish(sim);
    assert!(gdl90_out.status.success(), "{}", stderr(&gdl90_out));
    let seconds = (window.1 - window.0).as_secs_f64();
    let ahrs_rate = ahrs_roll.len() as f64 / seconds;
    assert!((4.4..=5.6).contains(&ahrs_rate), "AHRS at {ahrs_rate}/s");
    assert!(
        (4..=6).contains(&heartbeats),
        "{heartbeats} heartbeats in {seconds} s"
    );
    assert!(
        (4..=6).contains(&ownship_checked),
        "{ownship_checked} ownship reports"
    );
    for roll in &ahrs_roll {
        assert!((roll - 30.0).abs() <= 0.2, "AHRS roll {roll}");
    }
}

/// `decode --proto gdl90` reads the ICD's own heartbeat example, and a corrupted copy is an
/// error at its opening flag.
#[test]
fn decode_reads_the_icd_heartbeat_example() {
    let icd = [
        0x7E, 0x00, 0x81, 0x41, 0xDB, 0xD0, 0x08, 0x02, 0xB3, 0x8B, 0x7E,
    ];
    let mut bytes = icd.to_vec();
    let mut bad = icd;
    bad[3] ^= 0x01;
    bytes.extend(bad);
    let file = TempFile::new("gdl90", &bytes);
    let text = ok(&run(&[
        "decode",
        "--proto",
        "gdl90",
        "--from",
        &file.endpoint(),
    ]));
    let lines: Vec<&str> = text.lines().collect();
    assert!(
        lines[0].starts_with("@0 HEARTBEAT id=0 len=11 gps_position_valid=true"),
        "{text}"
    );
    assert!(lines[0].contains("utc_ok=true"), "{text}");
    assert!(lines[1].starts_with("@11 error: "), "{text}");
}

/// `--discover`: GDL90 goes to the host and port a ForeFlight announcement names, not to
/// `--to`.
#[test]
fn discover_follows_the_foreflight_announcement() {
    let (app, app_port) = udp();
    let (unused, unused_port) = udp();
    let gdl90 = spawn(&[
        "gdl90",
        "--from",
        "udp:0",
        "--to",
        &format!("127.0.0.1:{unused_port}"),
        "--discover",
        "--seconds",
        "8",
    ]);
    let announce = UdpSocket::bind("127.0.0.1:0").unwrap();
    let text = format!(r#"{{"App":"ForeFlight","GDL90":{{"port":{app_port}}}}}"#);
    let mut buf = [0u8; 512];
    let mut heard = 0;
    let started = Instant::now();
    // Announce every 100 ms (the tool may still be starting) until 5 datagrams came.
    while heard < 5 && started.elapsed() < Duration::from_secs(7) {
        let _ = announce.send_to(text.as_bytes(), ("127.0.0.1", 63093));
        while let Ok(n) = app.recv(&mut buf) {
            assert!(unframe(&buf[..n]).is_some());
            heard += 1;
        }
        std::thread::sleep(Duration::from_millis(100));
    }
    let out = finish(gdl90);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(heard >= 5, "{heard} datagrams reached the announced app");
    // Before the announcement datagrams went to --to: at most the first second's worth.
    let mut before = 0;
    while unused.recv(&mut buf).is_ok() {
        before += 1;
    }
    assert!(before <= 40, "{before} datagrams went to --to");
}
