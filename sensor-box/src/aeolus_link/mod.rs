//! AEOLUS on UART0: telemetry out, COMMAND and SETTIME in.
//!
//! Every [`AeolusLink::poll`] does three things, in this order, and never waits (a command
//! acts on the telemetry of the same millisecond; [`RX_BUDGET`] bounds what RX may cost first):
//!
//! 1. **RX**: takes what the port has received (up to [`RX_BUDGET`] bytes, in the contiguous
//!    slices the port lends: [`Receive`]), feeds them to an [`aeolus_proto::Decoder`] by slice
//!    (`feed`), and acts on each complete frame:
//!    * COMMAND `"a pause"`: telemetry stops ([`Shared::paused`]), TOAST `"AEOLUS paused"`;
//!    * COMMAND `"a resume"`: telemetry starts over, TOAST `"AEOLUS resumed"`;
//!    * COMMAND `"a reboot"`: TOAST `"AEOLUS rebooting"`, then [`Requests::reboot`] asks the
//!      main loop for a warm reset;
//!    * any other COMMAND: TOAST `"unknown command: <the command>"`;
//!    * SETTIME: stored in [`Shared::wall_clock`] with the arrival time, and logged (an
//!      out-of-range date is counted and ignored);
//!    * a frame whose data does not parse is counted as malformed, anything else counted and
//!      ignored; a frame the decoder drops is counted in `rx_errors` (the policy of
//!      [`crate::port`]).
//! 2. **Telemetry**: unless paused, the [`Kind`]s the [`Telemetry`] schedule says are due are
//!    built from the simulated flight at `now_ms` and encoded into the TX queue.
//! 3. **TX**: the TX queue (whole encoded frames, [`TX_QUEUE`] bytes) is drained into the port
//!    with non-blocking writes of slices, after each frame queued and at the end of the poll,
//!    until the port has no room (`write_ready()` is `false`); the rest waits for the next poll. So a slow UART never stalls
//!    the decoders: one poll costs at most the encoding of the frames due now and the copy of
//!    what the port accepts.
//!
//! A frame that does not fit in the queue is dropped whole (counted in
//! [`LinkCounters::tx_dropped`]), never cut; telemetry leaves [`TX_RESERVE`] bytes free so
//! that answers (TOASTs) still fit when the UART cannot keep up, and RX decodes a byte only
//! while one longest answer still fits, so a burst of COMMANDs is answered in full however
//! slowly the other side reads (the bytes wait in the port instead).
//!
//! This file holds the link's state, the poll halves and the TX queue; `commands.rs` what
//! UART0 receives (deframing, COMMAND, SETTIME).
//!
//! [`Requests::reboot`]: super::state::Requests::reboot
//!
//! ```
//! use aeolus_proto::{Decode, Decoder, message::{Message, Text}, CrcMode};
//! use sensor_box::{aeolus_link::AeolusLink, Persisted, Shared};
//! use sensor_box::serial::{PortStats, QueuedSerial};
//! use sensor_box::serial::Ring;
//!
//! let (rxq, txq) = (Ring::<256>::new(), Ring::<4096>::new());
//! let stats = PortStats::new();
//! let (mut port, mut isr) = QueuedSerial::split(&rxq, &txq, &stats, || {});
//! let mut shared = Shared::new(Persisted::default(), 0);
//! let mut link = AeolusLink::new(0);
//!
//! // The peer sends "a pause".
//! let mut frame = [0u8; 64];
//! let n = Message::Command(Text::new("a pause").unwrap())
//!     .encode(&mut frame, CrcMode::Compute)
//!     .unwrap();
//! for &b in &frame[..n] {
//!     isr.received(b);
//! }
//! link.poll(0, &mut port, &mut shared);
//! assert!(shared.paused);
//!
//! // On the wire: the boot TOAST, no telemetry (paused before it was due), the answer.
//! let mut toasts = Vec::new();
//! let mut decoder = Decoder::<256>::new();
//! while let Some(b) = isr.next_to_send() {
//!     decoder.feed(&[b], |event| {
//!         if let Ok(f) = event
//!             && let Ok(Message::Toast(t)) = f.message()
//!         {
//!             toasts.push(t.as_str().unwrap_or("").to_owned());
//!         }
//!     });
//! }
//! assert_eq!(toasts, ["AEOLUS on", "AEOLUS paused"]);
//! ```

