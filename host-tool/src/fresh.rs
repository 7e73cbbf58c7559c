//! How long a telemetry value stays current for what the faces send or show: an older one
//! goes out as its format's invalid form, never as the old value.

use std::time::{Duration, Instant};

/// How long PRESSURE, GPS, COMPASS, ATTITUDE and ACCEL stay current (they come 10 to 200 times
/// a second, GPS about once).
pub(crate) const FRESH: Duration = Duration::from_secs(1);

/// How long a TEMP or WIND stays current, which the box sends about once a second (spec
/// figure 1c: 829 ms and 1000 ms): two and a half of their intervals.
pub(crate) const FRESH_SLOW: Duration = Duration::from_millis(2500);

/// `v` if it arrived within `limit` of `now`.
pub(crate) fn fresh_within<T: Copy>(
    v: &Option<(T, Instant)>,
    now: Instant,
    limit: Duration,
) -> Option<T> {
    v.filter(|(_, at)| now.saturating_duration_since(*at) <= limit)
        .map(|(v, _)| v)
}

/// `v` if it arrived within [`FRESH`] of `now`.
pub(crate) fn fresh<T: Copy>(v: &Option<(T, Instant)>, now: Instant) -> Option<T> {
    fresh_within(v, now, FRESH)
}
