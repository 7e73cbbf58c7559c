//! `protolink gdl90 --ahrs stratux` on the release firmware in QEMU (every board): UART0 read
//! over TCP, the datagrams received as an EFB app receives them, every frame's CRC checked and
//! the Stratux AHRS report (0x4C) decoded by hand from Stratux's layout
//! (`protolink_tests::gdl90_hand`, not `gdl90-proto`). The firmware flies its default turn, 20°
//! of right bank at 50 m/s true airspeed at 1000 m: the report's roll is the bank, its IAS the
//! indicated airspeed of that flight (PL39), its pressure altitude carries Stratux's 5000 ft
//! offset, and it comes five times a second.

use std::net::UdpSocket;
use std::time::{Duration, Instant};

use crate::harness::*;
use protolink_tests::gdl90_hand::{stratux_report, unframe};

on_every_board!(an_efb_reads_the_firmwares_flight_as_stratux_ahrs);

fn an_efb_reads_the_firmwares_flight_as_stratux_ahrs(board: Board) {
    let ports = Ports::GDL90.on(board);
    let Some(mut q) = boot(board, ports) else {
        return;
    };
    q.uart0.disconnect();
    let efb_port = ports.uart(0) + 7;
    let efb = UdpSocket::bind(("127.0.0.1", efb_port)).unwrap();
    efb.set_read_timeout(Some(Duration::from_millis(200)))
        .unwrap();
    let gdl90 = spawn_protolink(&[
        "gdl90".to_string(),
        "--from".into(),
        format!("tcp:127.0.0.1:{}", ports.uart(0)),
        "--to".into(),
        format!("127.0.0.1:{efb_port}"),
        "--ahrs".into(),
        "stratux".into(),
        "--seconds".into(),
        "8".into(),
    ]);
    let started = Instant::now();
    let mut reports = Vec::new();
    let mut buf = [0u8; 2048];
    while started.elapsed() < Duration::from_secs(7) {
        let Ok(n) = efb.recv(&mut buf) else { continue };
        let (id, data) = unframe(&buf[..n]).expect("every datagram is one good frame");
        // The first 1.5 s may come before the box's first messages reach the tool.
        if id == 0x4C && started.elapsed() >= Duration::from_millis(1500) {
            reports.push(stratux_report(&data));
        }
    }
    let out = finish(gdl90);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // 5 Hz over about 5.5 s.
    assert!(reports.len() >= 20, "{} Stratux reports", reports.len());
    // 50 m/s true at 1000 m of the ISA (written here) is indicated at sqrt(rho / rho0) of it:
    // 92.6 kt.
    let kelvin = 288.15 - 0.0065 * 1000.0;
    let density = 101_325.0 * (kelvin / 288.15_f64).powf(5.255_88) / (287.05 * kelvin);
    let want_ias = 50.0 * 3600.0 / 1852.0 * (density / 1.225).sqrt();
    for r in &reports {
        let roll = f64::from(r.words[0]) / 10.0;
        assert!(
            (roll - 20.0).abs() <= 0.5,
            "roll {roll}°: the firmware banks 20° right"
        );
        let ias = f64::from(r.words[6]);
        assert!(
            (ias - want_ias).abs() <= 0.51,
            "IAS {ias} kt: the firmware flies 50 m/s true at 1000 m ({want_ias:.1} kt indicated)"
        );
        assert!(
            r.altitude_raw != 0xFFFF && r.altitude_raw >= 5000,
            "pressure altitude raw {:#06X}: valid, with its 5000 ft offset",
            r.altitude_raw
        );
        let g = f64::from(r.words[5]) / 10.0;
        assert!(
            (g - 1.06).abs() <= 0.15,
            "G {g}: 1 / cos 20° in a level turn"
        );
    }
}
