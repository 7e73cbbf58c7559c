//! `protolink watch` end to end: a fake box on a loopback TCP socket streams AEOLUS telemetry
//! with box timestamps 7 ms apart (ATTITUDE, GYRO), 5 ms (PRESSURE), 92 ms (GPS); stdout is a
//! pipe, so the plain summary is printed.

use std::io::Write;

use crate::common::*;
use aeolus_proto::CrcMode;
use aeolus_proto::message::{
    Attitude, CalibrationStatus, Compass, Gps, Gyro, Message, Pressure, Text, Wind,
};

fn frame(m: &Message<'_>) -> Vec<u8> {
    let mut buf = vec![0u8; 256];
    let n = m.encode(&mut buf, CrcMode::Compute).unwrap();
    buf.truncate(n);
    buf
}

/// One second of box time, and a corrupted frame in the middle.
fn telemetry() -> Vec<u8> {
    let mut out = frame(&Message::Toast(Text::new("AEOLUS on").unwrap()));
    for ms in 0..1000u32 {
        let t = f64::from(ms);
        if ms % 7 == 0 {
            out.extend(frame(&Message::Attitude(Attitude {
                valid: true,
                timestamp_ms: t,
                roll_rad: 30f32.to_radians(),
                pitch_rad: 2f32.to_radians(),
                yaw_rad: 90f32.to_radians(),
                slip_ball: 0.0,
                turn_coordinator: 0.5,
                qx: 0.0,
                qy: 0.0,
                qz: 0.0,
                qw: 1.0,
            })));
            out.extend(frame(&Message::Gyro(Gyro {
                valid: true,
                timestamp_ms: t,
                x: 0.0,
                y: 0.0,
                z: 0.1,
            })));
            out.extend(frame(&Message::Compass(Compass {
                valid: true,
                calibration: CalibrationStatus::Ok,
                has_value: true,
                calibration_percent: 100,
                calibration_remaining: 0,
                timestamp_ms: t,
                heading_deg: 91.5,
                soft_iron: [0.0; 3],
                hard_iron: [0.0; 9],
            })));
        }
        if ms % 5 == 0 {
            out.extend(frame(&Message::Pressure(Pressure {
                valid: true,
                timestamp_ms: t,
                static_mbar: 898.76,
                pitot_mbar: 6.1,
                // The box's own airspeed field, which no view shows (PL39).
                airspeed_mps: 99.0,
            })));
        }
        if ms % 92 == 0 {
            out.extend(frame(&Message::Gps(Gps {
                valid: true,
                has_fix: true,
                satellites: 9,
                timestamp_ms: t,
                latitude_deg: 37.9375,
                longitude_deg: 23.75,
                altitude_m: 1000.5,
                ground_speed_mps: 33.0,
            })));
        }
        if ms == 500 {
            out.extend(frame(&Message::Wind(Wind {
                valid: true,
                timestamp_ms: t,
                speed_mps: 5.5,
                direction_deg: 270.0,
            })));
            let mut bad = frame(&Message::Gyro(Gyro {
                valid: true,
                timestamp_ms: t,
                x: 1.0,
                y: 0.0,
                z: 0.0,
            }));
            bad[12] ^= 0x01;
            out.extend(bad);
        }
    }
    out
}

#[test]
fn plain_summary_shows_the_flight_and_the_box_intervals() {
    let (listener, ep) = listener();
    let stream = telemetry();
    let server = std::thread::spawn(move || {
        let Some(mut s) = accept(&listener) else {
            return;
        };
        for chunk in stream.chunks(997) {
            if s.write_all(chunk).is_err() {
                break;
            }
        }
    });
    let out = run(&["watch", "--from", &ep, "--seconds", "30"]);
    server.join().unwrap();
    let text = ok(&out);
    // The stream ended before 30 s: the final summary is the last block.
    let last = text.split("protolink watch").last().unwrap();
    let line = |key: &str| {
        last.lines()
            .find(|l| l.starts_with(key))
            .unwrap_or_else(|| panic!("no '{key}' line in:\n{last}"))
            .to_string()
    };
    assert!(
        line("attitude").contains("roll   30.00°  pitch    2.00°  yaw   90.00°"),
        "{}",
        line("attitude")
    );
    assert!(
        // 610 Pa of dynamic pressure at sea-level density: sqrt(2 * 610 / 1.225) = 31.558 m/s;
        // no TEMP, so no true airspeed.
        line("airspeed").contains("ias 31.56 m/s  tas -  "),
        "{}",
        line("airspeed")
    );
    assert!(
        line("altitude").contains("gps 1000.5 m"),
        "{}",
        line("altitude")
    );
    assert!(
        line("altitude").contains("pressure 999.9 m (ISA)"),
        "{}",
        line("altitude")
    );
    assert!(
        line("heading").contains(" 91.50°  calibration Ok"),
        "{}",
        line("heading")
    );
    assert!(
        line("gps").contains("lat 37.937500  lon 23.750000  fix yes  sats 9"),
        "{}",
        line("gps")
    );
    assert!(
        line("wind").contains("5.50 m/s  direction 270.0°"),
        "{}",
        line("wind")
    );
    assert!(line("toast").contains("\"AEOLUS on\""));
    // Box-clock intervals are exact: they come from the messages' own timestamps.
    let row = |name: &str| {
        last.lines()
            .find(|l| l.split_whitespace().next() == Some(name))
            .unwrap_or_else(|| panic!("no {name} row in:\n{last}"))
            .to_string()
    };
    assert!(
        row("ATTITUDE").contains("  143 ") && row("ATTITUDE").contains("7.0 ms"),
        "{}",
        row("ATTITUDE")
    );
    assert!(
        row("PRESSURE").contains("  200 ") && row("PRESSURE").contains("5.0 ms"),
        "{}",
        row("PRESSURE")
    );
    assert!(row("GPS").contains("92.0 ms"), "{}", row("GPS"));
    // TOAST is an event, never stale: "event N s ago".
    assert!(
        row("TOAST").ends_with(" s ago") && row("TOAST").contains("event "),
        "{}",
        row("TOAST")
    );
    assert!(line("errors").contains("crc 1 "), "{}", line("errors"));
}

