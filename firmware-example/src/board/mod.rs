//! Board support: one module per board, selected by a cargo feature.
//!
//! Every board module has the same shape:
//!
//! * `NAME`: the board's name, for the boot log;
//! * `Port`: its [`QueuedSerial`](firmware_example::QueuedSerial) (the sizes of its RX and TX rings);
//! * `Store`: its flash store type (`embedded-storage` `NorFlash`);
//! * `init() -> Board<Store>`: clocks, SysTick, three interrupt-driven UARTs,
//!   the flash store and the running watchdog;
//! * `Watchdog`: its watchdog (`feed`), and `reset_cause()`: its reset-status
//!   register, read and cleared, with `WATCHDOG_CAUSE` (the register's watchdog bit);
//! * the UART interrupt handlers, which move bytes between the UARTs and the
//!   queues behind [`QueuedSerial`](firmware_example::QueuedSerial).
//!
//! What is the same on every Cortex-M (the millisecond clock, the painted
//! stack, the warm reset, the HardFault handler, the count of resets the firmware did not
//! ask for) is in this file.
//!
//! ## The watchdog
//!
//! Every board starts its watchdog in `init`; only the main loop feeds it, once per pass
//! (`main.rs`), and the loop never sleeps longer than [`FEED_MS`]. A main loop that stops
//! (a hang, a livelock in a link, an interrupt storm that starves it) is reset; a hang in
//! an interrupt handler too, since the loop then never runs. Interrupts alone do not keep
//! the box alive: SysTick and the UARTs never feed it.
//!
//! | board | watchdog | clock | reset after | why that long |
//! |---|---|---|---|---|
//! | `board-qemu` | LM3S6965 watchdog (QEMU `luminary-watchdog`) | system clock, 12.5 MHz | 4 s (load 2 s: the first time-out raises the interrupt, the second resets) | 4 x [`FEED_MS`]; the store is RAM, no erase |
//! | `board-stm32f411` | IWDG | LSI, 32 kHz nominal (17 to 47 kHz) | 8 s nominal, 5.4 s to 15 s over the LSI's range | above the 4 s worst-case 128 KiB sector erase at x8 parallelism (the HAL's `PSIZE`), which blocks the loop |
//! | `qemu-stm32` | none in QEMU: `netduinoplus2`'s IWDG is an unimplemented-device stub (writes ignored) | | never | |
//!
//! | board feature     | target                 | module           | memory map                |
//! |-------------------|------------------------|------------------|---------------------------|
//! | `board-qemu`      | `thumbv7m-none-eabi`   | `qemu.rs`        | `memory.x` (top level)    |
//! | `board-stm32f411` | `thumbv7em-none-eabihf`| `stm32f411.rs`   | `board/stm32f411.x`       |

use core::cell::Cell;
use core::sync::atomic::{AtomicU8, Ordering};
use critical_section::Mutex;
use firmware_example::Clock;

#[cfg(all(feature = "board-qemu", feature = "board-stm32f411"))]
compile_error!("choose one board: `board-qemu` or `board-stm32f411`, not both");
#[cfg(not(any(feature = "board-qemu", feature = "board-stm32f411")))]
compile_error!(
    "the sensor-box firmware needs a board: `cargo qemu` / `--features board-qemu`, or `cargo stm32` / `--features board-stm32f411`"
);

#[cfg(feature = "board-qemu")]
mod qemu;
#[cfg(feature = "board-qemu")]
pub use qemu::{NAME, Port, WATCHDOG_CAUSE, Watchdog, init, reset_cause, store_layout};

#[cfg(feature = "board-stm32f411")]
mod stm32f411;
#[cfg(feature = "board-stm32f411")]
pub use stm32f411::{NAME, Port, WATCHDOG_CAUSE, Watchdog, init, reset_cause, store_layout};

/// What `init` hands to the application.
pub struct Board<S> {
    /// UART0: AEOLUS.
    pub uart0: Port,
    /// UART1: AYDP.
    pub uart1: Port,
    /// UART2: AOK.
    pub uart2: Port,
    /// Milliseconds since boot.
    pub clock: SysTickClock,
    /// The settings store.
    pub store: S,
    /// The watchdog, running: feed it once per main-loop pass.
    pub watchdog: Watchdog,
}