mod commands;

use crate::Shared;
use crate::budget::{Category, span};
use crate::port::{Receive, Transmit, TxQueue};
use crate::telemetry::{Kind, Telemetry, build_at};
use aeolus_proto::message::{Message, Text};
use aeolus_proto::{
    CrcMode, Decoder, Frame, MAX_FIXED_FRAME, Stream, TEXT_CAPACITY, max_encoded_len,
};
use commands::{Incoming, incoming};
use embedded_io::{Write, WriteReady};

/// Bytes of encoded frames the link queues for TX, in front of the port's own queue (512
/// bytes on both boards). Each frame is handed to the port as soon as it is queued, so this
/// queue only fills when the UART falls behind. The worst millisecond of the spec schedule
/// (the five 7 ms messages and PRESSURE together) is 298 bytes; at boot all ten kinds and the
/// TOAST are 468.
pub const TX_QUEUE: usize = 512;

/// Queue bytes telemetry leaves free for answers: one longest TOAST.
pub const TX_RESERVE: usize = FRAME_BUF;

/// The most bytes one poll reads from the port. The boards' RX rings hold 256 bytes (255 once wrapped), so one
/// poll empties them (bytes of an earlier read that were held back are decoded first, on top); the bound keeps a port that never runs dry (a flood) from starving the
/// others and the schedule: 256 bytes are about 2.8 ms of UART0 at 921 600 Bd, and decoding
/// them takes well under a millisecond of a 50 MHz Cortex-M3 (`docs/BENCHMARKS.md`,
/// "Firmware CPU budget"). What a flood sends beyond that waits in the port, or is dropped
/// and counted there, never a telemetry slot.
pub const RX_BUDGET: usize = 256;

/// Capacity of the RX decoder (unescaped ID + data + CRC): every fixed-size message and
/// every COMMAND of up to [`TEXT_CAPACITY`] characters.
pub const RX_FRAME: usize = MAX_FIXED_FRAME;

/// The longest frame the link sends: a TOAST of [`TEXT_CAPACITY`] characters and its NUL
/// (longer than the longest telemetry message, COMPASS).
const FRAME_BUF: usize = max_encoded_len(TEXT_CAPACITY + 1);

/// The boot TOAST.
pub const BOOT_TOAST: &str = "AEOLUS on";

/// Prefix of the answer to a COMMAND the box does not know.
pub const UNKNOWN_PREFIX: &[u8] = b"unknown command: ";

/// The answer (a TOAST) to `a reboot` in flight, which is refused ("flying": AEOLUS
/// telemetry not paused).
pub const REBOOT_REFUSED: &[u8] = b"AEOLUS reboot refused: flying";

/// What the link has done since boot (wrapping counters). The decoder keeps its own
/// ([`AeolusLink::rx_stats`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(all(feature = "defmt", target_os = "none"), derive(defmt::Format))]
pub struct LinkCounters {
    /// Telemetry frames queued, per [`Kind`] (indexed by [`Kind::index`]).
    pub sent: [u32; Kind::COUNT],
    /// TOASTs queued (boot, answers).
    pub toasts: u32,
    /// Frames dropped because the TX queue was full.
    pub tx_dropped: u32,
    /// COMMANDs obeyed ("a pause", "a resume", "a reboot").
    pub commands: u32,
    /// COMMANDs refused because the box is flying (`a reboot`, answered with
    /// [`REBOOT_REFUSED`]).
    pub refused_in_flight: u32,
    /// COMMANDs answered "unknown command".
    pub unknown_commands: u32,
    /// SETTIMEs stored.
    pub settime: u32,
    /// SETTIMEs ignored because a field was out of range.
    pub settime_rejected: u32,
    /// Good frames of a type the box does not act on (TOAST, telemetry, LOG, ...).
    pub ignored: u32,
    /// Good frames whose data does not parse as their type (a COMMAND or SETTIME of the
    /// wrong length, ...).
    pub malformed: u32,
    /// Frames the decoder dropped: every `Err` event (see [`crate::port`], "Receive errors").
    pub rx_errors: u32,
    /// Errors reported by the port itself, on either side.
    pub port_errors: u32,
}

