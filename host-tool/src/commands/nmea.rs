//! `protolink nmea`: the box's AEOLUS telemetry as NMEA 0183 for gliding and moving-map apps
//! (XCSoar, LK8000, Kobo varios running XCSoar), on a TCP server (127.0.0.1:4353 by default,
//! XCSoar's default TCP port) or as UDP datagrams (`--to`).
//!
//! Once a second `$GPRMC`, `$GPGGA`, `$PGRMZ` and `$LXWP0`; five times a second `$POV`; each
//! reader (`--for`, [`Reader`]) gets only the sentences it reads as meant. What goes in
//! ([`Picture`]; the sentences in [`crate::nmea::sentence`]):
//!
//! | field | sentence | from |
//! | --- | --- | --- |
//! | position, fix, satellites, altitude | RMC, GGA | GPS, only with a fix |
//! | ground speed | RMC | GPS, m/s to knots |
//! | track | RMC | the GPS fixes of the last half second or more (on the box's clock) |
//! | time, date | RMC, GGA | the host's UTC clock (AEOLUS carries no time of day) |
//! | pressure altitude | PGRMZ (ft), LXWP0 (m) | PRESSURE static pressure, standard atmosphere |
//! | static pressure, dynamic pressure | POV `P` (hPa), `Q` (Pa) | PRESSURE static and pitot (differential) pressure |
//! | temperature | POV `T` | TEMP |
//! | true airspeed | LXWP0 (km/h) | PRESSURE pitot pressure and the air density from static pressure and TEMP ([`crate::air_data`]) |
//! | vario | LXWP0 (m/s) | the pressure altitude's rate over the last second (box clock) |
//! | heading | LXWP0 | COMPASS (magnetic) |
//! | wind | LXWP0 (from, km/h) | WIND |
//!
//! Anything older than [`FRESH`](crate::fresh::FRESH) ([`FRESH_SLOW`] for TEMP and WIND,
//! which come about once a second) or marked invalid by the box goes out as RMC status `V`,
//! GGA fix 0, or an empty field (a left-out pair in `$POV`), never as an old value.

use std::collections::VecDeque;
use std::io::Write as _;
use std::net::SocketAddr;
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use aeolus_proto::message::{Compass, Gps, Message, Wind};
use clap::{Args, ValueEnum};
use serde_json::json;

use crate::air_data::AirDataSource;
use crate::decoders::AEOLUS_CAPACITY;
use crate::endpoint::{Endpoint, Input, parse_local_addr};
use crate::error::Result;
use crate::fresh::{FRESH_SLOW, fresh, fresh_within};
use crate::nmea::fanout::Fanout;
use crate::nmea::sentence::{self, Fix, Lxwp0, Pov, Utc};
use crate::render::{Out, text};
use crate::stop::{self, Deadline};
use crate::telemetry::decode_read;
use crate::units::{FT_PER_M as FEET_PER_M, KT_PER_MPS as KNOTS_PER_MPS};

/// The period of RMC, GGA, PGRMZ and LXWP0 (1 Hz).
pub(crate) const SECOND: Duration = Duration::from_secs(1);
/// The period of POV (5 Hz).
pub(crate) const AIR_PERIOD: Duration = Duration::from_millis(200);
/// The longest the loop waits for input before it serves the clients again.
const TURN: Duration = Duration::from_millis(20);

const KMH_PER_MPS: f64 = 3.6;

/// The reader the sentences are for: each gets what it understands and nothing it misreads.
///
/// | `--for` | sentences | why not the others |
/// | --- | --- | --- |
/// | `xcsoar` (default) | RMC, GGA, `$LXWP0`, `$POV` | XCSoar reads `$PGRMZ` as a QNH altitude unless a FLARM (`$PFLAU`) was seen; it takes the pressure altitude from `$LXWP0` (LX driver) or `$POV`'s `P` (OpenVario driver) |
/// | `lk8000` | RMC, GGA, `$PGRMZ`, `$LXWP0`, `$POV` | none: LK8000 reads `$PGRMZ` as the pressure altitude (QNE) |
/// | `gpsd` | RMC, GGA | gpsd reads `$PGRMZ` as a GPS altitude and its last field as the fix dimension (a 2D fix during an outage); a plain GPS reader (moving map, chart plotter) wants nothing else |
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, ValueEnum, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub(crate) enum Reader {
    /// XCSoar (also on Kobo varios and OpenVario): RMC, GGA, $LXWP0 and $POV; no $PGRMZ,
    /// which XCSoar reads as a QNH altitude without a FLARM.
    #[default]
    Xcsoar,
    /// LK8000: RMC, GGA, $PGRMZ (read as pressure altitude), $LXWP0 and $POV.
    Lk8000,
    /// gpsd, or any reader that only wants a GPS (moving maps, chart plotters): RMC and GGA.
    Gpsd,
}

