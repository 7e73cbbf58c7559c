//! `protolink sim --bank 30` through `protolink nmea`, read as an app reads it (a TCP client
//! on the server) and parsed by pynmea2, an NMEA library nobody here wrote
//! (`tests/python/nmea_check.py`): every checksum valid, the position within 1e-5 degrees of
//! a GPS fix that went in, altitudes and speeds in the units each sentence defines, and the
//! turn's heading advancing at the simulated rate. Then the void sentences of a box that says
//! nothing, and the command line's refusals.
//!
//! pynmea2 comes from PyPI (`scripts/setup.sh python`). Without python3 or pynmea2 the test is
//! skipped with the reason, and fails under CI (`CI=true`).

use std::io::{BufRead, BufReader};
use std::net::{TcpListener, TcpStream, UdpSocket};
use std::process::Command;
use std::time::{Duration, Instant};

use crate::common::*;
use aeolus_proto::message::Message;
use aeolus_proto::{Decode, Decoder};
use serde_json::Value;

fn udp() -> (UdpSocket, u16) {
    let s = UdpSocket::bind("127.0.0.1:0").unwrap();
    s.set_nonblocking(true).unwrap();
    let port = s.local_addr().unwrap().port();
    (s, port)
}

/// Whether `python3` with pynmea2 runs here; when not, the skip (a failure under CI).
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

