//! `protolink watch`: a live view of AEOLUS telemetry. On a terminal it redraws in place (ANSI
//! escapes); otherwise it prints a plain summary every second, so it reads well in CI logs.

use std::io::IsTerminal;
use std::time::{Duration, Instant};

use aeolus_proto::Decoder;
use clap::Args;

use crate::decoders::AEOLUS_CAPACITY;
use crate::endpoint::{Endpoint, Input};
use crate::error::Result;
use crate::render::Out;
use crate::stop::{self, Deadline};
use crate::telemetry::{EVENTS, NO_DATA_AFTER, View};
use crate::units::Units;

/// How often the terminal view redraws.
pub(crate) const TTY_REFRESH: Duration = Duration::from_millis(250);
/// How often the plain summary prints when stdout is not a terminal.
pub(crate) const PLAIN_REFRESH: Duration = Duration::from_secs(1);

/// Arguments of `protolink watch`.
#[derive(Debug, Clone, Args)]
pub(crate) struct WatchArgs {
    /// Where the AEOLUS telemetry comes from (tcp:HOST:PORT, udp:PORT, serial:PATH@BAUD, file:PATH, -).
    #[arg(long, value_name = "ENDPOINT")]
    pub(crate) from: Endpoint,
    /// Stop after this long: `10` (seconds), `500ms`, `2min` (default: on Ctrl-C, or at the end of the input).
    #[arg(long, value_name = "DURATION", value_parser = crate::args::run_time)]
    pub(crate) seconds: Option<std::time::Duration>,
    /// Print the plain summary even on a terminal.
    #[arg(long)]
    pub(crate) plain: bool,
    /// Display units: `si` (m/s, m, mbar, as the box sends them) or `aviation` (knots, feet,
    /// feet per minute, hPa and inHg).
    #[arg(long, value_enum, default_value_t = Units::Si)]
    pub(crate) units: Units,
}

/// The view as lines of text: what came in, one line per reading, the message types with
/// their intervals and state, and the decoder's error counters.
pub fn lines(
    view: &View,
    source: &str,
    elapsed: Duration,
    now: Instant,
    stats: &aeolus_proto::Stats,
) -> Vec<String> {
    let mut l = Vec::new();
    if view.bytes == 0 && elapsed >= NO_DATA_AFTER {
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
        view.bytes
    ));
    l.push(attitude_line(view));
    l.push(airspeed_line(view, now));
    l.push(altitude_line(view, now));
    l.push(heading_line(view));
    l.push(gps_line(view));
    l.push(wind_line(view));
    l.extend(occasional_lines(view));
    l.extend(type_lines(view, now));
    l.push(errors_line(view, stats));
    l
}

fn dash() -> String {
    "-".to_string()
}

fn attitude_line(view: &View) -> String {
    match &view.attitude {
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
    }
}

/// Indicated and true airspeed (from the air data: fresh values only), then the last
/// PRESSURE's static and pitot pressure as the box sent them.
fn airspeed_line(view: &View, now: Instant) -> String {
    let u = view.units;
    let speed = u.speed();
    let pitot_unit = match u {
        Units::Si => "mbar",
        Units::Aviation => "hPa",
    };
    let air = view.air.at(now);
    let shown =
        |v: Option<f64>| v.map_or_else(dash, |v| format!("{:.2} {}", speed.of(v), speed.unit));
    match &view.pressure {
        Some(p) => format!(
            "airspeed   ias {}  tas {}  static {}  pitot {:.2} {pitot_unit}{}",
            shown(air.ias_mps),
            shown(air.tas_mps),
            u.pressure(p.static_mbar),
            p.pitot_mbar,
            valid(p.valid)
        ),
        None => format!("airspeed   {}", dash()),
    }
}

/// GPS altitude, pressure altitude and vertical speed, those known (the last two from the air
/// data: fresh values only).
fn altitude_line(view: &View, now: Instant) -> String {
    let u = view.units;
    let (alt, vs) = (u.altitude(), u.vertical_speed());
    let air = view.air.at(now);
    let gps_alt = view
        .gps
        .map(|g| format!("gps {:.1} {}", alt.of(f64::from(g.altitude_m)), alt.unit));
    let baro_alt = air
        .pressure_altitude_m
        .map(|m| format!("pressure {:.1} {} (ISA)", alt.of(m), alt.unit));
    let vertical = air.vertical_speed_mps.map(|v| {
        let digits = if u == Units::Si { 2 } else { 0 };
        format!("vertical speed {:+.digits$} {}", vs.of(v), vs.unit)
    });
    format!(
        "altitude   {}",
        match (gps_alt, baro_alt, vertical) {
            (None, None, None) => dash(),
            (a, b, c) => [a, b, c]
                .into_iter()
                .flatten()
                .collect::<Vec<_>>()
                .join("  "),
        }
    )
}