/// Which sentences a [`Reader`] gets.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Sentences {
    /// `$GPRMC`.
    pub(crate) rmc: bool,
    /// `$GPGGA`.
    pub(crate) gga: bool,
    /// `$PGRMZ`.
    pub(crate) pgrmz: bool,
    /// `$POV`.
    pub(crate) pov: bool,
    /// `$LXWP0`.
    pub(crate) lxwp0: bool,
}

impl Reader {
    /// Its name on the command line.
    pub(crate) fn name(self) -> &'static str {
        match self {
            Reader::Xcsoar => "xcsoar",
            Reader::Lk8000 => "lk8000",
            Reader::Gpsd => "gpsd",
        }
    }

    /// The sentences this reader gets.
    pub(crate) fn sends(self) -> Sentences {
        let gliding = self != Reader::Gpsd;
        Sentences {
            rmc: true,
            gga: true,
            pgrmz: self == Reader::Lk8000,
            pov: gliding,
            lxwp0: gliding,
        }
    }
}

/// Arguments of `protolink nmea`.
#[derive(Debug, Clone, Args)]
pub(crate) struct NmeaArgs {
    /// Where the box's AEOLUS telemetry comes from (udp:5001, tcp:127.0.0.1:7000, ...).
    #[arg(long, value_name = "ENDPOINT")]
    pub(crate) from: Endpoint,
    /// The TCP server the apps connect to: PORT (on 127.0.0.1) or ADDR:PORT.
    #[arg(long, value_name = "[ADDR:]PORT", default_value = "127.0.0.1:4353", value_parser = parse_local_addr)]
    pub(crate) listen: SocketAddr,
    /// Send UDP datagrams (one sentence each) to PORT (on 127.0.0.1) or ADDR:PORT instead of
    /// serving TCP.
    #[arg(long, value_name = "[ADDR:]PORT", value_parser = destination, conflicts_with = "listen")]
    pub(crate) to: Option<SocketAddr>,
    /// The reader the sentences are for: each gets only what it reads as meant (default
    /// `xcsoar`, the most used gliding app).
    #[arg(long = "for", value_name = "READER", value_enum, default_value_t = Reader::Xcsoar)]
    pub(crate) reader: Reader,
    /// Stop after this long: `10` (seconds), `500ms`, `2min` (default: on Ctrl-C, or at the
    /// end of the input).
    #[arg(long, value_name = "DURATION", value_parser = crate::args::run_time)]
    pub(crate) seconds: Option<Duration>,
}

/// A destination: PORT (on 127.0.0.1) or ADDR:PORT, never port 0 or an unspecified address.
///
/// # Errors
/// A sentence naming what is wrong.
pub(crate) fn destination(text: &str) -> std::result::Result<SocketAddr, String> {
    let addr = parse_local_addr(text)?;
    if addr.port() == 0 {
        return Err(format!(
            "'{text}' names port 0, which nothing can be sent to"
        ));
    }
    if addr.ip().is_unspecified() {
        return Err(format!(
            "'{text}' names no host (an unspecified address): give the app's address"
        ));
    }
    Ok(addr)
}

/// The latest of each telemetry message, with when it arrived, the recent GPS fixes and the
/// air data.
#[derive(Debug, Default)]
pub struct Picture {
    air: AirDataSource,
    compass: Option<(Compass, Instant)>,
    gps: Option<(Gps, Instant)>,
    wind: Option<(Wind, Instant)>,
    /// Valid fixes of the last [`TRACK_HISTORY_MS`] of box time, oldest first.
    fixes: VecDeque<Gps>,
}

/// How much box time of fixes the track is taken over (at most).
const TRACK_HISTORY_MS: f64 = 1000.0;
/// The shortest span of box time the track is taken over.
const TRACK_SPAN_MS: f64 = 400.0;
/// Fixes kept for the track at most, whatever their rate.
const TRACK_FIXES: usize = 64;

impl Picture {
    /// Takes one telemetry message that arrived at `now`.
    pub fn take(&mut self, m: &Message<'_>, now: Instant) {
        match m {
            Message::Pressure(_) | Message::Temp(_) => self.air.take(m, now),
            Message::Compass(v) => self.compass = Some((*v, now)),
            Message::Wind(v) => self.wind = Some((*v, now)),
            Message::Gps(v) => {
                self.gps = Some((*v, now));
                self.keep_fix(v);
            }
            _ => {}
        }
    }

