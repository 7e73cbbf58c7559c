//! SysTick as a 64-bit tick counter.
//!
//! SysTick runs from the core clock with the largest reload (2^24 ticks per period); its
//! exception counts the periods, so [`Clock::now`] never wraps. Under QEMU `-icount shift=0`
//! virtual time advances exactly one nanosecond per executed instruction, so a tick is worth a
//! fixed number of instructions: `main.rs` calibrates it.

use core::sync::atomic::{AtomicU32, Ordering};

use cortex_m::peripheral::{SYST, syst::SystClkSource};
use cortex_m_rt::exception;

/// Reload value: the full 24 bits, so one period is 2^24 ticks.
const RELOAD: u32 = 0x00FF_FFFF;

/// SysTick periods elapsed since [`Clock::start`].
static WRAPS: AtomicU32 = AtomicU32::new(0);

/// The SysTick exception: one more full period. (Its own few instructions count into a
/// measurement that spans a wrap; `main.rs` reports the wraps, and a period is 2^24 ticks.)
#[exception]
fn SysTick() {
    WRAPS.fetch_add(1, Ordering::Relaxed);
}

/// The running SysTick (owning the peripheral, so nothing else reprograms it).
pub struct Clock {
    _syst: SYST,
}

impl Clock {
    /// Starts SysTick from the core clock, full reload, exception enabled.
    pub fn start(mut syst: SYST) -> Self {
        syst.disable_counter();
        syst.set_clock_source(SystClkSource::Core);
        syst.set_reload(RELOAD);
        syst.clear_current();
        syst.enable_interrupt();
        syst.enable_counter();
        Clock { _syst: syst }
    }

    /// Ticks since [`Clock::start`] (SysTick counts down; periods come from the exception).
    #[inline(always)]
    pub fn now(&self) -> u64 {
        loop {
            let wraps = WRAPS.load(Ordering::SeqCst);
            let current = SYST::get_current();
            // A wrap between the two loads would pair a new period with an old count.
            if WRAPS.load(Ordering::SeqCst) == wraps {
                return (u64::from(wraps) << 24) | u64::from(RELOAD - current);
            }
        }
    }

    /// SysTick periods so far (each one ran the exception once).
    pub fn wraps(&self) -> u32 {
        WRAPS.load(Ordering::SeqCst)
    }

    /// Waits for the next tick edge, so every measurement starts at the same phase of a tick
    /// (give or take the few instructions of this loop's iteration).
    #[inline(always)]
    fn sync(&self) {
        let start = SYST::get_current();
        while SYST::get_current() == start {}
    }

    /// Ticks spent in `f` (plus the fixed cost of the two reads, see `overhead` in `main.rs`),
    /// and its result.
    #[inline(never)]
    pub fn measure<R>(&self, f: impl FnOnce() -> R) -> (u64, R) {
        self.sync();
        let t0 = self.now();
        let r = f();
        let t1 = self.now();
        (t1 - t0, r)
    }
}
