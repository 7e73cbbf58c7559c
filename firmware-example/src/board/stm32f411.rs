//! STM32F411 (Black Pill F411CE, Nucleo-F411RE) through `stm32f4xx-hal`.
//!
//! | port  | protocol | USART  | TX   | RX   | baud    |
//! |-------|----------|--------|------|------|---------|
//! | UART0 | AEOLUS   | USART2 | PA2  | PA3  | 921 600 |
//! | UART1 | AYDP     | USART1 | PA9  | PA10 | 115 200 |
//! | UART2 | AOK      | USART6 | PA11 | PA12 | 38 400  |
//!
//! On the Nucleo, USART2 (PA2/PA3) is the ST-LINK virtual COM port, so AEOLUS
//! comes out of the USB cable (check that the ST-LINK firmware supports
//! 921 600 Bd, or lower `BAUD` for a quick look). On the Black Pill, PA11/PA12
//! are the USB connector's pins, unused by this firmware.
//!
//! * Clock: HSI (16 MHz, no crystal needed on either board) through the PLL
//!   to 100 MHz; SysTick at 1 kHz from the core clock.
//! * Log: `defmt` over RTT (`defmt-rtt`), shown by `probe-rs run`.
//! * Flash store: sectors 5 to 7 (3 x 128 KiB at 0x0802_0000), outside the
//!   program's memory map (`stm32f411.x`: sectors 0-4): the settings map on sectors 5
//!   and 6, the format 1-3 store on sectors 6 and 7 (its old place), which the map
//!   migrates from once (`sensor_box::persist`, [`store_layout`]).
//! * Watchdog: the IWDG (`IndependentWatchdog`), [`WATCHDOG_MS`] (8 s) at the LSI's nominal
//!   32 kHz (prescaler 256, reload 999); the LSI may run at 17 to 47 kHz (data sheet), so
//!   5.4 s to 15 s. Above the longest stall of the main loop: a 128 KiB sector erase takes
//!   up to 4 s at the x8 parallelism `stm32f4xx-hal` programs (`PSIZE` x8; 2 s at x32), and
//!   the loop sleeps at most `board::FEED_MS` (1 s). Once started only a reset stops it.
//! * Reset cause: RCC_CSR (IWDGRSTF, bit 29), read and cleared (RMVF) at boot.
//!
//! ## The simulated build (feature `qemu-stm32`)
//!
//! `cargo stm32-qemu` boots this same board code in QEMU's `netduinoplus2`
//! (an STM32F405: the same USART1/2/6 addresses and IRQ numbers, flash at
//! 0x0800_0000, SRAM at 0x2000_0000). The feature changes exactly four
//! things, each marked `qemu-stm32` (the fourth in `board/mod.rs`); everything
//! else is the real board's code:
//!
//! 1. **Clock**: HSI at 16 MHz without the PLL. The model has no RCC (every
//!    register reads 0), so the HAL's wait for PLLRDY would never end.
//! 2. **Settings store**: 8 KiB of the model's RAM at 0x2002_0000
//!    (`QEMU_STORE_ADDR`), above the F411's 128 KiB, so the program keeps the
//!    F411's memory map (`stm32f411.x`) and a stack overrun still faults. The
//!    model's flash is ROM behind a stub controller, and the flash-size
//!    register (0x1FFF_7A22) is unmapped (`LockedFlash::capacity` bus-faults).
//!    A warm reset leaves the region alone, so settings survive `a reboot`.
//! 3. **SysTick reload**: the model clocks SysTick from a fixed 168 MHz
//!    (`SYSTICK_HZ`) whatever RCC says; a reload for 16 MHz would make the
//!    millisecond clock run about ten times fast.
//! 4. **A main-loop wake every millisecond** (`EVERY_MS` in `board/mod.rs`):
//!    the model's USART raises no TXE interrupt, so queued bytes leave only
//!    when the application kicks the handler, which the main loop's `flush`
//!    does once a pass; the real part's TXE interrupt drains them by itself,
//!    and its main loop sleeps until a link has work.
//!
//! The model has no IWDG either (an unimplemented-device stub at 0x4000_3000: writes are
//! ignored, reads return 0), so the simulated build starts the same watchdog, which never
//! resets; and RCC_CSR reads 0, so no reset cause. `tests/tests/all/watchdog_qemu.rs` runs on the
//! QEMU board only for that reason.
//!
//! Besides these, only the boot log's board name ([`NAME`]) says the build is
//! simulated. The log stays `defmt` over RTT: `scripts/qemu-run.sh` reads the RTT buffer
//! through QEMU's GDB stub, as a probe would.

