//! AOK on UART2: the flight-controller side of the AOK protocol.
//!
//! [`AokLink::poll`] reads the commands the PC sends (through `aok_proto`'s [`CommandDecoder`]),
//! answers them, and sends the debug value stream. Nothing in it blocks: replies go into a
//! small TX queue of [`TX_CAPACITY`] bytes which is handed to the port with non-blocking
//! writes of slices, and a debug frame is only built when that queue is empty, so a reply never waits
//! behind more than one debug frame.
//!
//! What the link holds:
//! - the RAM parameters ([`AOK_PARAMS`] of them, loaded at boot from the start set in flash);
//! - the RAM waypoints (slots 0..=30, 254 POI and 255 FBC target; slot 31, the mission POI,
//!   lives in the flash record [`AokFlash::waypoints`](super::state::AokFlash));
//! - the motor-test outputs (held [`MOTOR_LAPSE_MS`] after the last frame) and the
//!   external-control sticks with their expiry.
//!
//! The parameter sets, the start set and the flash waypoints are in [`Shared::persisted`];
//! commands that change them set `shared.requests.store` and the [`App`](super::App) writes
//! the flash. The crate README (section "UART2: AOK") lists every protocol decision.
//!
//! The link is in rooms: this file holds its state, `poll` and the TX queue; `dispatch`
//! decodes and answers each command (one `match`, the short answers inline); `params` (reading
//! and setting one parameter), `waypoints` (the slots, loading them from flash) and `control`
//! (motor test, external control and their expiry) hold the rest of each family; `debug` is
//! the debug value stream.
//!
//! ```
//! use sensor_box::{Persisted, Shared, aok_link::{AokLink, DebugId, GAP_MS}};
//! use sensor_box::serial::{PortStats, QueuedSerial};
//! use sensor_box::serial::Ring;
//!
//! let shared = &mut Shared::new(Persisted::default(), 0);
//! let mut link = AokLink::new(shared);
//! let (rxq, txq) = (Ring::<64>::new(), Ring::<64>::new());
//! let stats = PortStats::new();
//! let (mut port, mut isr) = QueuedSerial::split(&rxq, &txq, &stats, || {});
//! // Debug is on at boot: the first poll sends the first value of the cycle (roll).
//! link.poll(0, &mut port, shared);
//! let frame: Vec<u8> = core::iter::from_fn(|| isr.next_to_send()).collect();
//! assert_eq!(frame.len(), 7);
//! assert_eq!(&frame[..2], &[0x1c, DebugId::Roll as u8]);
//! // Debug off and read parameter 3, in one write as a PC sends them: obeyed once the line
//! // has been silent for GAP_MS, and answered with the >= 0.31 reply `FF 03 B1..B4 CRC`.
//! for b in [0x63, 0x01, 0x67, 0x03] {
//!     isr.received(b);
//! }
//! link.poll(1, &mut port, shared);
//! assert_eq!(isr.next_to_send(), None); // the burst may not be over yet
//! assert_eq!(link.next_wake_ms(), 1 + GAP_MS); // when silence can be observed
//! link.poll(1 + GAP_MS, &mut port, shared);
//! let reply: Vec<u8> = core::iter::from_fn(|| isr.next_to_send()).collect();
//! assert_eq!(reply, [0xff, 0x03, 0, 0, 0, 0, 0]);
//! // Noise: a `63 07` (reset) behind a stray byte is never obeyed.
//! for b in [0x00, 0x63, 0x07] {
//!     isr.received(b);
//! }
//! link.poll(10, &mut port, shared);
//! link.poll(10 + GAP_MS, &mut port, shared);
//! assert!(!shared.requests.reboot);
//! assert_eq!(link.counters().bursts_discarded, 1);
//! ```

mod control;
mod debug;
mod dispatch;
mod params;
mod waypoints;

pub use debug::{DebugId, STATUS_EXTERNAL, STATUS_FLYING, STATUS_MOTOR_TEST};

