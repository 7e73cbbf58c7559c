//! The LM3S6965 as QEMU's `lm3s6965evb` models it, below the drivers: the core clock, the
//! watchdog, the reset records, the interrupt vectors, the fault and panic exits, the stack's
//! high-water mark. The register map and the interrupt table are the blocking QEMU board's
//! (`firmware_example::lm3s6965`), and so are the facts about QEMU's behaviour
//! (`firmware-example/src/board/qemu.rs`, which states their sources).

use core::mem::MaybeUninit;
use core::ptr::{addr_of_mut, read_volatile, write_volatile};

use firmware_example::lm3s6965::sysctl::{
    self, PLL_LOCK_POLLS, RCC_BYPASS, RCC_PWRDN, RCC_SYSDIV_MASK, RCC_SYSDIV_SHIFT, RCC_USESYSDIV,
    RCGC0_WDT, RCGC1_UARTS, RIS_PLLLRIS,
};
use firmware_example::lm3s6965::{self, uart, wdt};

use super::pl011;

/// The system clock divisor: 15, the reset value's (12.5 MHz), as the blocking board.
#[cfg(not(feature = "cpu-budget"))]
const SYSDIV: u32 = 15;
/// The `cpu-budget` build: 0, which QEMU's model turns into a 200 MHz core clock (5
/// instructions a SysTick count under `-icount shift=0`, the account's resolution), as the
/// blocking board's budget build. Only QEMU is meant: a real LM3S6965 would run out of spec.
#[cfg(feature = "cpu-budget")]
const SYSDIV: u32 = 0;
/// The core clock, Hz: what SysTick, the watchdog and the UARTs count.
pub const CORE_HZ: u32 = lm3s6965::core_hz(SYSDIV);

/// Runs the core from the PLL divided by `SYSDIV + 1` ([`CORE_HZ`]) and clocks the watchdog
/// and the three UARTs. Call once, first.
pub fn init_clocks() {
    // SAFETY: valid LM3S6965 system-control registers, used by nothing else; this runs before
    // SysTick, the UARTs and the watchdog start.
    unsafe {
        let rcc = read_volatile(sysctl::RCC as *const u32);
        write_volatile(sysctl::RCC as *mut u32, rcc & !RCC_PWRDN);
        let mut polls = 0;
        while read_volatile(sysctl::RIS as *const u32) & RIS_PLLLRIS == 0 && polls < PLL_LOCK_POLLS
        {
            polls += 1;
        }
        let run = (rcc & !(RCC_PWRDN | RCC_BYPASS | RCC_SYSDIV_MASK))
            | RCC_USESYSDIV
            | (SYSDIV << RCC_SYSDIV_SHIFT);
        write_volatile(sysctl::RCC as *mut u32, run);
        let rcgc0 = read_volatile(sysctl::RCGC0 as *const u32);
        write_volatile(sysctl::RCGC0 as *mut u32, rcgc0 | RCGC0_WDT);
        write_volatile(sysctl::RCGC1 as *mut u32, RCGC1_UARTS);
    }
}

// ------------------------------------------------------------------ watchdog

/// One time-out of the watchdog, ms: its interrupt (masked) after one, the reset after two,
/// so the box resets 4 s after the last feed, as the blocking QEMU board.
pub const WATCHDOG_LOAD_MS: u32 = 2_000;

/// The running watchdog; only the supervisor task holds it.
pub struct Watchdog(());

impl Watchdog {
    /// Starts the watchdog (load, then INTEN and RESEN; only a reset stops it).
    pub fn start() -> Self {
        // SAFETY: valid LM3S6965 watchdog registers, used by nothing else.
        unsafe {
            write_volatile(wdt::LOAD as *mut u32, CORE_HZ / 1_000 * WATCHDOG_LOAD_MS);
            write_volatile(wdt::CTL as *mut u32, wdt::CTL_INTEN_RESEN);
        }
        Watchdog(())
    }

    /// Clears the time-out interrupt and reloads the counter (a write of WDTICR).
    pub fn feed(&mut self) {
        // SAFETY: WDTICR is a valid LM3S6965 watchdog register; any value feeds.
        unsafe { write_volatile(wdt::ICR as *mut u32, 1) }
    }
}

// ------------------------------------------------------------------ resets

/// The RESC bit of a watchdog reset (QEMU's model never sets it).
pub const WATCHDOG_CAUSE: u32 = sysctl::RESC_WDT;

