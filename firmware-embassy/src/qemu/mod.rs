//! The QEMU `lm3s6965evb` board (feature `board-qemu`, `thumbv7m-none-eabi`): the same tasks
//! as the STM32F411 board on the chip QEMU models fully, so that CI runs the async firmware.
//!
//! | job | UART | base, IRQ | socket (`scripts/qemu-run.sh`) |
//! |---|---|---|---|
//! | AEOLUS | UART0 | 0x4000_C000, 5 | 7000 |
//! | AYDP | UART1 | 0x4000_D000, 6 | 7001 |
//! | AOK | UART2 | 0x4000_E000, 33 | 7002 |
//!
//! * UARTs: [`pl011`], interrupt-driven (QEMU's PL011 has no DMA), each an
//!   `embedded-io-async` reader and writer.
//! * Clock: [`systick`], the `embassy-time` driver on SysTick at 1 kHz from the 12.5 MHz core
//!   clock ([`chip::CORE_HZ`]).
//! * Watchdog: the LM3S6965's ([`chip::Watchdog`]), 4 s after the last feed, fed by the
//!   supervisor task (`links::supervise`) only while the tick, the three TX pumps and the
//!   AOK task show progress.
//! * Settings: the last 8 KiB of RAM (`.flash_emu`, which a warm reset keeps), laid out as on
//!   the blocking QEMU board (the map in the first 4 KiB, the format 1-3 store in the last),
//!   through [`store::Store`].
//! * Log: defmt over semihosting. The boot line names the board `qemu-lm3s6965evb-embassy`;
//!   the reset cause and the count of resets not asked for follow, in the blocking board's
//!   words, and the 5 s status lines carry the stack's high-water mark.

#[cfg(feature = "cpu-budget")]
mod budget;
mod chip;
mod executor;
mod pl011;
mod store;
mod systick;

use core::mem::MaybeUninit;
use core::ptr::addr_of_mut;
use core::sync::atomic::{AtomicBool, Ordering};

use defmt_semihosting as _;
use embassy_executor::Spawner;
use firmware_example::serial::Ring;
use firmware_example::{MemFlash, PortStats, QueuedSerial};
use sensor_box::App;
use sensor_box::persist::Layout;
use sensor_box::supervisor::Heartbeat;
use static_cell::{ConstStaticCell, StaticCell};

use crate::links::{
    self, Application, PortIsr, RxErrors, Shared, StoreJob, TX_QUEUE, TxReady, UNUSED_RX_LEN,
};
use crate::{aok, spawn};
use chip::Watchdog;
use pl011::{Rx, Tx};
use store::Store;

/// The board's name in the boot log.
const NAME: &str = "qemu-lm3s6965evb-embassy";
/// Bytes of the emulated flash (`.flash_emu`, `memory.x`).
const STORE_LEN: usize = 8192;

/// The settings map in the first 4 KiB of the store, the format 1-3 store in the last, as on
/// the blocking QEMU board.
fn store_layout() -> Layout {
    Layout::halves(STORE_LEN as u32, MemFlash::PAGE as u32)
}

/// The emulated flash: never initialised by the startup code.
#[unsafe(link_section = ".flash_emu")]
static mut FLASH_EMU: MaybeUninit<[u8; STORE_LEN]> = MaybeUninit::uninit();
/// Whether the board's one-time parts (the store's RAM) are taken.
static TAKEN: AtomicBool = AtomicBool::new(false);

static AEOLUS_READY: TxReady = TxReady::new();
static AYDP_READY: TxReady = TxReady::new();
static AOK_READY: TxReady = TxReady::new();
static AEOLUS_RX_ERRORS: RxErrors = RxErrors::new();
static AYDP_RX_ERRORS: RxErrors = RxErrors::new();
static AOK_RX_ERRORS: RxErrors = RxErrors::new();
static STATS: [PortStats; 3] = [const { PortStats::new() }; 3];
static STORE_JOB: StoreJob = StoreJob::new();
static TX_QUEUES: ConstStaticCell<[Ring<TX_QUEUE>; 3]> =
    ConstStaticCell::new([const { Ring::new() }; 3]);
/// The links' ports' RX rings are unused: the readers take the UARTs' bytes ([`pl011::Rx`]).
static UNUSED_RX: ConstStaticCell<[Ring<UNUSED_RX_LEN>; 3]> =
    ConstStaticCell::new([const { Ring::new() }; 3]);
static SHARED: StaticCell<Shared> = StaticCell::new();
/// The heartbeats the supervisor checks: the tick, the AEOLUS, AYDP and AOK pumps, the AOK
/// task.
static HEARTS: [Heartbeat; 5] = [const { Heartbeat::new() }; 5];

#[cortex_m_rt::entry]
fn main() -> ! {
    executor::run(|spawner| spawn(&spawner, boot(spawner)))
}