use crate::Shared;
use crate::port::{Receive, TxQueue};
use crate::state::{AOK_FLASH_WAYPOINTS, AOK_PARAMS, StoredWaypoint};
use aok_proto::message::HEADED_REPLY_LEN;
use aok_proto::{Ack, Command, CommandDecoder, ExternalControl, FirmwareVersion, Stats, Stream};
use embedded_io::{Write, WriteReady};

/// The AOK firmware version this box claims: 0.35, so parameter replies use the headed
/// (>= 0.31) form `FF NUM B1..B4 CRC` and bulk read (`47`, >= 0.35) is supported.
pub const FIRMWARE: FirmwareVersion = FirmwareVersion::new(0, 35);
const _: () = assert!(FIRMWARE.has_bulk_read());

/// A motor-test value lapses (back to 0) this long after the last frame for that motor.
pub const MOTOR_LAPSE_MS: u64 = 500;
/// Number of motors the test command addresses (`31..39`, `41..43`).
pub const MOTORS: usize = 12;
/// RAM waypoint slots 0..=30 (waypoints 1..=31).
pub const RAM_WAYPOINTS: usize = 31;
/// Index of the mission POI (wire slot 31) in the flash waypoints.
pub const MISSION_POI: usize = AOK_FLASH_WAYPOINTS - 1;
/// Parameters that may be set while flying: bit `n` set = parameter `n` is "in-flight"
/// settable. Parameters 0..=15 are (tuning values); 16..=31 are not (configuration).
pub const IN_FLIGHT_PARAMS: u32 = 0x0000_ffff;
/// Silence that ends a burst, ms: a poll observes it when, after receiving, the port is empty
/// and no byte has been taken for `GAP_MS` (the poll times are whole milliseconds, so two of
/// them guarantee more than 1 ms of true silence, over 3.5 characters at 38 400 Bd 8N1, which
/// last 0.91 ms: Modbus RTU's inter-frame gap). See [`AokLink`], "Framing".
pub const GAP_MS: u64 = 2;
/// Most commands one burst may carry and still be obeyed (a PC writes one command at a time;
/// a burst with more is discarded whole and counted in [`AokCounters::bursts_discarded`]).
pub const BURST_COMMANDS: usize = 4;
/// Capacity of the link's own TX queue, in bytes: one bulk reply (112 bytes) plus room.
pub const TX_CAPACITY: usize = 128;
/// The longest reply one command produces: the 16 frames of a bulk read.
const MAX_REPLY: usize = HEADED_REPLY_LEN * 16;
/// At most this many received bytes are read from the port per poll, so one poll stays short.
pub const RX_BUDGET: usize = 64;

/// Who steers the (simulated) aircraft.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(all(feature = "defmt", target_os = "none"), derive(defmt::Format))]
pub enum ControlSource {
    /// The RC transmitter (the default, and after external control expires).
    Rc,
    /// External control (`53` frames) until its expiry runs out.
    External,
}

/// "Flying", for the in-flight checks and the flight status: the simulated flight runs and
/// AEOLUS telemetry is not paused ("a pause" lands the box).
pub fn flying(shared: &Shared) -> bool {
    !shared.paused
}

/// Is parameter `number` settable while flying ([`IN_FLIGHT_PARAMS`])?
pub const fn in_flight_settable(number: u8) -> bool {
    match IN_FLIGHT_PARAMS.checked_shr(number as u32) {
        Some(bits) => bits & 1 == 1,
        None => false,
    }
}