use super::{Board, start_systick};
use core::ptr::addr_of_mut;
use core::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use cortex_m::peripheral::NVIC;
use defmt_rtt as _;
use embedded_hal_nb::serial::{Read, Write};
use firmware_example::serial::Ring;
use firmware_example::{PortStats, QueuedSerial, SerialIsr};
use panic_probe as _;
use stm32f4xx_hal::pac::{self, Interrupt, USART1, USART2, USART6, interrupt};
use stm32f4xx_hal::prelude::*;
use stm32f4xx_hal::rcc::Config;
use stm32f4xx_hal::serial::{self, Instance, Rx, Tx, TxISR, TxListen};
use stm32f4xx_hal::watchdog::IndependentWatchdog;
#[cfg(not(feature = "qemu-stm32"))]
use {
    embedded_storage::nor_flash::{ErrorType, NorFlash, ReadNorFlash},
    firmware_example::FlashWindow,
    stm32f4xx_hal::flash::{self, FlashExt, LockedFlash},
};

/// The port type the application sees.
pub type Port = QueuedSerial<'static, RX_CAP, TX_CAP>;

/// The board's name for the boot log.
#[cfg(not(feature = "qemu-stm32"))]
pub const NAME: &str = "stm32f411";
/// The board's name for the boot log.
#[cfg(feature = "qemu-stm32")]
pub const NAME: &str = "stm32f411 (simulated: QEMU netduinoplus2)";

/// The settings store: sectors 5 to 7 of the internal flash.
#[cfg(not(feature = "qemu-stm32"))]
pub type Store = FlashWindow<Stm32Flash>;
/// `qemu-stm32`: the settings store is NOR flash emulated in the model's RAM.
#[cfg(feature = "qemu-stm32")]
pub type Store = firmware_example::MemFlash<'static>;

/// Baud rates of UART0 (AEOLUS), UART1 (AYDP) and UART2 (AOK).
pub const BAUD: [u32; 3] = [921_600, 115_200, 38_400];
/// Offset of the store (sector 5, then 6 and 7) from the start of flash.
#[cfg(not(feature = "qemu-stm32"))]
const STORE_OFFSET: u32 = 0x2_0000;
/// Size of the store (sectors 5 to 7, each erased alone).
#[cfg(not(feature = "qemu-stm32"))]
const STORE_LEN: u32 = 0x6_0000;

/// Where the settings map and the format 1-3 store lie in [`Store`] (offsets from sector
/// 5): the map on sectors 5 and 6, the old store on sectors 6 and 7, where the firmware
/// before the map kept it. The migration first moves the old store's newest image into
/// sector 7 when it is in sector 6, then erases sectors 5 and 6 for the map.
#[cfg(not(feature = "qemu-stm32"))]
pub fn store_layout() -> sensor_box::persist::Layout {
    sensor_box::persist::Layout {
        map: Some(0..0x4_0000),
        legacy: 0x2_0000..0x6_0000,
    }
}

