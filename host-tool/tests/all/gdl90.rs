//! `protolink sim --bank 30` through `protolink gdl90`, with the GDL90 datagrams decoded here
//! by hand from the ICD's byte layout and checked with a CRC computed here bit by bit from the
//! ICD's polynomial (not by `gdl90-proto` or `aeolus-proto`): AHRS roll, pitch and heading, the
//! rates, and the ownship position, pressure altitude and geometric altitude against the
//! AEOLUS messages that went in. The Stratux AHRS report (0x4C) is decoded by hand from
//! Stratux's layout the same way, fresh and stale, and the ownship identity (`--icao`,
//! `--callsign`) is checked in the report and across runs.

use std::net::UdpSocket;
use std::time::{Duration, Instant};

use crate::common::*;
use aeolus_proto::message::Message;
use aeolus_proto::{Decode, Decoder};
use protolink_tests::gdl90_hand::{icd_crc, stratux_report, unframe};

fn udp() -> (UdpSocket, u16) {
    let s = UdpSocket::bind("127.0.0.1:0").unwrap();
    s.set_nonblocking(true).unwrap();
    let port = s.local_addr().unwrap().port();
    (s, port)
}

#[test]
fn the_independent_crc_gives_the_icd_heartbeat_check() {
    // ICD section 2.2.4: the heartbeat 00 81 41 DB D0 08 02 has the check B3 8B, LSB first.
    assert_eq!(icd_crc(&[0x00, 0x81, 0x41, 0xDB, 0xD0, 0x08, 0x02]), 0x8BB3);
    // The check value of the GDL90 CRC (DECISIONS A2): not CRC-16/XMODEM's 0x31C3.
    assert_eq!(icd_crc(b"123456789"), 0xBEEF);
}

/// Passes every datagram `sim` has sent on to `gdl90` (UDP `gdl90_in`), noting the AEOLUS
/// messages in it (decoded here, a datagram at a time) in `went_in`.
fn relay(
    from_sim: &UdpSocket,
    to_gdl90: &UdpSocket,
    gdl90_in: u16,
    decoder: &mut Decoder<1024>,
    went_in: &mut Inputs,
) {
    let mut buf = [0u8; 2048];
    while let Ok(n) = from_sim.recv(&mut buf) {
        decoder.reset();
        decoder.feed(&buf[..n], |event| {
            if let Ok(f) = event
                && let Ok(m) = f.message()
            {
                went_in.take(&m);
            }
        });
        let _ = to_gdl90.send_to(&buf[..n], ("127.0.0.1", gdl90_in));
    }
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
    let mut decoder = Box::new(Decoder::<1024>::new());
    let mut went_in = Inputs::default();
    let mut got = Outputs::default();
    let mut buf = [0u8; 2048];
    let started = Instant::now();
    // The first 1.5 s let the picture fill; the next 5 s are counted.
    let window = (Duration::from_millis(1500), Duration::from_millis(6500));
    while started.elapsed() < window.1 {
        relay(&from_sim, &to_gdl90, gdl90_in, &mut decoder, &mut went_in);
        while let Ok(n) = efb.recv(&mut buf) {
            let (id, data) = unframe(&buf[..n]).expect("every datagram is one good frame");
            if started.elapsed() >= window.0 {
                got.check(id, &data, &went_in);
            }
        }
        std::thread::sleep(Duration::from_millis(1));
    }
    let gdl90_out = finish(gdl90);
    let _ = finish(sim);
    assert!(gdl90_out.status.success(), "{}", stderr(&gdl90_out));
    let seconds = (window.1 - window.0).as_secs_f64();
    let ahrs_rate = got.ahrs_roll.len() as f64 / seconds;
    assert!((4.4..=5.6).contains(&ahrs_rate), "AHRS at {ahrs_rate}/s");
    assert!(
        (4..=6).contains(&got.heartbeats),
        "{} heartbeats in {seconds} s",
        got.heartbeats
    );
    for (what, n) in [
        ("ownship", got.ownship),
        ("geometric altitude", got.geo_altitude),
    ] {
        assert!((4..=6).contains(&n), "{n} {what} reports in {seconds} s");
    }
    for roll in &got.ahrs_roll {
        assert!((roll - 30.0).abs() <= 0.2, "AHRS roll {roll}");
    }
}