impl LinkCounters {
    /// All telemetry frames queued.
    ///
    /// ```
    /// let c = sensor_box::aeolus_link::LinkCounters::default();
    /// assert_eq!(c.telemetry_total(), 0);
    /// ```
    pub fn telemetry_total(&self) -> u32 {
        self.sent.iter().fold(0u32, |a, &n| a.wrapping_add(n))
    }
}

/// The AEOLUS link.
pub struct AeolusLink {
    telemetry: Telemetry,
    /// The decoder, through the contract's one adapter.
    decoder: Stream<Decoder<RX_FRAME>>,
    tx: TxQueue<TX_QUEUE>,
    /// Whether the last poll saw `shared.paused`: a resume restarts the schedule.
    was_paused: bool,
    /// The millisecond the schedule was last run for: the main loop may poll many times a
    /// millisecond (a UART's interrupt wakes it) and the schedule can only change when the
    /// millisecond does.
    scheduled_ms: Option<u64>,
    /// The last poll stopped at [`RX_BUDGET`]: bytes may be waiting in the port.
    rx_more: bool,
    counters: LinkCounters,
}

impl AeolusLink {
    /// The link at boot: TOAST "AEOLUS on" is queued and every telemetry kind is due at
    /// `now_ms`.
    ///
    /// ```
    /// let link = sensor_box::aeolus_link::AeolusLink::new(0);
    /// assert_eq!(link.counters().toasts, 1);
    /// assert_eq!(link.tx_pending(), 15); // 7E 52 "AEOLUS on" 00 CRC CRC 7E
    /// ```
    pub fn new(now_ms: u64) -> Self {
        let mut link = AeolusLink {
            telemetry: Telemetry::new(now_ms),
            decoder: Stream::new(Decoder::new()),
            tx: TxQueue::new(),
            was_paused: false,
            scheduled_ms: None,
            rx_more: false,
            counters: LinkCounters::default(),
        };
        link.toast(BOOT_TOAST.as_bytes());
        link
    }

    /// Reads what arrived on the port, answers, and sends what is due at `now_ms`.
    pub fn poll<P: Receive + Transmit + Write + WriteReady>(
        &mut self,
        now_ms: u64,
        port: &mut P,
        shared: &mut Shared,
    ) {
        span(Category::AeolusRx, || self.receive(now_ms, port, shared));
        self.poll_tx(now_ms, port, shared);
    }

    /// Whether a poll at `now_ms` has anything to do besides what the port received since the
    /// last one: `now_ms` has reached [`AeolusLink::next_wake_ms`]. What
    /// [`App::poll_pending`](crate::App::poll_pending) asks before it runs the link.
    ///
    /// ```
    /// use sensor_box::{aeolus_link::AeolusLink, Persisted, Shared};
    /// let shared = Shared::new(Persisted::default(), 0);
    /// let link = AeolusLink::new(0);
    /// assert!(link.has_work(0, &shared)); // the boot TOAST waits
    /// ```
    pub fn has_work(&self, now_ms: u64, shared: &Shared) -> bool {
        now_ms >= self.next_wake_ms(shared)
    }

    /// The earliest instant at which a poll has something to do without a received byte: 0
    /// (at once) while TX bytes wait for room in the port, while received bytes wait that
    /// the last poll's [`RX_BUDGET`] left in the port, and after a pause or a resume the link
    /// has not seen; else when the schedule has the next kind due
    /// ([`Telemetry::next_due`]: at once after a change of the intervals), never while paused.
    /// A main loop that sleeps until the earliest of its links' instants misses nothing.
    ///
    /// ```
    /// use sensor_box::serial::{PortStats, QueuedSerial, Ring};
    /// use sensor_box::{aeolus_link::AeolusLink, Persisted, Shared};
    /// let (rxq, txq) = (Ring::<2>::new(), Ring::<1024>::new());
    /// let stats = PortStats::new();
    /// let (mut port, _isr) = QueuedSerial::split(&rxq, &txq, &stats, || {});
    /// let mut shared = Shared::new(Persisted::default(), 0);
    /// let mut link = AeolusLink::new(0);
    /// assert_eq!(link.next_wake_ms(&shared), 0); // the boot TOAST and the first telemetry
    /// link.poll(0, &mut port, &mut shared);
    /// assert_eq!(link.next_wake_ms(&shared), 5); // PRESSURE, every 5 ms
    /// shared.paused = true;
    /// assert_eq!(link.next_wake_ms(&shared), 0); // the pause is news to the link
    /// link.poll(1, &mut port, &mut shared);
    /// assert_eq!(link.next_wake_ms(&shared), u64::MAX);
    /// ```
    pub fn next_wake_ms(&self, shared: &Shared) -> u64 {
        if self.rx_more || !self.tx.is_empty() || shared.paused != self.was_paused {
            0
        } else if shared.paused {
            u64::MAX
        } else {
            self.telemetry.next_due(&shared.settings().intervals)
        }
    }

