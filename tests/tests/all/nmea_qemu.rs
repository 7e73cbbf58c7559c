//! `protolink nmea` on the release firmware in QEMU (every board): UART0 read over TCP, the
//! NMEA server read as an app reads it (a TCP client), every sentence parsed by pynmea2
//! (`host-tool/tests/python/nmea_check.py`, checksums included). The firmware flies its
//! default turn (20° right bank at 50 m/s): RMC and GGA carry a fix, PGRMZ a pressure
//! altitude, POV the pressures and temperature, LXWP0 the true airspeed (180 km/h) and a
//! heading that turns right.
//!
//! Skipped when QEMU is missing (the harness says so), and when python3 or pynmea2 is missing
//! outside CI (`CI=true` fails instead; `scripts/setup.sh python` installs them).

use std::io::{BufRead, BufReader};
use std::net::TcpStream;
use std::process::Command;
use std::time::{Duration, Instant};

use crate::harness::*;
use serde_json::Value;

on_every_board!(an_app_reads_the_firmwares_flight_as_nmea);

const SCRIPT: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../host-tool/tests/python/nmea_check.py"
);

fn pynmea2_available() -> bool {
    let ok = Command::new("python3")
        .args(["-c", "import pynmea2"])
        .output()
        .is_ok_and(|o| o.status.success());
    if !ok {
        protolink_tests::skip::skip(
            "python3 with pynmea2 is not installed, so no outside NMEA parser can read the \
             output (scripts/setup.sh python installs it)",
        );
    }
    ok
}

/// Lines from the NMEA server on `port` for `seconds`, with their arrival time.
fn read_lines(port: u16, seconds: Duration) -> Vec<(f64, String)> {
    let started = Instant::now();
    let client = loop {
        if let Ok(c) = TcpStream::connect(("127.0.0.1", port)) {
            break c;
        }
        assert!(
            started.elapsed() < Duration::from_secs(10),
            "no NMEA server"
        );
        std::thread::sleep(Duration::from_millis(50));
    };
    client
        .set_read_timeout(Some(Duration::from_secs(5)))
        .unwrap();
    let t0 = Instant::now();
    let mut lines = Vec::new();
    for line in BufReader::new(client).lines() {
        let Ok(line) = line else { break };
        lines.push((t0.elapsed().as_secs_f64(), line));
        if t0.elapsed() >= seconds {
            break;
        }
    }
    lines
}

fn an_app_reads_the_firmwares_flight_as_nmea(board: Board) {
    if !pynmea2_available() {
        return;
    }
    let ports = Ports::NMEA.on(board);
    let Some(mut q) = boot(board, ports) else {
        return;
    };
    q.uart0.disconnect();
    let server = ports.uart(0) + 7;
    let nmea = spawn_protolink(&[
        "nmea".to_string(),
        "--from".into(),
        format!("tcp:127.0.0.1:{}", ports.uart(0)),
        "--listen".into(),
        format!("127.0.0.1:{server}"),
        // Every sentence: LK8000's set is all five.
        "--for".into(),
        "lk8000".into(),
        "--seconds".into(),
        "20".into(),
    ]);
    let lines = read_lines(server, Duration::from_secs(10));
    let out = finish(nmea);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text: String = lines
        .iter()
        .map(|(t, l)| format!("{t:.3}\t{l}\n"))
        .collect();
    let file = std::env::temp_dir().join(format!("nmea-qemu-{}-{board:?}", std::process::id()));
    std::fs::write(&file, text).unwrap();
    let parsed = Command::new("python3")
        .arg(SCRIPT)
        .arg(&file)
        .output()
        .unwrap();
    let _ = std::fs::remove_file(&file);
    assert!(
        parsed.status.success(),
        "pynmea2 refused sentences:\n{}",
        String::from_utf8_lossy(&parsed.stderr)
    );
    let parsed: Vec<Value> = String::from_utf8_lossy(&parsed.stdout)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    check(&parsed);
}

fn check(parsed: &[Value]) {
    let of = |kind: &str| -> Vec<&Value> { parsed.iter().filter(|v| v["type"] == kind).collect() };
    // The first second may come before the box's first fix: judge from the third sentence on.
    let rmc = of("RMC");
    assert!(rmc.len() >= 6, "{} RMC", rmc.len());
    assert!(rmc[2..].iter().all(|v| v["status"] == "A"), "{rmc:?}");
    assert!(of("GGA")[2..].iter().all(|v| v["quality"] == 1));
    assert!(of("PGRMZ")[2..].iter().all(|v| v["altitude"].is_f64()));
    let pov = of("POV");
    assert!(pov.len() >= 20, "{} POV", pov.len());
    assert!(
        pov[5..]
            .iter()
            .all(|v| v["P"].is_f64() && v["Q"].is_f64() && v["T"].is_f64())
    );
    let lx = &of("LXWP0")[2..];
    for v in lx {
        let tas = v["tas_kmh"].as_f64().unwrap();
        assert!(
            (tas - 180.0).abs() <= 1.0,
            "TAS {tas} km/h, the firmware flies 50 m/s"
        );
    }
    // A right turn: the heading grows (the emulated box may run slower than the host clock,
    // so only the direction and a rough rate are judged here; the rate in the box's own clock
    // is web_qemu's and qemu_firmware's test).
    let heading: Vec<f64> = lx
        .iter()
        .map(|v| v["heading_deg"].as_f64().unwrap())
        .collect();
    let turned: f64 = heading
        .windows(2)
        .map(|w| (w[1] - w[0] + 540.0).rem_euclid(360.0) - 180.0)
        .sum();
    let span = lx.last().unwrap()["t"].as_f64().unwrap() - lx[0]["t"].as_f64().unwrap();
    let expected = (9.806_65 * 20f64.to_radians().tan() / 50.0).to_degrees();
    assert!(
        turned > 0.3 * expected * span && turned < 1.1 * expected * span,
        "{turned:.1} degrees in {span:.1} s, the firmware turns {expected:.2} deg/s"
    );
}
