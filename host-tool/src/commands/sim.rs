//! `protolink sim`: a virtual AEOLUS-SENSE box on UDP, for app developers without hardware.
//!
//! It is not a second implementation of the box: [`Sim`] runs the firmware's own AEOLUS link
//! ([`sensor_box::aeolus_link::AeolusLink`]), with the same telemetry schedule, the
//! same simulated flight ([`flight_sim`]) and the same command handling, over a port whose
//! output is cut into datagrams at the frame flags and whose input is the datagrams received
//! on the in-port. So the rates (spec figure 1c), the messages, the answers to COMMAND
//! (`a pause`, `a resume`, `a reboot`, TOAST `unknown command: ...`) and the SETTIME handling
//! are the firmware's, by construction.
//!
//! [`run`] adds the sockets and a millisecond clock: the link is polled once per millisecond
//! of wall time, and the frames it produces go out through a [`Packer`] (one frame per
//! datagram by default, `--pack N` to pack).
//!
//! One thing is the host's, not the firmware's: a GPS outage (`--gps-outage FROM..TO`,
//! [`Sim::gps_outage`]). The box always has a fix, so the sim rewrites the GPS frames the link
//! sends inside the window, re-encoded as a receiver without a fix reports it.

use std::collections::VecDeque;
use std::convert::Infallible;
use std::io::{self, IsTerminal, Write as _};
use std::ops::Range;
use std::time::{Duration, Instant};

use aeolus_proto::message::{Gps, Message};
use aeolus_proto::{CrcMode, FLAG, decode_datagram, max_encoded_len};
use clap::Args;
use embedded_io::{ErrorType, Write, WriteReady};
use sensor_box::aeolus_link::{AeolusLink, LinkCounters};
use sensor_box::port::{Receive, Transmit};
use sensor_box::telemetry::Kind;
use sensor_box::{Persisted, Settings, Shared};
use serde_json::{Map, Value, json};

use crate::datagrams::{Packer, UdpArgs, receive_some};
use crate::error::{Error, Result};
use crate::render::{Out, text, to_json};
use crate::stop::{self, Deadline};

/// Arguments of `protolink sim`.
#[derive(Debug, Clone, Args)]
pub(crate) struct SimArgs {
    /// The UDP side: telemetry out, COMMAND and SETTIME in.
    #[command(flatten)]
    pub(crate) udp: UdpArgs,
    /// Simulated true airspeed, m/s (10..=150, the box's own range; the firmware's default
    /// otherwise).
    // The box's range (AYDP 0x0110): its simulated wind blows at 5 m/s, and the flight needs
    // an airspeed above the wind, so the flight model's own floor (5 m/s) cannot be flown.
    #[arg(long, value_name = "M/S", value_parser = |t: &str| crate::args::number_in(t, 10.0, 150.0, "m/s"))]
    pub(crate) airspeed: Option<f32>,
    /// Simulated bank angle, degrees (-60..=60; positive turns right).
    #[arg(long, value_name = "DEG", allow_negative_numbers = true,
          value_parser = |t: &str| crate::args::number_in(t, -60.0, 60.0, "degrees"))]
    pub(crate) bank: Option<f32>,
    /// Simulated altitude, m (the ISA troposphere: -500..=11000).
    #[arg(long, value_name = "M", allow_negative_numbers = true,
          value_parser = |t: &str| crate::args::number_in(t, -500.0, 11000.0, "m"))]
    pub(crate) altitude: Option<f32>,
    /// Simulated vertical speed, m/s, positive up (at most half the airspeed): the box climbs
    /// or descends at this rate to the edge of the ISA troposphere (11000 m, -500 m), then
    /// flies level (default 0: level).
    #[arg(long, value_name = "M/S", allow_negative_numbers = true,
          value_parser = |t: &str| crate::args::number_in(t, -75.0, 75.0, "m/s"))]
    pub(crate) climb: Option<f32>,
    /// A GPS outage from FROM to TO seconds after the sim starts (`4..8`; 0..=86400, FROM
    /// before TO; a reboot does not restart this clock): every GPS message in the window says
    /// "no fix" (still valid, 0 satellites, position, altitude and ground speed zero).
    #[arg(long, value_name = "FROM..TO", allow_hyphen_values = true,
          value_parser = crate::args::time_window)]
    pub(crate) gps_outage: Option<Range<Duration>>,
    /// Stop after this long: `10` (seconds), `500ms`, `2min` (default: on Ctrl-C).
    #[arg(long, value_name = "DURATION", value_parser = crate::args::run_time)]
    pub(crate) seconds: Option<std::time::Duration>,
}