    /// The TX half of [`AeolusLink::poll`]: queues the telemetry due at `now_ms` (unless
    /// paused) and hands queued frames to the port, without reading it. For a board whose
    /// own reader deframes (an async `aeolus_proto::embedded_io_async::FrameReader`) and
    /// passes each frame to [`AeolusLink::handle_frame`].
    ///
    /// ```
    /// use sensor_box::{aeolus_link::AeolusLink, Persisted, Shared};
    /// use sensor_box::serial::{PortStats, QueuedSerial};
    /// let (rxq, txq) = (sensor_box::serial::Ring::<2>::new(), sensor_box::serial::Ring::<1024>::new());
    /// let stats = PortStats::new();
    /// let (mut port, _isr) = QueuedSerial::split(&rxq, &txq, &stats, || {});
    /// let shared = Shared::new(Persisted::default(), 0);
    /// let mut link = AeolusLink::new(0);
    /// link.poll_tx(0, &mut port, &shared);
    /// assert_eq!(link.tx_pending(), 0); // the boot TOAST and every kind went to the port
    /// assert_eq!(link.counters().telemetry_total(), 10);
    /// ```
    pub fn poll_tx<P: Transmit + Write + WriteReady>(
        &mut self,
        now_ms: u64,
        port: &mut P,
        shared: &Shared,
    ) {
        // Within a millisecond already scheduled, and with nothing queued, there is nothing
        // to do: a wake for received bytes costs the TX half two comparisons.
        if self.scheduled_ms != Some(now_ms) || shared.paused != self.was_paused {
            span(Category::Telemetry, || self.queue_due(now_ms, port, shared));
        }
        if !self.tx.is_empty() {
            span(Category::TxQueue, || {
                drain(&mut self.tx, port, &mut self.counters)
            });
        }
    }

    fn queue_due<P: Transmit + Write + WriteReady>(
        &mut self,
        now_ms: u64,
        port: &mut P,
        shared: &Shared,
    ) {
        self.scheduled_ms = Some(now_ms);
        if shared.paused {
            self.was_paused = true;
        } else {
            if core::mem::take(&mut self.was_paused) {
                self.telemetry.restart(now_ms);
            }
            self.send_due(now_ms, port, shared);
        }
    }

    /// Acts on one frame from a decoder the caller runs, the per-frame half of
    /// [`AeolusLink::poll`]'s RX: `Ok` is a received frame (COMMAND and SETTIME are obeyed,
    /// anything else counted), `Err` a frame the decoder dropped (counted in
    /// [`LinkCounters::rx_errors`]). Answers are queued and go out with the next
    /// [`AeolusLink::poll_tx`]. The link's own decoder (and so [`AeolusLink::rx_stats`]) is
    /// not used on this path: the caller's decoder has the counters.
    ///
    /// ```
    /// use aeolus_proto::{CrcMode, Decode, Decoder, message::{Message, Text}};
    /// use sensor_box::{aeolus_link::AeolusLink, Persisted, Shared};
    /// let mut shared = Shared::new(Persisted::default(), 0);
    /// let mut link = AeolusLink::new(0);
    /// let mut wire = [0u8; 64];
    /// let n = Message::Command(Text::new("a pause").unwrap()).encode(&mut wire, CrcMode::Compute).unwrap();
    /// let mut decoder = Decoder::<64>::new();
    /// decoder.feed(&wire[..n], |frame| {
    ///     link.handle_frame(frame.as_ref().map_err(|e| *e), 5, &mut shared);
    /// });
    /// assert!(shared.paused);
    /// link.handle_frame(Err(aeolus_proto::Error::TooShort), 6, &mut shared);
    /// assert_eq!(link.counters().rx_errors, 1);
    /// ```
    pub fn handle_frame(
        &mut self,
        frame: Result<&Frame<'_>, aeolus_proto::Error>,
        now_ms: u64,
        shared: &mut Shared,
    ) {
        let incoming = frame.map_or(Incoming::Error, incoming);
        self.handle(incoming, now_ms, shared);
    }