/// Warm reset (`SCB::sys_reset`), asked for by the firmware (a reboot command): RAM is not
/// cleared, so QEMU's emulated flash survives; the STM32's real flash survives anyway.
pub fn reset() -> ! {
    set_run(REQUESTED);
    cortex_m::peripheral::SCB::sys_reset()
}

/// A HardFault (a bad memory access, an undefined instruction, an escalated fault): one fixed
/// line in the log, `HardFault: resetting` with the faulting PC, then a warm reset, so a box
/// in the field comes back instead of hanging, and a test that reads the log sees it (the
/// soak, `tests/tests/all/soak.rs`, fails on that line). Counted as a reset not asked for.
#[cortex_m_rt::exception]
unsafe fn HardFault(frame: &cortex_m_rt::ExceptionFrame) -> ! {
    defmt::error!("HardFault: resetting (pc {=u32:#010x})", frame.pc());
    cortex_m::peripheral::SCB::sys_reset()
}

// ------------------------------------------------------------ resets not asked for

/// The longest the main loop sleeps, ms: it feeds the watchdog once per pass, and its
/// deadline is clamped to this (with telemetry paused the next wake could be the 5 s
/// status report). A quarter of the shortest watchdog time-out (4 s, QEMU board).
pub const FEED_MS: u64 = 1_000;

/// [`RUN`]'s first word while the firmware runs: a reset that finds it there was not asked
/// for (the watchdog, a HardFault, the reset pin).
const RUNNING: u32 = 0x5744_4F47;
/// [`RUN`]'s first word after [`reset`]: the firmware asked for the reset.
const REQUESTED: u32 = 0x5245_5154;

/// How the last run ended (`RUNNING`, `REQUESTED`, anything else after power-on) and the
/// resets not asked for since power-on. In `.uninit` (cortex-m-rt never initialises it), so a
/// warm reset, or the watchdog's, keeps it.
#[unsafe(link_section = ".uninit.sensor_box_run")]
static mut RUN: core::mem::MaybeUninit<[u32; 2]> = core::mem::MaybeUninit::uninit();

fn set_run(state: u32) {
    // SAFETY: a word of RAM only this file touches, from the main loop before a reset.
    unsafe { core::ptr::write_volatile(core::ptr::addr_of_mut!(RUN).cast::<u32>(), state) }
}

/// Called once at boot: whether this reset was not asked for (the last run was still
/// running), and the count of such resets since power-on (this one included). From then on
/// the run counts as running until [`reset`].
pub fn unrequested_resets() -> (bool, u32) {
    let p = core::ptr::addr_of_mut!(RUN).cast::<u32>();
    // SAFETY: two words of RAM only this file touches; whatever they hold (power-on garbage
    // included) is a valid `u32`, and it is read volatile, as hardware state.
    unsafe {
        let (state, count) = (
            core::ptr::read_volatile(p),
            core::ptr::read_volatile(p.add(1)),
        );
        let (unrequested, count) = match state {
            RUNNING => (true, count.wrapping_add(1)),
            REQUESTED => (false, count),
            _ => (false, 0),
        };
        core::ptr::write_volatile(p, RUNNING);
        core::ptr::write_volatile(p.add(1), count);
        (unrequested, count)
    }
}

// ------------------------------------------------------------ pending

/// Bit `n` set: UART `n`'s interrupt moved received bytes into the port since the main loop
/// last looked (`sensor_box::App::poll_pending` runs that port's link only then, or when the
/// link's own timer says so); bit [`TICK`]: a millisecond has passed. One byte, so the main
/// loop takes all its work in one swap, and any other wake (a run of received bytes below
/// [`WAKE_BYTES`], a TX FIFO refilled) finds it zero and goes back to sleep at once.
static RECEIVED: AtomicU8 = AtomicU8::new(0);

/// The bit of [`RECEIVED`] that SysTick sets when the clock reaches the main loop's deadline
/// ([`wake_at`]): a link's timer or the telemetry schedule is due.
const TICK: u8 = 1 << 7;

/// Bit `n` set: UART `n`'s interrupt holds received bytes its link has not been woken for
/// (fewer than [`WAKE_BYTES`]): the next SysTick has the interrupt publish them (QEMU board,
/// `SerialIsr::receive_batched`), or wakes the link (STM32 board).
static HELD: AtomicU8 = AtomicU8::new(0);

