//! The `embassy-time` driver of the QEMU board: SysTick at 1 kHz (the crate's
//! `tick-hz-1_000`), one timer queue.
//!
//! Why SysTick and not a Stellaris GPTM: QEMU models the Cortex-M3's SysTick from the core
//! clock it derives from the LM3S6965's RCC (the blocking board's clock, which
//! `tests/tests/all/box_clock.rs` checks against the host's), and under `-icount` it counts
//! instructions, which the CPU budget needs (`scripts/budget.py`). The links' tick runs every
//! millisecond anyway (`links::TICK_MS`), so an interrupt every millisecond costs nothing a
//! tickless one-shot timer would save, and the driver is a counter and a comparison.
//!
//! The clock is the count of SysTick interrupts, a `u64` (it never wraps). An alarm is the
//! earliest instant in the queue: each tick that reaches it wakes the due tasks
//! ([`Queue::next_expiration`]) and takes the next one. A wake asked for at or before now is
//! woken at once.

use core::cell::{Cell, RefCell};
use core::task::Waker;

use cortex_m::peripheral::SYST;
use cortex_m::peripheral::syst::SystClkSource;
use critical_section::Mutex;
use embassy_time_driver::Driver;
use embassy_time_queue_utils::Queue;

/// The SysTick time driver (the one `embassy-time` calls through `time_driver_impl!`).
struct SysTickDriver {
    /// Milliseconds since SysTick started.
    now: Mutex<Cell<u64>>,
    /// The earliest wake in `queue`, ms (`u64::MAX`: none).
    alarm: Mutex<Cell<u64>>,
    queue: Mutex<RefCell<Queue>>,
}

impl Driver for SysTickDriver {
    fn now(&self) -> u64 {
        critical_section::with(|cs| self.now.borrow(cs).get())
    }

    fn schedule_wake(&self, at: u64, waker: &Waker) {
        critical_section::with(|cs| {
            let mut queue = self.queue.borrow_ref_mut(cs);
            if queue.schedule_wake(at, waker) {
                let now = self.now.borrow(cs).get();
                self.alarm.borrow(cs).set(queue.next_expiration(now));
            }
        });
    }
}

embassy_time_driver::time_driver_impl!(static DRIVER: SysTickDriver = SysTickDriver {
    now: Mutex::new(Cell::new(0)),
    alarm: Mutex::new(Cell::new(u64::MAX)),
    queue: Mutex::new(RefCell::new(Queue::new())),
});

/// Starts SysTick at 1 kHz from the core clock (`core_hz`).
pub fn start(mut syst: SYST, core_hz: u32) {
    syst.set_clock_source(SystClkSource::Core);
    syst.set_reload(core_hz / 1_000 - 1);
    syst.clear_current();
    syst.enable_counter();
    syst.enable_interrupt();
}

/// One millisecond: the clock advances, and the tasks whose wake is due are woken.
#[cortex_m_rt::exception]
fn SysTick() {
    let previous = sensor_box::budget::enter(sensor_box::budget::Category::Tick);
    critical_section::with(|cs| {
        let now = DRIVER.now.borrow(cs).get().wrapping_add(1);
        DRIVER.now.borrow(cs).set(now);
        let alarm = DRIVER.alarm.borrow(cs);
        if now >= alarm.get() {
            alarm.set(DRIVER.queue.borrow_ref_mut(cs).next_expiration(now));
        }
    });
    sensor_box::budget::leave(previous);
}
