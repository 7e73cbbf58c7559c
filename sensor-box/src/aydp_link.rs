//! AYDP on UART1 (profile `Spec`): the box's system-value registry, direct outputs, and a
//! heartbeat, position and fix quality at 1 Hz.
//!
//! # What arrives
//!
//! Every received byte goes through an [`aydp_proto::Decoder`]; every event it yields (a
//! rescan can yield several per byte) is handled:
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
//!   "Store configuration" sets [`Shared::requests`]`.store`; the App writes the flash.
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
//!
//! ```
//! use aydp_proto::{Decoder, Message, Profile};
//! use sensor_box::{Persisted, Shared, aydp_link::AydpLink};
//!
//! /// A port that takes nothing in and keeps what goes out.
//! struct Wire(Vec<u8>);
//! impl embedded_hal_nb::serial::ErrorType for Wire { type Error = core::convert::Infallible; }
//! impl embedded_hal_nb::serial::Read<u8> for Wire {
//!     fn read(&mut self) -> nb::Result<u8, Self::Error> { Err(nb::Error::WouldBlock) }
//! }
//! impl embedded_hal_nb::serial::Write<u8> for Wire {
//!     fn write(&mut self, b: u8) -> nb::Result<(), Self::Error> { self.0.push(b); Ok(()) }
//!     fn flush(&mut self) -> nb::Result<(), Self::Error> { Ok(()) }
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

use super::Shared;
use super::state::{Intervals, OUTPUTS};
use aydp_proto::registry::{Cell, Registry, Slot};
use aydp_proto::{
    Decoder, Encoder, FixQuality, Frame, Message, Payload, Position, Profile, Stats, SystemControl,
    SystemValueUpdate, Timestamp,
};
use embedded_hal_nb::serial::{Read, Write};

/// The registry's addresses.
pub mod addr {
    /// Enable direct control, u8 0/1, read-write (prescribed, Y9).
    pub const DIRECT_CONTROL: u16 = 0x0000;
    /// System name, char\[40\], read-only (prescribed).
    pub const SYSTEM_NAME: u16 = 0x0001;
    /// System ID, char\[40\], read-only (prescribed).
    pub const SYSTEM_ID: u16 = 0x0002;
    /// Hardware version, char\[40\], read-only (prescribed).
    pub const HARDWARE_VERSION: u16 = 0x0003;
    /// Firmware version, char\[40\], read-only (prescribed).
    pub const FIRMWARE_VERSION: u16 = 0x0004;
    /// AEOLUS telemetry intervals in ms, u32\[6\]: IMU (GYRO, ACCEL, MAGNET, ATTITUDE,
    /// COMPASS), PRESSURE, GPS, TEMP, WIND, AEOLUSINFO.
    pub const INTERVALS: u16 = 0x0100;
    /// Simulated true airspeed, m/s, f32.
    pub const AIRSPEED: u16 = 0x0110;
    /// Simulated bank angle, degrees (positive: right turn), f32.
    pub const BANK: u16 = 0x0111;
    /// Simulated altitude, m, f32.
    pub const ALTITUDE: u16 = 0x0112;
    /// AOK debug value stream period, ms, u32 (0: as fast as the link allows).
    pub const AOK_DEBUG_PERIOD: u16 = 0x0120;
    /// The direct outputs (device 1, channels 0..=7), f32\[8\], read-only.
    pub const OUTPUTS: u16 = 0x0200;
    /// The link counters, u32\[10\], read-only (order: [`super::COUNTER_NAMES`]).
    pub const LINK_COUNTERS: u16 = 0x0300;
}

/// Longest message the link accepts, bytes. The largest the box expects is a direct output
/// of 8 channels (22 + 2 + 48 + 1 = 73 bytes, normal); 128 leaves room for 17 entries.
pub const DECODER_CAPACITY: usize = 128;
/// Heartbeat period, ms.
pub const HEARTBEAT_PERIOD_MS: u64 = 1000;
/// Position and fix quality period, ms.
pub const NAV_PERIOD_MS: u64 = 1000;
/// Most received bytes handled per poll (keeps one poll short under a flood).
pub const RX_BUDGET: usize = 256;
/// Tries per byte while the TX queue is full before the rest of a message is dropped.
const TX_SPIN: u32 = 10_000;

