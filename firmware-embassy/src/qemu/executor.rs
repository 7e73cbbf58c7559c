//! The thread-mode executor of the QEMU board: `embassy-executor`'s raw executor, asleep in
//! `wfi` while no task is ready.
//!
//! `embassy-executor`'s own Cortex-M thread executor sleeps in `wfe` and is woken by `sev`.
//! QEMU 7.2 does not halt an M-profile core on `wfe` (it only yields to its main loop), so that
//! executor never sleeps there: the emulated box spun a whole host core while idle (94 % of one
//! core against the blocking board's 11 %, 10 s after boot with nothing received), which
//! starved QEMU's own I/O thread on a 2-core host, and under `-icount` every idle nanosecond of
//! the box's clock was an executed instruction. `wfi` halts QEMU's core until an interrupt.
//!
//! A wake-up ([`__pender`]) sets [`READY`]; the loop clears it before each poll and sleeps
//! only if nothing set it meanwhile, checked with interrupts masked so that a wake-up from an
//! interrupt between the check and the `wfi` is not lost (`wfi` returns on a pending
//! interrupt even while they are masked; the handler runs when they are unmasked). Every
//! wake-up comes from an interrupt (SysTick's time driver, a UART's) or from a task during a
//! poll.

use core::mem::MaybeUninit;
use core::ptr::addr_of_mut;
use core::sync::atomic::{AtomicBool, Ordering};

use embassy_executor::{Spawner, raw};

/// A task became ready since the loop last cleared it.
static READY: AtomicBool = AtomicBool::new(false);

/// The executor's wake-up (`embassy-executor` calls it when a task becomes ready).
#[unsafe(export_name = "__pender")]
fn __pender(_context: *mut ()) {
    READY.store(true, Ordering::Release);
}

/// Runs the executor for ever: `init` spawns the first tasks, then the loop polls while tasks
/// are ready and sleeps in `wfi` when none is. Call once, from `main`.
pub fn run(init: impl FnOnce(Spawner)) -> ! {
    static mut EXECUTOR: MaybeUninit<raw::Executor> = MaybeUninit::uninit();
    // SAFETY: `main` calls this once and it never returns, so this is the only reference to
    // the executor, for ever.
    let executor: &'static raw::Executor =
        unsafe { (*addr_of_mut!(EXECUTOR)).write(raw::Executor::new(core::ptr::null_mut())) };
    init(executor.spawner());
    loop {
        READY.store(false, Ordering::Release);
        // SAFETY: polled from thread mode only, by this loop.
        unsafe { executor.poll() };
        cortex_m::interrupt::free(|_| {
            if !READY.load(Ordering::Acquire) {
                cortex_m::asm::wfi();
            }
        });
    }
}