impl SimArgs {
    /// The firmware's default settings with the flight options applied.
    ///
    /// # Errors
    /// A flight option out of range, as one sentence.
    pub(crate) fn settings(&self) -> Result<Settings> {
        let mut s = Settings::default();
        if let Some(v) = self.airspeed {
            s.airspeed_mps = v;
        }
        if let Some(v) = self.bank {
            s.bank_deg = v;
        }
        if let Some(v) = self.altitude {
            s.altitude_m = v;
        }
        let climb = flight_sim::FlightParams {
            climb_mps: self.climb.unwrap_or(0.0),
            ..s.flight_params()
        };
        flight_sim::Flight::new(climb)
            .map_err(|e| Error::Usage(format!("cannot simulate that flight: {e}")))?;
        Ok(s)
    }
}

/// A serial port for the AEOLUS link whose output is cut into frames at the flags, and whose
/// input is whatever datagrams were received.
#[derive(Debug, Default)]
struct DatagramPort {
    rx: VecDeque<u8>,
    frame: Vec<u8>,
    in_frame: bool,
    frames: Vec<Vec<u8>>,
}

impl ErrorType for DatagramPort {
    type Error = Infallible;
}

impl Receive for DatagramPort {
    /// What was received, lent in place (the queue made contiguous first).
    fn receive(
        &mut self,
        take: impl FnOnce(&[u8]) -> usize,
    ) -> std::result::Result<usize, Infallible> {
        if self.rx.is_empty() {
            return Ok(0);
        }
        let bytes = self.rx.make_contiguous();
        let n = take(bytes).min(bytes.len());
        self.rx.drain(..n);
        Ok(n)
    }
}

/// No buffer to lend: the link queues its telemetry and writes it (a datagram is cut at the
/// flags as the bytes arrive, whichever way they come).
impl Transmit for DatagramPort {}

impl WriteReady for DatagramPort {
    fn write_ready(&mut self) -> std::result::Result<bool, Infallible> {
        Ok(true)
    }
}

impl Write for DatagramPort {
    fn write(&mut self, bytes: &[u8]) -> std::result::Result<usize, Infallible> {
        for &byte in bytes {
            self.push(byte);
        }
        Ok(bytes.len())
    }

    fn flush(&mut self) -> std::result::Result<(), Infallible> {
        Ok(())
    }
}

impl DatagramPort {
    /// Cuts the output into frames at the flags.
    fn push(&mut self, byte: u8) {
        // The link writes whole frames, each with its opening and closing flag, and escapes
        // every 0x7E inside: so flags alternate between opening and closing.
        if byte == FLAG {
            if self.in_frame {
                self.frame.push(byte);
                self.frames.push(std::mem::take(&mut self.frame));
            } else {
                self.frame.clear();
                self.frame.push(byte);
            }
            self.in_frame = !self.in_frame;
        } else if self.in_frame {
            self.frame.push(byte);
        }
    }
}

/// The virtual box: the firmware's AEOLUS link and shared state, without sockets or clock.
pub(crate) struct Sim {
    shared: Shared,
    link: AeolusLink,
    port: DatagramPort,
    /// Counters of the links that ended in a reboot, summed.
    before_reboots: LinkCounters,
    reboots: u32,
    dropped: u64,
    /// The vertical speed the flight adds to the settings' level turn, m/s.
    climb_mps: f32,
    /// When the sim started (the `now_ms` of [`Sim::new`]; a reboot keeps it).
    started_ms: u64,
    /// Milliseconds after the start during which GPS frames say "no fix".
    gps_outage_ms: Option<Range<u64>>,
}

/// Bytes the virtual box holds for its link to read (the link reads up to
/// `aeolus_link::RX_BUDGET` per millisecond poll).
pub(crate) const RX_QUEUE: usize = 4 * sensor_box::aeolus_link::RX_BUDGET;

