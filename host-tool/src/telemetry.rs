//! The live AEOLUS telemetry model that `watch` prints and `web` shows: the latest message of
//! each kind, the arrivals of every message type (count, intervals on the box's and the
//! host's clock, staleness), the vertical speed, and the counts of malformed and truncated
//! frames.

use std::collections::BTreeMap;
use std::time::{Duration, Instant};

use aeolus_proto::message::{AeolusInfo, Attitude, Compass, Gps, Message, Pressure, Temp, Wind};
use aeolus_proto::{Decode, Decoder};

use crate::air_data::AirDataSource;
use crate::decoders::AEOLUS_CAPACITY;
use crate::units::Units;

/// The message IDs the box sends as events, not on a schedule: LOG, TOAST, COMMAND, SETTIME.
/// They are shown as "event N s ago", never as stale.
pub(crate) const EVENTS: [u8; 4] = [
    aeolus_proto::message::id::LOG,
    aeolus_proto::message::id::TOAST,
    aeolus_proto::message::id::COMMAND,
    aeolus_proto::message::id::SETTIME,
];

/// A type is never called stale sooner than this after its last message (host jitter).
pub(crate) const STALE_FLOOR: Duration = Duration::from_millis(100);
/// With no byte at all after this long, the view says so and names the likely causes.
pub(crate) const NO_DATA_AFTER: Duration = Duration::from_secs(2);

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
/// `protolink web` shows the same model in the browser ([`crate::commands::web::state`]).
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
    /// The air data (airspeeds, pressure altitude, vertical speed) every face shares.
    pub(crate) air: AirDataSource,
    /// The units the views show.
    pub(crate) units: Units,
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
            Message::Pressure(v) => {
                self.pressure = Some(*v);
                self.air.take_pressure(v, now);
            }
            Message::Gps(v) => self.gps = Some(*v),
            Message::Compass(v) => self.compass = Some(*v),
            Message::Wind(v) => self.wind = Some(*v),
            Message::Temp(v) => {
                self.temp = Some(*v);
                self.air.take(m, now);
            }
            Message::AeolusInfo(v) => self.info = Some(*v),
            Message::Toast(t) => self.toast = Some(crate::render::escape_text(t.as_bytes())),
            _ => {}
        }
    }

    /// Decodes `bytes` (one read of the endpoint; a whole datagram when `datagram`) with
    /// `decoder` and takes every message into the view, handing each to `also` as well.
    /// Bytes, malformed messages and datagrams that end inside a frame are counted.
    pub(crate) fn feed(
        &mut self,
        decoder: &mut Decoder<AEOLUS_CAPACITY>,
        bytes: &[u8],
        datagram: bool,
        now: Instant,
        mut also: impl FnMut(&Message<'_>),
    ) {
        self.bytes += bytes.len() as u64;
        let read = decode_read(decoder, bytes, datagram, |m| {
            self.take(m, now);
            also(m);
        });
        self.malformed = self.malformed.wrapping_add(read.malformed);
        self.truncated = self.truncated.wrapping_add(u32::from(read.truncated));
    }
}

/// What [`decode_read`] saw besides the messages.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(crate) struct Read {
    /// Frames with a good check whose data did not parse as their type.
    pub(crate) malformed: u32,
    /// A datagram ended inside a frame.
    pub(crate) truncated: bool,
}

/// Decodes one read of AEOLUS telemetry with `decoder` (its `feed` fast path) and hands every
/// message to `take`. A datagram is a whole unit: after it the decoder starts afresh, and a
/// frame it ended inside is reported. The one receive rule of `watch`, `web`, `gdl90` and
/// `nmea`.
pub(crate) fn decode_read(
    decoder: &mut Decoder<AEOLUS_CAPACITY>,
    bytes: &[u8],
    datagram: bool,
    mut take: impl FnMut(&Message<'_>),
) -> Read {
    let mut read = Read::default();
    decoder.feed(bytes, |ev| {
        if let Ok(frame) = ev {
            match frame.message() {
                Ok(m) => take(&m),
                Err(_) => read.malformed = read.malformed.wrapping_add(1),
            }
        }
    });
    if datagram {
        read.truncated = decoder.held_bytes() > 0;
        decoder.reset();
    }
    read
}