/// Runs the pynmea2 script on `lines` (host seconds, sentence) and returns its JSON objects.
fn pynmea2_parse(lines: &[(f64, String)]) -> Vec<Value> {
    let text: String = lines
        .iter()
        .map(|(t, s)| format!("{t:.3}\t{s}\n"))
        .collect();
    let file = TempFile::new("nmea-lines", text.as_bytes());
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/python/nmea_check.py");
    let out = Command::new("python3")
        .arg(script)
        .arg(&file.0)
        .output()
        .expect("python3 runs");
    assert!(
        out.status.success(),
        "pynmea2 refused sentences:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    json_lines(&String::from_utf8_lossy(&out.stdout))
}

/// The AEOLUS values that went into `nmea`, in the units the sentences use.
#[derive(Default)]
struct Inputs {
    /// GPS fixes: latitude, longitude (deg), altitude (m), ground speed (kt), satellites.
    fixes: Vec<(f64, f64, f64, f64, u8)>,
    /// COMPASS headings, degrees.
    heading: Vec<f64>,
    /// PRESSURE: static (hPa), dynamic (Pa), pressure altitude (m, ISA troposphere).
    pressure: Vec<(f64, f64, f64)>,
    /// TEMP, °C.
    celsius: Vec<f64>,
    /// WIND: from (deg), speed (km/h).
    wind: Vec<(f64, f64)>,
}

impl Inputs {
    fn take(&mut self, m: &Message<'_>) {
        match m {
            Message::Gps(g) if g.has_fix => self.fixes.push((
                f64::from(g.latitude_deg),
                f64::from(g.longitude_deg),
                f64::from(g.altitude_m),
                f64::from(g.ground_speed_mps) * 3600.0 / 1852.0,
                g.satellites,
            )),
            Message::Compass(c) if c.has_value => self.heading.push(f64::from(c.heading_deg)),
            // The ISA troposphere, written here: T0 / L * (1 - (p / p0)^(R L / g)).
            Message::Pressure(p) => self.pressure.push((
                f64::from(p.static_mbar),
                f64::from(p.pitot_mbar) * 100.0,
                288.15 / 0.0065 * (1.0 - (f64::from(p.static_mbar) / 1013.25).powf(0.190_263)),
            )),
            Message::Temp(t) => self.celsius.push(f64::from(t.celsius)),
            Message::Wind(w) => self
                .wind
                .push((f64::from(w.direction_deg), f64::from(w.speed_mps) * 3.6)),
            _ => {}
        }
    }
}

/// Whether one of the `values` that went in during the run is within `tolerance` by
/// `distance` (the run is shorter than one circle, so a position or heading is not repeated).
fn near<T: Copy>(values: &[T], tolerance: f64, distance: impl Fn(T) -> f64) -> bool {
    values.iter().any(|&v| distance(v) <= tolerance)
}

fn angular(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(360.0);
    d.min(360.0 - d)
}

/// The least-squares slope of unwrapped angles over time, degrees per second.
fn turn_rate(samples: &[(f64, f64)]) -> f64 {
    let mut unwrapped = Vec::new();
    let mut offset = 0.0;
    for (i, &(t, a)) in samples.iter().enumerate() {
        if i > 0 {
            let step = a - samples[i - 1].1;
            if step < -180.0 {
                offset += 360.0;
            } else if step > 180.0 {
                offset -= 360.0;
            }
        }
        unwrapped.push((t, a + offset));
    }
    let n = unwrapped.len() as f64;
    let (mt, ma) = unwrapped
        .iter()
        .fold((0.0, 0.0), |(st, sa), (t, a)| (st + t / n, sa + a / n));
    let (num, den) = unwrapped.iter().fold((0.0, 0.0), |(num, den), (t, a)| {
        (num + (t - mt) * (a - ma), den + (t - mt) * (t - mt))
    });
    num / den
}

/// Relays the sim's datagrams to `nmea` for `window.1`, decoding them as they pass, while a
/// TCP client reads the server; returns what went in and the lines read after `window.0`.
fn run_sim_through_nmea(window: (Duration, Duration)) -> (Inputs, Vec<(f64, String)>) {
    let (from_sim, sim_out) = udp();
    let (to_nmea, _) = udp();
    let nmea_in = free_udp_port();
    let listen = free_tcp_port();
    let sim = spawn(&[
        "sim",
        "--udp-out",
        &format!("127.0.0.1:{sim_out}"),
        "--udp-in",
        "0",
        "--bank",
        "30",
        "--seconds",
        "10",
    ]);
    let nmea = spawn(&[
        "nmea",
        "--from",
        &format!("udp:{nmea_in}"),
        "--listen",
        &listen.to_string(),
        // Every sentence: LK8000's set is all five.
        "--for",
        "lk8000",
        "--seconds",
        "9",
    ]);
    let started = Instant::now();
    let client = loop {
        if let Ok(c) = TcpStream::connect(("127.0.0.1", listen)) {
            break c;
        }
        assert!(
            started.elapsed() < Duration::from_secs(5),
            "no server on {listen}"
        );
        std::thread::sleep(Duration::from_millis(20));
    };
    // A thread reads the lines with their arrival time; this one relays.
    let reader = std::thread::spawn(move || {
        let t0 = Instant::now();
        let mut lines = Vec::new();
        client
            .set_read_timeout(Some(window.1 + Duration::from_secs(2)))
            .unwrap();
        for line in BufReader::new(client).lines() {
            let Ok(line) = line else { break };
            let t = t0.elapsed();
            if t > window.1 {
                break;
            }
            if t >= window.0 {
                lines.push((t.as_secs_f64(), line));
            }
        }
        lines
    });
    let mut decoder = Box::new(Decoder::<1024>::new());
    let mut went_in = Inputs::default();
    let mut buf = [0u8; 2048];
    while started.elapsed() < window.1 + Duration::from_millis(200) {
        while let Ok(n) = from_sim.recv(&mut buf) {
            decoder.reset();
            decoder.feed(&buf[..n], |event| {
                if let Ok(f) = event
                    && let Ok(m) = f.message()
                {
                    went_in.take(&m);
                }
            });
            let _ = to_nmea.send_to(&buf[..n], ("127.0.0.1", nmea_in));
        }
        std::thread::sleep(Duration::from_millis(1));
    }
    let lines = reader.join().expect("reader");
    let out = finish(nmea);
    let _ = finish(sim);
    assert!(out.status.success(), "{}", stderr(&out));
    (went_in, lines)
}

#[test]
fn sim_at_30_degrees_of_bank_reaches_a_gliding_app_as_nmea() {
    if !pynmea2_available() {
        return;
    }
    let (went_in, lines) =
        run_sim_through_nmea((Duration::from_millis(1500), Duration::from_millis(7500)));
    let parsed = pynmea2_parse(&lines);
    assert_eq!(
        parsed.len(),
        lines.len(),
        "every line a sentence pynmea2 read"
    );
    let of = |kind: &str| -> Vec<&Value> { parsed.iter().filter(|v| v["type"] == kind).collect() };
    for (kind, lo, hi) in [
        ("RMC", 5, 7),
        ("GGA", 5, 7),
        ("PGRMZ", 5, 7),
        ("LXWP0", 5, 7),
        ("POV", 27, 33),
    ] {
        let n = of(kind).len();
        assert!((lo..=hi).contains(&n), "{n} {kind} in 6 s");
    }
    check_position(&of("RMC"), &of("GGA"), &went_in);
    check_air_data(&of("PGRMZ"), &of("POV"), &of("LXWP0"), &went_in);
    check_the_turn(&of("RMC"), &of("LXWP0"), &went_in);
}

/// RMC and GGA: a fix, within 1e-5 degrees of a GPS fix that went in; speed in knots,
/// altitude in metres, the satellites of the fix.
fn check_position(rmc: &[&Value], gga: &[&Value], went_in: &Inputs) {
    for v in rmc.iter().chain(gga) {
        let (lat, lon) = (v["lat"].as_f64().unwrap(), v["lon"].as_f64().unwrap());
        assert!(
            near(&went_in.fixes, 1e-5, |f| (f.0 - lat)
                .abs()
                .max((f.1 - lon).abs())),
            "{v} is not within 1e-5 degrees of a GPS fix that went in"
        );
    }
    for v in rmc {
        assert_eq!(v["status"], "A");
        let kt = v["speed_kt"].as_f64().unwrap();
        assert!(
            near(&went_in.fixes, 0.05 + 1e-9, |f| (f.3 - kt).abs()),
            "RMC speed {kt} kt is not a ground speed in knots"
        );
    }
    for v in gga {
        assert_eq!(v["quality"], 1);
        assert_eq!(v["altitude_units"], "M");
        let m = v["altitude"].as_f64().unwrap();
        let sats = v["satellites"].as_u64().unwrap();
        assert!(
            near(&went_in.fixes, 0.05 + 1e-9, |f| (f.2 - m).abs()),
            "GGA altitude {m} m is not a GPS altitude"
        );
        assert!(near(&went_in.fixes, 0.0, |f| (f64::from(f.4)
            - sats as f64)
            .abs()));
    }
}

/// PGRMZ in feet, POV in hPa, Pa and °C, LXWP0's altitude in metres, TAS and wind in km/h.
fn check_air_data(pgrmz: &[&Value], pov: &[&Value], lxwp0: &[&Value], went_in: &Inputs) {
    for v in pgrmz {
        assert_eq!(v["unit"], "f");
        let ft = v["altitude"].as_f64().unwrap();
        assert!(
            near(&went_in.pressure, 0.5 + 0.1, |p| (p.2 / 0.3048 - ft).abs()),
            "PGRMZ {ft} ft is not a pressure altitude in feet"
        );
    }
    for v in pov {
        let (p, q, t) = (
            v["P"].as_f64().unwrap(),
            v["Q"].as_f64().unwrap(),
            v["T"].as_f64().unwrap(),
        );
        assert!(
            near(&went_in.pressure, 0.005 + 1e-6, |x| (x.0 - p).abs()),
            "POV P {p}"
        );
        assert!(
            near(&went_in.pressure, 0.005 + 1e-6, |x| (x.1 - q).abs()),
            "POV Q {q}"
        );
        assert!(
            near(&went_in.celsius, 0.005 + 1e-6, |x| (x - t).abs()),
            "POV T {t}"
        );
    }
    for v in lxwp0 {
        assert_eq!(v["logger"], "N");
        let m = v["altitude_m"].as_f64().unwrap();
        assert!(
            near(&went_in.pressure, 0.05 + 1e-6, |p| (p.2 - m).abs()),
            "LXWP0 {m} m"
        );
        // TAS from the pressures and temperature (rho = p / (R T)), and the sim's 50 m/s.
        let tas = v["tas_kmh"].as_f64().unwrap();
        let (ps, q, _) = *went_in.pressure.last().unwrap();
        let rho = ps * 100.0 / (287.05 * (went_in.celsius.last().unwrap() + 273.15));
        let want = (2.0 * q / rho).sqrt() * 3.6;
        assert!(
            (tas - want).abs() <= 0.15,
            "LXWP0 TAS {tas} km/h, {want} from the pressures"
        );
        assert!(
            (tas - 180.0).abs() <= 0.5,
            "LXWP0 TAS {tas} km/h, the sim flies 50 m/s"
        );
        let vario = v["vario_mps"].as_array().unwrap();
        assert!(
            vario.iter().all(|x| x.as_f64().unwrap().abs() < 0.1),
            "level: {v}"
        );
        let (from, kmh) = (v["wind_from_deg"].as_f64(), v["wind_kmh"].as_f64());
        if let (Some(from), Some(kmh)) = (from, kmh) {
            assert!(near(&went_in.wind, 0.05 + 1e-6, |w| angular(w.0, from)
                + (w.1 - kmh).abs()));
        }
    }
    let winds = lxwp0.iter().filter(|v| v["wind_kmh"].is_f64()).count();
    assert!(
        winds + 1 >= lxwp0.len(),
        "{winds} of {} LXWP0 with wind",
        lxwp0.len()
    );
}

/// The heading (LXWP0, the compass) advances at the coordinated turn's rate, g tan(bank) / V
/// (the sim's 50 m/s true airspeed), and the RMC track turns the same way on average.
fn check_the_turn(rmc: &[&Value], lxwp0: &[&Value], went_in: &Inputs) {
    let rate = 9.806_65 * 30f64.to_radians().tan() / 50.0;
    let want = rate.to_degrees();
    let headings: Vec<(f64, f64)> = lxwp0
        .iter()
        .map(|v| (v["t"].as_f64().unwrap(), v["heading_deg"].as_f64().unwrap()))
        .collect();
    for &(_, h) in &headings {
        assert!(
            near(&went_in.heading, 0.05 + 1e-6, |x| angular(x, h)),
            "LXWP0 heading {h} is not a COMPASS heading"
        );
    }
    let got = turn_rate(&headings);
    assert!(
        (got - want).abs() <= 0.03 * want,
        "heading turns at {got:.3} deg/s, the sim at {want:.3}"
    );
    let tracks: Vec<(f64, f64)> = rmc
        .iter()
        .map(|v| (v["t"].as_f64().unwrap(), v["track_deg"].as_f64().unwrap()))
        .collect();
    // The wind (5 m/s) makes the ground track turn unevenly: a looser bound.
    let track_rate = turn_rate(&tracks);
    assert!(
        (track_rate - want).abs() <= 0.25 * want,
        "track turns at {track_rate:.3} deg/s, the sim at {want:.3}"
    );
}

/// With no telemetry at all: RMC void, GGA fix 0, PGRMZ and LXWP0 empty, no POV; over UDP.
/// Each reader (`--for`) gets its sentences and no other; with a silent box every one of
/// them is void (`$POV`, with nothing to carry, is not sent at all).
#[test]
fn a_silent_box_gives_each_reader_void_sentences_never_old_values() {
    let readers = [
        ("xcsoar", &["GPGGA", "GPRMC", "LXWP0"][..]),
        ("lk8000", &["GPGGA", "GPRMC", "LXWP0", "PGRMZ"][..]),
        ("gpsd", &["GPGGA", "GPRMC"][..]),
    ];
    let runs: Vec<_> = readers
        .iter()
        .map(|&(reader, _)| {
            let (app, app_port) = udp();
            let child = spawn(&[
                "nmea",
                "--from",
                &format!("udp:{}", free_udp_port()),
                "--to",
                &format!("127.0.0.1:{app_port}"),
                "--for",
                reader,
                "--seconds",
                "2.5",
            ]);
            (app, child)
        })
        .collect();
    for ((reader, want), (app, child)) in readers.iter().zip(runs) {
        let out = finish(child);
        assert!(out.status.success(), "{}", stderr(&out));
        assert!(
            stdout(&out).contains(&format!("for={reader}")),
            "{}",
            stdout(&out)
        );
        let mut buf = [0u8; 256];
        let mut lines = Vec::new();
        while let Ok(n) = app.recv(&mut buf) {
            lines.push(String::from_utf8(buf[..n].to_vec()).unwrap());
        }
        assert!(lines.len() >= 2 * want.len(), "{reader}: {lines:?}");
        let mut kinds = Vec::new();
        for line in &lines {
            // The checksum, computed here: the XOR of the bytes between '$' and '*'.
            let (body, sum) = line.trim_end()[1..].split_once('*').unwrap();
            assert_eq!(
                u8::from_str_radix(sum, 16).unwrap(),
                body.bytes().fold(0, |x, b| x ^ b)
            );
            let fields: Vec<&str> = body.split(',').collect();
            match fields[0] {
                "GPRMC" => assert_eq!((fields[2], fields[3], fields[12]), ("V", "", "N"), "{line}"),
                "GPGGA" => assert_eq!((fields[2], fields[6], fields[9]), ("", "0", ""), "{line}"),
                "PGRMZ" => assert_eq!(fields[1], "", "{line}"),
                "LXWP0" => assert!(fields[2..].iter().all(|f| f.is_empty()), "{line}"),
                other => panic!("{other} without telemetry: {line}"),
            }
            kinds.push(fields[0]);
        }
        kinds.sort_unstable();
        kinds.dedup();
        assert_eq!(kinds, *want, "the sentences {reader} gets");
    }
}

#[test]
fn command_line_mistakes_are_one_sentence_and_status_2() {
    for (args, says) in [
        (&["nmea", "--from", "udp:0", "--to", "0"][..], "port 0"),
        (
            &["nmea", "--from", "udp:0", "--to", "0.0.0.0:10110"][..],
            "no host",
        ),
        (
            &["nmea", "--from", "udp:0", "--listen", "99999"][..],
            "neither a port",
        ),
        (
            &[
                "nmea", "--from", "udp:0", "--listen", "4353", "--to", "10110",
            ][..],
            "cannot be used with",
        ),
        (
            &["nmea", "--from", "udp:0", "--seconds", "inf"][..],
            "out of range",
        ),
        (&["nmea"][..], "--from"),
    ] {
        let err = usage_failed(&run(args));
        assert!(err.contains(says), "{args:?}: {err}");
    }
}

/// A port already taken is one sentence and status 1.
#[test]
fn a_taken_port_is_an_error_sentence() {
    let taken = TcpListener::bind("127.0.0.1:0").unwrap();
    let port = taken.local_addr().unwrap().port().to_string();
    let err = failed(&run(&[
        "nmea",
        "--from",
        "udp:0",
        "--listen",
        &port,
        "--seconds",
        "1",
    ]));
    assert!(
        err.contains("cannot open a TCP server on 127.0.0.1:"),
        "{err}"
    );
}