/// Received bytes that wake a link at once; fewer wait for the next millisecond's SysTick, so a
/// link takes a flood in runs of at least this many bytes (its cost per wake spread over them)
/// and a lone command waits at most 1 ms. On the QEMU board the PL011 holds bytes back while
/// the RX ring is full, so nothing is lost while the link waits; its interrupt also publishes
/// the bytes to the ring's reader in runs of this many (`SerialIsr::receive_batched`: one
/// grant and commit of the ring per run, not per interrupt). 128 is half the AEOLUS link's
/// `RX_BUDGET` and a quarter of the board's 512-byte RX rings (64 with 256-byte rings until
/// issue 29's seventh round: twice the main-loop passes under a flood).
#[cfg(feature = "board-qemu")]
pub const WAKE_BYTES: usize = 128;

/// On the STM32 board every received byte wakes its link: its USART has no FIFO and cannot
/// hold bytes back, so a full RX ring drops them, and a link that had stopped decoding to keep
/// room for its answers must run again as soon as possible (with 64, as on the QEMU board then, a
/// CI run of `qemu_firmware` lost 33 and 45 bytes of the board's 40-command burst, once the
/// main loop no longer ran on every interrupt).
#[cfg(feature = "board-stm32f411")]
pub const WAKE_BYTES: usize = 1;

/// Marks UART `index`'s link to run at the next main-loop pass.
fn mark_received(index: usize) {
    RECEIVED.fetch_or(1u8 << (index & 7), Ordering::Relaxed);
}

/// Marks UART `index` as holding received bytes its link has not been woken for: the next
/// SysTick has them published (QEMU board) or wakes the link (STM32 board). A plain load
/// first: under a flood the bit is already set on most interrupts.
fn hold(index: usize) {
    let bit = 1u8 << (index & 7);
    if HELD.load(Ordering::Relaxed) & bit == 0 {
        HELD.fetch_or(bit, Ordering::Relaxed);
    }
}

/// Called by UART `index`'s interrupt after it queued `n` received bytes, `since` of them
/// (`n` included) since it last woke the link: wakes the link when they reach [`WAKE_BYTES`]
/// (and returns 0, the new count), else leaves it to the next SysTick (and returns `since`).
#[cfg(feature = "board-stm32f411")]
pub fn received(index: usize, since: usize) -> usize {
    if since >= WAKE_BYTES {
        mark_received(index);
        0
    } else {
        hold(index);
        since
    }
}

/// Which UARTs received bytes since the last call (and clears the flags).
pub fn take_received() -> [bool; 3] {
    let bits = RECEIVED.swap(0, Ordering::Relaxed);
    [bits & 1 != 0, bits & 2 != 0, bits & 4 != 0]
}

/// Whether the main loop has work: a millisecond passed, or a UART woke its link, since it
/// last took the flags ([`take_received`]). The loop sleeps only when it has none; call with
/// interrupts off, so none can slip in before the `wfi`.
pub fn has_work() -> bool {
    RECEIVED.load(Ordering::Relaxed) != 0
}

// ---------------------------------------------------------------- clock

static MILLIS: Mutex<Cell<u64>> = Mutex::new(Cell::new(0));

/// The millisecond at which SysTick wakes the main loop ([`wake_at`]); 0 at boot, so the
/// first tick wakes it.
static DEADLINE: Mutex<Cell<u64>> = Mutex::new(Cell::new(0));

/// Whether SysTick wakes the main loop every millisecond whatever its deadline: only in the
/// STM32 board's QEMU build (`qemu-stm32`), where the USART model raises no TXE interrupt, so
/// queued bytes leave only when the application kicks the handler, which the main loop's
/// `flush` of each port does once a pass (with the deadline alone, a TOAST queued while
/// telemetry was paused waited for the next AOK debug frame's wake, a byte per wake).
const EVERY_MS: bool = cfg!(feature = "qemu-stm32");

/// Asks SysTick to wake the main loop when the clock reaches `deadline_ms` (ms since boot),
/// or at once if it already has. Until the next call, a millisecond before it costs SysTick
/// one comparison and the main loop nothing; received bytes still wake their links.
pub fn wake_at(deadline_ms: u64) {
    critical_section::with(|cs| {
        if MILLIS.borrow(cs).get() >= deadline_ms {
            RECEIVED.fetch_or(TICK, Ordering::Relaxed);
        }
        DEADLINE.borrow(cs).set(deadline_ms);
    });
}