/// Length of the prescribed texts.
pub const TEXT_LEN: usize = 40;

/// `s` as a NUL-padded `char[40]` (cut at 40 bytes).
const fn text(s: &str) -> [u8; TEXT_LEN] {
    let b = s.as_bytes();
    let mut out = [0u8; TEXT_LEN];
    let mut i = 0;
    while i < b.len() && i < TEXT_LEN {
        out[i] = b[i];
        i += 1;
    }
    out
}

/// 0x0001 system name.
pub const SYSTEM_NAME: [u8; TEXT_LEN] = text("protolink sensor box");
/// 0x0002 system ID.
pub const SYSTEM_ID: [u8; TEXT_LEN] = text("SBX-0001");
/// 0x0003 hardware version: the board the firmware was built for (board features only take
/// effect on the target, like the rest of the board support).
pub const HARDWARE_VERSION: [u8; TEXT_LEN] = text(
    if cfg!(all(target_os = "none", feature = "hardware-stm32f411")) {
        "STM32F411"
    } else if cfg!(all(target_os = "none", feature = "hardware-lm3s6965evb")) {
        "QEMU lm3s6965evb"
    } else {
        "host"
    },
);
/// 0x0004 firmware version.
pub const FIRMWARE_VERSION: [u8; TEXT_LEN] =
    text(concat!("sensor-box ", env!("CARGO_PKG_VERSION")));

/// The fix quality the simulated GPS reports (3D fix, 10 satellites).
pub const FIX_QUALITY: FixQuality = FixQuality {
    fix_type: 3,
    mean_dop: 1.25,
    hdop: 0.875,
    vdop: 1.5,
    satellites: 10,
};

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
    /// Store-configuration commands (flash writes requested).
    pub stores_requested: u32,
    /// Direct output messages obeyed.
    pub direct_applied: u32,
    /// Direct output messages refused: direct control off, unknown channel or bad value.
    pub direct_refused: u32,
    /// Heartbeats received.
    pub heartbeats_received: u32,
    /// Good frames of a type the box does not act on.
    pub ignored: u32,
    /// Messages not sent completely because the TX queue stayed full.
    pub tx_dropped: u32,
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
    counters: LinkCounters,
    next_heartbeat_ms: u64,
    next_nav_ms: u64,
}

/// The AYDP link.
pub struct AydpLink {
    decoder: Decoder<DECODER_CAPACITY>,
    ctx: Ctx,
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
            decoder: Decoder::new(Profile::Spec),
            ctx: Ctx {
                encoder: Encoder::new(Profile::Spec),
                counters: LinkCounters::default(),
                next_heartbeat_ms: now_ms,
                next_nav_ms: now_ms,
            },
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
        self.decoder.stats()
    }

    /// Reads what arrived on the port, answers, and sends what is due at `now_ms`.
    ///
    /// See the [module documentation](self) for an example.
    pub fn poll<P: Read<u8> + Write<u8>>(
        &mut self,
        now_ms: u64,
        port: &mut P,
        shared: &mut Shared,
    ) {
        for _ in 0..RX_BUDGET {
            let Ok(byte) = port.read() else { break };
            // The counters as of before this byte: what 0x0300 reports to a request it ends.
            let stats = self.decoder.stats();
            let mut event = self.decoder.push(byte);
            while let Some(ev) = event {
                match ev {
                    Ok(frame) => self.ctx.handle(&frame, &stats, now_ms, port, shared),
                    Err(e) => crate::debug!("AYDP: dropped a candidate: {}", e),
                }
                event = self.decoder.poll();
            }
        }
        self.ctx.send_due(now_ms, port, shared);
    }
}

