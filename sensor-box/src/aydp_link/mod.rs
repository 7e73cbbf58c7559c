//! AYDP on UART1 (profile `Spec`): the box's system-value registry, direct outputs, and a
//! heartbeat, position and fix quality at 1 Hz.
//!
//! # What arrives
//!
//! The port lends its received bytes a slice at a time ([`crate::port::Receive`], at
//! most [`RX_BUDGET`] a poll), and a byte is decoded only while the TX queue has room for one
//! longest reply (the rest waits in the port). Every received byte goes through an [`aydp_proto::Decoder`]
//! by `push`, not the slice path `feed`: a request for [`addr::LINK_COUNTERS`] reports the
//! decoder's counters as of before the byte that completed it, which only the per-byte path
//! can read. Every event it yields (a rescan can yield several per byte) is handled:
//!
//! * **System value update** (8), all three modes: applied through an
//!   [`aydp_proto::registry::Registry`] built over [`Shared`] (the addresses in [`addr`]).
//!   The registry checks access, mode, size, bounds and range, and either changes exactly what
//!   the update names or nothing; a rejection is counted ([`LinkCounters::rejected`]) and
//!   logged. A change of airspeed, bank or altitude rebuilds the simulated flight
//!   ([`Shared::settings_changed`]).
//! * **System control** (9): "request data" is answered with a system value update of the
//!   whole value (scalars in mode 1, arrays and texts in mode 2), in the form the request came
//!   in (expedited request, expedited reply; normal request, normal reply with a timestamp).
//!   An unknown address is not answered (AYDP has no negative reply) and counts as rejected.
//!   "Store configuration" asks [`Shared::request_store`] (refused in flight and past the
//!   rate limit, counted at 0x0310); the App writes the flash.
//! * **Direct output control** (7): obeyed only while address 0x0000 is 1, and all or
//!   nothing: an entry naming a (device, channel) the box does not have, or a non-finite
//!   value, rejects the whole message. The new values are logged and readable at
//!   [`addr::OUTPUTS`].
//! * **Heartbeat** (128) is counted; anything else (time sync, positions, user messages) is
//!   counted as ignored. A frame whose data does not parse counts as malformed.
//!
//! # What is sent
//!
//! A heartbeat (expedited type 0) every [`HEARTBEAT_PERIOD_MS`], and a position (3) and fix
//! quality (4) every [`NAV_PERIOD_MS`] from the simulated flight, all starting at boot.
//! Normal messages carry the wall-clock time of the last AEOLUS SETTIME when the box has one,
//! else the time since boot ([`timestamp`]).
//!
//! # Registry
//!
//! | address | name | type | access | range | default |
//! |---|---|---|---|---|---|
//! | 0x0000 | enable direct control | u8 | rw | 0..=1 | 0 |
//! | 0x0001 | system name | char\[40\] | ro | | [`SYSTEM_NAME`] |
//! | 0x0002 | system ID | char\[40\] | ro | | [`SYSTEM_ID`] |
//! | 0x0003 | hardware version | char\[40\] | ro | | [`HARDWARE_VERSION`] |
//! | 0x0004 | firmware version | char\[40\] | ro | | [`FIRMWARE_VERSION`] |
//! | 0x0100 | AEOLUS intervals, ms: IMU, pressure, GPS, temp, wind, info | u32\[6\] | rw | 1..=60 000 | 7, 5, 92, 829, 1000, 1000 |
//! | 0x0110 | simulated airspeed, m/s | f32 | rw | 10..=150 | 50 |
//! | 0x0111 | simulated bank, deg | f32 | rw | -60..=60 | 20 |
//! | 0x0112 | simulated altitude, m | f32 | rw | -500..=11 000 | 1000 |
//! | 0x0120 | AOK debug period, ms | u32 | rw | 0..=60 000 | 20 |
//! | 0x0200 | direct outputs (device 1, channels 0..=7) | f32\[8\] | ro | | 0 |
//! | 0x0300 | link counters ([`COUNTER_NAMES`]) | u32\[10\] | ro | | 0 |
//! | 0x0310 | flash store counters of all links ([`STORE_COUNTER_NAMES`]) | u32\[5\] | ro | | 0 |
//! | 0x0311 | setting groups whose newest flash copy did not verify at boot (older copies loaded) | u32 | ro | | 0 |
//!
//! # Files
//!
//! This file holds the link's state, `poll` and the per-frame entry points; `dispatch` what
//! each received message does; `registry` the addresses, the texts and the view of
//! [`Shared`] the registry works on; `periodic` the 1 Hz messages, their timestamps and
//! sending into the port.
//!
//! ```
//! use aydp_proto::{Decode, Decoder, Message, Profile};
//! use sensor_box::{Persisted, Shared, aydp_link::AydpLink};
//!
//! /// A port that takes nothing in and keeps what goes out.
//! struct Wire(Vec<u8>);
//! impl embedded_io::ErrorType for Wire { type Error = core::convert::Infallible; }
//! impl sensor_box::port::Receive for Wire {
//!     fn receive(&mut self, _: impl FnOnce(&[u8]) -> usize) -> Result<usize, Self::Error> { Ok(0) }
//! }
//! impl embedded_io::WriteReady for Wire {
//!     fn write_ready(&mut self) -> Result<bool, Self::Error> { Ok(true) }
//! }
//! impl embedded_io::Write for Wire {
//!     fn write(&mut self, b: &[u8]) -> Result<usize, Self::Error> { self.0.extend_from_slice(b); Ok(b.len()) }
//!     fn flush(&mut self) -> Result<(), Self::Error> { Ok(()) }
//! }
//!
//! let mut shared = Shared::new(Persisted::default(), 0);
//! let mut link = AydpLink::new(0);
//! let mut wire = Wire(Vec::new());
//! link.poll(0, &mut wire, &mut shared); // at boot: heartbeat, position, fix quality
//! let mut dec = Decoder::<128>::new(Profile::Spec);
//! let mut types = Vec::new();
//! dec.feed(&wire.0, |ev| types.push(ev.unwrap().type_byte()));
//! assert_eq!(types, [0x80, 3, 4]);
//! ```