/// The link's own counters (the decoder's are in [`AokLink::decoder_stats`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(all(feature = "defmt", target_os = "none"), derive(defmt::Format))]
pub struct AokCounters {
    /// 'E' acks sent (bad checksum, invalid waypoint slot, unknown parameter or set number).
    pub rejected: u32,
    /// Commands refused because the box is flying ('I' sent, or motor test ignored).
    pub refused_in_flight: u32,
    /// Replies dropped because the TX queue was full.
    pub replies_dropped: u32,
    /// Debug frames queued.
    pub debug_frames: u32,
    /// Frames the decoder dropped: every `Err` event (bad checksum, invalid slot or stick
    /// value, a frame cut by a quiet line; see [`crate::port`], "Receive errors").
    pub rx_errors: u32,
    /// Errors reported by the port itself, on either side.
    pub port_errors: u32,
    /// Bursts received but not obeyed: not framed by silence as a PC sends a command (garbage
    /// skipped, a decode error, a frame cut short, a line fault, or more than
    /// [`BURST_COMMANDS`] commands).
    pub bursts_discarded: u32,
    /// Line faults the port reported ([`Receive::receive_faults`]: UART receive errors,
    /// bytes dropped); each spoils the burst it falls in.
    pub line_faults: u32,
    /// Motor-test frames that armed a motor without driving it: the first frame for a motor
    /// at rest (it runs from the second, see [`AokLink`], "Motor test").
    pub motor_frames_armed: u32,
}

#[derive(Debug, Clone, Copy, Default)]
struct MotorOutput {
    value: u8,
    until_ms: u64,
    /// A first frame for this motor at rest arms it until this instant (0: not armed).
    armed_until_ms: u64,
    /// The burst ([`AokLink`]'s `bursts_obeyed`) whose frame armed it.
    armed_burst: u32,
}

#[derive(Debug, Clone, Copy)]
struct External {
    control: ExternalControl,
    until_ms: u64,
}

/// The AOK link.
///
/// # Framing
///
/// AOK's `63` commands carry no checksum and the others an 8-bit XOR, and the decoder rescans
/// every byte after a failed frame, so line noise holds commands (a reset every 15 s or so of
/// random bytes at 38 400 Bd). The link therefore obeys a command only as a PC sends it: in a
/// *burst* of bytes framed by silence before and after (Modbus RTU's 3.5-character gap).
/// Every command the decoder finds goes into the burst's buffer (at most [`BURST_COMMANDS`]);
/// when a poll observes [`GAP_MS`] of silence, the burst is obeyed, in order, only if it
/// decoded cleanly: every byte part of a command, no decode error, nothing left half-held, at
/// most [`BURST_COMMANDS`] commands. Otherwise it is discarded whole
/// ([`AokCounters::bursts_discarded`]; one 'E' if a checksum or a waypoint slot was bad).
/// Silence is observed, never inferred: the port is empty after the poll's receive and no byte
/// was taken for [`GAP_MS`], so a main loop that stalls and then finds many bytes at once
/// sees no gap, nor do bytes left in the port by [`RX_BUDGET`]; there the gap is where the
/// UART handler saw it by its own clock, if its board tells it the time ([`crate::burst_marks`]:
/// commands that waited in the ring through a store stall are obeyed one by one). Reads go
/// through the gate too.
/// The reply comes about [`GAP_MS`] after the command ([`AokLink::next_wake_ms`] wakes the
/// poll for it).
///
/// A line fault (a UART receive error or a dropped byte, [`Receive::receive_faults`]) is line
/// activity: it opens a burst if none is open and spoils it, so a command with a damaged or
/// lost byte, or one that follows a fault without silence between, is discarded.
///
/// # In flight
///
/// A command without a check of its own changes nothing in flight: every `63` command but
/// debug off/on (`63 01`, `63 02`) answers 'I' ([`AokCounters::refused_in_flight`]), so a
/// glitch or one flipped bit (`67 09` read as `63 09`) cannot reset the box, load or store
/// anything. The checked commands keep their own rules: `73` only for the in-flight
/// parameters, `77` for the RAM slots, `53` always, the motor test never.
///
/// # Motor test
///
/// A motor at rest runs only from the second valid frame for it, in a later burst within
/// [`MOTOR_LAPSE_MS`] of the first (a PC holding a test sends a frame every 200 ms or so);
/// the first frame arms it ([`AokCounters::motor_frames_armed`]). While it runs each frame
/// sets its value and holds it [`MOTOR_LAPSE_MS`] more; a frame with value 0 stops it at
/// once. A glitch, which is one burst, never starts a motor.
pub struct AokLink {
    decoder: Stream<CommandDecoder>,
    /// The commands of the burst being received, or of the accepted burst being obeyed.
    burst: heapless::Vec<Command, BURST_COMMANDS>,
    /// The next command of an accepted burst to obey, while one is being obeyed.
    obey_next: Option<u8>,
    /// Bytes were taken since the last silence observed.
    burst_open: bool,
    /// The open burst has decoded cleanly so far.
    burst_clean: bool,
    /// The decoder's `bytes_discarded` when the last burst ended.
    burst_discarded: u32,
    /// The open burst held a frame with a bad checksum or waypoint slot (answered 'E').
    burst_bad_check: bool,
    /// Bursts accepted and obeyed (wrapping): tells a motor-test frame from its repeat.
    bursts_obeyed: u32,
    /// The port's [`Receive::receive_faults`] at the last poll.
    faults_seen: u32,
    tx: TxQueue<TX_CAPACITY>,
    debug_on: bool,
    next_debug_ms: u64,
    debug_index: usize,
    last_rx_ms: u64,
    params: [i32; AOK_PARAMS],
    waypoints: [StoredWaypoint; RAM_WAYPOINTS],
    ram_poi: StoredWaypoint,
    fbc_target: StoredWaypoint,
    motors: [MotorOutput; MOTORS],
    external: Option<External>,
    /// When the next poll has something to do by the clock (a debug value, a motor-test
    /// lapse, external control's expiry, the end of a burst), from the last poll.
    wake_ms: u64,
    /// The last poll stopped at [`RX_BUDGET`]: bytes may be waiting in the port.
    rx_more: bool,
    counters: AokCounters,
}