impl AydpLink {
    /// Acts on one message from a decoder the caller runs, the per-message half of
    /// [`AydpLink::poll`]'s RX (an async `aydp_proto::embedded_io_async::FrameReader`, say):
    /// updates, requests, store configuration, direct outputs. Replies go to `port` at once.
    /// `stats` is what 0x0300 reports for the decoder counters (the caller's decoder: the
    /// link's own, and so [`AydpLink::decoder_stats`], is not used on this path).
    ///
    /// ```
    /// use aydp_proto::{Decoder, Profile, Stats};
    /// use sensor_box::{aydp_link::AydpLink, Persisted, Shared};
    /// use firmware_example::{PortStats, QueuedSerial};
    /// let (mut rxq, mut txq) = (heapless::spsc::Queue::<u8, 2>::new(), heapless::spsc::Queue::<u8, 256>::new());
    /// let stats = PortStats::new();
    /// let (mut port, mut isr) = QueuedSerial::split(&mut rxq, &mut txq, &stats, || {});
    /// let mut shared = Shared::new(Persisted::default(), 0);
    /// let mut link = AydpLink::new(0);
    /// // Expedited request data at 0x0110 (airspeed).
    /// let request = [0xFF, 0x89, 0x0A, 0, 0, 0, 0x01, 0x10, 0x01, 0x6C];
    /// let mut decoder = Decoder::<128>::new(Profile::Spec);
    /// for &b in &request {
    ///     if let Some(Ok(frame)) = decoder.push(b) {
    ///         link.handle_frame(&frame, &Stats::default(), 5, &mut port, &mut shared);
    ///     }
    /// }
    /// assert_eq!(link.counters().requests_answered, 1);
    /// assert_eq!(isr.next_to_send(), Some(0xFF)); // the reply
    /// ```
    pub fn handle_frame<P: Write<u8>>(
        &mut self,
        frame: &Frame<'_>,
        stats: &Stats,
        now_ms: u64,
        port: &mut P,
        shared: &mut Shared,
    ) {
        self.ctx.handle(frame, stats, now_ms, port, shared);
    }

    /// The TX half of [`AydpLink::poll`]: sends the heartbeat, position and fix quality due at
    /// `now_ms`, without reading the port.
    ///
    /// ```
    /// use sensor_box::{aydp_link::AydpLink, Persisted, Shared};
    /// use firmware_example::{PortStats, QueuedSerial};
    /// let (mut rxq, mut txq) = (heapless::spsc::Queue::<u8, 2>::new(), heapless::spsc::Queue::<u8, 256>::new());
    /// let stats = PortStats::new();
    /// let (mut port, mut isr) = QueuedSerial::split(&mut rxq, &mut txq, &stats, || {});
    /// let shared = Shared::new(Persisted::default(), 0);
    /// let mut link = AydpLink::new(0);
    /// link.poll_tx(0, &mut port, &shared);
    /// let sent = core::iter::from_fn(|| isr.next_to_send()).count();
    /// assert_eq!(sent, 7 + 43 + 31); // heartbeat, position, fix quality
    /// ```
    pub fn poll_tx<P: Write<u8>>(&mut self, now_ms: u64, port: &mut P, shared: &Shared) {
        self.ctx.send_due(now_ms, port, shared);
    }
}

/// Next deadline after a send at `now`: the next point of the `period` grid that started at
/// `due`, so a late poll neither bursts nor drifts.
fn next_due(due: u64, now: u64, period: u64) -> u64 {
    let late = now.saturating_sub(due);
    now.saturating_sub(late % period.max(1))
        .saturating_add(period)
}

impl Ctx {
    fn handle<P: Write<u8>>(
        &mut self,
        frame: &Frame<'_>,
        stats: &Stats,
        now_ms: u64,
        port: &mut P,
        shared: &mut Shared,
    ) {
        let message = match frame.message() {
            Ok(m) => m,
            Err(e) => {
                self.counters.malformed = self.counters.malformed.wrapping_add(1);
                crate::warn!("AYDP: malformed type {=u8}: {}", frame.base_type(), e);
                return;
            }
        };
        match message {
            Message::SystemValueUpdate(update) => self.update(&update, stats, now_ms, shared),
            Message::SystemControl(SystemControl::RequestData { address }) => {
                let ts = (!frame.is_expedited()).then(|| timestamp(shared, now_ms));
                self.request(address, ts, stats, port, shared);
            }
            Message::SystemControl(SystemControl::StoreConfiguration) => {
                shared.requests.store = true;
                self.counters.stores_requested = self.counters.stores_requested.wrapping_add(1);
                crate::info!("AYDP: store configuration");
            }
            Message::DirectOutput(out) => self.direct(&out, shared),
            Message::Heartbeat => {
                self.counters.heartbeats_received =
                    self.counters.heartbeats_received.wrapping_add(1);
            }
            _ => {
                self.counters.ignored = self.counters.ignored.wrapping_add(1);
                crate::debug!("AYDP: ignored type {=u8}", frame.base_type());
            }
        }
    }