impl Sim {
    /// A box booting at `now_ms` with `settings` (its TOAST "AEOLUS on" goes out first).
    pub(crate) fn new(settings: Settings, now_ms: u64) -> Self {
        let persisted = Persisted {
            settings,
            ..Persisted::default()
        };
        Sim {
            shared: Shared::new(persisted, now_ms),
            link: AeolusLink::new(now_ms),
            port: DatagramPort::default(),
            before_reboots: LinkCounters::default(),
            reboots: 0,
            dropped: 0,
            climb_mps: 0.0,
            started_ms: now_ms,
            gps_outage_ms: None,
        }
    }

    /// The same box with a GPS outage from `window_ms.start` to `window_ms.end` milliseconds
    /// after the sim started (the `now_ms` of [`Sim::new`]; a reboot does not restart this
    /// clock). Every GPS frame [`Sim::poll`] sends in the window says what a working receiver
    /// without a fix says: still `valid`, `has_fix` false, 0 satellites, and position,
    /// altitude and ground speed zero (its timestamp stays). The box itself always has a fix,
    /// so the sim rewrites its frames; the firmware knows no outage.
    #[must_use]
    pub(crate) fn gps_outage(mut self, window_ms: Range<u64>) -> Self {
        self.gps_outage_ms = Some(window_ms);
        self
    }

    /// The same box climbing (or descending, `climb_mps` < 0) from its settings' altitude at
    /// `climb_mps` m/s; a reboot starts the climb again. The box's settings (and AYDP) know
    /// no climb: only the simulated flight changes.
    ///
    /// # Errors
    /// The climb is steeper than the flight allows (more than half the airspeed).
    pub(crate) fn climbing(mut self, climb_mps: f32) -> Result<Self> {
        self.climb_mps = climb_mps;
        self.apply_climb()?;
        Ok(self)
    }

    /// The flight the box simulates.
    #[cfg(test)]
    pub(crate) fn flight(&self) -> &flight_sim::Flight {
        &self.shared.flight
    }

    fn apply_climb(&mut self) -> Result<()> {
        if self.climb_mps == 0.0 {
            return Ok(());
        }
        let params = flight_sim::FlightParams {
            climb_mps: self.climb_mps,
            ..self.shared.settings().flight_params()
        };
        self.shared.flight = flight_sim::Flight::new(params)
            .map_err(|e| Error::Usage(format!("cannot simulate that flight: {e}")))?;
        Ok(())
    }

    /// Hands the box one received datagram (one or more frames; anything else is counted by
    /// its decoder and ignored). A datagram that does not fit whole into the box's receive
    /// queue ([`RX_QUEUE`] bytes, about four of the box's polls) is dropped and counted, as a
    /// real box's full UART FIFO would drop it; returns whether it was taken.
    pub(crate) fn receive(&mut self, datagram: &[u8]) -> bool {
        if self.port.rx.len() + datagram.len() > RX_QUEUE {
            self.dropped = self.dropped.wrapping_add(1);
            return false;
        }
        self.port.rx.extend(datagram);
        true
    }

    /// Runs the box at `now_ms`: acts on what was received, and hands each frame it sends
    /// (escaped, flags included) to `send`. A `a reboot` command restarts the box, which
    /// keeps its settings and starts again with its boot TOAST. In a GPS outage
    /// ([`Sim::gps_outage`]) its GPS frames go out without a fix.
    pub(crate) fn poll(&mut self, now_ms: u64, mut send: impl FnMut(&[u8])) {
        self.link.poll(now_ms, &mut self.port, &mut self.shared);
        let outage = self
            .gps_outage_ms
            .as_ref()
            .is_some_and(|w| w.contains(&now_ms.saturating_sub(self.started_ms)));
        for frame in self.port.frames.drain(..) {
            match outage.then(|| without_fix(&frame)).flatten() {
                Some(rewritten) => send(&rewritten),
                None => send(&frame),
            }
        }
        if std::mem::take(&mut self.shared.requests.reboot) {
            add_counters(&mut self.before_reboots, self.link.counters());
            self.reboots += 1;
            let persisted = self.shared.persisted.clone();
            self.shared = Shared::new(persisted, now_ms);
            // Valid when the sim was built, and a reboot keeps the settings.
            let _ = self.apply_climb();
            self.link = AeolusLink::new(now_ms);
            self.port.rx.clear();
        }
    }

    /// Whether telemetry is paused ("a pause").
    pub(crate) fn paused(&self) -> bool {
        self.shared.paused
    }

    /// The link's counters since the sim started (across reboots).
    pub(crate) fn counters(&self) -> LinkCounters {
        let mut all = self.before_reboots;
        add_counters(&mut all, self.link.counters());
        all
    }