/// `qemu-stm32`: the map in the first 4 KiB of the RAM store, the old store in the last.
#[cfg(feature = "qemu-stm32")]
pub fn store_layout() -> sensor_box::persist::Layout {
    sensor_box::persist::Layout::halves(
        QEMU_STORE_LEN as u32,
        firmware_example::MemFlash::PAGE as u32,
    )
}
/// `qemu-stm32`: where the RAM settings store lives: the first 8 KiB past
/// the F411's 128 KiB of SRAM, which exist only in the model (an STM32F405
/// with 192 KiB at 0x2000_0000). Nothing links there (`stm32f411.x` ends the
/// RAM at 128 KiB), and the startup code never touches it.
#[cfg(feature = "qemu-stm32")]
pub const QEMU_STORE_ADDR: usize = 0x2002_0000;
/// `qemu-stm32`: size of the RAM settings store, bytes.
#[cfg(feature = "qemu-stm32")]
const QEMU_STORE_LEN: usize = 8192;
/// The core clock: 100 MHz from HSI through the PLL.
#[cfg(not(feature = "qemu-stm32"))]
const SYSCLK_HZ: u32 = 100_000_000;
/// `qemu-stm32`: the model clocks SysTick from a fixed 168 MHz, whatever the
/// RCC says (QEMU 7.2 `netduinoplus2`, `SYSCLK_FRQ`).
#[cfg(feature = "qemu-stm32")]
pub const SYSTICK_HZ: u32 = 168_000_000;
/// The IWDG time-out at the LSI's nominal 32 kHz, ms (see the module docs).
pub const WATCHDOG_MS: u32 = 8_000;
/// RCC_CSR's IWDGRSTF: the IWDG reset the MCU.
pub const WATCHDOG_CAUSE: u32 = 1 << 29;

/// The running IWDG; only the main loop holds it.
pub struct Watchdog(IndependentWatchdog);

impl Watchdog {
    /// Reloads the IWDG's counter.
    pub fn feed(&mut self) {
        self.0.feed();
    }
}

/// RCC_CSR as it was at boot (read in `init`, before the HAL takes the RCC, then cleared).
static CSR_AT_BOOT: AtomicUsize = AtomicUsize::new(0);

/// RCC_CSR at boot: what caused this reset ([`WATCHDOG_CAUSE`] for the IWDG).
pub fn reset_cause() -> u32 {
    CSR_AT_BOOT.load(Ordering::Relaxed) as u32
}

/// RX ring bytes per USART. The USART has no FIFO and no flow control, so whatever arrives
/// while the ring is full is dropped (counted in `rx_dropped`): the ring must hold a burst for
/// as long as its link waits for room for the answers. 1 KiB is 11 ms of 921 600 Bd and holds
/// `qemu_firmware`'s whole 40-command burst (560 bytes); at 256, two CI runs and a local run of
/// the CI script lost 33, 45 and 54 bytes of it, the host delivering the paced commands in
/// bunches (3 KiB of the F411's 128 KiB RAM for the three).
const RX_CAP: usize = 1024;
const TX_CAP: usize = 512;

/// The internal flash as `embedded-storage` NOR flash; it is unlocked only
/// for the duration of each erase or write.
#[cfg(not(feature = "qemu-stm32"))]
pub struct Stm32Flash(LockedFlash);

#[cfg(not(feature = "qemu-stm32"))]
impl ErrorType for Stm32Flash {
    type Error = flash::Error;
}

#[cfg(not(feature = "qemu-stm32"))]
impl ReadNorFlash for Stm32Flash {
    const READ_SIZE: usize = 1;

    fn read(&mut self, offset: u32, bytes: &mut [u8]) -> Result<(), flash::Error> {
        ReadNorFlash::read(&mut self.0, offset, bytes)
    }

    fn capacity(&self) -> usize {
        ReadNorFlash::capacity(&self.0)
    }
}

#[cfg(not(feature = "qemu-stm32"))]
impl NorFlash for Stm32Flash {
    const WRITE_SIZE: usize = 1;
    /// The largest sector; only sectors 5 to 7 are ever erased, one at a time (see
    /// `STORE_OFFSET`).
    const ERASE_SIZE: usize = 128 * 1024;

    fn erase(&mut self, from: u32, to: u32) -> Result<(), flash::Error> {
        NorFlash::erase(&mut self.0.unlocked(), from, to)
    }

    fn write(&mut self, offset: u32, bytes: &[u8]) -> Result<(), flash::Error> {
        NorFlash::write(&mut self.0.unlocked(), offset, bytes)
    }
}

/// One USART as its interrupt handler sees it.
struct IsrPort<U: Instance> {
    tx: Tx<U>,
    rx: Rx<U>,
    half: SerialIsr<'static, RX_CAP, TX_CAP>,
}

