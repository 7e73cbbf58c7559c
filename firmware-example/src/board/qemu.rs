//! QEMU `lm3s6965evb` (TI Stellaris LM3S6965, Cortex-M3).
//!
//! * UART0/1/2: PL011-compatible UARTs at 0x4000_C000/D000/E000, IRQs 5, 6
//!   and 33. `scripts/qemu-run.sh` puts them on TCP sockets.
//! * Log: `defmt` over semihosting (`defmt-semihosting`), decoded on the
//!   host by `defmt-print`.
//! * Flash store: the last 8 KiB of RAM (`.flash_emu`, a NOLOAD section of
//!   `memory.x`), which a warm reset leaves alone: the settings map in its first 4 KiB, the
//!   format 1-3 store in the last 4 KiB, where the firmware before the map kept it
//!   ([`store_layout`]).
//! * Clock: the PLL divided by 16 (12.5 MHz, the reset's divisor, set explicitly in
//!   `set_core_clock`); SysTick counts it. QEMU without `-icount` follows the host's clock,
//!   so the box's millisecond is the host's (`tests/tests/all/box_clock.rs` checks it).
//! * Watchdog: the LM3S6965's watchdog timer at 0x4000_0000, which QEMU 7.2 models
//!   (`luminary-watchdog`, its CMSDK APB watchdog in the Stellaris variant, clocked by the
//!   system clock, `info mtree` shows it as `cmsdk-apb-watchdog`). Load
//!   [`WATCHDOG_LOAD_MS`] (2 s) of the system clock: the first time-out raises its
//!   interrupt (left masked in the NVIC), the second resets the box, so a main loop that
//!   stops feeding it is reset 4 s later. A feed writes WDTICR (clears the interrupt and
//!   reloads the counter). QEMU's reset leaves RAM alone, so the settings survive it.
//! * Reset cause: RESC (0x400F_E05C; bit 3, WDT). QEMU's model never sets its bits (a
//!   plain register, 0 after power-on): in QEMU the cause shows only as a reset the
//!   firmware did not ask for (`board::unrequested_resets`).

use super::{Board, start_systick};
use core::mem::MaybeUninit;
use core::ptr::{addr_of_mut, read_volatile, write_volatile};
use core::sync::atomic::{AtomicBool, AtomicU8, Ordering};
use cortex_m::peripheral::NVIC;
use defmt_semihosting as _;
use firmware_example::lm3s6965::sysctl::{
    self, PLL_LOCK_POLLS, RCC_BYPASS, RCC_PWRDN, RCC_SYSDIV_MASK, RCC_SYSDIV_SHIFT, RCC_USESYSDIV,
    RCGC0_WDT, RCGC1_UARTS, RIS_PLLLRIS,
};
use firmware_example::lm3s6965::uart::{self, *};
use firmware_example::lm3s6965::{self, wdt};
use firmware_example::serial::Ring;
use firmware_example::{MemFlash, PortStats, QueuedSerial, SerialIsr};
use sensor_box::budget::{self, Category};

/// The port type the application sees.
pub type Port = QueuedSerial<'static, RX_CAP, TX_CAP>;

/// The board's name for the boot log.
pub const NAME: &str = "qemu-lm3s6965evb";

/// The flash store: NOR flash emulated in the `.flash_emu` RAM region.
pub type Store = MemFlash<'static>;

/// Bytes of the emulated flash.
const STORE_LEN: usize = 8192;

/// Where the settings map and the format 1-3 store lie in [`Store`]: the map in the first
/// 4 KiB (four 1 KiB pages), the old store in the last 4 KiB.
pub fn store_layout() -> sensor_box::persist::Layout {
    sensor_box::persist::Layout::halves(STORE_LEN as u32, MemFlash::PAGE as u32)
}

/// The system clock divisor `init` writes into RCC. 15 is the reset value's
/// (RCC = 0x078E_3AC0 at reset: SYSDIV 15, so 12.5 MHz, not 12 MHz).
#[cfg(not(feature = "cpu-budget"))]
const SYSDIV: u32 = 15;

/// The `cpu-budget` build sets SYSDIV to 0, which QEMU's model turns into a 5 ns core clock
/// period (200 MHz: its PLL output undivided): one SysTick count is 5 instructions under
/// `-icount shift=0` instead of 80, the resolution of the account. The millisecond stays a
/// millisecond (the reload follows). Only QEMU is meant: on a real LM3S6965 this would run the
/// PLL out of spec.
#[cfg(feature = "cpu-budget")]
const SYSDIV: u32 = 0;