/// Two seconds of a box climbing at 2.5 m/s (its static pressure falling as the ISA says),
/// after a TOAST and a LOG.
fn climbing() -> Vec<u8> {
    let mut out = frame(&Message::Toast(Text::new("AEOLUS on").unwrap()));
    out.extend(frame(&Message::Log(b"boot")));
    for ms in (0..2000u32).step_by(5) {
        let t = f64::from(ms);
        let altitude = 1000.0 + 2.5 * t as f32 / 1000.0;
        out.extend(frame(&Message::Pressure(Pressure {
            valid: true,
            timestamp_ms: t,
            static_mbar: flight_sim::atmosphere::pressure_pa(altitude) / 100.0,
            pitot_mbar: 6.1,
            airspeed_mps: 99.0,
        })));
        if ms % 100 == 0 {
            out.extend(frame(&Message::Gps(Gps {
                valid: true,
                has_fix: true,
                satellites: 9,
                timestamp_ms: t,
                latitude_deg: 37.9375,
                longitude_deg: 23.75,
                altitude_m: altitude,
                ground_speed_mps: 33.0,
            })));
        }
    }
    out
}

#[test]
fn aviation_units_vertical_speed_and_events() {
    let (listener, ep) = listener();
    let stream = climbing();
    let server = std::thread::spawn(move || {
        let Some(mut s) = accept(&listener) else {
            return;
        };
        let _ = s.write_all(&stream);
    });
    let out = run(&[
        "watch",
        "--from",
        &ep,
        "--units",
        "aviation",
        "--seconds",
        "30",
    ]);
    server.join().unwrap();
    let text = ok(&out);
    let last = text.split("protolink watch").last().unwrap();
    let line = |key: &str| {
        last.lines()
            .find(|l| l.split_whitespace().next() == Some(key))
            .unwrap_or_else(|| panic!("no '{key}' line in:\n{last}"))
            .to_string()
    };
    // 31.558 m/s = 61.34 kt; 33 m/s = 64.15 kt.
    let air = line("airspeed");
    assert!(air.contains("ias 61.34 kt "), "{air}");
    assert!(air.contains(" hPa (") && air.contains(" inHg)"), "{air}");
    assert!(
        line("gps").contains("ground speed 64.15 kt"),
        "{}",
        line("gps")
    );
    // The last GPS: 1000 m + 2.5 m/s x 1.9 s = 1004.75 m = 3296.4 ft.
    let alt = line("altitude");
    assert!(alt.contains("gps 3296.4 ft"), "{alt}");
    // 2.5 m/s = 492.1 ft/min, from the pressure altitude over the last second.
    let vs: f64 = alt
        .split("vertical speed ")
        .nth(1)
        .and_then(|r| r.split_whitespace().next())
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("no vertical speed in {alt}"));
    assert!((vs - 492.0).abs() <= 3.0, "{alt}");
    assert!(alt.ends_with(" ft/min"), "{alt}");
    for event in ["TOAST", "LOG"] {
        let row = line(event);
        assert!(row.contains("event ") && !row.contains("STALE"), "{row}");
    }
}

#[test]
fn watch_of_a_missing_file_is_one_clear_error() {
    let out = run(&["watch", "--from", "file:/nonexistent/protolink.bin"]);
    let err = failed(&out);
    assert!(
        err.starts_with("error: cannot open file:/nonexistent/protolink.bin: "),
        "{err}"
    );
}
