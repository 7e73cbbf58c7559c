//! `protolink watch`: a live view of AEOLUS telemetry. On a terminal it redraws in place (ANSI
//! escapes); otherwise it prints a plain summary every second, so it reads well in CI logs.

use std::collections::BTreeMap;
use std::io::IsTerminal;
use std::time::{Duration, Instant};

use aeolus_proto::Decoder;
use aeolus_proto::message::{AeolusInfo, Attitude, Compass, Gps, Message, Pressure, Temp, Wind};
use clap::Args;

use crate::decode::AEOLUS_CAPACITY;
use crate::endpoint::{Endpoint, Input};
use crate::error::Result;
use crate::render::Out;
use crate::stop::{self, Deadline};

/// How often the terminal view redraws.
pub const TTY_REFRESH: Duration = Duration::from_millis(250);
/// How often the plain summary prints when stdout is not a terminal.
pub const PLAIN_REFRESH: Duration = Duration::from_secs(1);

/// Arguments of `protolink watch`.
#[derive(Debug, Clone, Args)]
pub struct WatchArgs {
    /// Where the AEOLUS telemetry comes from (tcp:HOST:PORT, udp:PORT, serial:PATH@BAUD, file:PATH, -).
    #[arg(long, value_name = "ENDPOINT")]
    pub from: Endpoint,
    /// Stop after this long: `10` (seconds), `500ms`, `2min` (default: on Ctrl-C, or at the end of the input).
    #[arg(long, value_name = "DURATION", value_parser = crate::args::run_time)]
    pub seconds: Option<std::time::Duration>,
    /// Print the plain summary even on a terminal.
    #[arg(long)]
    pub plain: bool,
}

/// A type is never called stale sooner than this after its last message (host jitter).
pub const STALE_FLOOR: Duration = Duration::from_millis(100);
/// With no byte at all after this long, the view says so and names the likely causes.
pub const NO_DATA_AFTER: Duration = Duration::from_secs(2);

/// Arrivals of one message type.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Arrivals {
    pub(crate) count: u64,
    first_host: Instant,
    pub(crate) last_host: Instant,
    pub(crate) last_box_ms: Option<f64>,
    /// Sum and number of the forward steps of the box clock (a reboot's step back is skipped).
    box_sum_ms: f64,
    box_steps: u64,
}

impl Arrivals {
    /// Mean interval on the box's clock (message timestamps), ms.
    pub(crate) fn box_interval_ms(&self) -> Option<f64> {
        (self.box_steps > 0).then(|| self.box_sum_ms / self.box_steps as f64)
    }

    /// Whether this type has missed three of its intervals (measured on the host, or 1 s
    /// when only one has arrived), and how long ago the last one came.
    pub(crate) fn stale(&self, now: Instant) -> Option<Duration> {
        let age = now.saturating_duration_since(self.last_host);
        let interval = self
            .host_interval_ms()
            .map_or(Duration::from_secs(1), |ms| {
                Duration::from_secs_f64(ms / 1000.0)
            });
        (age > (interval * 3).max(STALE_FLOOR)).then_some(age)
    }

    /// Mean interval of arrival on the host, ms.
    pub(crate) fn host_interval_ms(&self) -> Option<f64> {
        let span = self.last_host.duration_since(self.first_host).as_secs_f64() * 1000.0;
        (self.count > 1).then(|| span / (self.count - 1) as f64)
    }
}

/// Everything the view shows, updated message by message.
#[derive(Debug, Default)]
///
/// `protolink web` shows the same model in the browser ([`crate::web::state`]).
pub struct View {
    pub(crate) attitude: Option<Attitude>,
    pub(crate) pressure: Option<Pressure>,
    pub(crate) gps: Option<Gps>,
    pub(crate) compass: Option<Compass>,
    pub(crate) wind: Option<Wind>,
    pub(crate) temp: Option<Temp>,
    pub(crate) info: Option<AeolusInfo>,
    pub(crate) toast: Option<String>,
    pub(crate) types: BTreeMap<u8, (&'static str, Arrivals)>,
    pub(crate) malformed: u32,
    pub(crate) truncated: u32,
    pub(crate) bytes: u64,
}

/// Pressure altitude in the ISA, m, from static pressure in mbar.
///
/// ```
/// assert!(protolink::watch::isa_altitude_m(1013.25).abs() < 0.01);
/// assert!((protolink::watch::isa_altitude_m(898.76) - 1000.0).abs() < 1.0);
/// ```
pub fn isa_altitude_m(static_mbar: f32) -> f64 {
    44_330.77 * (1.0 - (f64::from(static_mbar) / 1013.25).powf(0.190_263))
}

impl View {
    /// Takes one message into the view.
    pub fn take(&mut self, m: &Message<'_>, now: Instant) {
        let ts = m.timestamp_ms();
        let entry = self.types.entry(m.id()).or_insert((
            m.name(),
            Arrivals {
                count: 0,
                first_host: now,
                last_host: now,
                last_box_ms: None,
                box_sum_ms: 0.0,
                box_steps: 0,
            },
        ));
        let a = &mut entry.1;
        a.count += 1;
        a.last_host = now;
        if let Some(ts) = ts {
            if let Some(prev) = a.last_box_ms
                && ts > prev
            {
                a.box_sum_ms += ts - prev;
                a.box_steps += 1;
            }
            a.last_box_ms = Some(ts);
        }
        match m {
            Message::Attitude(v) => self.attitude = Some(*v),
            Message::Pressure(v) => self.pressure = Some(*v),
            Message::Gps(v) => self.gps = Some(*v),
            Message::Compass(v) => self.compass = Some(*v),
            Message::Wind(v) => self.wind = Some(*v),
            Message::Temp(v) => self.temp = Some(*v),
            Message::AeolusInfo(v) => self.info = Some(*v),
            Message::Toast(t) => self.toast = Some(crate::render::escape_text(t.as_bytes())),
            _ => {}
        }
    }