/// The core clock, Hz: what SysTick counts. It follows from the RCC value `init` writes, never
/// from a separate guess (a 12 MHz guess made the box's millisecond 4 % short of the host's).
const CORE_HZ: u32 = lm3s6965::core_hz(SYSDIV);

// The reset configuration gives the 12.5 MHz `scripts/cm3-bench.sh` measures (80 ns a tick).
#[cfg(not(feature = "cpu-budget"))]
const _: () = assert!(CORE_HZ == 12_500_000);

/// Puts the core on the PLL divided by `SYSDIV + 1`, the configuration `CORE_HZ` describes:
/// the PLL is powered up, locked (bounded wait), then BYPASS cleared with the divisor in use.
fn set_core_clock() {
    // SAFETY: RCC and RIS are valid lm3s6965 system-control registers; nothing else uses
    // them, and this runs before SysTick and the UARTs are started.
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
    }
}

/// The UARTs' baud rate (QEMU's PL011 ignores it; a real part needs it).
const BAUD: u32 = 115_200;
/// The PL011 baud divisor in 64ths: core clock / (16 x baud), rounded.
const BAUD_DIV_64THS: u32 = uart::baud_div_64ths(CORE_HZ, BAUD);
/// Each UART's RX ring: room for four of the link's wake thresholds (`WAKE_BYTES`), so a flood
/// keeps arriving into the ring while the link decodes the run that woke it.
const RX_CAP: usize = 512;
const TX_CAP: usize = 512;

/// The RESC bit that names a watchdog reset.
pub const WATCHDOG_CAUSE: u32 = sysctl::RESC_WDT;

/// One time-out of the watchdog, ms: the interrupt after one, the reset after two.
pub const WATCHDOG_LOAD_MS: u32 = 2_000;
const WDT_LOAD_COUNT: u32 = CORE_HZ / 1_000 * WATCHDOG_LOAD_MS;

/// The running watchdog; only the main loop holds it.
pub struct Watchdog(());

impl Watchdog {
    /// Clears the time-out interrupt and reloads the counter (a write of WDTICR).
    pub fn feed(&mut self) {
        // SAFETY: WDTICR is a valid lm3s6965 watchdog register; any value feeds.
        unsafe { write_volatile(wdt::ICR as *mut u32, 1) }
    }
}

/// Starts the watchdog (its clock gate, the load, then INTEN and RESEN), left unlocked.
fn start_watchdog() -> Watchdog {
    // SAFETY: valid lm3s6965 system-control and watchdog registers; nothing else uses them.
    unsafe {
        let rcgc0 = read_volatile(sysctl::RCGC0 as *const u32);
        write_volatile(sysctl::RCGC0 as *mut u32, rcgc0 | RCGC0_WDT);
        write_volatile(wdt::LOAD as *mut u32, WDT_LOAD_COUNT);
        write_volatile(wdt::CTL as *mut u32, wdt::CTL_INTEN_RESEN);
    }
    Watchdog(())
}

/// RESC, read and cleared: what caused this reset ([`WATCHDOG_CAUSE`] for the watchdog).
pub fn reset_cause() -> u32 {
    // SAFETY: RESC is a valid lm3s6965 system-control register.
    unsafe {
        let resc = read_volatile(sysctl::RESC as *const u32);
        write_volatile(sysctl::RESC as *mut u32, 0);
        resc
    }
}

/// The lm3s6965 interrupt numbers this board uses.
#[derive(Clone, Copy)]
#[repr(u16)]
enum Irq {
    Uart0 = uart::IRQ[0],
    Uart1 = uart::IRQ[1],
    Uart2 = uart::IRQ[2],
}

// SAFETY: the numbers are the lm3s6965's UART0..2 interrupt lines.
unsafe impl cortex_m::interrupt::InterruptNumber for Irq {
    fn number(self) -> u16 {
        self as u16
    }
}

const IRQS: [Irq; 3] = [Irq::Uart0, Irq::Uart1, Irq::Uart2];

// --------------------------------------------------------- vector table

firmware_example::lm3s6965_interrupts!(uart0, uart1, uart2);

// ------------------------------------------------------------- statics