    fn update(
        &mut self,
        update: &SystemValueUpdate<'_>,
        stats: &Stats,
        now_ms: u64,
        shared: &mut Shared,
    ) {
        let mut view = View::new(shared, stats, &self.counters);
        let result = Registry::new(&mut view.slots()).apply(update);
        match result {
            Ok(()) => {
                view.write_back(shared, now_ms);
                self.counters.updates_applied = self.counters.updates_applied.wrapping_add(1);
                crate::info!("AYDP: value at {=u16:#x} updated", update.address);
            }
            Err(e) => {
                self.counters.rejected = self.counters.rejected.wrapping_add(1);
                crate::warn!("AYDP: update of {=u16:#x} rejected: {}", update.address, e);
            }
        }
    }

    fn request<P: Write<u8>>(
        &mut self,
        address: u16,
        ts: Option<Timestamp>,
        stats: &Stats,
        port: &mut P,
        shared: &Shared,
    ) {
        let mut view = View::new(shared, stats, &self.counters);
        let mut slots = view.slots();
        let registry = Registry::new(&mut slots);
        let mut out = [0u8; 64];
        match registry.read(address, &mut out) {
            Ok(reply) => {
                self.counters.requests_answered = self.counters.requests_answered.wrapping_add(1);
                send(&self.encoder, &mut self.counters, port, &reply, ts);
            }
            Err(e) => {
                self.counters.rejected = self.counters.rejected.wrapping_add(1);
                crate::warn!("AYDP: request for {=u16:#x} rejected: {}", address, e);
            }
        }
    }

    fn direct(&mut self, out: &aydp_proto::DirectOutput<'_>, shared: &mut Shared) {
        if !shared.direct_control {
            self.counters.direct_refused = self.counters.direct_refused.wrapping_add(1);
            crate::warn!("AYDP: direct output refused: direct control is off (0x0000 = 0)");
            return;
        }
        let mut outputs = shared.outputs;
        for e in out.entries() {
            let slot = outputs
                .iter_mut()
                .find(|o| o.device == e.device && o.channel == e.channel);
            match slot {
                Some(o) if e.value.is_finite() => o.value = e.value,
                _ => {
                    self.counters.direct_refused = self.counters.direct_refused.wrapping_add(1);
                    crate::warn!(
                        "AYDP: direct output refused: output {=u8}.{=u8} = {=f32}",
                        e.device,
                        e.channel,
                        e.value
                    );
                    return;
                }
            }
        }
        for (o, new) in shared.outputs.iter().zip(outputs.iter()) {
            if o.value.to_bits() != new.value.to_bits() {
                crate::info!(
                    "AYDP: output {=u8}.{=u8} = {=f32}",
                    new.device,
                    new.channel,
                    new.value
                );
            }
        }
        shared.outputs = outputs;
        self.counters.direct_applied = self.counters.direct_applied.wrapping_add(1);
    }

    fn send_due<P: Write<u8>>(&mut self, now_ms: u64, port: &mut P, shared: &Shared) {
        if now_ms >= self.next_heartbeat_ms {
            self.next_heartbeat_ms = next_due(self.next_heartbeat_ms, now_ms, HEARTBEAT_PERIOD_MS);
            send(
                &self.encoder,
                &mut self.counters,
                port,
                &Message::Heartbeat,
                None,
            );
        }
        if now_ms >= self.next_nav_ms {
            self.next_nav_ms = next_due(self.next_nav_ms, now_ms, NAV_PERIOD_MS);
            let s = shared.flight_state(now_ms);
            let ts = Some(timestamp(shared, now_ms));
            let position = Position {
                latitude: s.latitude_deg,
                longitude: s.longitude_deg,
                altitude: s.gps_altitude_m,
            };
            send(&self.encoder, &mut self.counters, port, &position, ts);
            send(&self.encoder, &mut self.counters, port, &FIX_QUALITY, ts);
        }
    }
}

/// Sends one message (normal with `Some(timestamp)`, expedited with `None`) byte by byte.
/// While the TX queue is full it retries; if it stays full the rest is dropped and counted.
fn send<P: Write<u8>, M: Payload + ?Sized>(
    encoder: &Encoder,
    counters: &mut LinkCounters,
    port: &mut P,
    message: &M,
    timestamp: Option<Timestamp>,
) {
    let Ok(bytes) = encoder.iter(message, timestamp) else {
        return;
    };
    for b in bytes {
        if !write_byte(port, b) {
            counters.tx_dropped = counters.tx_dropped.wrapping_add(1);
            crate::warn!("AYDP: TX queue full, message dropped");
            return;
        }
    }
}

