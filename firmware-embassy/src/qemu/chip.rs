//! The LM3S6965 as QEMU's `lm3s6965evb` models it, below the drivers: the core clock, the
//! watchdog, the reset records, the interrupt vectors, the fault and panic exits, the stack's
//! high-water mark. The facts (addresses, bits, QEMU's behaviour) are the blocking QEMU
//! board's (`firmware-example/src/board/qemu.rs`), which states their sources.

use core::mem::MaybeUninit;
use core::ptr::{addr_of_mut, read_volatile, write_volatile};

use super::pl011;

/// The PLL output SYSDIV divides, Hz (QEMU: a 5 ns period times SYSDIV + 1).
const PLL_HZ: u32 = 200_000_000;
/// The system clock divisor: 15, the reset value's (12.5 MHz), as the blocking board.
#[cfg(not(feature = "cpu-budget"))]
const SYSDIV: u32 = 15;
/// The `cpu-budget` build: 0, which QEMU's model turns into a 200 MHz core clock (5
/// instructions a SysTick count under `-icount shift=0`, the account's resolution), as the
/// blocking board's budget build. Only QEMU is meant: a real LM3S6965 would run out of spec.
#[cfg(feature = "cpu-budget")]
const SYSDIV: u32 = 0;
/// The core clock, Hz: what SysTick, the watchdog and the UARTs count.
pub const CORE_HZ: u32 = PLL_HZ / (SYSDIV + 1);

const SYSCTL_RIS: usize = 0x400F_E050;
const SYSCTL_RESC: usize = 0x400F_E05C;
const SYSCTL_RCC: usize = 0x400F_E060;
const SYSCTL_RCGC0: usize = 0x400F_E100;
const SYSCTL_RCGC1: usize = 0x400F_E104;
const RCC_SYSDIV_SHIFT: u32 = 23;
const RCC_SYSDIV_MASK: u32 = 0xF << RCC_SYSDIV_SHIFT;
const RCC_USESYSDIV: u32 = 1 << 22;
const RCC_PWRDN: u32 = 1 << 13;
const RCC_BYPASS: u32 = 1 << 11;
const RIS_PLLLRIS: u32 = 1 << 6;
const PLL_LOCK_POLLS: u32 = 100_000;
const RCGC0_WDT: u32 = 1 << 3;
/// RCGC1: UART0..2 clocked.
const RCGC1_UARTS: u32 = 0b111;

/// Runs the core from the PLL divided by `SYSDIV + 1` ([`CORE_HZ`]) and clocks the watchdog
/// and the three UARTs. Call once, first.
pub fn init_clocks() {
    // SAFETY: valid LM3S6965 system-control registers, used by nothing else; this runs before
    // SysTick, the UARTs and the watchdog start.
    unsafe {
        let rcc = read_volatile(SYSCTL_RCC as *const u32);
        write_volatile(SYSCTL_RCC as *mut u32, rcc & !RCC_PWRDN);
        let mut polls = 0;
        while read_volatile(SYSCTL_RIS as *const u32) & RIS_PLLLRIS == 0 && polls < PLL_LOCK_POLLS {
            polls += 1;
        }
        let run = (rcc & !(RCC_PWRDN | RCC_BYPASS | RCC_SYSDIV_MASK))
            | RCC_USESYSDIV
            | (SYSDIV << RCC_SYSDIV_SHIFT);
        write_volatile(SYSCTL_RCC as *mut u32, run);
        let rcgc0 = read_volatile(SYSCTL_RCGC0 as *const u32);
        write_volatile(SYSCTL_RCGC0 as *mut u32, rcgc0 | RCGC0_WDT);
        write_volatile(SYSCTL_RCGC1 as *mut u32, RCGC1_UARTS);
    }
}

// ------------------------------------------------------------------ watchdog

const WDT_LOAD: usize = 0x4000_0000;
const WDT_CTL: usize = 0x4000_0008;
const WDT_ICR: usize = 0x4000_000C;
/// WDTCTL: INTEN (start counting) and RESEN (the second time-out resets).
const WDT_CTL_INTEN_RESEN: u32 = 0b11;
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
            write_volatile(WDT_LOAD as *mut u32, CORE_HZ / 1_000 * WATCHDOG_LOAD_MS);
            write_volatile(WDT_CTL as *mut u32, WDT_CTL_INTEN_RESEN);
        }
        Watchdog(())
    }

    /// Clears the time-out interrupt and reloads the counter (a write of WDTICR).
    pub fn feed(&mut self) {
        // SAFETY: WDTICR is a valid LM3S6965 watchdog register; any value feeds.
        unsafe { write_volatile(WDT_ICR as *mut u32, 1) }
    }
}

// ------------------------------------------------------------------ resets

/// The RESC bit of a watchdog reset (QEMU's model never sets it).
pub const WATCHDOG_CAUSE: u32 = 1 << 3;

/// RESC, read and cleared: what caused this reset.
pub fn reset_cause() -> u32 {
    // SAFETY: RESC is a valid LM3S6965 system-control register; writing 0 clears it.
    unsafe {
        let resc = read_volatile(SYSCTL_RESC as *const u32);
        write_volatile(SYSCTL_RESC as *mut u32, 0);
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
    Uart0 = 5,
    /// UART1 (AYDP).
    Uart1 = 6,
    /// UART2 (AOK).
    Uart2 = 33,
}

// SAFETY: the numbers are the LM3S6965's UART0..2 interrupt lines.
unsafe impl cortex_m::interrupt::InterruptNumber for Irq {
    fn number(self) -> u16 {
        self as u16
    }
}

/// One entry of the device interrupt table.
#[derive(Clone, Copy)]
#[repr(C)]
pub union Vector {
    handler: unsafe extern "C" fn(),
    reserved: usize,
}

unsafe extern "C" {
    fn DefaultHandler();
}

/// The LM3S6965's interrupt vectors 0..=33 (cortex-m-rt's `device` feature expects them).
#[unsafe(link_section = ".vector_table.interrupts")]
#[unsafe(no_mangle)]
pub static __INTERRUPTS: [Vector; 34] = {
    let mut v = [Vector {
        handler: DefaultHandler,
    }; 34];
    v[Irq::Uart0 as usize] = Vector { handler: uart0 };
    v[Irq::Uart1 as usize] = Vector { handler: uart1 };
    v[Irq::Uart2 as usize] = Vector { handler: uart2 };
    v
};

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