/// The board: brings up the chip, the UARTs, the store and the watchdog, spawns the tasks,
/// then runs the 1 ms tick ([`links::run`]) until a reboot.
#[embassy_executor::task]
async fn boot(spawner: Spawner) {
    let Some(mut core) = cortex_m::Peripherals::take() else {
        chip::reset();
    };
    if TAKEN.swap(true, Ordering::AcqRel) {
        chip::reset();
    }
    chip::init_clocks();
    systick::start(core.SYST, chip::CORE_HZ);
    defmt::info!(
        "sensor-box-embassy {=str} on {=str}: booting; flash store {=usize} bytes",
        env!("CARGO_PKG_VERSION"),
        NAME,
        STORE_LEN
    );
    let cause = chip::reset_cause();
    let (unrequested, count) = chip::unrequested_resets();
    defmt::info!(
        "reset cause: register {=u32:#x}, watchdog {=bool}; not asked for {=bool} ({=u32} since power-on)",
        cause,
        cause & chip::WATCHDOG_CAUSE != 0,
        unrequested,
        count
    );
    let watchdog = Watchdog::start();

    let [st0, st1, st2] = &STATS;
    let (Some((aeolus_rx, aeolus_tx)), Some((aydp_rx, aydp_tx)), Some((aok_rx, aok_tx))) = (
        pl011::init(0, st0, &mut core.NVIC),
        pl011::init(1, st1, &mut core.NVIC),
        pl011::init(2, st2, &mut core.NVIC),
    ) else {
        defmt::error!("UART set-up failed: resetting");
        chip::reset();
    };
    let [rx0, rx1, rx2] = UNUSED_RX.take();
    let [q0, q1, q2] = TX_QUEUES.take();
    let (aeolus_port, aeolus_isr) = QueuedSerial::split(rx0, q0, st0, || AEOLUS_READY.signal(()));
    let (aydp_port, aydp_isr) = QueuedSerial::split(rx1, q1, st1, || AYDP_READY.signal(()));
    let (aok_port, aok_isr) = QueuedSerial::split(rx2, q2, st2, || AOK_READY.signal(()));

    // SAFETY: `TAKEN` makes this the only reference to the region. Its bytes are whatever
    // the RAM holds (zero after power-on, the stored settings after a warm reset); the
    // store's format tells them apart.
    let mem: &'static mut [u8; STORE_LEN] = unsafe { (*addr_of_mut!(FLASH_EMU)).assume_init_mut() };
    let mut flash = Store(MemFlash::new(mem));

    // The boot is blocking, before any other task exists (as on the STM32 board).
    let app = App::with_layout(&mut flash, store_layout(), links::now_ms());
    let (high_water, _) = chip::stack();
    defmt::info!(
        "booted: App {=usize} bytes, stack high-water {=usize} bytes",
        core::mem::size_of::<App>(),
        high_water
    );
    let shared: &'static Shared = SHARED.init(Shared::new(Application {
        app,
        aeolus_tx: aeolus_port,
        aydp_tx: aydp_port,
        aok_tx: aok_port,
        aeolus_rx: aeolus_proto::Stats::default(),
        aydp_rx: aydp_proto::Stats::default(),
    }));

    let [
        tick_heart,
        aeolus_heart,
        aydp_heart,
        aok_pump_heart,
        aok_heart,
    ] = &HEARTS;
    spawn(&spawner, aeolus_rx_task(aeolus_rx, shared));
    spawn(&spawner, aydp_rx_task(aydp_rx, shared));
    spawn(&spawner, aok_task(aok_rx, shared, aok_heart));
    spawn(
        &spawner,
        tx_task(aeolus_isr, aeolus_tx, &AEOLUS_READY, aeolus_heart),
    );
    spawn(
        &spawner,
        tx_task(aydp_isr, aydp_tx, &AYDP_READY, aydp_heart),
    );
    spawn(
        &spawner,
        tx_task(aok_isr, aok_tx, &AOK_READY, aok_pump_heart),
    );
    spawn(&spawner, watchdog_task(watchdog));
    spawn(&spawner, store_task(flash, shared));
    #[cfg(feature = "cpu-budget")]
    spawn(&spawner, budget::run(shared));
    links::run(
        shared,
        [&AEOLUS_RX_ERRORS, &AYDP_RX_ERRORS, &AOK_RX_ERRORS],
        tick_heart,
        &STORE_JOB,
        links::BoardReport {
            stack: Some(chip::stack),
            port_rx: true,
        },
    )
    .await;
    chip::reset();
}

/// The watchdog's supervisor ([`links::supervise`]).
#[embassy_executor::task]
async fn watchdog_task(mut watchdog: Watchdog) {
    links::supervise(&HEARTS, || watchdog.feed()).await
}

/// The settings store ([`links::store`]) on the RAM store.
#[embassy_executor::task]
async fn store_task(flash: Store, shared: &'static Shared) {
    links::store(flash, shared, &STORE_JOB).await
}

/// AEOLUS receive: UART0 into the AEOLUS link ([`links::aeolus_rx`]).
#[embassy_executor::task]
async fn aeolus_rx_task(uart: Rx, shared: &'static Shared) {
    links::aeolus_rx(uart, shared, &AEOLUS_RX_ERRORS).await
}

/// AYDP receive: UART1 into the AYDP link ([`links::aydp_rx`]).
#[embassy_executor::task]
async fn aydp_rx_task(uart: Rx, shared: &'static Shared) {
    links::aydp_rx(uart, shared, &AYDP_RX_ERRORS).await
}

/// AOK: UART2 into the AOK link ([`aok::aok`]).
#[embassy_executor::task]
async fn aok_task(uart: Rx, shared: &'static Shared, heart: &'static Heartbeat) {
    aok::aok(uart, shared, &AOK_RX_ERRORS, heart).await
}

/// Transmit: one port's TX queue to its UART ([`links::pump_tx`]); one per UART.
#[embassy_executor::task(pool_size = 3)]
async fn tx_task(isr: PortIsr, uart: Tx, ready: &'static TxReady, heart: &'static Heartbeat) {
    links::pump_tx(isr, uart, ready, heart).await
}