    /// The link's counters.
    pub fn counters(&self) -> &LinkCounters {
        &self.counters
    }

    /// The RX decoder's counters (frames, CRC errors, bytes discarded, ...).
    ///
    /// ```
    /// let link = sensor_box::aeolus_link::AeolusLink::new(0);
    /// assert_eq!(link.rx_stats().frames_ok, 0);
    /// ```
    pub fn rx_stats(&self) -> aeolus_proto::Stats {
        self.decoder.decoder().stats()
    }

    /// The telemetry schedule.
    pub fn telemetry(&self) -> &Telemetry {
        &self.telemetry
    }

    /// Encoded bytes waiting in the TX queue.
    pub fn tx_pending(&self) -> usize {
        self.tx.len()
    }

    /// Builds and queues the telemetry due at `now_ms`: one flight state for the messages that
    /// move with time, the flight's steady values for the others ([`Shared::steady_state`]).
    fn send_due<P: Transmit + Write + WriteReady>(
        &mut self,
        now_ms: u64,
        port: &mut P,
        shared: &Shared,
    ) {
        let intervals = shared.settings().intervals;
        let AeolusLink {
            telemetry,
            tx,
            counters,
            ..
        } = self;
        let mut state = None;
        let timestamp_ms = now_ms as f64;
        for kind in telemetry.due(now_ms, &intervals) {
            let msg = if kind.moves_with_time() {
                build_at(
                    kind,
                    state.get_or_insert_with(|| shared.flight_state(now_ms)),
                    timestamp_ms,
                )
            } else {
                build_at(kind, &shared.steady_state(now_ms), timestamp_ms)
            };
            if send(tx, port, counters, &msg) {
                if let Some(n) = counters.sent.get_mut(kind.index()) {
                    bump(n);
                }
            } else {
                bump(&mut counters.tx_dropped);
            }
            span(Category::TxQueue, || drain(tx, port, counters));
        }
    }

    /// Queues a TOAST (text truncated to [`TEXT_CAPACITY`]).
    fn toast(&mut self, text: &[u8]) {
        let text = text.get(..TEXT_CAPACITY).unwrap_or(text);
        let queued = Text::from_bytes(text)
            .map(|t| enqueue(&mut self.tx, &Message::Toast(t), 0))
            .unwrap_or(false);
        if queued {
            bump(&mut self.counters.toasts);
        } else {
            bump(&mut self.counters.tx_dropped);
        }
    }
}

/// Moves queued bytes into the port, a slice per write, until it has no room.
fn drain<P: Write + WriteReady>(
    tx: &mut TxQueue<TX_QUEUE>,
    port: &mut P,
    counters: &mut LinkCounters,
) {
    if tx.drain(port).is_err() {
        bump(&mut counters.port_errors);
    }
}

/// Encodes a telemetry frame straight into the port's free bytes when the link's queue is
/// empty (nothing to overtake) and the port lends a run that holds it; otherwise queues it
/// with [`TX_RESERVE`] kept for answers. Whether it went to the port or the queue.
fn send<P: Transmit>(
    tx: &mut TxQueue<TX_QUEUE>,
    port: &mut P,
    counters: &mut LinkCounters,
    msg: &Message<'_>,
) -> bool {
    if tx.is_empty() {
        match port.transmit(|free| msg.encode(free, CrcMode::Compute).unwrap_or(0)) {
            Ok(0) => {}
            Ok(_) => return true,
            Err(_) => bump(&mut counters.port_errors),
        }
    }
    enqueue(tx, msg, TX_RESERVE)
}

/// Encodes `msg` and queues the whole frame if it fits with `reserve` bytes to spare: straight
/// into the queue's free bytes (no buffer to clear, no copy), unless the frame would wrap.
fn enqueue(tx: &mut TxQueue<TX_QUEUE>, msg: &Message<'_>, reserve: usize) -> bool {
    tx.push_with::<FRAME_BUF>(reserve, |out| msg.encode(out, CrcMode::Compute).ok())
}

fn bump(counter: &mut u32) {
    *counter = counter.wrapping_add(1);
}
