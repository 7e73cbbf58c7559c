//! The schedule: when each [`Kind`] is next due.

use super::Kind;
use crate::state::Intervals;

/// The next-due instant of a kind whose interval is 0.
const OFF: u64 = u64::MAX;

/// The telemetry schedule: when each [`Kind`] is next due.
///
/// ```
/// use sensor_box::{state::Intervals, telemetry::{Kind, Telemetry}};
///
/// let mut t = Telemetry::new(1_000);
/// // At boot everything is due once.
/// assert_eq!(t.due(1_000, &Intervals::SPEC).count(), Kind::COUNT);
/// assert_eq!(t.due(1_001, &Intervals::SPEC).count(), 0);
/// // 5 ms later: PRESSURE; 7 ms later: the five IMU messages.
/// assert_eq!(t.due(1_005, &Intervals::SPEC).collect::<Vec<_>>(), [Kind::Pressure]);
/// assert_eq!(t.due(1_007, &Intervals::SPEC).count(), 5);
/// assert_eq!(t.next_due_ms(Kind::Gps), 1_092);
/// ```
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Telemetry {
    next_ms: [u64; Kind::COUNT],
    skipped: u32,
    /// After a complete [`Telemetry::due`] pass: its instant, the earliest next due instant
    /// and the intervals of that pass. While the intervals stay the same nothing is due before it, so
    /// a millisecond with nothing due costs one comparison instead of a pass over every kind
    /// (a changed interval, or a kind turned on or off, takes the full pass again).
    quiet: Option<(u64, u64, Intervals)>,
}

impl Telemetry {
    /// Due instants kept per kind after a stall; older ones are dropped.
    pub const MAX_LATE: u64 = 2;

    /// A schedule starting at `now_ms`: every kind is due at once.
    pub const fn new(now_ms: u64) -> Self {
        Telemetry {
            next_ms: [now_ms; Kind::COUNT],
            skipped: 0,
            quiet: None,
        }
    }

    /// Starts the schedule over at `now_ms` (after a pause): every kind is due at once and
    /// nothing missed meanwhile is sent or counted.
    ///
    /// ```
    /// use sensor_box::{state::Intervals, telemetry::Telemetry};
    /// let mut t = Telemetry::new(0);
    /// t.restart(60_000);
    /// assert_eq!(t.due(60_000, &Intervals::SPEC).count(), 10);
    /// assert_eq!(t.skipped(), 0);
    /// ```
    pub fn restart(&mut self, now_ms: u64) {
        self.next_ms = [now_ms; Kind::COUNT];
        self.quiet = None;
    }

    /// When `kind` is next due, ms (`u64::MAX` while its interval is 0).
    pub fn next_due_ms(&self, kind: Kind) -> u64 {
        self.next_ms.get(kind.index()).copied().unwrap_or(u64::MAX)
    }

    /// The earliest instant at which [`Telemetry::due`] with `intervals` can yield a kind: the
    /// end of the quiet time the last complete pass saw, while the intervals are the ones it saw;
    /// 0 (due at once) before a complete pass and after a change of the intervals, which only
    /// a pass can take in. A caller that sleeps until then misses nothing.
    ///
    /// ```
    /// use sensor_box::{state::Intervals, telemetry::Telemetry};
    /// let mut t = Telemetry::new(1_000);
    /// assert_eq!(t.next_due(&Intervals::SPEC), 0); // no pass yet
    /// assert_eq!(t.due(1_000, &Intervals::SPEC).count(), 10);
    /// assert_eq!(t.next_due(&Intervals::SPEC), 1_005); // PRESSURE, every 5 ms
    /// let faster = Intervals { pressure_ms: 2, ..Intervals::SPEC };
    /// assert_eq!(t.next_due(&faster), 0); // a changed interval takes a pass at once
    /// ```
    pub fn next_due(&self, intervals: &Intervals) -> u64 {
        match self.quiet {
            Some((_, until, seen)) if seen == *intervals => until,
            _ => 0,
        }
    }