impl AokLink {
    /// The link at boot: debug on, the parameters of the start set, the waypoints from flash
    /// (as `63 09` would load them: flash slot 31 into the RAM POI), FBC target 0/0.
    pub fn new(shared: &Shared) -> Self {
        let aok = &shared.persisted.aok;
        let params = match aok.sets.get(usize::from(aok.start_set)) {
            Some(set) => *set,
            None => {
                crate::warn!(
                    "AOK: start set {=u8} does not exist, parameters are 0",
                    aok.start_set
                );
                [0; AOK_PARAMS]
            }
        };
        let mut link = AokLink {
            decoder: Stream::new(CommandDecoder::new()),
            burst: heapless::Vec::new(),
            obey_next: None,
            burst_open: false,
            burst_clean: true,
            burst_discarded: 0,
            burst_bad_check: false,
            bursts_obeyed: 0,
            faults_seen: 0,
            tx: TxQueue::new(),
            debug_on: true,
            next_debug_ms: 0,
            debug_index: 0,
            last_rx_ms: 0,
            params,
            waypoints: [StoredWaypoint::default(); RAM_WAYPOINTS],
            ram_poi: StoredWaypoint::default(),
            fbc_target: StoredWaypoint::default(),
            motors: [MotorOutput::default(); MOTORS],
            external: None,
            wake_ms: 0,
            rx_more: false,
            counters: AokCounters::default(),
        };
        link.load_waypoints(shared);
        link
    }

    /// Reads what arrived on the port, answers, and sends what is due at `now_ms`.
    pub fn poll<P: Receive + Write + WriteReady>(
        &mut self,
        now_ms: u64,
        port: &mut P,
        shared: &mut Shared,
    ) {
        self.flush(port);
        self.receive(now_ms, port, shared);
        self.expire(now_ms);
        if self.debug_on && self.tx.is_empty() && now_ms >= self.next_debug_ms {
            self.send_debug(now_ms, shared);
        }
        self.flush(port);
        self.wake_ms = self.clock_wake_ms();
    }