/// The recent values of the AEOLUS messages that went into `gdl90`, in GDL90's units.
#[derive(Default)]
struct Inputs {
    /// GPS fixes: latitude, longitude (degrees), altitude (feet).
    fixes: Vec<(f64, f64, f64)>,
    /// ATTITUDE pitch, degrees.
    pitch: Vec<f64>,
    /// COMPASS heading (magnetic), degrees.
    heading: Vec<f64>,
    /// Pressure altitude from PRESSURE's static pressure, feet.
    pressure_altitude: Vec<f64>,
    /// Indicated airspeed from PRESSURE's dynamic (pitot) pressure, knots.
    ias_kt: Vec<f64>,
    /// True airspeed from PRESSURE's dynamic and static pressure and the last TEMP, knots.
    tas_kt: Vec<f64>,
    /// The last TEMP, °C.
    celsius: Option<f64>,
}

/// The last values to match an output against: the outputs lag the inputs by at most a
/// second, and every input comes at 10 Hz or more.
const RECENT: usize = 30;

impl Inputs {
    fn take(&mut self, m: &Message<'_>) {
        match m {
            Message::Gps(g) if g.has_fix => self.fixes.push((
                f64::from(g.latitude_deg),
                f64::from(g.longitude_deg),
                f64::from(g.altitude_m) / 0.3048,
            )),
            Message::Attitude(a) => self.pitch.push(f64::from(a.pitch_rad).to_degrees()),
            Message::Compass(c) if c.has_value => self.heading.push(f64::from(c.heading_deg)),
            // The standard atmosphere's pressure altitude (1013.25 hPa datum), written here
            // from the ICAO ISA rather than taken from the tool: T0 / L = 288.15 K / 6.5 K/km
            // = 44 330.77 m, exponent R L / (g M) = 0.190 263, in international feet.
            Message::Pressure(p) => {
                self.pressure_altitude.push(
                    44_330.77 * (1.0 - (f64::from(p.static_mbar) / 1013.25).powf(0.190_263))
                        / 0.3048,
                );
                // V = sqrt(2 q / rho): rho0 = 1.225 kg/m³ for IAS, p / (R T) for TAS.
                let q = f64::from(p.pitot_mbar) * 100.0;
                let kt = 3600.0 / 1852.0;
                self.ias_kt.push((2.0 * q / 1.225).sqrt() * kt);
                if let Some(c) = self.celsius {
                    let rho = f64::from(p.static_mbar) * 100.0 / (287.05 * (c + 273.15));
                    self.tas_kt.push((2.0 * q / rho).sqrt() * kt);
                }
            }
            Message::Temp(t) => self.celsius = Some(f64::from(t.celsius)),
            _ => {}
        }
    }
}

/// Whether `got` is within `tolerance` of one of the last [`RECENT`] of `values` (`distance`
/// measures the difference).
fn near(values: &[f64], got: f64, tolerance: f64, distance: impl Fn(f64, f64) -> f64) -> bool {
    values
        .iter()
        .rev()
        .take(RECENT)
        .any(|&v| distance(v, got) <= tolerance)
}

fn linear(a: f64, b: f64) -> f64 {
    (a - b).abs()
}

fn angular(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(360.0);
    d.min(360.0 - d)
}

/// What came out of `gdl90`, each field checked against the inputs as it arrives.
#[derive(Default)]
struct Outputs {
    heartbeats: usize,
    ownship: usize,
    geo_altitude: usize,
    ahrs_roll: Vec<f64>,
}