/// The SysTick millisecond, for the UART handlers: each tells its `SerialIsr` the time before
/// it takes bytes (`SerialIsr::at`), so that the AOK link tells apart the commands that waited
/// in the RX ring while the main loop stalled (a flash store).
fn now_ms() -> u64 {
    critical_section::with(|cs| MILLIS.borrow(cs).get())
}

/// The SysTick millisecond clock (a handle; the count lives in a static).
#[derive(Clone, Copy)]
pub struct SysTickClock(());

impl Clock for SysTickClock {
    fn now_ms(&self) -> u64 {
        now_ms()
    }
}

/// Starts SysTick at 1 kHz from the core clock.
fn start_systick(mut syst: cortex_m::peripheral::SYST, core_hz: u32) -> SysTickClock {
    use cortex_m::peripheral::syst::SystClkSource;
    syst.set_clock_source(SystClkSource::Core);
    syst.set_reload(core_hz / 1000 - 1);
    syst.clear_current();
    syst.enable_counter();
    syst.enable_interrupt();
    SysTickClock(())
}

#[cortex_m_rt::exception]
fn SysTick() {
    let previous = sensor_box::budget::enter(sensor_box::budget::Category::Tick);
    let due = critical_section::with(|cs| {
        let c = MILLIS.borrow(cs);
        let now = c.get().wrapping_add(1);
        c.set(now);
        EVERY_MS || now >= DEADLINE.borrow(cs).get()
    });
    // The main loop runs when its deadline has come, and for the links of UARTs with bytes
    // below the wake threshold: on the QEMU board their interrupts publish those bytes first
    // (and wake the links), elsewhere the links are woken here. A plain load first: most
    // milliseconds nothing is held.
    let held = if HELD.load(Ordering::Relaxed) != 0 {
        HELD.swap(0, Ordering::Relaxed)
    } else {
        0
    };
    #[cfg(feature = "board-qemu")]
    let held = {
        if held != 0 {
            qemu::publish_held(held);
        }
        0
    };
    let work = held | if due { TICK } else { 0 };
    if work != 0 {
        RECEIVED.fetch_or(work, Ordering::Relaxed);
    }
    sensor_box::budget::leave(previous);
}

// ---------------------------------------------------------------- stack

/// The value cortex-m-rt's `paint-stack` feature writes over the whole stack
/// before `main` (it must match cortex-m-rt's `STACK_PAINT_VALUE`).
const STACK_PAINT: u32 = 0xCCCC_CCCC;

unsafe extern "C" {
    static _stack_start: u32;
    static _stack_end: u32;
}

/// Stack size, bytes: from the end of static RAM to the top of RAM.
pub fn stack_size() -> usize {
    let top = &raw const _stack_start as usize;
    let bottom = &raw const _stack_end as usize;
    top.saturating_sub(bottom)
}

/// The stack high-water mark, bytes: the deepest the stack has ever been,
/// found as the lowest word no longer holding the paint.
pub fn stack_high_water() -> usize {
    let top = &raw const _stack_start as usize;
    let mut p = &raw const _stack_end as usize;
    // Four painted words a step while four fit (the unpainted word among them is then found
    // one word at a time below): the report scans the whole unused stack, tens of KiB.
    while p + 16 <= top {
        // SAFETY: p..p + 16 is word-aligned and inside the stack region, which is always
        // mapped RAM; volatile because the stack changes under us.
        let (a, b, c, d) = unsafe {
            (
                core::ptr::read_volatile(p as *const u32),
                core::ptr::read_volatile((p + 4) as *const u32),
                core::ptr::read_volatile((p + 8) as *const u32),
                core::ptr::read_volatile((p + 12) as *const u32),
            )
        };
        if (a ^ STACK_PAINT) | (b ^ STACK_PAINT) | (c ^ STACK_PAINT) | (d ^ STACK_PAINT) != 0 {
            break;
        }
        p += 16;
    }
    while p < top {
        // SAFETY: p is a word-aligned address inside the stack region, which
        // is always mapped RAM; volatile because the stack changes under us.
        let word = unsafe { core::ptr::read_volatile(p as *const u32) };
        if word != STACK_PAINT {
            break;
        }
        p += 4;
    }
    top - p
}