    /// Whether a poll at `now_ms` has anything to do besides what the port received since the
    /// last one: something due by the clock, TX bytes waiting for room in the port, or
    /// received bytes left in the port by the last poll's [`RX_BUDGET`].
    ///
    /// ```
    /// use sensor_box::{Persisted, Shared, aok_link::AokLink};
    /// let link = AokLink::new(&Shared::new(Persisted::default(), 0));
    /// assert!(link.has_work(0)); // the first debug value
    /// ```
    pub fn has_work(&self, now_ms: u64) -> bool {
        now_ms >= self.next_wake_ms()
    }

    /// The earliest instant at which a poll has something to do without a received byte: 0
    /// (at once) while TX bytes wait for room in the port, received bytes wait that the last
    /// poll's [`RX_BUDGET`] left in the port, or commands of an accepted burst wait; else the
    /// earliest of its timers (the debug stream, the [`GAP_MS`] that ends a burst, a motor
    /// test's or an external control's end).
    ///
    /// ```
    /// use sensor_box::{Persisted, Shared, aok_link::AokLink};
    /// let link = AokLink::new(&Shared::new(Persisted::default(), 0));
    /// assert_eq!(link.next_wake_ms(), 0); // the first debug value is due at boot
    /// ```
    pub fn next_wake_ms(&self) -> u64 {
        if self.rx_more || self.obey_next.is_some() || !self.tx.is_empty() {
            0
        } else {
            self.wake_ms
        }
    }

    /// The earliest instant something is due by the clock.
    fn clock_wake_ms(&self) -> u64 {
        let mut at = u64::MAX;
        if self.debug_on {
            at = at.min(self.next_debug_ms);
        }
        if self.burst_open {
            at = at.min(self.last_rx_ms.saturating_add(GAP_MS));
        }
        for m in self.motors.iter().filter(|m| m.value != 0) {
            at = at.min(m.until_ms);
        }
        if let Some(e) = self.external {
            at = at.min(e.until_ms);
        }
        at
    }

    /// Is the debug stream on (`63 02`) or off (`63 01`)?
    pub fn debug_enabled(&self) -> bool {
        self.debug_on
    }

    /// The RAM parameters.
    pub fn parameters(&self) -> &[i32; AOK_PARAMS] {
        &self.params
    }

    /// The motor-test outputs, motor 1 first (0 = off).
    pub fn motor_outputs(&self) -> [u8; MOTORS] {
        self.motors.map(|m| m.value)
    }

    /// Who steers now.
    pub fn control_source(&self) -> ControlSource {
        if self.external.is_some() {
            ControlSource::External
        } else {
            ControlSource::Rc
        }
    }

    /// The external-control sticks while external control has the aircraft.
    pub fn external_control(&self) -> Option<ExternalControl> {
        self.external.map(|e| e.control)
    }

    /// The link's counters.
    pub fn counters(&self) -> &AokCounters {
        &self.counters
    }

    /// The command decoder's counters.
    pub fn decoder_stats(&self) -> Stats {
        self.decoder.decoder().stats()
    }

    /// Bytes waiting in the link's TX queue (not yet accepted by the port).
    pub fn tx_pending(&self) -> usize {
        self.tx.len()
    }

    /// Hands queued bytes to the port, a slice per write, until it has no room.
    fn flush<P: Write + WriteReady>(&mut self, port: &mut P) {
        if self.tx.drain(port).is_err() {
            self.counters.port_errors = self.counters.port_errors.wrapping_add(1);
        }
    }

    fn tx_free(&self) -> usize {
        self.tx.free()
    }

    /// Queues a whole reply, or drops it (counted) when it does not fit.
    fn queue(&mut self, bytes: &[u8]) {
        if !self.tx.push(bytes) {
            crate::warn!("AOK: TX queue full, reply dropped");
            self.counters.replies_dropped = self.counters.replies_dropped.wrapping_add(1);
        }
    }

    fn ack(&mut self, ack: Ack) {
        match ack {
            Ack::Ok => {}
            Ack::Error => self.counters.rejected = self.counters.rejected.wrapping_add(1),
            Ack::InFlight => {
                self.counters.refused_in_flight = self.counters.refused_in_flight.wrapping_add(1)
            }
        }
        self.queue(&[ack.byte()]);
    }
}