impl Outputs {
    fn check(&mut self, id: u8, data: &[u8], went_in: &Inputs) {
        match (id, data.first()) {
            (0x00, _) => self.heartbeats += 1,
            (0x65, Some(0x01)) => {
                // ForeFlight AHRS: roll, pitch (signed tenths of a degree), heading word
                // (bit 15 magnetic, bits 14-0 signed tenths), all most significant byte first.
                let tenths =
                    |at: usize| f64::from(i16::from_be_bytes([data[at], data[at + 1]])) / 10.0;
                self.ahrs_roll.push(tenths(1));
                let pitch = tenths(3);
                assert!(
                    near(&went_in.pitch, pitch, 0.1, linear),
                    "AHRS pitch {pitch} is not one of the last ATTITUDE pitches"
                );
                let word = u16::from_be_bytes([data[5], data[6]]);
                assert_ne!(word, 0xFFFF, "the heading is marked invalid");
                assert_eq!(word >> 15, 1, "COMPASS is a magnetic heading");
                let heading = f64::from(((word << 1) as i16) >> 1) / 10.0;
                assert!(
                    near(&went_in.heading, heading, 0.1, angular),
                    "AHRS heading {heading} is not one of the last COMPASS headings"
                );
                // IAS and TAS, whole knots: IAS from the pitot's dynamic pressure at sea-level
                // density, TAS at the density of the static pressure and TEMP (PL39).
                let (ias, tas) = (
                    f64::from(u16::from_be_bytes([data[7], data[8]])),
                    f64::from(u16::from_be_bytes([data[9], data[10]])),
                );
                assert!(
                    near(&went_in.ias_kt, ias, 0.51, linear),
                    "AHRS IAS {ias} kt is not that of a recent PRESSURE"
                );
                assert!(
                    near(&went_in.tas_kt, tas, 0.51, linear),
                    "AHRS TAS {tas} kt is not that of a recent PRESSURE and TEMP"
                );
            }
            (0x0A, _) => {
                // Latitude at data bytes 4..7, longitude 7..10: 24-bit semicircles.
                let (lat, lon) = (i24(&data[4..7]), i24(&data[7..10]));
                let lsb = 180.0 / f64::from(1 << 23);
                let near_fix = went_in
                    .fixes
                    .iter()
                    .rev()
                    .take(RECENT)
                    .any(|(la, lo, _)| (la - lat).abs() <= lsb && (lo - lon).abs() <= lsb);
                assert!(
                    near_fix,
                    "ownship {lat},{lon} is not one of the last GPS fixes"
                );
                // Pressure altitude: the 12 bits at data bytes 10..12, 25 ft steps from
                // -1000 ft; rounding to a step is 12.5 ft at most.
                let raw = u16::from(data[10]) << 4 | u16::from(data[11]) >> 4;
                assert_ne!(raw, 0xFFF, "the pressure altitude is marked invalid");
                let altitude = f64::from(raw) * 25.0 - 1000.0;
                assert!(
                    near(&went_in.pressure_altitude, altitude, 12.5 + 0.5, linear),
                    "ownship pressure altitude {altitude} ft is not that of a recent PRESSURE"
                );
                self.ownship += 1;
            }
            (0x0B, _) => {
                // Geometric altitude: a signed 16-bit count of 5 ft at data bytes 0..2.
                let altitude = f64::from(i16::from_be_bytes([data[0], data[1]])) * 5.0;
                let fixes: Vec<f64> = went_in.fixes.iter().map(|f| f.2).collect();
                assert!(
                    near(&fixes, altitude, 2.5 + 0.5, linear),
                    "geometric altitude {altitude} ft is not that of a recent GPS fix"
                );
                self.geo_altitude += 1;
            }
            _ => {}
        }
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
/// A UDP socket on `ip` (another loopback address stands for another machine), non-blocking.
fn udp_on(ip: &str) -> (UdpSocket, u16) {
    let s = UdpSocket::bind((ip, 0)).unwrap();
    s.set_nonblocking(true).unwrap();
    let port = s.local_addr().unwrap().port();
    (s, port)
}

/// Runs `gdl90 --discover[=WHOM]` while a ForeFlight on 127.0.0.2 announces itself, and from
/// 3 s on a second one on 127.0.0.3; returns the GDL90 datagrams each got after the second
/// began, those that went to `--to`, and the run's stderr and stdout.
fn discover_with(discover: &str) -> (usize, usize, usize, String, String) {
    // A turn at UDP 63093, which `--discover` binds on every interface: the lock of one file
    // in the temporary folder, which protolink-tests' README and help examples take around their
    // `--discover` runs too (`harness::discovery_port_turn`); they run beside these in CI.
    let turn = std::fs::OpenOptions::new()
        .create(true)
        .truncate(false)
        .write(true)
        .open(std::env::temp_dir().join("protolink-tests-udp-63093.lock"))
        .expect("the discovery port's lock file");
    turn.lock().expect("the discovery port's lock");
    let (first, first_port) = udp_on("127.0.0.2");
    let (second, second_port) = udp_on("127.0.0.3");
    let (unused, unused_port) = udp();
    let gdl90 = spawn(&[
        "gdl90",
        "--from",
        "udp:0",
        "--to",
        &format!("127.0.0.1:{unused_port}"),
        discover,
        "--seconds",
        "6",
    ]);
    let announce = |ip: &str, port: u16| {
        let s = UdpSocket::bind((ip, 0)).unwrap();
        let text = format!(r#"{{"App":"ForeFlight","GDL90":{{"port":{port}}}}}"#);
        let _ = s.send_to(text.as_bytes(), ("127.0.0.1", 63093));
    };
    let mut buf = [0u8; 512];
    let (mut to_first, mut to_second) = (0, 0);
    let started = Instant::now();
    // Each announces every 100 ms (the tool may still be starting; ForeFlight repeats its
    // announcement too).
    while started.elapsed() < Duration::from_millis(5500) {
        announce("127.0.0.2", first_port);
        let second_on = started.elapsed() >= Duration::from_secs(3);
        if second_on {
            announce("127.0.0.3", second_port);
        }
        // Settle for half a second after the second began, then count.
        let counting = started.elapsed() >= Duration::from_millis(3500);
        while let Ok(n) = first.recv(&mut buf) {
            assert!(unframe(&buf[..n]).is_some());
            to_first += usize::from(counting);
        }
        while let Ok(n) = second.recv(&mut buf) {
            assert!(unframe(&buf[..n]).is_some());
            to_second += usize::from(counting);
        }
        std::thread::sleep(Duration::from_millis(100));
    }
    let out = finish(gdl90);
    assert!(out.status.success(), "{}", stderr(&out));
    let mut to_unused = 0;
    while unused.recv(&mut buf).is_ok() {
        to_unused += 1;
    }
    (to_first, to_second, to_unused, stderr(&out), stdout(&out))
}

/// `--discover` sends to the first ForeFlight that announces itself, here on another address
/// (127.0.0.2), and keeps it when a second one (127.0.0.3) announces itself later: the second
/// is ignored, counted and named. `--discover=follow` goes to the latest.
#[test]
fn discover_keeps_the_first_announcer_unless_told_to_follow() {
    let (first, second, unused, err, out) = discover_with("--discover");
    assert!(
        first >= 10,
        "{first} datagrams reached the first announcer; {err}"
    );
    assert_eq!(
        second, 0,
        "the second announcer took the stream over; {err}"
    );
    // Before the announcement datagrams went to --to: at most the first second's worth.
    assert!(unused <= 40, "{unused} datagrams went to --to");
    assert!(
        err.contains("sending to the ForeFlight at 127.0.0.2:"),
        "{err}"
    );
    assert!(
        err.contains("ignored the ForeFlight at 127.0.0.3:"),
        "{err}"
    );
    let ignored: u64 = out
        .split("announcements_ignored=")
        .nth(1)
        .and_then(|t| t.split_whitespace().next())
        .and_then(|n| n.parse().ok())
        .unwrap_or(0);
    assert!(ignored >= 10, "announcements_ignored={ignored}: {out}");

    let (first, second, _, err, _) = discover_with("--discover=follow");
    assert!(
        second >= 10,
        "{second} datagrams reached the latest announcer; {err}"
    );
    // Both announce every 100 ms: the stream follows whichever spoke last, so both get some.
    assert!(first + second >= 20, "{first} + {second} datagrams; {err}");
}

#[test]
fn the_stratux_ahrs_report_carries_the_bank_and_the_pressure_altitude() {
    let (from_sim, sim_out) = udp();
    let (to_gdl90, _) = udp();
    let (efb, efb_port) = udp();
    let gdl90_in = free_udp_port();
    let sim = spawn(&[
        "sim",
        "--udp-out",
        &format!("127.0.0.1:{sim_out}"),
        "--udp-in",
        "0",
        "--bank",
        "30",
        "--seconds",
        "6",
    ]);
    let gdl90 = spawn(&[
        "gdl90",
        "--from",
        &format!("udp:{gdl90_in}"),
        "--to",
        &format!("127.0.0.1:{efb_port}"),
        "--ahrs",
        "stratux",
        "--seconds",
        "5",
    ]);
    let mut decoder = Box::new(Decoder::<1024>::new());
    let mut went_in = Inputs::default();
    let (mut reports, mut foreflight) = (Vec::new(), 0);
    let mut buf = [0u8; 2048];
    let started = Instant::now();
    while started.elapsed() < Duration::from_millis(4500) {
        relay(&from_sim, &to_gdl90, gdl90_in, &mut decoder, &mut went_in);
        while let Ok(n) = efb.recv(&mut buf) {
            let (id, data) = unframe(&buf[..n]).expect("every datagram is one good frame");
            match id {
                0x4C if started.elapsed() >= Duration::from_millis(1500) => {
                    let r = stratux_report(&data);
                    // Against the PRESSURE messages of the last moments, as it arrives.
                    let feet = f64::from(r.altitude_raw) - 5000.0;
                    assert!(
                        near(&went_in.pressure_altitude, feet, 0.5 + 0.5, linear),
                        "pressure altitude {feet} ft (raw {}) is not a recent one",
                        r.altitude_raw
                    );
                    reports.push(r);
                }
                0x65 if data[0] == 0x01 => foreflight += 1,
                _ => {}
            }
        }
        std::thread::sleep(Duration::from_millis(1));
    }
    let out = finish(gdl90);
    let _ = finish(sim);
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(foreflight, 0, "--ahrs stratux sends no ForeFlight AHRS");
    assert!(reports.len() >= 12, "{} reports in 3 s", reports.len());
    for r in &reports {
        let roll = f64::from(r.words[0]) / 10.0;
        assert!((roll - 30.0).abs() <= 0.1, "roll {roll}");
        for (i, w) in r.words.iter().enumerate().take(7) {
            assert_ne!(*w, 0x7FFF, "field {i} invalid with fresh data");
        }
        assert_ne!(r.altitude_raw, 0xFFFF);
        // Level flight: the vertical speed is about 0 ft/min; G about 1/cos(30°) = 1.15.
        assert!(r.words[8].abs() <= 20, "vertical speed {}", r.words[8]);
        let g = f64::from(r.words[5]) / 10.0;
        assert!((g - 1.0 / 30f64.to_radians().cos()).abs() <= 0.06, "G {g}");
    }
}

/// Without telemetry every field of the Stratux report is invalid: `7FFF`, and `FFFF` for
/// the pressure altitude.
#[test]
fn a_silent_box_sends_an_all_invalid_stratux_report() {
    let (efb, efb_port) = udp();
    let out = finish(spawn(&[
        "gdl90",
        "--from",
        &format!("udp:{}", free_udp_port()),
        "--to",
        &format!("127.0.0.1:{efb_port}"),
        "--seconds",
        "1",
    ]));
    assert!(out.status.success(), "{}", stderr(&out));
    let mut buf = [0u8; 512];
    let mut reports = 0;
    while let Ok(n) = efb.recv(&mut buf) {
        if let Some((0x4C, data)) = unframe(&buf[..n]) {
            let r = stratux_report(&data);
            assert_eq!(r.words[..7], [0x7FFF; 7]);
            assert_eq!((r.altitude_raw, r.words[8]), (0xFFFF, 0x7FFF));
            reports += 1;
        }
    }
    assert!(reports >= 4, "{reports} Stratux reports in 1 s");
}

/// `--icao` and `--callsign` go into the ownship report (address type 0, ICAO) and are kept
/// for the box: the next run without them sends the same identity.
#[test]
fn the_ownship_identity_is_set_and_kept_per_box() {
    let state = std::env::temp_dir().join(format!("protolink-ownship-{}", std::process::id()));
    let from = format!("udp:{}", free_udp_port());
    let run_gdl90 = |extra: &[&str]| {
        let (efb, efb_port) = udp();
        let mut args = vec!["gdl90", "--from", from.as_str(), "--seconds", "0.5"];
        let to = format!("127.0.0.1:{efb_port}");
        args.extend(["--to", to.as_str()]);
        args.extend(extra);
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_protolink"))
            .args(&args)
            .env("XDG_STATE_HOME", &state)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let mut buf = [0u8; 512];
        let mut ownship = None;
        while let Ok(n) = efb.recv(&mut buf) {
            if let Some((0x0A, data)) = unframe(&buf[..n]) {
                ownship = Some(data);
            }
        }
        ownship.expect("an ownship report")
    };
    let first = run_gdl90(&["--icao", "a1b2c3", "--callsign", "n123ab"]);
    for data in [first, run_gdl90(&[])] {
        assert_eq!(data[0] & 0x0F, 0, "address type 0: ADS-B with ICAO address");
        assert_eq!(&data[1..4], &[0xA1, 0xB2, 0xC3]);
        assert_eq!(&data[18..26], b"N123AB  ");
    }
    let kept = std::fs::read_to_string(state.join("protolink/ownship.json")).unwrap();
    let port = from.trim_start_matches("udp:");
    assert!(
        kept.contains(&format!("\"udp:127.0.0.1:{port}\"")),
        "{kept}"
    );
    let _ = std::fs::remove_dir_all(&state);
    for (bad, says) in [
        (["--icao", "1234567"], "24-bit"),
        (["--icao", "000000"], "not assigned"),
        (["--callsign", "D-EKAB"], "only 0-9 and A-Z"),
        (["--callsign", "ABCDEFGHI"], "1 to 8"),
        (["--broadcast", "ff02::1"], "IPv6 has no broadcast"),
        (["--broadcast", "everyone"], "not an IPv4 address"),
    ] {
        let mut args = vec!["gdl90", "--from", "udp:0"];
        args.extend(bad);
        let err = usage_failed(&run(&args));
        assert!(err.contains(says), "{err}");
    }
}