    /// How often the box rebooted.
    pub(crate) fn reboots(&self) -> u32 {
        self.reboots
    }

    /// The counters as JSON: per-kind telemetry, TOASTs, commands, SETTIMEs, reboots.
    pub(crate) fn counters_json(&self) -> Value {
        let c = self.counters();
        let mut sent = Map::new();
        for kind in Kind::ALL {
            let n = c.sent.get(kind.index()).copied().unwrap_or(0);
            sent.insert(kind.name().to_owned(), json!(n));
        }
        json!({
            "telemetry": c.telemetry_total(),
            "per_type": sent,
            "toasts": c.toasts,
            "commands": c.commands,
            "unknown_commands": c.unknown_commands,
            "refused_in_flight": c.refused_in_flight,
            "settime": c.settime,
            "settime_rejected": c.settime_rejected,
            "rx_errors": c.rx_errors,
            "malformed": c.malformed,
            "reboots": self.reboots,
            "datagrams_dropped": self.dropped,
        })
    }
}

/// A GPS frame (escaped, flags included) as a receiver without a fix sends it: still valid,
/// no fix, 0 satellites, position, altitude and ground speed zero, the same timestamp;
/// `None` for any other frame, which goes out unchanged.
fn without_fix(frame: &[u8]) -> Option<Vec<u8>> {
    // The ID follows the opening flag; GPS's (66) is never escaped, so other frames stop here.
    if frame.get(1) != Some(&Gps::ID) {
        return None;
    }
    let mut unescaped = frame.to_vec();
    let decoded = decode_datagram(&mut unescaped, true).next()?.ok()?;
    let Ok(Message::Gps(g)) = decoded.message() else {
        return None;
    };
    let no_fix = Gps {
        has_fix: false,
        satellites: 0,
        latitude_deg: 0.0,
        longitude_deg: 0.0,
        altitude_m: 0.0,
        ground_speed_mps: 0.0,
        ..g
    };
    let mut out = vec![0u8; max_encoded_len(Gps::LEN)];
    let n = Message::Gps(no_fix)
        .encode(&mut out, CrcMode::Compute)
        .ok()?;
    out.truncate(n);
    Some(out)
}

fn add_counters(into: &mut LinkCounters, c: &LinkCounters) {
    for (a, b) in into.sent.iter_mut().zip(c.sent) {
        *a = a.wrapping_add(b);
    }
    let pairs = [
        (&mut into.toasts, c.toasts),
        (&mut into.tx_dropped, c.tx_dropped),
        (&mut into.commands, c.commands),
        (&mut into.refused_in_flight, c.refused_in_flight),
        (&mut into.unknown_commands, c.unknown_commands),
        (&mut into.settime, c.settime),
        (&mut into.settime_rejected, c.settime_rejected),
        (&mut into.ignored, c.ignored),
        (&mut into.malformed, c.malformed),
        (&mut into.rx_errors, c.rx_errors),
        (&mut into.port_errors, c.port_errors),
    ];
    for (a, b) in pairs {
        *a = a.wrapping_add(b);
    }
}

/// How far behind the millisecond clock the loop may fall before it stops catching up (after
/// the process was suspended, say): the firmware's schedule drops what it missed anyway.
const MAX_BEHIND: Duration = Duration::from_millis(50);