static RX_QUEUES: [Ring<RX_CAP>; 3] = [const { Ring::new() }; 3];
static TX_QUEUES: [Ring<TX_CAP>; 3] = [const { Ring::new() }; 3];
static STATS: [PortStats; 3] = [const { PortStats::new() }; 3];
/// Per USART: bytes received since the interrupt last woke the link (see `board::received`).
/// Only that USART's interrupt touches its entry.
static UNWOKEN: [AtomicUsize; 3] = [const { AtomicUsize::new(0) }; 3];
/// Written once in `init` before the USART interrupts are unmasked, used
/// only by the interrupt handlers afterwards.
static mut PORT0: Option<IsrPort<USART2>> = None;
static mut PORT1: Option<IsrPort<USART1>> = None;
static mut PORT2: Option<IsrPort<USART6>> = None;
static TAKEN: AtomicBool = AtomicBool::new(false);

/// Brings the board up. Call once.
pub fn init() -> Board<Store> {
    if TAKEN.swap(true, Ordering::AcqRel) {
        super::reset();
    }
    let (Some(dp), Some(cp)) = (pac::Peripherals::take(), cortex_m::Peripherals::take()) else {
        super::reset();
    };
    let csr = dp.RCC.csr().read().bits();
    CSR_AT_BOOT.store(csr as usize, Ordering::Relaxed);
    dp.RCC.csr().modify(|_, w| w.rmvf().set_bit());
    #[cfg(not(feature = "qemu-stm32"))]
    let mut rcc = dp.RCC.freeze(Config::hsi().sysclk(SYSCLK_HZ.Hz()));
    // qemu-stm32: HSI (16 MHz) without the PLL; the model's RCC never reports PLLRDY.
    #[cfg(feature = "qemu-stm32")]
    let mut rcc = dp.RCC.freeze(Config::hsi());
    // SysTick counts the core clock (HCLK) on the real part.
    #[cfg(not(feature = "qemu-stm32"))]
    let systick_hz = rcc.clocks.hclk().raw();
    // qemu-stm32: the model's fixed SysTick clock instead.
    #[cfg(feature = "qemu-stm32")]
    let systick_hz = SYSTICK_HZ;
    let clock = start_systick(cp.SYST, systick_hz);
    let gpioa = dp.GPIOA.split(&mut rcc);

    let cfg = |baud: u32| serial::Config::default().baudrate(baud.bps());
    let (Ok(s0), Ok(s1), Ok(s2)) = (
        dp.USART2
            .serial((gpioa.pa2, gpioa.pa3), cfg(BAUD[0]), &mut rcc),
        dp.USART1
            .serial((gpioa.pa9, gpioa.pa10), cfg(BAUD[1]), &mut rcc),
        dp.USART6
            .serial((gpioa.pa11, gpioa.pa12), cfg(BAUD[2]), &mut rcc),
    ) else {
        super::reset();
    };

    // `TAKEN` makes this run once, so each ring is split once; the handlers' halves are
    // stored before the interrupts are unmasked below.
    let [rx0, rx1, rx2] = &RX_QUEUES;
    let [tx0, tx1, tx2] = &TX_QUEUES;
    let [st0, st1, st2] = &STATS;
    let (uart0, h0) = QueuedSerial::split(rx0, tx0, st0, || NVIC::pend(Interrupt::USART2));
    let (uart1, h1) = QueuedSerial::split(rx1, tx1, st1, || NVIC::pend(Interrupt::USART1));
    let (uart2, h2) = QueuedSerial::split(rx2, tx2, st2, || NVIC::pend(Interrupt::USART6));
    // SAFETY: `TAKEN` makes this the only writer of the handlers' statics; the interrupts
    // are still masked.
    unsafe {
        *addr_of_mut!(PORT0) = Some(isr_port(s0, h0));
        *addr_of_mut!(PORT1) = Some(isr_port(s1, h1));
        *addr_of_mut!(PORT2) = Some(isr_port(s2, h2));
        NVIC::unmask(Interrupt::USART2);
        NVIC::unmask(Interrupt::USART1);
        NVIC::unmask(Interrupt::USART6);
    }

    #[cfg(not(feature = "qemu-stm32"))]
    let Ok(store) = FlashWindow::new(
        Stm32Flash(LockedFlash::new(dp.FLASH)),
        STORE_OFFSET,
        STORE_LEN,
    ) else {
        super::reset();
    };
    // qemu-stm32: the RAM store (see `QEMU_STORE_ADDR`).
    // SAFETY: the region is RAM in the model, outside everything the linker
    // places (`stm32f411.x`), and `TAKEN` makes this the only reference to
    // it. Its bytes are whatever the RAM holds (zero after power-on, the
    // stored settings after a warm reset); the store's format tells them apart.
    #[cfg(feature = "qemu-stm32")]
    let store = firmware_example::MemFlash::new(unsafe {
        core::slice::from_raw_parts_mut(QEMU_STORE_ADDR as *mut u8, QEMU_STORE_LEN)
    });
    let mut watchdog = IndependentWatchdog::new(dp.IWDG);
    watchdog.start(WATCHDOG_MS.millis());
    Board {
        uart0,
        uart1,
        uart2,
        clock,
        store,
        watchdog: Watchdog(watchdog),
    }
}

