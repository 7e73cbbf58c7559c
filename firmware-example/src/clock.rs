//! A monotonic millisecond clock.
//!
//! The boards count SysTick interrupts at 1 kHz; host tests and simulations
//! drive a [`ManualClock`] by hand, so a test of "10 simulated seconds" takes
//! no real time.

use core::cell::Cell;

/// Milliseconds since boot, never going backwards.
///
/// The application only needs `now_ms`; it takes `&self` so one clock can be
/// shared by everything that schedules work.
pub trait Clock {
    /// Milliseconds since boot.
    fn now_ms(&self) -> u64;
}

impl<C: Clock + ?Sized> Clock for &C {
    fn now_ms(&self) -> u64 {
        (**self).now_ms()
    }
}

/// A clock that only moves when told to.
///
/// ```
/// use firmware_example::{Clock, ManualClock};
/// let clock = ManualClock::new(0);
/// clock.advance(7);
/// assert_eq!(clock.now_ms(), 7);
/// ```
#[derive(Debug, Default, Clone)]
pub struct ManualClock {
    now: Cell<u64>,
}

impl ManualClock {
    /// A clock reading `start_ms`.
    ///
    /// ```
    /// use firmware_example::{Clock, ManualClock};
    /// assert_eq!(ManualClock::new(5).now_ms(), 5);
    /// ```
    pub const fn new(start_ms: u64) -> Self {
        Self {
            now: Cell::new(start_ms),
        }
    }

    /// Moves the clock forward (saturating at `u64::MAX`).
    ///
    /// ```
    /// use firmware_example::{Clock, ManualClock};
    /// let c = ManualClock::new(u64::MAX - 1);
    /// c.advance(10);
    /// assert_eq!(c.now_ms(), u64::MAX);
    /// ```
    pub fn advance(&self, ms: u64) {
        self.now.set(self.now.get().saturating_add(ms));
    }

    /// Sets the clock, but never backwards: an earlier time is ignored.
    ///
    /// ```
    /// use firmware_example::{Clock, ManualClock};
    /// let c = ManualClock::new(100);
    /// c.set(50);
    /// assert_eq!(c.now_ms(), 100);
    /// c.set(150);
    /// assert_eq!(c.now_ms(), 150);
    /// ```
    pub fn set(&self, ms: u64) {
        if ms > self.now.get() {
            self.now.set(ms);
        }
    }
}

impl Clock for ManualClock {
    fn now_ms(&self) -> u64 {
        self.now.get()
    }
}