/// Runs `protolink sim`.
///
/// # Errors
/// A flight option out of range, the sockets cannot be opened, the output fails, or every
/// datagram's send failed.
pub(crate) fn run(args: &SimArgs) -> Result<()> {
    let settings = args.settings()?;
    let (mut packer, in_socket) = args.udp.open()?;
    let to = packer.destination();
    let _ = writeln!(
        io::stderr(),
        "sim: AEOLUS-SENSE box, telemetry -> udp {to}, commands <- udp {} (Ctrl-C to stop)",
        args.udp.udp_in
    );
    stop::install_ctrl_c();
    let deadline = Deadline::after(args.seconds);
    let start = Instant::now();
    let mut sim = Sim::new(settings, 0).climbing(args.climb.unwrap_or(0.0))?;
    if let Some(w) = &args.gps_outage {
        let ms = |d: Duration| u64::try_from(d.as_millis()).unwrap_or(u64::MAX);
        sim = sim.gps_outage(ms(w.start)..ms(w.end));
        let _ = writeln!(
            io::stderr(),
            "sim: GPS outage from {} to {} after the start (no fix)",
            crate::args::show(w.start),
            crate::args::show(w.end)
        );
    }
    let mut datagram = vec![0u8; 65_536];
    let mut received = 0u64;
    let mut status = Status::new();
    let mut next = start;
    while !deadline.reached() {
        receive_some(&in_socket, &mut datagram, |d| {
            received += 1;
            sim.receive(d);
        })?;
        let now_ms = u64::try_from(start.elapsed().as_millis()).unwrap_or(u64::MAX);
        sim.poll(now_ms, |wire| packer.push(wire));
        packer.poll();
        status.show(&sim, &packer, received);
        next += Duration::from_millis(1);
        let now = Instant::now();
        if next > now {
            std::thread::sleep(next - now);
        } else if now - next > MAX_BEHIND {
            next = now;
        }
    }
    packer.flush();
    status.clear();
    let mut out = Out::new();
    let mut summary = sim.counters_json();
    if let Value::Object(map) = &mut summary {
        map.insert("datagrams_sent".into(), json!(packer.counters().datagrams));
        map.insert("send_errors".into(), json!(packer.counters().errors));
        map.insert("datagrams_received".into(), json!(received));
    }
    out.line(&format!("sim: {}", text(&summary)))?;
    out.line(&format!(
        "sim decoder: {}",
        text(&to_json(&sim.link.rx_stats()))
    ))?;
    out.flush()?;
    packer.check()
}

/// The progress line on stderr: refreshed in place every second on a terminal, a line every
/// ten seconds otherwise.
struct Status {
    tty: bool,
    last: Instant,
    started: Instant,
    shown: bool,
}

impl Status {
    fn new() -> Self {
        let now = Instant::now();
        Status {
            tty: io::stderr().is_terminal(),
            last: now,
            started: now,
            shown: false,
        }
    }

    fn show(&mut self, sim: &Sim, packer: &Packer, received: u64) {
        let every = if self.tty {
            Duration::from_secs(1)
        } else {
            Duration::from_secs(10)
        };
        if self.last.elapsed() < every {
            return;
        }
        self.last = Instant::now();
        let c = sim.counters();
        let line = format!(
            "sim {:.0} s: {} telemetry frames in {} datagrams, {} datagrams in, {}{}",
            self.started.elapsed().as_secs_f64(),
            c.telemetry_total(),
            packer.counters().datagrams,
            received,
            if sim.paused() { "paused" } else { "running" },
            match sim.reboots() {
                0 => String::new(),
                n => format!(", {n} reboots"),
            }
        );
        let mut err = io::stderr().lock();
        let _ = if self.tty {
            write!(err, "\r\x1b[2K{line}")
        } else {
            writeln!(err, "{line}")
        };
        let _ = err.flush();
        self.shown = true;
    }

    fn clear(&self) {
        if self.tty && self.shown {
            let _ = write!(io::stderr(), "\r\x1b[2K");
        }
    }
}

#[cfg(test)]
mod tests {
    use aeolus_proto::message::{Message, Text};
    use aeolus_proto::{CrcMode, decode_datagram};
    use sensor_box::Settings;

    use crate::commands::sim::Sim;

    /// The GPS frames `sim` sends from `from_ms` to `to_ms`: (poll time, has a fix).
    fn gps_fixes(sim: &mut Sim, from_ms: u64, to_ms: u64) -> Vec<(u64, bool)> {
        let mut gps = Vec::new();
        for now_ms in from_ms..to_ms {
            sim.poll(now_ms, |wire| {
                let mut frame = wire.to_vec();
                if let Some(Ok(f)) = decode_datagram(&mut frame, true).next()
                    && let Ok(Message::Gps(g)) = f.message()
                {
                    gps.push((now_ms, g.has_fix));
                }
            });
        }
        gps
    }

