//! `protolink sim --gps-outage 5..10` through `protolink nmea --for gpsd` into gpsd, a GPS
//! daemon nobody here wrote, read the two ways gpsd's clients read it: its watch stream
//! (`gpspipe -w`) and a client of this test's own that sends `?WATCH={"enable":true};` and then
//! `?POLL;` twice a second. Both must say what went in: mode 3 (a 3D fix) while the sim has a
//! fix, the position within 1e-5 degrees of a GPS fix that went in, `altMSL` that fix's GPS
//! altitude (never the pressure altitude), `speed` its ground speed and `track` the direction
//! the fixes move in; and mode 1 (no fix, no position, no altitude) during the outage. A
//! transition second at each edge of the outage is not judged.
//!
//! The sim flies the standard atmosphere, where the pressure altitude and the GPS altitude are
//! the same. The test relays every datagram from the sim to nmea and decodes it on the way (so
//! it knows every GPS fix that went in), and it lowers each PRESSURE's static pressure by
//! [`LOW_PRESSURE_HPA`] (a low-pressure day) and re-encodes it: the pressure altitude is then
//! about 180 m above the GPS altitude, and a reader that takes one for the other is caught.
//!
//! gpsd and gpspipe come from Debian (`scripts/setup.sh gpsd`). Without them the test is
//! skipped with the reason, and fails under CI (`CI=true`).

use std::io::{BufRead, BufReader, Read, Write};
use std::net::{TcpStream, UdpSocket};
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread::JoinHandle;
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use crate::common::*;
use aeolus_proto::message::{Message, Pressure};
use aeolus_proto::{CrcMode, decode_datagram, max_encoded_len};
use serde_json::Value;

/// How `protolink nmea` is started for gpsd (`--from`, `--listen` and `--seconds` follow).
/// A set with `$PGRMZ` (`--for lk8000`) fails here:
/// gpsd's stream is right, but its polls give the pressure altitude as `altMSL`, and mode 2
/// with that altitude through the outage (gpsd 3.22 reads `$PGRMZ` as Garmin's altitude and
/// fix type).
const NMEA: &[&str] = &["nmea", "--for", "gpsd"];

/// How long the sim runs, seconds.
const RUN_S: f64 = 15.0;
/// The GPS outage, seconds after the sim starts (`--gps-outage`).
const OUTAGE_S: (f64, f64) = (5.0, 10.0);
/// Not judged: the run's first seconds (nmea's first sentences, gpsd learning their cycle).
const START_S: f64 = 1.5;
/// Not judged around each edge of the outage: from this long before it (the sim's clock
/// starts a little after the test's)...
const BEFORE_EDGE_S: f64 = 0.5;
/// ... to this long after it (a transition second).
const AFTER_EDGE_S: f64 = 1.0;
/// How far below the standard atmosphere's the relayed static pressure is, hPa.
const LOW_PRESSURE_HPA: f32 = 20.0;
/// An `altMSL` this close to a pressure altitude that went in is the pressure altitude, m.
const PRESSURE_ALTITUDE_M: f64 = 50.0;