    /// Keeps a valid fix for the track; a step back of the box clock (a reboot) starts over.
    fn keep_fix(&mut self, g: &Gps) {
        if !(g.valid && g.has_fix && g.timestamp_ms.is_finite()) {
            return;
        }
        if self
            .fixes
            .back()
            .is_some_and(|last| g.timestamp_ms <= last.timestamp_ms)
        {
            self.fixes.clear();
        }
        if self.fixes.len() == TRACK_FIXES {
            self.fixes.pop_front();
        }
        self.fixes.push_back(*g);
        while self
            .fixes
            .front()
            .is_some_and(|f| g.timestamp_ms - f.timestamp_ms > TRACK_HISTORY_MS)
        {
            self.fixes.pop_front();
        }
    }

    /// A fresh, valid GPS fix, as RMC and GGA carry it.
    pub(crate) fn fix(&self, now: Instant) -> Option<Fix> {
        let g = fresh(&self.gps, now).filter(|g| g.valid && g.has_fix)?;
        Some(Fix {
            lat_deg: f64::from(g.latitude_deg),
            lon_deg: f64::from(g.longitude_deg),
            altitude_m: f64::from(g.altitude_m),
            satellites: g.satellites,
            ground_speed_kt: f64::from(g.ground_speed_mps) * KNOTS_PER_MPS,
            track_deg: self.track_deg(&g),
        })
    }

    /// The track: the bearing from the oldest kept fix at least [`TRACK_SPAN_MS`] before
    /// `now_fix` to it, when they are a metre apart or more.
    fn track_deg(&self, now_fix: &Gps) -> Option<f64> {
        let from = self
            .fixes
            .iter()
            .find(|f| now_fix.timestamp_ms - f.timestamp_ms >= TRACK_SPAN_MS)?;
        bearing_deg(from, now_fix)
    }

    /// The satellites a fresh GPS message reports, fix or not.
    fn satellites(&self, now: Instant) -> Option<u8> {
        fresh(&self.gps, now)
            .filter(|g| g.valid)
            .map(|g| g.satellites)
    }

    /// The pressure altitude in feet, for `$PGRMZ`.
    pub(crate) fn pressure_altitude_ft(&self, now: Instant) -> Option<f64> {
        self.air.at(now).pressure_altitude_m.map(|m| m * FEET_PER_M)
    }

    /// The static and dynamic pressure and the temperature, for `$POV`.
    pub fn pov(&self, now: Instant) -> Pov {
        let air = self.air.at(now);
        Pov {
            static_hpa: air.static_hpa,
            dynamic_pa: air.dynamic_pa,
            celsius: air.celsius,
        }
    }

    /// Airspeed, altitude, vario, heading and wind, for `$LXWP0`.
    pub fn lxwp0(&self, now: Instant) -> Lxwp0 {
        let air = self.air.at(now);
        let wind = fresh_within(&self.wind, now, FRESH_SLOW).filter(|w| w.valid);
        Lxwp0 {
            tas_kmh: air.tas_mps.map(|v| v * KMH_PER_MPS),
            pressure_altitude_m: air.pressure_altitude_m,
            vario_mps: air.vertical_speed_mps,
            heading_deg: fresh(&self.compass, now)
                .filter(|c| c.valid && c.has_value)
                .map(|c| f64::from(c.heading_deg)),
            wind_from_deg: wind.map(|w| f64::from(w.direction_deg)),
            wind_kmh: wind.map(|w| f64::from(w.speed_mps) * KMH_PER_MPS),
        }
    }
}

/// The true course from fix `a` to fix `b`, when they are at least a metre apart.
fn bearing_deg(a: &Gps, b: &Gps) -> Option<f64> {
    let (la1, la2) = (
        f64::from(a.latitude_deg).to_radians(),
        f64::from(b.latitude_deg).to_radians(),
    );
    let dlon = (f64::from(b.longitude_deg) - f64::from(a.longitude_deg)).to_radians();
    let y = dlon.sin() * la2.cos();
    let x = la1.cos() * la2.sin() - la1.sin() * la2.cos() * dlon.cos();
    let metres = y.hypot(x) * 6_371_000.0;
    (metres >= 1.0).then(|| y.atan2(x).to_degrees().rem_euclid(360.0))
}

/// What `nmea` sent, printed on exit.
#[derive(Debug, Default, Clone, Copy, serde::Serialize)]
pub(crate) struct Counters {
    /// The reader the sentences were for.
    #[serde(rename = "for")]
    pub(crate) reader: Reader,
    /// AEOLUS messages taken in.
    pub(crate) telemetry_in: u64,
    /// `$GPRMC` sentences.
    pub(crate) rmc: u64,
    /// `$GPGGA` sentences.
    pub(crate) gga: u64,
    /// `$PGRMZ` sentences.
    pub(crate) pgrmz: u64,
    /// `$POV` sentences.
    pub(crate) pov: u64,
    /// `$LXWP0` sentences.
    pub(crate) lxwp0: u64,
}

fn utc_now() -> Utc {
    Utc::from_unix(
        SystemTime::now()
            .duration_since(UNIX_EPOCH)
            .unwrap_or_default(),
    )
}