    /// Decodes `bytes` (one read of the endpoint; a whole datagram when `datagram`) with
    /// `decoder` and takes every message into the view, handing each to `also` as well.
    /// Bytes, malformed messages and datagrams that end inside a frame are counted.
    pub fn feed(
        &mut self,
        decoder: &mut Decoder<AEOLUS_CAPACITY>,
        bytes: &[u8],
        datagram: bool,
        now: Instant,
        mut also: impl FnMut(&Message<'_>),
    ) {
        self.bytes += bytes.len() as u64;
        for &b in bytes {
            if let Some(Ok(frame)) = decoder.push(b) {
                match frame.message() {
                    Ok(m) => {
                        self.take(&m, now);
                        also(&m);
                    }
                    Err(_) => self.malformed = self.malformed.wrapping_add(1),
                }
            }
        }
        if datagram {
            if decoder.held_bytes() > 0 {
                self.truncated = self.truncated.wrapping_add(1);
            }
            decoder.reset();
        }
    }

    /// The view as lines of text.
    pub fn lines(
        &self,
        source: &str,
        elapsed: Duration,
        now: Instant,
        stats: &aeolus_proto::Stats,
    ) -> Vec<String> {
        let dash = || "-".to_string();
        let mut l = Vec::new();
        if self.bytes == 0 && elapsed >= NO_DATA_AFTER {
            l.push(format!(
                "NO DATA    nothing from {source} for {:.1} s: is it the right port, is the box \
                 running, or does another client hold the QEMU socket (QEMU serves one client \
                 per UART)?",
                elapsed.as_secs_f64()
            ));
        }
        l.push(format!(
            "protolink watch  {source}  {:.1} s  {} bytes",
            elapsed.as_secs_f64(),
            self.bytes
        ));
        l.push(match &self.attitude {
            Some(a) => format!(
                "attitude   roll {:7.2}°  pitch {:7.2}°  yaw {:7.2}°  slip {:6.3}  turn {:6.3}{}",
                a.roll_rad.to_degrees(),
                a.pitch_rad.to_degrees(),
                a.yaw_rad.to_degrees(),
                a.slip_ball,
                a.turn_coordinator,
                valid(a.valid)
            ),
            None => format!("attitude   {}", dash()),
        });
        l.push(match &self.pressure {
            Some(p) => format!(
                "airspeed   {:6.2} m/s  static {:8.2} mbar  pitot {:6.2} mbar{}",
                p.airspeed_mps,
                p.static_mbar,
                p.pitot_mbar,
                valid(p.valid)
            ),
            None => format!("airspeed   {}", dash()),
        });
        let gps_alt = self.gps.map(|g| format!("gps {:.1} m", g.altitude_m));
        let baro_alt = self
            .pressure
            .map(|p| format!("pressure {:.1} m (ISA)", isa_altitude_m(p.static_mbar)));
        l.push(format!(
            "altitude   {}",
            match (gps_alt, baro_alt) {
                (None, None) => dash(),
                (a, b) => [a, b].into_iter().flatten().collect::<Vec<_>>().join("  "),
            }
        ));
        l.push(match &self.compass {
            Some(c) => format!(
                "heading    {:6.2}°  calibration {:?}{}",
                c.heading_deg,
                c.calibration,
                valid(c.valid && c.has_value)
            ),
            None => format!("heading    {}", dash()),
        });
        l.push(match &self.gps {
            Some(g) => format!(
                "gps        lat {:.6}  lon {:.6}  fix {}  sats {}  ground speed {:.2} m/s{}",
                g.latitude_deg,
                g.longitude_deg,
                if g.has_fix { "yes" } else { "no" },
                g.satellites,
                g.ground_speed_mps,
                valid(g.valid)
            ),
            None => format!("gps        {}", dash()),
        });
        l.push(match &self.wind {
            Some(w) => format!(
                "wind       {:.2} m/s  direction {:.1}°{}",
                w.speed_mps,
                w.direction_deg,
                valid(w.valid)
            ),
            None => format!("wind       {}", dash()),
        });
        if let Some(t) = &self.temp {
            l.push(format!("temp       {:.2} °C{}", t.celsius, valid(t.valid)));
        }
        if let Some(i) = &self.info {
            let model = match i.model {
                b'S' => "AEOLUS-SENSE".to_string(),
                b'A' => "AEOLUS".to_string(),
                m => format!("model {m}"),
            };
            let mac = i
                .mac
                .iter()
                .map(|b| format!("{b:02x}"))
                .collect::<Vec<_>>()
                .join(":");
            l.push(format!(
                "box        {model}  firmware {}.{}.{}  mac {mac}",
                i.firmware[0], i.firmware[1], i.firmware[2]
            ));
        }
        if let Some(t) = &self.toast {
            l.push(format!("toast      {t:?}"));
        }
        l.push(format!(
            "messages   {:<12} {:>4} {:>8} {:>15} {:>15}  state",
            "type", "id", "count", "interval (box)", "interval (host)"
        ));
        let ms = |v: Option<f64>| v.map_or_else(|| "-".to_string(), |v| format!("{v:.1} ms"));
        for (id, (name, a)) in &self.types {
            let state = match a.stale(now) {
                Some(age) => format!("STALE, last {:.1} s ago", age.as_secs_f64()),
                None => "live".to_string(),
            };
            l.push(format!(
                "           {:<12} {:>4} {:>8} {:>15} {:>15}  {state}",
                name,
                id,
                a.count,
                ms(a.box_interval_ms()),
                ms(a.host_interval_ms())
            ));
        }
        l.push(format!(
            "errors     crc {}  no-crc frames {}  overflows {}  too short {}  bad escapes {}  \
             malformed {}  truncated {}  bytes discarded {}",
            stats.checksum_errors,
            stats.frames_no_crc,
            stats.overflows,
            stats.too_short,
            stats.bad_escapes,
            self.malformed,
            self.truncated,
            stats.bytes_discarded
        ));
        l
    }
}

fn valid(v: bool) -> &'static str {
    if v { "" } else { "  (invalid)" }
}

/// Runs `protolink watch`.
///
/// # Errors
/// Opening or reading the endpoint, or writing the output.
pub fn run(args: &WatchArgs) -> Result<()> {
    let mut link = args.from.open()?;
    stop::install_ctrl_c();
    let deadline = Deadline::after(args.seconds);
    let tty = !args.plain && std::io::stdout().is_terminal();
    let refresh = if tty { TTY_REFRESH } else { PLAIN_REFRESH };
    let mut out = Out::new();
    let mut view = View::default();
    let mut decoder = Box::new(Decoder::<AEOLUS_CAPACITY>::new());
    let mut buf = vec![0u8; 65_536];
    let started = Instant::now();
    let mut next_draw = started + refresh;
    let source = link.name().to_string();
    let draw =
        |out: &mut Out, view: &View, stats: &aeolus_proto::Stats, last: bool| -> Result<()> {
            let lines = view.lines(&source, started.elapsed(), Instant::now(), stats);
            if tty {
                // Home, then each line cleared to its end, then everything below cleared.
                out.raw("\x1b[H")?;
                for line in &lines {
                    out.raw(line)?;
                    out.raw("\x1b[K\n")?;
                }
                out.raw("\x1b[J")?;
                if last {
                    out.line("(stopped)")?;
                }
            } else {
                for line in &lines {
                    out.line(line)?;
                }
                out.line("")?;
            }
            out.flush()
        };
    if tty {
        out.raw("\x1b[2J")?;
    }
    while !deadline.reached() {
        let wait = deadline.left(next_draw.saturating_duration_since(Instant::now()));
        match link.read(&mut buf, wait)? {
            Input::Data(n) => {
                view.feed(
                    &mut decoder,
                    &buf[..n],
                    link.is_datagram(),
                    Instant::now(),
                    |_| {},
                );
            }
            Input::Idle => {}
            Input::End => break,
        }
        if Instant::now() >= next_draw {
            draw(&mut out, &view, &decoder.stats(), false)?;
            next_draw += refresh;
            if next_draw < Instant::now() {
                next_draw = Instant::now() + refresh;
            }
        }
    }
    draw(&mut out, &view, &decoder.stats(), true)
}