static RX_QUEUES: [Ring<RX_CAP>; 3] = [const { Ring::new() }; 3];
static TX_QUEUES: [Ring<TX_CAP>; 3] = [const { Ring::new() }; 3];
static STATS: [PortStats; 3] = [const { PortStats::new() }; 3];
/// The interrupt handlers' halves; written once in `init` before the UART
/// interrupts are unmasked, used only by the handlers afterwards.
static mut ISR: [Option<SerialIsr<'static, RX_CAP, TX_CAP>>; 3] = [const { None }; 3];

/// The emulated flash: never initialised by the startup code.
#[unsafe(link_section = ".flash_emu")]
static mut FLASH_EMU: MaybeUninit<[u8; STORE_LEN]> = MaybeUninit::uninit();

static TAKEN: AtomicBool = AtomicBool::new(false);

/// Bit `n` set: SysTick asks UART `n`'s interrupt to publish the received bytes it holds in
/// the RX ring (`SerialIsr::receive_batched`), so that its link sees them within a millisecond.
static PUBLISH: AtomicU8 = AtomicU8::new(0);

/// Called by SysTick for the UARTs whose interrupt holds unpublished bytes (`bits`, bit `n`
/// for UART `n`): marks them and pends their interrupts, which publish and wake the links.
pub(super) fn publish_held(bits: u8) {
    PUBLISH.fetch_or(bits, Ordering::Relaxed);
    for (n, irq) in IRQS.iter().enumerate() {
        if bits & (1 << n) != 0 {
            NVIC::pend(*irq);
        }
    }
}

fn reg(base: usize, offset: usize) -> *mut u32 {
    (base + offset) as *mut u32
}

/// Brings the board up. Call once.
pub fn init() -> Board<Store> {
    if TAKEN.swap(true, Ordering::AcqRel) {
        // A second call would alias the queues and the store.
        super::reset();
    }
    let mut core = cortex_m::Peripherals::take().unwrap_or_else(|| super::reset());
    set_core_clock();
    let clock = start_systick(core.SYST, CORE_HZ);

    // SAFETY: RCGC1 is a valid lm3s6965 system-control register.
    unsafe { write_volatile(sysctl::RCGC1 as *mut u32, RCGC1_UARTS) };

    let kicks: [fn(); 3] = [
        || NVIC::pend(Irq::Uart0),
        || NVIC::pend(Irq::Uart1),
        || NVIC::pend(Irq::Uart2),
    ];
    // SAFETY: `TAKEN` makes this run once, so this is the only reference to the ISR halves
    // (and the rings are split once); they are stored before the interrupts are unmasked
    // below.
    let isr = unsafe { &mut *addr_of_mut!(ISR) };
    let mut ports = RX_QUEUES
        .iter()
        .zip(TX_QUEUES.iter())
        .zip(STATS.iter())
        .zip(kicks)
        .zip(isr.iter_mut())
        .map(|((((rx, tx), stats), kick), slot)| {
            let (port, half) = QueuedSerial::split(rx, tx, stats, kick);
            *slot = Some(half);
            // One kick per burst (the main loop flushes after each poll): one interrupt
            // fills the FIFO instead of one interrupt per byte.
            port.batched()
        });
    let (Some(uart0), Some(uart1), Some(uart2)) = (ports.next(), ports.next(), ports.next()) else {
        super::reset();
    };

    for (base, irq) in BASE.iter().zip(IRQS) {
        // SAFETY: valid PL011 registers of the lm3s6965; the UART is
        // disabled while it is configured.
        unsafe {
            write_volatile(reg(*base, CTL), 0);
            // 115200 Bd at 12.5 MHz: 12.5e6 / (16 * 115200) = 6.78 -> 6 + 50/64.
            write_volatile(reg(*base, IBRD), BAUD_DIV_64THS / 64);
            write_volatile(reg(*base, FBRD), BAUD_DIV_64THS % 64);
            write_volatile(reg(*base, LCRH), LCRH_WLEN8_FEN);
            write_volatile(reg(*base, IFLS), IFLS_RX_HALF_TX_EIGHTH);
            write_volatile(reg(*base, ICR), INT_ALL);
            write_volatile(reg(*base, IMSC), INT_RX | INT_RT);
            write_volatile(reg(*base, CTL), CTL_UARTEN_TXE_RXE);
        }
        // SAFETY: the handler's state is in place (above).
        unsafe {
            core.NVIC.set_priority(irq, 0x40);
            NVIC::unmask(irq);
        }
    }

    // SAFETY: `TAKEN` makes this the only reference to the region. The bytes
    // are whatever the RAM holds (zero after power-on, the stored settings
    // after a warm reset); the store's own format tells them apart.
    let mem: &'static mut [u8; STORE_LEN] = unsafe { (*addr_of_mut!(FLASH_EMU)).assume_init_mut() };

    Board {
        uart0,
        uart1,
        uart2,
        clock,
        store: MemFlash::new(mem),
        watchdog: start_watchdog(),
    }
}

/// Moves bytes between one PL011 and its queues. Called by its interrupt,
/// which fires on RX and RX timeout (while the RX queue has room), TX FIFO room
/// (only while bytes wait), and when the application pends it: after queueing
/// a byte, and after reading from a full RX queue.
fn service(index: usize) {
    let Some(&base) = BASE.get(index) else {
        return;
    };
    // SAFETY: only this interrupt handler uses the ISR halves after `init`.
    let slot = unsafe { (*addr_of_mut!(ISR)).get_mut(index) };
    let Some(Some(isr)) = slot else {
        return;
    };
    let previous = budget::enter(Category::RxIrq);
    // SAFETY: valid PL011 registers; reads of DR pop the RX FIFO.
    unsafe {
        // What raised the interrupt: nothing (the application pended it: a kick to send, or
        // to take bytes it had left in the UART), RX / RX timeout, or TX FIFO room.
        let mis = read_volatile(reg(base, MIS));
        write_volatile(reg(base, ICR), INT_RX | INT_RT | INT_TX);
        // Bytes stay in the PL011 FIFO while the RX queue is full: QEMU then stops reading
        // the socket, and nothing is dropped. The application's next read pends this
        // interrupt again (see `SerialIsr::rx_room`).
        // The bytes are published to the link in runs of `WAKE_BYTES` (one ring grant and
        // commit per run, not per interrupt); SysTick asks for the rest once a millisecond.
        // A TX interrupt finds the RX FIFO empty: nothing to do on the RX side then.
        let bit = 1u8 << index;
        let publish = PUBLISH.load(Ordering::Relaxed) & bit != 0;
        if publish {
            PUBLISH.fetch_and(!bit, Ordering::Relaxed);
        }
        if publish || read_volatile(reg(base, FR)) & FR_RXFE == 0 {
            isr.at(super::now_ms());
            let published = isr.receive_batched(super::WAKE_BYTES, publish, || {
                if read_volatile(reg(base, FR)) & FR_RXFE != 0 {
                    return None;
                }
                let dr = read_volatile(reg(base, DR));
                Some(if dr & DR_ERRORS != 0 {
                    Err(())
                } else {
                    Ok(dr as u8)
                })
            });
            if published > 0 {
                super::mark_received(index);
            }
            if isr.unpublished() > 0 {
                super::hold(index);
            }
        }
        if mis & INT_TX == 0 && mis != 0 {
            // RX only: the TX side has nothing new to do. A full RX queue stops RX
            // interrupts until the application's next read kicks this handler.
            if isr.rx_held() {
                write_volatile(reg(base, IMSC), read_volatile(reg(base, IMSC)) & INT_TX);
            }
            budget::leave(previous);
            return;
        }
        budget::leave(previous);
        let previous = budget::enter(Category::TxIrq);
        // A FIFO's worth per empty FIFO (one flag read per 16 bytes), then byte by byte
        // while a part-full FIFO has room.
        let pending = isr.send_fifo(
            FIFO,
            || read_volatile(reg(base, FR)) & FR_TXFE != 0,
            || read_volatile(reg(base, FR)) & FR_TXFF == 0,
            |b| write_volatile(reg(base, DR), u32::from(b)),
        );
        let tx = if pending { INT_TX } else { 0 };
        // RX interrupts stay on unless the RX ring filled up (the RX side marks it held, and
        // a full ring met by an RX interrupt marks it too): only then is its room asked.
        let rx = if !isr.rx_held() || isr.rx_room() {
            INT_RX | INT_RT
        } else {
            0
        };
        write_volatile(reg(base, IMSC), rx | tx);
        budget::leave(previous);
    }
}

unsafe extern "C" fn uart0() {
    service(0);
}

unsafe extern "C" fn uart1() {
    service(1);
}

unsafe extern "C" fn uart2() {
    service(2);
}

#[panic_handler]
fn panic(info: &core::panic::PanicInfo) -> ! {
    match info.location() {
        Some(l) => defmt::error!("panic at {=str}:{=u32}", l.file(), l.line()),
        None => defmt::error!("panic"),
    }
    semihosting::process::exit(101)
}