/// Every process the test started, killed and reaped when the test ends, passing or panicking.
#[derive(Default)]
struct Children(Vec<(&'static str, Child)>);

impl Children {
    fn add(&mut self, name: &'static str, child: Child) {
        self.0.push((name, child));
    }

    fn get(&mut self, name: &str) -> &mut Child {
        let (_, child) = self
            .0
            .iter_mut()
            .find(|(n, _)| *n == name)
            .expect("started");
        child
    }

    /// Kills the named process and reaps it.
    fn kill(&mut self, name: &str) {
        let child = self.get(name);
        let _ = child.kill();
        let _ = child.wait();
    }

    /// The named process's exit and stderr, if it has ended.
    fn ended(&mut self, name: &str) -> Option<String> {
        let child = self.get(name);
        let status = child.try_wait().ok().flatten()?;
        let err = child
            .stderr
            .take()
            .map(|e| String::from_utf8_lossy(&read_all(e)).into_owned());
        Some(format!("{status}: {}", err.unwrap_or_default().trim_end()))
    }
}

impl Drop for Children {
    fn drop(&mut self) {
        for (_, child) in &mut self.0 {
            let _ = child.kill();
            let _ = child.wait();
        }
    }
}

/// `name` on the PATH, or in /usr/sbin (gpsd's place, which a user's PATH may lack).
fn find_tool(name: &str) -> Option<PathBuf> {
    let path = std::env::var_os("PATH").unwrap_or_default();
    std::env::split_paths(&path)
        .chain([PathBuf::from("/usr/sbin")])
        .map(|dir| dir.join(name))
        .find(|p| p.is_file())
}

/// gpsd and gpspipe; when either is missing, the skip (a failure under CI).
fn gpsd_tools() -> Option<(PathBuf, PathBuf)> {
    match (find_tool("gpsd"), find_tool("gpspipe")) {
        (Some(gpsd), Some(gpspipe)) => Some((gpsd, gpspipe)),
        _ => {
            protolink_tests::skip::skip(
                "gpsd or gpspipe is not installed, so no GPS daemon can read the NMEA \
                 (scripts/setup.sh gpsd installs them)",
            );
            None
        }
    }
}

/// Waits until something accepts on `port`, failing with `name`'s exit if it ended first.
fn wait_for_server(port: u16, name: &str, children: &mut Children) {
    let started = Instant::now();
    while TcpStream::connect(("127.0.0.1", port)).is_err() {
        if let Some(ended) = children.ended(name) {
            panic!("{name} ended before it served on {port}: {ended}");
        }
        assert!(
            started.elapsed() < Duration::from_secs(10),
            "{name} does not serve on {port}"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// One GPS fix that went in.
#[derive(Debug, Clone, Copy)]
struct Fix {
    /// The box's clock, ms.
    timestamp_ms: f64,
    lat_deg: f64,
    lon_deg: f64,
    altitude_m: f64,
    ground_speed_mps: f64,
}

/// What the relay saw go in.
#[derive(Default)]
struct WentIn {
    /// The GPS fixes, in order.
    fixes: Vec<Fix>,
    /// GPS messages without a fix.
    without_fix: usize,
    /// Pressure altitudes of the relayed static pressures, m (standard atmosphere).
    pressure_altitudes: Vec<f64>,
}

/// The pressure altitude of a static pressure in the standard atmosphere's troposphere, m:
/// T0 / L * (1 - (p / p0)^(R L / g)).
fn pressure_altitude_m(static_hpa: f64) -> f64 {
    288.15 / 0.0065 * (1.0 - (static_hpa / 1013.25).powf(0.190_263))
}

/// One datagram of the sim's as it goes on to nmea: GPS noted as it is, each PRESSURE's
/// static pressure lowered by [`LOW_PRESSURE_HPA`] and re-encoded; a datagram without
/// PRESSURE goes on unchanged.
fn relay(datagram: &[u8], went_in: &mut WentIn) -> Vec<u8> {
    let mut unescaped = datagram.to_vec();
    let mut rewritten = Vec::new();
    let mut changed = false;
    for frame in decode_datagram(&mut unescaped, true) {
        let frame = frame.expect("the sim sends whole frames with good CRCs");
        let message = match frame.message().expect("the sim sends known messages") {
            Message::Gps(g) if g.has_fix => {
                went_in.fixes.push(Fix {
                    timestamp_ms: g.timestamp_ms,
                    lat_deg: f64::from(g.latitude_deg),
                    lon_deg: f64::from(g.longitude_deg),
                    altitude_m: f64::from(g.altitude_m),
                    ground_speed_mps: f64::from(g.ground_speed_mps),
                });
                Message::Gps(g)
            }
            Message::Gps(g) => {
                went_in.without_fix += 1;
                Message::Gps(g)
            }
            Message::Pressure(p) => {
                let low = Pressure {
                    static_mbar: p.static_mbar - LOW_PRESSURE_HPA,
                    ..p
                };
                went_in
                    .pressure_altitudes
                    .push(pressure_altitude_m(f64::from(low.static_mbar)));
                changed = true;
                Message::Pressure(low)
            }
            other => other,
        };
        let mut wire = vec![0u8; max_encoded_len(message.buffer_len())];
        let n = message.encode(&mut wire, CrcMode::Compute).expect("encode");
        rewritten.extend_from_slice(&wire[..n]);
    }
    if changed {
        rewritten
    } else {
        datagram.to_vec()
    }
}

/// Reads gpspipe's lines as they come, each with its arrival, until it ends.
fn read_lines(pipe: impl Read + Send + 'static) -> JoinHandle<Vec<(Instant, String)>> {
    std::thread::spawn(move || {
        BufReader::new(pipe)
            .lines()
            .map_while(Result::ok)
            .map(|line| (Instant::now(), line))
            .collect()
    })
}

/// A client of gpsd's own: `?WATCH={"enable":true};`, then `?POLL;` every half second until
/// `stop`; returns every line gpsd sent it.
fn poll_gpsd(mut gpsd: TcpStream, stop: Arc<AtomicBool>) -> JoinHandle<Vec<(Instant, String)>> {
    std::thread::spawn(move || {
        gpsd.set_read_timeout(Some(Duration::from_millis(20)))
            .unwrap();
        gpsd.write_all(br#"?WATCH={"enable":true};"#).unwrap();
        let mut next_poll = Instant::now();
        let (mut pending, mut lines, mut chunk) = (Vec::new(), Vec::new(), [0u8; 4096]);
        while !stop.load(Ordering::Relaxed) {
            if Instant::now() >= next_poll {
                gpsd.write_all(b"?POLL;").expect("gpsd takes a poll");
                next_poll += Duration::from_millis(500);
            }
            match gpsd.read(&mut chunk) {
                Ok(0) => break,
                Ok(n) => pending.extend_from_slice(&chunk[..n]),
                Err(_) => {}
            }
            while let Some(end) = pending.iter().position(|&b| b == b'\n') {
                let line: Vec<u8> = pending.drain(..=end).collect();
                lines.push((
                    Instant::now(),
                    String::from_utf8_lossy(&line).trim_end().to_owned(),
                ));
            }
        }
        lines
    })
}

/// Days from 1970-01-01 to a date of the proleptic Gregorian calendar (eras of 400 years,
/// each year counted from March, so that the leap day comes last).
fn days_from_civil(year: i64, month: i64, day: i64) -> i64 {
    let year = if month <= 2 { year - 1 } else { year };
    let era = year.div_euclid(400);
    let year_of_era = year - era * 400;
    let day_of_year = (153 * ((month + 9) % 12) + 2) / 5 + day - 1;
    let day_of_era = year_of_era * 365 + year_of_era / 4 - year_of_era / 100 + day_of_year;
    era * 146_097 + day_of_era - 719_468
}

/// Seconds since 1970 of one of gpsd's times, `2026-11-28T05:25:31.680Z`.
fn unix_seconds(iso: &str) -> Option<f64> {
    let (date, time) = iso.strip_suffix('Z')?.split_once('T')?;
    let date: Vec<i64> = date
        .split('-')
        .map(str::parse)
        .collect::<Result<_, _>>()
        .ok()?;
    let time: Vec<f64> = time
        .split(':')
        .map(str::parse)
        .collect::<Result<_, _>>()
        .ok()?;
    let (&[y, mo, d], &[h, mi, s]) = (&date[..], &time[..]) else {
        return None;
    };
    Some(days_from_civil(y, mo, d) as f64 * 86_400.0 + h * 3600.0 + mi * 60.0 + s)
}

/// One TPV report, and when the sentences it came from were sent, in seconds after the sim
/// started: from the TPV's `time` (the sentences' UTC, the host's clock) when it has one.
struct Sample {
    at_s: f64,
    tpv: Value,
}

/// The clocks of the sim's start: the test's and UTC.
struct Start {
    instant: Instant,
    unix_s: f64,
}

impl Start {
    /// A sample of `tpv`, at `fallback` seconds after the start when it has no time.
    fn sample(&self, tpv: &Value, fallback: f64) -> Sample {
        let at_s = tpv["time"]
            .as_str()
            .and_then(unix_seconds)
            .map_or(fallback, |t| t - self.unix_s);
        Sample {
            at_s,
            tpv: tpv.clone(),
        }
    }

    /// Seconds from the start to `at` on the test's clock.
    fn since(&self, at: Instant) -> f64 {
        at.saturating_duration_since(self.instant).as_secs_f64()
    }
}

/// The stream's TPVs (the arrival when a TPV has no time).
fn stream_samples(lines: &[(Instant, String)], start: &Start) -> Vec<Sample> {
    lines
        .iter()
        .filter_map(|(at, line)| {
            let v: Value = serde_json::from_str(line).ok()?;
            (v["class"] == "TPV").then(|| start.sample(&v, start.since(*at)))
        })
        .collect()
}

/// The first TPV of each POLL reply (the POLL's own time when the TPV has none).
fn poll_samples(lines: &[(Instant, String)], start: &Start) -> Vec<Sample> {
    lines
        .iter()
        .filter_map(|(at, line)| {
            let v: Value = serde_json::from_str(line).ok()?;
            if v["class"] != "POLL" {
                return None;
            }
            let polled = v["time"]
                .as_str()
                .and_then(unix_seconds)
                .map_or(start.since(*at), |t| t - start.unix_s);
            Some(start.sample(v["tpv"].get(0)?, polled))
        })
        .collect()
}

/// What a sample sent at `at_s` must say.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Phase {
    /// The fix before the outage.
    Before,
    Outage,
    /// The fix after it.
    After,
    /// Not judged: the start, an edge of the outage, the run's last 0.3 s and after it.
    Transition,
}

/// The phase of a sample sent `at_s` seconds after the sim started.
fn phase(at_s: f64) -> Phase {
    let near = |edge: f64| (edge - BEFORE_EDGE_S..edge + AFTER_EDGE_S).contains(&at_s);
    if at_s < START_S || near(OUTAGE_S.0) || near(OUTAGE_S.1) || at_s > RUN_S - 0.3 {
        Phase::Transition
    } else if at_s < OUTAGE_S.0 {
        Phase::Before
    } else if at_s < OUTAGE_S.1 {
        Phase::Outage
    } else {
        Phase::After
    }
}

fn angular(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(360.0);
    d.min(360.0 - d)
}

/// The initial great-circle bearing from `a` to `b`, degrees true.
fn bearing_deg(a: &Fix, b: &Fix) -> f64 {
    let (la1, la2) = (a.lat_deg.to_radians(), b.lat_deg.to_radians());
    let dlon = (b.lon_deg - a.lon_deg).to_radians();
    let y = dlon.sin() * la2.cos();
    let x = la1.cos() * la2.sin() - la1.sin() * la2.cos() * dlon.cos();
    y.atan2(x).to_degrees().rem_euclid(360.0)
}

/// The direction the fixes moved in over the second up to fix `i`: the mean of the bearings
/// between successive fixes (one step of 92 ms is a few metres, which the f32 position
/// resolves only to a few degrees).
fn direction_of_motion(fixes: &[Fix], i: usize) -> Option<f64> {
    let (mut sin, mut cos) = (0.0, 0.0);
    for j in (1..=i).rev() {
        if fixes[i].timestamp_ms - fixes[j - 1].timestamp_ms > 1000.0 {
            break;
        }
        let b = bearing_deg(&fixes[j - 1], &fixes[j]).to_radians();
        sin += b.sin();
        cos += b.cos();
    }
    (sin != 0.0 || cos != 0.0).then(|| sin.atan2(cos).to_degrees().rem_euclid(360.0))
}

/// Judges one reader's samples against what went in; returns how many were judged in each
/// phase (before, during and after the outage), and one line for each that disagrees.
fn judge(samples: &[Sample], went_in: &WentIn) -> ([usize; 3], Vec<String>) {
    let mut counts = [0; 3];
    let mut wrong = Vec::new();
    for Sample { at_s, tpv } in samples {
        let mut problems = Vec::new();
        let mut fail = |what: String| problems.push(what);
        let mode = tpv["mode"].as_u64().unwrap_or(0);
        match phase(*at_s) {
            Phase::Transition => continue,
            Phase::Outage => {
                counts[1] += 1;
                if mode != 1 {
                    fail(format!("mode {mode} during the outage, want 1"));
                }
                for key in ["lat", "lon", "altMSL"] {
                    if tpv.get(key).is_some() {
                        fail(format!("{key} during the outage"));
                    }
                }
            }
            p @ (Phase::Before | Phase::After) => {
                counts[if p == Phase::Before { 0 } else { 2 }] += 1;
                if mode != 3 {
                    fail(format!("mode {mode} while the sim has a fix, want 3"));
                }
                judge_fix(tpv, went_in, &mut fail);
            }
        }
        if !problems.is_empty() {
            wrong.push(format!(
                "at {at_s:.2} s: {}; TPV {tpv}",
                problems.join(", ")
            ));
        }
    }
    (counts, wrong)
}

/// A TPV with a fix: position, altitude, speed and track of a fix that went in.
fn judge_fix(tpv: &Value, went_in: &WentIn, fail: &mut impl FnMut(String)) {
    let number = |key: &str| tpv[key].as_f64();
    let (Some(lat), Some(lon)) = (number("lat"), number("lon")) else {
        return fail("no position".into());
    };
    let off = |f: &Fix| (f.lat_deg - lat).abs().max((f.lon_deg - lon).abs());
    let Some((i, fix)) = went_in
        .fixes
        .iter()
        .enumerate()
        .min_by(|a, b| off(a.1).total_cmp(&off(b.1)))
        .filter(|(_, f)| off(f) <= 1e-5)
    else {
        return fail("the position is not within 1e-5 degrees of a GPS fix that went in".into());
    };
    match number("altMSL") {
        None => fail("no altMSL".into()),
        Some(alt) => {
            if (alt - fix.altitude_m).abs() > 0.1 {
                fail(format!(
                    "altMSL {alt} m, the fix's GPS altitude is {} m",
                    fix.altitude_m
                ));
            }
            if let Some(p) = went_in
                .pressure_altitudes
                .iter()
                .find(|p| (*p - alt).abs() < PRESSURE_ALTITUDE_M)
            {
                fail(format!(
                    "altMSL {alt} m is the pressure altitude ({p:.1} m went in)"
                ));
            }
        }
    }
    match number("speed") {
        // Knots with one decimal in RMC: 0.05 kt is 0.026 m/s.
        Some(v) if (v - fix.ground_speed_mps).abs() <= 0.03 => {}
        other => fail(format!(
            "speed {other:?} m/s, the fix's ground speed is {} m/s",
            fix.ground_speed_mps
        )),
    }
    let moving = direction_of_motion(&went_in.fixes, i);
    match (number("track"), moving) {
        (Some(t), Some(m)) if angular(t, m) <= 3.0 => {}
        (track, moving) => fail(format!(
            "track {track:?}, the fixes moved towards {moving:?} degrees"
        )),
    }
}

/// What is wrong with one reader's samples: each that disagrees with what went in, and too
/// few judged in a phase (fewer than `least`); empty when all is right.
fn check_reader(name: &str, samples: &[Sample], went_in: &WentIn, least: [usize; 3]) -> String {
    let (counts, wrong) = judge(samples, went_in);
    let judged: usize = counts.iter().sum();
    eprintln!(
        "{name}: {counts:?} TPVs judged before, during and after the outage, {} disagree",
        wrong.len()
    );
    let mut report = String::new();
    if !wrong.is_empty() {
        report = format!(
            "{name}: {} of the {judged} TPVs judged disagree with what went in:\n{}\n",
            wrong.len(),
            wrong.join("\n")
        );
    }
    if counts.iter().zip(least).any(|(n, least)| *n < least) {
        report += &format!(
            "{name}: {counts:?} TPVs judged before, during and after the outage, want at least \
             {least:?}\n"
        );
    }
    report
}

#[test]
fn gpsd_reads_a_gps_outage_and_the_gps_altitude_from_nmea_for_gpsd() {
    let Some((gpsd_bin, gpspipe_bin)) = gpsd_tools() else {
        return;
    };
    let mut children = Children::default();
    let from_sim = UdpSocket::bind("127.0.0.1:0").unwrap();
    from_sim.set_nonblocking(true).unwrap();
    let sim_out = from_sim.local_addr().unwrap().port();
    let to_nmea = UdpSocket::bind("127.0.0.1:0").unwrap();
    let (nmea_in, nmea_port, gpsd_port) = (free_udp_port(), free_tcp_port(), free_tcp_port());

    let mut nmea_args = NMEA.to_vec();
    let (from, listen, seconds) = (
        format!("udp:{nmea_in}"),
        format!("127.0.0.1:{nmea_port}"),
        (RUN_S + 10.0).to_string(),
    );
    nmea_args.extend(["--from", &from, "--listen", &listen, "--seconds", &seconds]);
    children.add("nmea", spawn(&nmea_args));
    wait_for_server(nmea_port, "nmea", &mut children);

    let gpsd = Command::new(&gpsd_bin)
        .args(["-N", "-n", "-S", &gpsd_port.to_string()])
        .arg(format!("tcp://127.0.0.1:{nmea_port}"))
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("gpsd starts");
    children.add("gpsd", gpsd);
    wait_for_server(gpsd_port, "gpsd", &mut children);

    let mut gpspipe = Command::new(&gpspipe_bin)
        .args(["-w", &format!("127.0.0.1:{gpsd_port}")])
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("gpspipe starts");
    let stream = read_lines(gpspipe.stdout.take().unwrap());
    children.add("gpspipe", gpspipe);
    let stop = Arc::new(AtomicBool::new(false));
    let polls = poll_gpsd(
        TcpStream::connect(("127.0.0.1", gpsd_port)).expect("a client of gpsd"),
        Arc::clone(&stop),
    );

    let outage = format!("{}..{}", OUTAGE_S.0, OUTAGE_S.1);
    let start = Start {
        instant: Instant::now(),
        unix_s: SystemTime::now()
            .duration_since(UNIX_EPOCH)
            .unwrap()
            .as_secs_f64(),
    };
    children.add(
        "sim",
        spawn(&[
            "sim",
            "--udp-out",
            &format!("127.0.0.1:{sim_out}"),
            "--udp-in",
            "0",
            "--gps-outage",
            &outage,
            "--seconds",
            &RUN_S.to_string(),
        ]),
    );
    let mut went_in = WentIn::default();
    let mut datagram = [0u8; 2048];
    while start.since(Instant::now()) < RUN_S + 0.5 {
        match from_sim.recv(&mut datagram) {
            Ok(n) => {
                let relayed = relay(&datagram[..n], &mut went_in);
                to_nmea.send_to(&relayed, ("127.0.0.1", nmea_in)).unwrap();
            }
            Err(_) => std::thread::sleep(Duration::from_millis(1)),
        }
    }
    stop.store(true, Ordering::Relaxed);
    let polls = polls.join().expect("the polling client");
    children.kill("gpspipe");
    let stream = stream.join().expect("gpspipe's reader");
    drop(children);

    // The outage went in: about 5 s of GPS without a fix (one every 92 ms), and fixes around it.
    assert!(
        went_in.without_fix >= 45 && went_in.fixes.len() >= 90,
        "{} GPS without a fix and {} fixes went in",
        went_in.without_fix,
        went_in.fixes.len()
    );
    let stream = stream_samples(&stream, &start);
    let polls = poll_samples(&polls, &start);
    let report = check_reader("gpspipe -w", &stream, &went_in, [2, 3, 2])
        + &check_reader("?POLL", &polls, &went_in, [3, 5, 3]);
    assert!(report.is_empty(), "{report}");
}