fn write_byte<P: Write<u8>>(port: &mut P, byte: u8) -> bool {
    for _ in 0..TX_SPIN {
        match port.write(byte) {
            Ok(()) => return true,
            Err(nb::Error::WouldBlock) => {}
            Err(nb::Error::Other(_)) => return false,
        }
    }
    false
}

/// The header time of a normal message at `now_ms`: the wall clock of the last SETTIME plus
/// the time since it arrived, or, without a (valid) SETTIME, the time since boot.
///
/// ```
/// use aeolus_proto::message::SetTime;
/// use aydp_proto::Timestamp;
/// use sensor_box::{Persisted, Shared, aydp_link::timestamp};
/// let mut shared = Shared::new(Persisted::default(), 0);
/// assert_eq!(timestamp(&shared, 12_345), Timestamp::new(12, 345));
/// // 2024-03-01 12:00:00 arrived at 10 s; 2.5 s later:
/// let t = SetTime { year_since_1900: 124, month0: 2, day: 1, hour: 12, minute: 0, second: 0 };
/// shared.wall_clock = Some((t, 10_000));
/// assert_eq!(timestamp(&shared, 12_500), Timestamp::new(1_709_294_402, 500));
/// ```
pub fn timestamp(shared: &Shared, now_ms: u64) -> Timestamp {
    let (base_s, since_ms) = match shared.wall_clock {
        Some((t, at_ms)) => match unix_seconds(&t) {
            Some(s) => (s, now_ms.saturating_sub(at_ms)),
            None => (0, now_ms),
        },
        None => (0, now_ms),
    };
    let secs = i64::try_from(since_ms / 1000).unwrap_or(i64::MAX);
    let ms = i64::try_from(since_ms % 1000).unwrap_or(0);
    Timestamp::new(base_s.saturating_add(secs), ms)
}

/// Seconds since 1970-01-01 00:00:00 UTC of an AEOLUS SETTIME, or `None` if a field is out
/// of range (month 0..=11, a day that exists in that month, hour < 24, minute and second < 60).
///
/// ```
/// use aeolus_proto::message::SetTime;
/// use sensor_box::aydp_link::unix_seconds;
/// let t = SetTime { year_since_1900: 70, month0: 0, day: 1, hour: 0, minute: 0, second: 1 };
/// assert_eq!(unix_seconds(&t), Some(1));
/// let feb29 = SetTime { year_since_1900: 123, month0: 1, day: 29, ..t };
/// assert_eq!(unix_seconds(&feb29), None); // 2023 is not a leap year
/// ```
pub fn unix_seconds(t: &aeolus_proto::message::SetTime) -> Option<i64> {
    let year = 1900 + i64::from(t.year_since_1900);
    let month = i64::from(t.month0) + 1;
    let day = i64::from(t.day);
    let leap = (year % 4 == 0 && year % 100 != 0) || year % 400 == 0;
    let month_days = match month {
        1 | 3 | 5 | 7 | 8 | 10 | 12 => 31,
        4 | 6 | 9 | 11 => 30,
        2 if leap => 29,
        2 => 28,
        _ => return None,
    };
    if day < 1 || day > month_days || t.hour > 23 || t.minute > 59 || t.second > 59 {
        return None;
    }
    // Days from the civil date (years starting in March, so the leap day comes last).
    // Years are 1900..=2155 here, so nothing below can overflow.
    let y = if month <= 2 { year - 1 } else { year };
    let era = y.div_euclid(400);
    let yoe = y - era * 400;
    let mp = (month + 9) % 12;
    let doy = (153 * mp + 2) / 5 + day - 1;
    let doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    let days = era * 146_097 + doe - 719_468;
    Some(days * 86_400 + i64::from(t.hour) * 3600 + i64::from(t.minute) * 60 + i64::from(t.second))
}