fn isr_port<U: Instance>(
    serial: serial::Serial<U>,
    half: SerialIsr<'static, RX_CAP, TX_CAP>,
) -> IsrPort<U> {
    let (tx, mut rx) = serial.split();
    rx.listen();
    IsrPort { tx, rx, half }
}

/// Moves bytes between one USART and its queues: drains RXNE, feeds TXE, and
/// keeps the TXE interrupt enabled only while bytes wait.
///
/// Transmit has two ways into this handler. On the real part the TXE
/// interrupt (enabled by `listen` below while bytes wait) calls it once per
/// byte as the shift register empties: that is the path real hardware takes
/// at 921 600 Bd, where the queue fills far faster than the wire drains. The
/// application's `kick` (`NVIC::pend` after every queued byte) also calls it,
/// which starts transmission from idle. QEMU's USART model sends a byte the
/// moment DR is written and raises no TXE/TC interrupt, so in the simulated
/// build (`qemu-stm32`) only the kick path runs: each queued byte pends the
/// interrupt, and this handler finds TXE set and sends it at once.
fn service<U: Instance>(index: usize, port: &mut IsrPort<U>) {
    // A few rounds at most: each read either returns a byte, clears an error
    // (the HAL reads DR), or says the register is empty.
    let mut n = 0;
    port.half.at(super::now_ms());
    for _ in 0..4 {
        match port.rx.read() {
            Ok(b) => {
                port.half.received(b);
                n += 1;
            }
            Err(nb::Error::Other(_)) => port.half.receive_error(),
            Err(nb::Error::WouldBlock) => break,
        }
    }
    if n > 0
        && let Some(since) = UNWOKEN.get(index)
    {
        let total = since.load(Ordering::Relaxed).saturating_add(n);
        since.store(super::received(index, total), Ordering::Relaxed);
    }
    if port.tx.is_tx_empty()
        && let Some(b) = port.half.next_to_send()
    {
        let _ = port.tx.write(b);
    }
    if port.half.tx_pending() {
        port.tx.listen();
    } else {
        port.tx.unlisten();
    }
}

#[interrupt]
fn USART2() {
    // SAFETY: only this handler touches PORT0 after `init`.
    if let Some(p) = unsafe { (*addr_of_mut!(PORT0)).as_mut() } {
        service(0, p);
    }
}

#[interrupt]
fn USART1() {
    // SAFETY: only this handler touches PORT1 after `init`.
    if let Some(p) = unsafe { (*addr_of_mut!(PORT1)).as_mut() } {
        service(1, p);
    }
}

#[interrupt]
fn USART6() {
    // SAFETY: only this handler touches PORT2 after `init`.
    if let Some(p) = unsafe { (*addr_of_mut!(PORT2)).as_mut() } {
        service(2, p);
    }
}