fn heading_line(view: &View) -> String {
    match &view.compass {
        Some(c) => format!(
            "heading    {:6.2}°  calibration {:?}{}",
            c.heading_deg,
            c.calibration,
            valid(c.valid && c.has_value)
        ),
        None => format!("heading    {}", dash()),
    }
}

fn gps_line(view: &View) -> String {
    let speed = view.units.speed();
    match &view.gps {
        Some(g) => format!(
            "gps        lat {:.6}  lon {:.6}  fix {}  sats {}  ground speed {:.2} {}{}",
            g.latitude_deg,
            g.longitude_deg,
            if g.has_fix { "yes" } else { "no" },
            g.satellites,
            speed.of(f64::from(g.ground_speed_mps)),
            speed.unit,
            valid(g.valid)
        ),
        None => format!("gps        {}", dash()),
    }
}

fn wind_line(view: &View) -> String {
    let speed = view.units.speed();
    match &view.wind {
        Some(w) => format!(
            "wind       {:.2} {}  direction {:.1}°{}",
            speed.of(f64::from(w.speed_mps)),
            speed.unit,
            w.direction_deg,
            valid(w.valid)
        ),
        None => format!("wind       {}", dash()),
    }
}

/// Temperature, the box's identity and its last TOAST: shown once they have arrived.
fn occasional_lines(view: &View) -> Vec<String> {
    let mut l = Vec::new();
    if let Some(t) = &view.temp {
        l.push(format!("temp       {:.2} °C{}", t.celsius, valid(t.valid)));
    }
    if let Some(i) = &view.info {
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
    if let Some(t) = &view.toast {
        l.push(format!("toast      {t:?}"));
    }
    l
}

/// The message types seen: count, intervals on both clocks, and live, stale or event.
fn type_lines(view: &View, now: Instant) -> Vec<String> {
    let mut l = vec![format!(
        "messages   {:<12} {:>4} {:>8} {:>15} {:>15}  state",
        "type", "id", "count", "interval (box)", "interval (host)"
    )];
    let ms = |v: Option<f64>| v.map_or_else(|| "-".to_string(), |v| format!("{v:.1} ms"));
    for (id, (name, a)) in &view.types {
        let state = if EVENTS.contains(id) {
            let age = now.saturating_duration_since(a.last_host);
            format!("event {:.0} s ago", age.as_secs_f64())
        } else {
            match a.stale(now) {
                Some(age) => format!("STALE, last {:.1} s ago", age.as_secs_f64()),
                None => "live".to_string(),
            }
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
    l
}

fn errors_line(view: &View, stats: &aeolus_proto::Stats) -> String {
    format!(
        "errors     crc {}  no-crc frames {}  overflows {}  too short {}  bad escapes {}  \
         malformed {}  truncated {}  bytes discarded {}",
        stats.checksum_errors,
        stats.frames_no_crc,
        stats.overflows,
        stats.too_short,
        stats.bad_escapes,
        view.malformed,
        view.truncated,
        stats.bytes_discarded
    )
}

fn valid(v: bool) -> &'static str {
    if v { "" } else { "  (invalid)" }
}

/// Runs `protolink watch`.
///
/// # Errors
/// Opening or reading the endpoint, or writing the output.
pub(crate) fn run(args: &WatchArgs) -> Result<()> {
    let mut link = args.from.open()?;
    stop::install_ctrl_c();
    let deadline = Deadline::after(args.seconds);
    let tty = !args.plain && std::io::stdout().is_terminal();
    let refresh = if tty { TTY_REFRESH } else { PLAIN_REFRESH };
    let mut out = Out::new();
    let mut view = View {
        units: args.units,
        ..View::default()
    };
    let mut decoder = Box::new(Decoder::<AEOLUS_CAPACITY>::new());
    let mut buf = vec![0u8; 65_536];
    let started = Instant::now();
    let mut next_draw = started + refresh;
    let source = link.name().to_string();
    let draw =
        |out: &mut Out, view: &View, stats: &aeolus_proto::Stats, last: bool| -> Result<()> {
            let text = lines(view, &source, started.elapsed(), Instant::now(), stats);
            if tty {
                // Home, then each line cleared to its end, then everything below cleared.
                out.raw("\x1b[H")?;
                for line in &text {
                    out.raw(line)?;
                    out.raw("\x1b[K\n")?;
                }
                out.raw("\x1b[J")?;
                if last {
                    out.line("(stopped)")?;
                }
            } else {
                for line in &text {
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