/// The registry's storage: a copy of the values in [`Shared`] (and the texts and counters)
/// that the registry's slots point at. An accepted update is copied back with
/// [`View::write_back`]; a rejected one is simply dropped with the view.
struct View {
    direct: u8,
    name: [u8; TEXT_LEN],
    id: [u8; TEXT_LEN],
    hardware: [u8; TEXT_LEN],
    firmware: [u8; TEXT_LEN],
    intervals: [u32; 6],
    airspeed: f32,
    bank: f32,
    altitude: f32,
    aok_period: u32,
    outputs: [f32; OUTPUTS],
    counters: [u32; 10],
}

impl View {
    fn new(shared: &Shared, stats: &Stats, c: &LinkCounters) -> Self {
        let s = shared.settings();
        let i = s.intervals;
        let mut outputs = [0.0; OUTPUTS];
        for (v, o) in outputs.iter_mut().zip(shared.outputs.iter()) {
            *v = o.value;
        }
        View {
            direct: u8::from(shared.direct_control),
            name: SYSTEM_NAME,
            id: SYSTEM_ID,
            hardware: HARDWARE_VERSION,
            firmware: FIRMWARE_VERSION,
            intervals: [
                i.imu_ms,
                i.pressure_ms,
                i.gps_ms,
                i.temp_ms,
                i.wind_ms,
                i.info_ms,
            ],
            airspeed: s.airspeed_mps,
            bank: s.bank_deg,
            altitude: s.altitude_m,
            aok_period: s.aok_debug_period_ms,
            outputs,
            counters: [
                stats.frames_ok,
                stats.checksum_errors,
                stats.length_errors,
                stats.bytes_discarded,
                c.updates_applied,
                c.rejected,
                c.malformed,
                c.requests_answered,
                c.direct_applied,
                c.direct_refused,
            ],
        }
    }

    /// The registry table over this view (see the module table).
    fn slots(&mut self) -> [Slot<'_>; 12] {
        [
            Slot::value(addr::DIRECT_CONTROL, Cell::u8(&mut self.direct)).with_range(0.0, 1.0),
            Slot::value(addr::SYSTEM_NAME, Cell::Chars(&mut self.name)).read_only(),
            Slot::value(addr::SYSTEM_ID, Cell::Chars(&mut self.id)).read_only(),
            Slot::value(addr::HARDWARE_VERSION, Cell::Chars(&mut self.hardware)).read_only(),
            Slot::value(addr::FIRMWARE_VERSION, Cell::Chars(&mut self.firmware)).read_only(),
            Slot::array(addr::INTERVALS, Cell::U32(&mut self.intervals)).with_range(1.0, 60_000.0),
            Slot::value(addr::AIRSPEED, Cell::f32(&mut self.airspeed)).with_range(10.0, 150.0),
            Slot::value(addr::BANK, Cell::f32(&mut self.bank)).with_range(-60.0, 60.0),
            Slot::value(addr::ALTITUDE, Cell::f32(&mut self.altitude)).with_range(-500.0, 11_000.0),
            Slot::value(addr::AOK_DEBUG_PERIOD, Cell::u32(&mut self.aok_period))
                .with_range(0.0, 60_000.0),
            Slot::array(addr::OUTPUTS, Cell::F32(&mut self.outputs)).read_only(),
            Slot::array(addr::LINK_COUNTERS, Cell::U32(&mut self.counters)).read_only(),
        ]
    }

    /// Copies the writable values back into `shared`; rebuilds the flight if airspeed, bank
    /// or altitude changed.
    fn write_back(&self, shared: &mut Shared, now_ms: u64) {
        shared.direct_control = self.direct == 1;
        let s = &mut shared.persisted.settings;
        let [imu_ms, pressure_ms, gps_ms, temp_ms, wind_ms, info_ms] = self.intervals;
        s.intervals = Intervals {
            imu_ms,
            pressure_ms,
            gps_ms,
            temp_ms,
            wind_ms,
            info_ms,
        };
        s.aok_debug_period_ms = self.aok_period;
        let flight_changed = s.airspeed_mps.to_bits() != self.airspeed.to_bits()
            || s.bank_deg.to_bits() != self.bank.to_bits()
            || s.altitude_m.to_bits() != self.altitude.to_bits();
        s.airspeed_mps = self.airspeed;
        s.bank_deg = self.bank;
        s.altitude_m = self.altitude;
        if flight_changed {
            shared.settings_changed(now_ms);
        }
    }
}
