//! When a command may store the record in flash: the one policy every link asks.
//!
//! | rule | why |
//! |---|---|
//! | refused while flying ([`Verdict::InFlight`]) | on the STM32F411 an erase stalls the CPU, so all three links, for one to two seconds (a 128 KiB sector); no protocol requires a store in the air |
//! | at most [`STORE_BURST`] at once, then one per [`STORE_INTERVAL_MS`] ([`Verdict::TooSoon`]) | bounds the flash wear under any command stream: see `docs/RELIABILITY.md`, "Power cuts and flash wear" |
//! | the limit survives resets | each store writes the bucket's debt ([`StorePolicy::debt_ms`]) with the record; boot resumes it ([`StorePolicy::resumed`]), counting only uptime |
//! | an unchanged record is not written | decided by [`persist::store_in`](crate::persist::store_in), which compares each setting group with the map's: no write |
//!
//! The burst lets a PC save everything in one go (the five AOK parameter sets, the start set,
//! the waypoints and the mission POI are eight stores); a minute between stores after it is
//! far more than a person at a PC needs, and at that rate, with the largest record changed
//! every time, a 128 KiB sector of the STM32F411 is erased about 8.4 times a day: its
//! 10 000 cycles last more than three years of a nonstop worst-case command stream.
//!
//! Every refusal is answered by the link (AOK: 'I' in flight, 'E' too soon; AYDP "store
//! configuration" has no answer in the protocol), counted in [`Counters`](crate::state::Counters)
//! (AYDP register 0x0310) and logged. [`Shared::request_store`](crate::Shared::request_store)
//! applies the policy and sets the request.
//!
//! ```
//! use sensor_box::store_policy::{STORE_BURST, STORE_INTERVAL_MS, StorePolicy, Verdict};
//! let mut policy = StorePolicy::new();
//! assert_eq!(policy.check(0, true), Verdict::InFlight);
//! for _ in 0..STORE_BURST {
//!     assert_eq!(policy.check(0, false), Verdict::Accepted);
//! }
//! assert_eq!(policy.check(1_000, false), Verdict::TooSoon);
//! assert_eq!(policy.check(STORE_INTERVAL_MS, false), Verdict::Accepted);
//! assert_eq!(policy.check(STORE_INTERVAL_MS, false), Verdict::TooSoon);
//! ```

/// Stores accepted at once (from a quiet start) before the rate limit applies.
pub const STORE_BURST: u64 = 8;
/// After a burst, one store per this many ms.
pub const STORE_INTERVAL_MS: u64 = 60_000;

/// The policy's answer to a store request.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(all(feature = "defmt", target_os = "none"), derive(defmt::Format))]
pub enum Verdict {
    /// Store.
    Accepted,
    /// Refused: the box is flying.
    InFlight,
    /// Refused: the rate limit (a burst of [`STORE_BURST`], then one per
    /// [`STORE_INTERVAL_MS`]).
    TooSoon,
}

/// The rate limit's state: a token bucket of [`STORE_BURST`] stores refilled one per
/// [`STORE_INTERVAL_MS`], kept as one instant (the generic cell rate algorithm).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct StorePolicy {
    /// The instant the bucket is full again: each accepted store moves it on by the interval.
    full_at_ms: u64,
    /// `full_at_ms` less the time of the last accepted store.
    debt_ms: u64,
}

impl StorePolicy {
    /// A full bucket.
    ///
    /// ```
    /// let mut p = sensor_box::store_policy::StorePolicy::new();
    /// assert_eq!(p.check(0, false), sensor_box::store_policy::Verdict::Accepted);
    /// ```
    pub const fn new() -> Self {
        StorePolicy {
            full_at_ms: 0,
            debt_ms: 0,
        }
    }

    /// Whether a store asked for at `now_ms` may go ahead; an accepted one is counted
    /// against the rate limit.
    pub fn check(&mut self, now_ms: u64, flying: bool) -> Verdict {
        if flying {
            return Verdict::InFlight;
        }
        let slack = (STORE_BURST - 1) * STORE_INTERVAL_MS;
        if self.full_at_ms > now_ms.saturating_add(slack) {
            return Verdict::TooSoon;
        }
        self.full_at_ms = self
            .full_at_ms
            .max(now_ms)
            .saturating_add(STORE_INTERVAL_MS);
        self.debt_ms = self.full_at_ms.saturating_sub(now_ms);
        Verdict::Accepted
    }

    /// How far the bucket was from full right after the last accepted store, ms: what a store
    /// writes to flash with the record, so that the next boot resumes the limit
    /// ([`StorePolicy::resumed`]).
    ///
    /// ```
    /// use sensor_box::store_policy::{STORE_INTERVAL_MS, StorePolicy};
    /// let mut p = StorePolicy::new();
    /// p.check(5_000, false);
    /// p.check(5_000, false);
    /// assert_eq!(p.debt_ms(), 2 * STORE_INTERVAL_MS);
    /// ```
    pub const fn debt_ms(&self) -> u64 {
        self.debt_ms
    }

    /// The policy after a boot at `now_ms` (uptime) with `debt_ms` stored by the last store:
    /// the bucket is full again `debt_ms` after the boot. Time without power does not refill
    /// it (the box cannot tell how long it was off), so resets never add stores.
    ///
    /// ```
    /// use sensor_box::store_policy::{STORE_BURST, STORE_INTERVAL_MS, StorePolicy, Verdict};
    /// let mut p = StorePolicy::resumed(STORE_BURST * STORE_INTERVAL_MS, 0);
    /// assert_eq!(p.check(1_000, false), Verdict::TooSoon); // the burst was spent before the reset
    /// assert_eq!(p.check(STORE_INTERVAL_MS, false), Verdict::Accepted);
    /// ```
    pub const fn resumed(debt_ms: u64, now_ms: u64) -> Self {
        StorePolicy {
            full_at_ms: now_ms.saturating_add(debt_ms),
            debt_ms,
        }
    }
}