    /// Due instants dropped after stalls (wrapping).
    ///
    /// ```
    /// use sensor_box::{state::Intervals, telemetry::{Kind, Telemetry}};
    /// let mut t = Telemetry::new(0);
    /// let _ = t.due(0, &Intervals::SPEC).count();
    /// // A 50 ms stall: PRESSURE had 10 due instants (5, 10, ..., 50), keeps 2 and sends one.
    /// let late: Vec<Kind> = t.due(50, &Intervals::SPEC).collect();
    /// assert!(late.contains(&Kind::Pressure));
    /// assert_eq!(t.next_due_ms(Kind::Pressure), 50); // the second kept instant, sent next poll
    /// assert_eq!(t.skipped(), 8 + 5 * 5); // PRESSURE 8 of 10, each 7 ms kind 5 of 7
    /// ```
    pub const fn skipped(&self) -> u32 {
        self.skipped
    }

    /// The kinds due at `now_ms`, each at most once, in [`Kind::ALL`] order. Iterating
    /// consumes them (their next due instant moves on); kinds not reached because the iterator
    /// was dropped early stay due.
    pub fn due(&mut self, now_ms: u64, intervals: &Intervals) -> Due<'_> {
        let (quiet, settled) = match self.quiet {
            Some((from, until, seen)) if from <= now_ms && seen == *intervals => {
                (now_ms < until, true)
            }
            _ => (false, false),
        };
        if !quiet {
            self.quiet = None;
        }
        Due {
            telemetry: self,
            now_ms,
            intervals: *intervals,
            // Nothing can be due: an iterator that is already at its end.
            index: if quiet { Kind::COUNT } else { 0 },
            settled,
            until: OFF,
        }
    }

    /// Whether `kind` is due at `now_ms`; if it is, moves its due instant on.
    fn take(&mut self, kind: Kind, now_ms: u64, interval_ms: u32) -> bool {
        let Some(next) = self.next_ms.get_mut(kind.index()) else {
            return false;
        };
        if interval_ms == 0 {
            *next = OFF;
            return false;
        }
        if *next == OFF {
            // Turned on again: due at once.
            *next = now_ms;
        }
        let interval = u64::from(interval_ms);
        let latest = now_ms.saturating_add(interval);
        if *next > latest {
            // The interval was shortened: do not wait out the old one.
            *next = latest;
        }
        if now_ms < *next {
            return false;
        }
        let late = now_ms - *next;
        // On time (the usual case) without a 64-bit division.
        let due_instants = if late < interval {
            1
        } else {
            late / interval + 1
        };
        if due_instants > Self::MAX_LATE {
            let drop = due_instants - Self::MAX_LATE;
            *next = next.saturating_add(drop.saturating_mul(interval));
            self.skipped = self
                .skipped
                .wrapping_add(u32::try_from(drop).unwrap_or(u32::MAX));
        }
        *next = next.saturating_add(interval);
        true
    }
}

/// The iterator of [`Telemetry::due`].
pub struct Due<'a> {
    telemetry: &'a mut Telemetry,
    now_ms: u64,
    intervals: Intervals,
    index: usize,
    /// The last complete pass had these intervals, at or before `now_ms`: every due instant
    /// is then at most one interval after `now_ms` and each kind is on or off as it was, so a
    /// kind not yet due needs no other rule than `now_ms < next` (the clamp of a shortened
    /// interval and the turn on or off cannot apply).
    settled: bool,
    /// The earliest due instant seen in this pass, after its kind was taken.
    until: u64,
}

impl Iterator for Due<'_> {
    type Item = Kind;

    fn next(&mut self) -> Option<Kind> {
        while let Some(&kind) = Kind::ALL.get(self.index) {
            self.index += 1;
            let next = self.telemetry.next_due_ms(kind);
            let due = if self.settled && self.now_ms < next {
                false
            } else {
                let interval = kind.interval_ms(&self.intervals);
                self.telemetry.take(kind, self.now_ms, interval)
            };
            self.until = self.until.min(self.telemetry.next_due_ms(kind));
            if self.index == Kind::COUNT {
                // A complete pass: nothing is due before `until` while the intervals stay.
                self.telemetry.quiet = Some((self.now_ms, self.until, self.intervals));
            }
            if due {
                return Some(kind);
            }
        }
        None
    }
}