/// RESC, read and cleared: what caused this reset.
pub fn reset_cause() -> u32 {
    // SAFETY: RESC is a valid LM3S6965 system-control register; writing 0 clears it.
    unsafe {
        let resc = read_volatile(sysctl::RESC as *const u32);
        write_volatile(sysctl::RESC as *mut u32, 0);
        resc
    }
}

/// [`RUN`]'s first word while the firmware runs: a boot that finds it was not asked for.
const RUNNING: u32 = 0x5744_4F47;
/// [`RUN`]'s first word after [`reset`]: the firmware asked for the reset.
const REQUESTED: u32 = 0x5245_5154;

/// How the last run ended and the resets not asked for since power-on, in `.uninit` (a warm
/// reset keeps it; QEMU's reset leaves RAM alone).
#[unsafe(link_section = ".uninit.sensor_box_run")]
static mut RUN: MaybeUninit<[u32; 2]> = MaybeUninit::uninit();

/// Called once at boot: whether this reset was not asked for (the last run was still
/// running: the watchdog, a HardFault) and the count of those since power-on.
pub fn unrequested_resets() -> (bool, u32) {
    let p = addr_of_mut!(RUN).cast::<u32>();
    // SAFETY: two words of RAM only this file touches; any bit pattern is a valid `u32`.
    unsafe {
        let (state, count) = (read_volatile(p), read_volatile(p.add(1)));
        let (unrequested, count) = match state {
            RUNNING => (true, count.wrapping_add(1)),
            REQUESTED => (false, count),
            _ => (false, 0),
        };
        write_volatile(p, RUNNING);
        write_volatile(p.add(1), count);
        (unrequested, count)
    }
}

/// A warm reset the firmware asked for (a reboot command): RAM, and with it the settings in
/// `.flash_emu`, survives it.
pub fn reset() -> ! {
    // SAFETY: the word only this file touches.
    unsafe { write_volatile(addr_of_mut!(RUN).cast::<u32>(), REQUESTED) };
    cortex_m::peripheral::SCB::sys_reset()
}

/// A HardFault: one line with the faulting PC, then a warm reset (not asked for).
#[cortex_m_rt::exception]
unsafe fn HardFault(frame: &cortex_m_rt::ExceptionFrame) -> ! {
    defmt::error!("HardFault: resetting (pc {=u32:#010x})", frame.pc());
    cortex_m::peripheral::SCB::sys_reset()
}

#[panic_handler]
fn panic(info: &core::panic::PanicInfo) -> ! {
    match info.location() {
        Some(l) => defmt::error!("panic at {=str}:{=u32}", l.file(), l.line()),
        None => defmt::error!("panic"),
    }
    semihosting::process::exit(101)
}

// ------------------------------------------------------------------ interrupts

/// The LM3S6965 interrupt lines the board uses.
#[derive(Clone, Copy)]
#[repr(u16)]
pub enum Irq {
    /// UART0 (AEOLUS).
    Uart0 = uart::IRQ[0],
    /// UART1 (AYDP).
    Uart1 = uart::IRQ[1],
    /// UART2 (AOK).
    Uart2 = uart::IRQ[2],
}

// SAFETY: the numbers are the LM3S6965's UART0..2 interrupt lines.
unsafe impl cortex_m::interrupt::InterruptNumber for Irq {
    fn number(self) -> u16 {
        self as u16
    }
}

firmware_example::lm3s6965_interrupts!(uart0, uart1, uart2);

unsafe extern "C" fn uart0() {
    pl011::on_interrupt(0);
}

unsafe extern "C" fn uart1() {
    pl011::on_interrupt(1);
}

unsafe extern "C" fn uart2() {
    pl011::on_interrupt(2);
}

// ------------------------------------------------------------------ stack

/// What cortex-m-rt's `paint-stack` writes over the stack before `main`.
const STACK_PAINT: u32 = 0xCCCC_CCCC;

unsafe extern "C" {
    static _stack_start: u32;
    static _stack_end: u32;
}

/// The stack's size and its high-water mark (the deepest it has been: the lowest word no
/// longer holding the paint), bytes.
pub fn stack() -> (usize, usize) {
    let top = &raw const _stack_start as usize;
    let bottom = &raw const _stack_end as usize;
    let mut p = bottom;
    while p < top {
        // SAFETY: a word-aligned address inside the stack region (always mapped RAM);
        // volatile, as the stack changes under us.
        if unsafe { read_volatile(p as *const u32) } != STACK_PAINT {
            break;
        }
        p += 4;
    }
    (top.saturating_sub(p), top.saturating_sub(bottom))
}