mod dispatch;
mod periodic;
mod registry;

pub use periodic::{FIX_QUALITY, timestamp, unix_seconds};
pub use registry::{
    FIRMWARE_VERSION, HARDWARE_VERSION, STORE_COUNTER_NAMES, SYSTEM_ID, SYSTEM_NAME, TEXT_LEN, addr,
};

use crate::Shared;
use crate::port::{Receive, TxQueue, receive_slices};
use aydp_proto::{Decoder, Encoder, Frame, Profile, Stats, Stream};
use embedded_io::{Write, WriteReady};
use periodic::SEND_BUF;

/// Longest message the link accepts, bytes. The largest the box expects is a direct output
/// of 8 channels (22 + 2 + 48 + 1 = 73 bytes, normal); 128 leaves room for 17 entries.
pub const DECODER_CAPACITY: usize = 128;
/// Heartbeat period, ms.
pub const HEARTBEAT_PERIOD_MS: u64 = 1000;
/// Position and fix quality period, ms.
pub const NAV_PERIOD_MS: u64 = 1000;
/// Most received bytes handled per poll (keeps one poll short under a flood).
pub const RX_BUDGET: usize = 256;
/// Bytes of encoded messages the link queues for TX, in front of the port: the 1 Hz messages
/// (81 bytes) and one longest reply, twice over.
pub const TX_QUEUE: usize = 256;

/// What the link counted. All counters wrap.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct LinkCounters {
    /// System value updates applied.
    pub updates_applied: u32,
    /// Updates and requests the registry rejected (unknown address, read-only, wrong mode or
    /// size, out of bounds or range); nothing changed.
    pub rejected: u32,
    /// Frames with a good checksum whose data does not parse as their type.
    pub malformed: u32,
    /// Request-data commands answered.
    pub requests_answered: u32,
    /// Store-configuration commands received (accepted or refused by the store policy: see
    /// register 0x0310).
    pub stores_requested: u32,
    /// Direct output messages obeyed.
    pub direct_applied: u32,
    /// Direct output messages refused: direct control off, unknown channel or bad value.
    pub direct_refused: u32,
    /// Heartbeats received.
    pub heartbeats_received: u32,
    /// Good frames of a type the box does not act on.
    pub ignored: u32,
    /// Messages dropped whole because the TX queue had no room for them.
    pub tx_dropped: u32,
    /// Frames the decoder dropped: every `Err` event (see [`crate::port`], "Receive errors").
    pub rx_errors: u32,
    /// Errors reported by the port itself, on either side.
    pub port_errors: u32,
}

/// Names of the u32\[10\] at [`addr::LINK_COUNTERS`], in order: the first four are the
/// decoder's, the rest [`LinkCounters`].
pub const COUNTER_NAMES: [&str; 10] = [
    "messages ok",
    "checksum errors",
    "length errors",
    "bytes discarded",
    "updates applied",
    "rejected",
    "malformed",
    "requests answered",
    "direct applied",
    "direct refused",
];