    /// The outage's clock is the sim's, from the `now_ms` it started at: a reboot in the
    /// middle (which restarts the box's own clock) neither ends nor moves the window.
    #[test]
    fn a_reboot_keeps_the_outage_window_on_the_sims_clock() {
        let mut sim = Sim::new(Settings::default(), 10_000).gps_outage(1_000..3_000);
        let mut gps = gps_fixes(&mut sim, 10_000, 11_500);
        // Landed ("a pause"), as the box obeys a reboot only then.
        for command in ["a pause", "a reboot"] {
            let mut frame = [0u8; 32];
            let n = Message::Command(Text::new(command).unwrap())
                .encode(&mut frame, CrcMode::Compute)
                .unwrap();
            assert!(sim.receive(&frame[..n]));
        }
        gps.extend(gps_fixes(&mut sim, 11_500, 14_000));
        assert_eq!(sim.reboots(), 1);
        let in_window = |now_ms: u64| (11_000..13_000).contains(&now_ms);
        for &(now_ms, has_fix) in &gps {
            assert_eq!(has_fix, !in_window(now_ms), "GPS at {now_ms} ms");
        }
        // GPS every 92 ms, on both sides of the reboot.
        let inside = gps.iter().filter(|g| in_window(g.0)).count();
        assert!(inside >= 15 && gps.len() - inside >= 20, "{gps:?}");
    }
}

/// The examples of this module's items, as tests (the items are crate-private, so rustdoc
/// does not run them).
#[cfg(test)]
#[allow(unused_imports, clippy::unnecessary_wraps)]
mod examples {
    use super::*;

    #[test]
    fn sim_example() -> Result<(), Box<dyn std::error::Error>> {
        use aeolus_proto::{
            CrcMode, decode_datagram,
            message::{Message, Text},
        };
        use sensor_box::Settings;

        let mut sim = Sim::new(Settings::default(), 0);
        let mut frames = Vec::new();
        for now_ms in 0..1_000 {
            sim.poll(now_ms, |wire| frames.push(wire.to_vec()));
        }
        // The boot TOAST, then one second at the spec rates (as the firmware sends them).
        assert_eq!(frames.len(), 1 + 5 * 143 + 200 + 11 + 2 + 1 + 1);

        // "a pause" arrives as a datagram: the box answers and telemetry stops.
        let mut datagram = [0u8; 32];
        let n = Message::Command(Text::new("a pause").unwrap())
            .encode(&mut datagram, CrcMode::Compute)
            .unwrap();
        sim.receive(&datagram[..n]);
        frames.clear();
        for now_ms in 1_000..1_500 {
            sim.poll(now_ms, |wire| frames.push(wire.to_vec()));
        }
        assert_eq!(frames.len(), 1);
        let frame = decode_datagram(&mut frames[0], true)
            .next()
            .unwrap()
            .unwrap();
        match frame.message() {
            Ok(Message::Toast(t)) => assert_eq!(t.as_bytes(), b"AEOLUS paused"),
            other => panic!("{other:?}"),
        }
        Ok(())
    }

    #[test]
    fn gps_outage_example() -> Result<(), Box<dyn std::error::Error>> {
        use aeolus_proto::{decode_datagram, message::Message};

        let mut sim = Sim::new(sensor_box::Settings::default(), 0).gps_outage(1_000..2_000);
        // (time after the start, has a fix, satellites, latitude) of every GPS frame in 3 s.
        let mut gps = Vec::new();
        for now_ms in 0..3_000 {
            sim.poll(now_ms, |wire| {
                let mut frame = wire.to_vec();
                let f = decode_datagram(&mut frame, true).next().unwrap().unwrap();
                if let Ok(Message::Gps(g)) = f.message() {
                    assert!(g.valid, "the receiver works, fix or not");
                    gps.push((now_ms, g.has_fix, g.satellites, g.latitude_deg));
                }
            });
        }
        let mut inside = 0;
        for &(now_ms, has_fix, satellites, latitude) in &gps {
            if (1_000..2_000).contains(&now_ms) {
                inside += 1;
                assert!(
                    !has_fix && satellites == 0 && latitude == 0.0,
                    "no fix at {now_ms} ms"
                );
            } else {
                assert!(
                    has_fix && satellites > 0 && latitude != 0.0,
                    "a fix at {now_ms} ms"
                );
            }
        }
        // GPS every 92 ms: about 10 frames in the window and 20 outside it.
        assert!(inside >= 10 && gps.len() - inside >= 20);
        Ok(())
    }

    #[test]
    fn climbing_example() -> Result<(), Box<dyn std::error::Error>> {
        let sim = Sim::new(sensor_box::Settings::default(), 0).climbing(2.5)?;
        assert_eq!(sim.flight().altitude_m(60_000), 1150.0);
        Ok(())
    }
}
