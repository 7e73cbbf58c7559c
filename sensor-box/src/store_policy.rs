//! When a command may store the record in flash: the one policy every link asks.
//!
//! | rule | why |
//! |---|---|
//! | refused while flying ([`Verdict::InFlight`]) | on the STM32F411 an erase stalls the CPU, so all three links, for one to two seconds (a 128 KiB sector); no protocol requires a store in the air |
//! | at most [`STORE_BURST`] at once, then one per [`STORE_INTERVAL_MS`] ([`Verdict::TooSoon`]) | bounds the flash wear under any command stream: see `docs/RELIABILITY.md`, "Power cuts and flash wear" |
//! | an unchanged record is not written | decided by [`persist::store`](crate::persist::store), which compares the record with the newest image: no erase, no write |
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
}

impl StorePolicy {
    /// A full bucket.
    ///
    /// ```
    /// let mut p = sensor_box::store_policy::StorePolicy::new();
    /// assert_eq!(p.check(0, false), sensor_box::store_policy::Verdict::Accepted);
    /// ```
    pub const fn new() -> Self {
        StorePolicy { full_at_ms: 0 }
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
        Verdict::Accepted
    }
}