/// Everything but the decoder (so a frame can borrow the decoder while this is mutated).
struct Ctx {
    encoder: Encoder,
    tx: TxQueue<TX_QUEUE>,
    counters: LinkCounters,
    next_heartbeat_ms: u64,
    next_nav_ms: u64,
}

/// The AYDP link.
pub struct AydpLink {
    decoder: Stream<Decoder<DECODER_CAPACITY>>,
    ctx: Ctx,
    /// The last poll stopped at [`RX_BUDGET`]: bytes may be waiting in the port.
    rx_more: bool,
}

impl AydpLink {
    /// The link at boot: the first heartbeat, position and fix quality are due at `now_ms`.
    ///
    /// ```
    /// let link = sensor_box::aydp_link::AydpLink::new(0);
    /// assert_eq!(link.counters().updates_applied, 0);
    /// ```
    pub fn new(now_ms: u64) -> Self {
        AydpLink {
            decoder: Stream::new(Decoder::new(Profile::Spec)),
            ctx: Ctx {
                encoder: Encoder::new(Profile::Spec),
                tx: TxQueue::new(),
                counters: LinkCounters::default(),
                next_heartbeat_ms: now_ms,
                next_nav_ms: now_ms,
            },
            rx_more: false,
        }
    }

    /// What the link counted.
    ///
    /// ```
    /// let link = sensor_box::aydp_link::AydpLink::new(0);
    /// assert_eq!(link.counters().rejected, 0);
    /// ```
    pub fn counters(&self) -> LinkCounters {
        self.ctx.counters
    }

    /// The decoder's counters (messages ok, checksum and length errors, bytes discarded).
    ///
    /// ```
    /// let link = sensor_box::aydp_link::AydpLink::new(0);
    /// assert_eq!(link.decoder_stats().frames_ok, 0);
    /// ```
    pub fn decoder_stats(&self) -> Stats {
        self.decoder.decoder().stats()
    }

    /// Reads what arrived on the port, answers, and sends what is due at `now_ms`.
    ///
    /// See the [module documentation](self) for an example.
    pub fn poll<P: Receive + Write + WriteReady>(
        &mut self,
        now_ms: u64,
        port: &mut P,
        shared: &mut Shared,
    ) {
        self.ctx.drain(port);
        let taken = receive_slices(port, RX_BUDGET, |bytes| self.decode(bytes, now_ms, shared));
        self.rx_more = matches!(taken, Ok(n) if n >= RX_BUDGET);
        if taken.is_err() {
            self.ctx.counters.port_errors = self.ctx.counters.port_errors.wrapping_add(1);
        }
        // The replies first, so the 1 Hz messages find the room they leave in the port.
        self.ctx.drain(port);
        self.ctx.queue_due(now_ms, shared);
        self.ctx.drain(port);
    }

    /// Whether a poll at `now_ms` has anything to do besides what the port received since the
    /// last one: a 1 Hz message due, TX bytes waiting for room in the port, or received bytes
    /// left in the port by the last poll's [`RX_BUDGET`].
    ///
    /// ```
    /// let link = sensor_box::aydp_link::AydpLink::new(0);
    /// assert!(link.has_work(0)); // the first heartbeat
    /// ```
    pub fn has_work(&self, now_ms: u64) -> bool {
        now_ms >= self.next_wake_ms()
    }

    /// The earliest instant at which a poll has something to do without a received byte: 0
    /// (at once) while TX bytes wait for room in the port or received bytes wait that the last
    /// poll's [`RX_BUDGET`] left in the port; else the next 1 Hz message.
    ///
    /// ```
    /// let link = sensor_box::aydp_link::AydpLink::new(0);
    /// assert_eq!(link.next_wake_ms(), 0); // the first heartbeat is due at boot
    /// ```
    pub fn next_wake_ms(&self) -> u64 {
        if self.rx_more || !self.ctx.tx.is_empty() {
            0
        } else {
            self.ctx.next_heartbeat_ms.min(self.ctx.next_nav_ms)
        }
    }

    /// What the TX queue is still waiting to hand to the port, bytes.
    ///
    /// ```
    /// let link = sensor_box::aydp_link::AydpLink::new(0);
    /// assert_eq!(link.tx_pending(), 0);
    /// ```
    pub fn tx_pending(&self) -> usize {
        self.ctx.tx.len()
    }