/// Writes the once-a-second sentences the reader gets.
fn each_second(out: &mut Fanout, picture: &Picture, now: Instant, counters: &mut Counters) {
    let sends = counters.reader.sends();
    let utc = utc_now();
    let fix = picture.fix(now);
    if sends.rmc {
        out.send(sentence::rmc(&utc, fix.as_ref()).as_bytes());
        counters.rmc += 1;
    }
    if sends.gga {
        out.send(sentence::gga(&utc, fix.as_ref(), picture.satellites(now)).as_bytes());
        counters.gga += 1;
    }
    if sends.pgrmz {
        out.send(sentence::pgrmz(picture.pressure_altitude_ft(now)).as_bytes());
        counters.pgrmz += 1;
    }
    if sends.lxwp0 {
        out.send(sentence::lxwp0(&picture.lxwp0(now)).as_bytes());
        counters.lxwp0 += 1;
    }
}

/// Runs `protolink nmea`.
///
/// # Errors
/// Opening the input or the server, reading the input, or every datagram failing.
pub(crate) fn run(args: &NmeaArgs) -> Result<()> {
    let mut link = args.from.open()?;
    let mut out = match args.to {
        Some(to) => Fanout::udp(to)?,
        None => Fanout::listen(args.listen)?,
    };
    let where_to = match (args.to, out.local_addr()) {
        (Some(to), _) => format!("udp {to}"),
        (None, Ok(addr)) => format!("a TCP server on {addr}"),
        (None, Err(_)) => format!("a TCP server on {}", args.listen),
    };
    let _ = writeln!(
        std::io::stderr(),
        "nmea: {} -> NMEA 0183 for {} on {where_to} (Ctrl-C to stop)",
        link.name(),
        args.reader.name()
    );
    stop::install_ctrl_c();
    let deadline = Deadline::after(args.seconds);
    let mut picture = Picture::default();
    let mut counters = Counters {
        reader: args.reader,
        ..Counters::default()
    };
    let mut decoder = Box::new(aeolus_proto::Decoder::<AEOLUS_CAPACITY>::new());
    let mut buf = vec![0u8; 65_536];
    let start = Instant::now();
    let (mut next_air, mut next_second) = (start, start);
    while !deadline.reached() {
        let wait = next_air
            .min(next_second)
            .saturating_duration_since(Instant::now())
            .clamp(Duration::from_millis(1), TURN);
        match link.read(&mut buf, deadline.left(wait))? {
            Input::Data(n) => {
                let now = Instant::now();
                let bytes = buf.get(..n).unwrap_or(&[]);
                decode_read(&mut decoder, bytes, link.is_datagram(), |m| {
                    counters.telemetry_in += 1;
                    picture.take(m, now);
                });
            }
            Input::Idle => {}
            Input::End => break,
        }
        let now = Instant::now();
        if now >= next_air {
            if let Some(s) = sentence::pov(&picture.pov(now)).filter(|_| args.reader.sends().pov) {
                out.send(s.as_bytes());
                counters.pov += 1;
            }
            next_air += AIR_PERIOD;
        }
        if now >= next_second {
            each_second(&mut out, &picture, now, &mut counters);
            next_second += SECOND;
        }
        out.poll(|note| {
            let _ = writeln!(std::io::stderr(), "nmea: {note}");
        });
    }
    finish(out, counters)
}

/// Serves the clients one last time, prints the counters, and fails when every datagram
/// failed.
fn finish(mut out: Fanout, counters: Counters) -> Result<()> {
    out.poll(|_| {});
    let mut o = Out::new();
    o.line(&format!(
        "nmea: {} {}",
        text(&json!(counters)),
        text(&json!(out.counters()))
    ))?;
    o.flush()?;
    out.check()
}

/// The examples of this module's items, as tests (the items are crate-private, so rustdoc
/// does not run them).
#[cfg(test)]
#[allow(unused_imports, clippy::unnecessary_wraps)]
mod examples {
    use super::*;

    #[test]
    fn reader_example() -> Result<(), Box<dyn std::error::Error>> {
        assert!(!Reader::Xcsoar.sends().pgrmz && Reader::Xcsoar.sends().lxwp0);
        assert!(Reader::Lk8000.sends().pgrmz);
        let gpsd = Reader::Gpsd.sends();
        assert!(gpsd.rmc && gpsd.gga && !gpsd.pgrmz && !gpsd.pov && !gpsd.lxwp0);
        Ok(())
    }

    #[test]
    fn destination_example() -> Result<(), Box<dyn std::error::Error>> {
        assert_eq!(destination("10110").unwrap().to_string(), "127.0.0.1:10110");
        assert!(destination("0").unwrap_err().contains("port 0"));
        assert!(destination("0.0.0.0:10110").is_err());
        Ok(())
    }
}
