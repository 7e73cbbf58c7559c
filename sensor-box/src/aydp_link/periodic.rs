//! What the box sends by itself: the heartbeat, the position and the fix quality on a 1 s
//! grid, the timestamps they carry, and the TX path: every message is encoded into the
//! link's [`TxQueue`](crate::port::TxQueue), which is drained into the port without waiting.

use super::{Ctx, HEARTBEAT_PERIOD_MS, NAV_PERIOD_MS};
use crate::Shared;
use aydp_proto::{FixQuality, Payload, Position, Raw, Timestamp};
use embedded_io::{Write, WriteReady};

/// The heartbeat's payload (sent expedited: type 0x80, no data).
const HEARTBEAT: Raw<'static> = Raw {
    msg_type: 0,
    data: &[],
};

/// The fix quality the simulated GPS reports (3D fix, 10 satellites).
pub const FIX_QUALITY: FixQuality = FixQuality {
    fix_type: 3,
    mean_dop: 1.25,
    hdop: 0.875,
    vdop: 1.5,
    satellites: 10,
};

/// Next deadline after a send at `now`: the next point of the `period` grid that started at
/// `due`, so a late poll neither bursts nor drifts.
fn next_due(due: u64, now: u64, period: u64) -> u64 {
    let late = now.saturating_sub(due);
    now.saturating_sub(late % period.max(1))
        .saturating_add(period)
}

impl Ctx {
    /// Queues the heartbeat, position and fix quality due at `now_ms`, each leaving room for
    /// one longest reply in the TX queue.
    pub(super) fn queue_due(&mut self, now_ms: u64, shared: &Shared) {
        if now_ms >= self.next_heartbeat_ms {
            self.next_heartbeat_ms = next_due(self.next_heartbeat_ms, now_ms, HEARTBEAT_PERIOD_MS);
            // Expedited type 0 with no data: `Message::Heartbeat`, without linking the
            // encoder of every message type behind the `Message` enum.
            self.send(&HEARTBEAT, None, SEND_BUF);
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
            self.send(&position, ts, SEND_BUF);
            self.send(&FIX_QUALITY, ts, SEND_BUF);
        }
    }

    /// Queues one message (normal with `Some(timestamp)`, expedited with `None`), encoded
    /// straight into the TX queue, whole, if it fits with `reserve` bytes to spare; otherwise
    /// it is dropped and counted.
    pub(super) fn send<M: Payload + ?Sized>(
        &mut self,
        message: &M,
        timestamp: Option<Timestamp>,
        reserve: usize,
    ) {
        let encoder = &self.encoder;
        let queued = self
            .tx
            .push_with::<SEND_BUF>(reserve, |out| encoder.encode(message, timestamp, out).ok());
        if !queued {
            self.counters.tx_dropped = self.counters.tx_dropped.wrapping_add(1);
            crate::warn!("AYDP: TX queue full, message dropped");
        }
    }

    /// Hands queued bytes to the port until it has no room.
    pub(super) fn drain<P: Write + WriteReady>(&mut self, port: &mut P) {
        if self.tx.drain(port).is_err() {
            self.counters.port_errors = self.counters.port_errors.wrapping_add(1);
        }
    }
}

/// The longest message the link sends: a registry reply of 64 bytes of value, its address and
/// mode, in a normal (22-byte header) message, with room to spare. Periodic messages leave
/// this much of the TX queue free, and RX decodes a byte only while this much is free.
pub(super) const SEND_BUF: usize = 128;

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