    /// Decodes `bytes` one at a time while one longest reply still fits in the TX queue, and
    /// handles every event; the count decoded. The contract's adapter in its pull form
    /// (`Stream::next_event`) a byte at a time, then on nothing for the events a rescan left queued:
    /// a request for [`addr::LINK_COUNTERS`] reports the decoder's counters as of before the
    /// byte that completed it, which only a byte-at-a-time read can tell.
    fn decode(&mut self, bytes: &[u8], now_ms: u64, shared: &mut Shared) -> usize {
        let mut done = 0;
        for byte in bytes {
            if self.ctx.tx.free() < SEND_BUF {
                break;
            }
            done += 1;
            let stats = self.decoder.decoder().stats();
            // Every event of the byte before it was taken, so the byte is used at once; the
            // events a rescan left queued come with nothing (`&[]`).
            let mut input = core::slice::from_ref(byte);
            loop {
                match self.decoder.next_event(input).1 {
                    Some((_, Ok(frame))) => self.ctx.handle(&frame, &stats, now_ms, shared),
                    Some((_, Err(e))) => self.ctx.rx_error(e),
                    None => break,
                }
                input = &[];
            }
        }
        done
    }
}

impl AydpLink {
    /// Acts on one message from a decoder the caller runs, the per-message half of
    /// [`AydpLink::poll`]'s RX (an async `aydp_proto::embedded_io_async::FrameReader`, say):
    /// `Ok` is a received message (updates, requests, store configuration, direct outputs),
    /// `Err` a candidate the decoder dropped (counted in [`LinkCounters::rx_errors`], as on
    /// the link's own path). Replies go into the TX queue and on to `port` at once.
    /// `stats` is what 0x0300 reports for the decoder counters (the caller's decoder: the
    /// link's own, and so [`AydpLink::decoder_stats`], is not used on this path).
    ///
    /// ```
    /// use aydp_proto::{Decode, Decoder, Profile, Stats};
    /// use sensor_box::{aydp_link::AydpLink, Persisted, Shared};
    /// use sensor_box::serial::{PortStats, QueuedSerial};
    /// let (rxq, txq) = (sensor_box::serial::Ring::<2>::new(), sensor_box::serial::Ring::<256>::new());
    /// let stats = PortStats::new();
    /// let (mut port, mut isr) = QueuedSerial::split(&rxq, &txq, &stats, || {});
    /// let mut shared = Shared::new(Persisted::default(), 0);
    /// let mut link = AydpLink::new(0);
    /// // Expedited request data at 0x0110 (airspeed).
    /// let request = [0xFF, 0x89, 0x0A, 0, 0, 0, 0x01, 0x10, 0x01, 0x6C];
    /// let mut decoder = Decoder::<128>::new(Profile::Spec);
    /// decoder.feed(&request, |frame| {
    ///     link.handle_frame(frame.as_ref().map_err(|e| *e), &Stats::default(), 5, &mut port, &mut shared);
    /// });
    /// assert_eq!(link.counters().requests_answered, 1);
    /// assert_eq!(isr.next_to_send(), Some(0xFF)); // the reply
    /// link.handle_frame(Err(aydp_proto::Error::ChecksumMismatch { id: 0x80, computed: 0x12, received: 0x13 }), &Stats::default(), 6, &mut port, &mut shared);
    /// assert_eq!(link.counters().rx_errors, 1);
    /// ```
    pub fn handle_frame<P: Write + WriteReady>(
        &mut self,
        frame: Result<&Frame<'_>, aydp_proto::Error>,
        stats: &Stats,
        now_ms: u64,
        port: &mut P,
        shared: &mut Shared,
    ) {
        match frame {
            Ok(frame) => self.ctx.handle(frame, stats, now_ms, shared),
            Err(e) => self.ctx.rx_error(e),
        }
        self.ctx.drain(port);
    }

    /// The TX half of [`AydpLink::poll`]: sends the heartbeat, position and fix quality due at
    /// `now_ms`, without reading the port.
    ///
    /// ```
    /// use sensor_box::{aydp_link::AydpLink, Persisted, Shared};
    /// use sensor_box::serial::{PortStats, QueuedSerial};
    /// let (rxq, txq) = (sensor_box::serial::Ring::<2>::new(), sensor_box::serial::Ring::<256>::new());
    /// let stats = PortStats::new();
    /// let (mut port, mut isr) = QueuedSerial::split(&rxq, &txq, &stats, || {});
    /// let shared = Shared::new(Persisted::default(), 0);
    /// let mut link = AydpLink::new(0);
    /// link.poll_tx(0, &mut port, &shared);
    /// let sent = core::iter::from_fn(|| isr.next_to_send()).count();
    /// assert_eq!(sent, 7 + 43 + 31); // heartbeat, position, fix quality
    /// ```
    pub fn poll_tx<P: Write + WriteReady>(&mut self, now_ms: u64, port: &mut P, shared: &Shared) {
        self.ctx.drain(port);
        self.ctx.queue_due(now_ms, shared);
        self.ctx.drain(port);
    }
}
