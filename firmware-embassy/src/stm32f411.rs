//! The STM32F411 board (Black Pill F411CE / Nucleo-F411RE) with `embassy-stm32` (feature
//! `board-stm32f411`, the default): clocks, pins, DMA streams, interrupts, the flash store,
//! and one task per job; the application is the `sensor-box` crate and the async glue is
//! [`links`] and [`aok`](crate::aok).
//!
//! | job | UART | pins (TX, RX) | baud | DMA (RX ring, TX) |
//! |---|---|---|---|---|
//! | AEOLUS | USART2 | PA2, PA3 | 921 600 | DMA1 stream 5, stream 6 |
//! | AYDP | USART1 | PA9, PA10 | 115 200 | DMA2 stream 2, stream 7 |
//! | AOK | USART6 | PA11, PA12 | 38 400 | DMA2 stream 1, stream 6 |
//!
//! The settings live in the `sequential-storage` map on flash sectors 5 and 6, stored by a task
//! on the async flash driver ([`links::store`]); the boot loads them, or migrates the format 3
//! store from sectors 6 and 7 ([`store_layout`]).
//!
//! The IWDG resets the box [`WATCHDOG_US`] (8 s at the LSI's nominal 32 kHz; 5.4 s to 15 s
//! over its 17-47 kHz) after the last feed. Only the supervisor task feeds it, and only while
//! the tick, the three TX pumps and the AOK task show progress ([`links::supervise`],
//! `sensor_box::supervisor`). The boot log has RCC_CSR (IWDGRSTF, bit 29: the last reset was
//! the watchdog's).
use crate::links::{
    Application, PortIsr, RxErrors, Shared, StoreJob, TX_QUEUE, TxReady, UNUSED_RX_LEN,
};
use crate::spawn;
use crate::{aok, links};
use defmt_rtt as _;
use embassy_executor::Spawner;
use embassy_stm32::flash::{self, Flash};
use embassy_stm32::mode::Async;
use embassy_stm32::usart::{self, RingBufferedUartRx, Uart, UartTx};
use embassy_stm32::wdg::IndependentWatchdog;
use embassy_stm32::{bind_interrupts, dma, peripherals, rcc};
use firmware_example::serial::Ring;
use firmware_example::{PortStats, QueuedSerial};
use panic_probe as _;
use sensor_box::App;
use sensor_box::persist::Layout;
use sensor_box::supervisor::Heartbeat;
use static_cell::{ConstStaticCell, StaticCell};

/// USART2 (AEOLUS) baud rate: the spec schedule needs about 453 kbit/s (see
/// `firmware-example/README.md`).
const AEOLUS_BAUD: u32 = 921_600;
/// USART1 (AYDP) baud rate.
const AYDP_BAUD: u32 = 115_200;
/// USART6 (AOK) baud rate, as on the blocking board.
const AOK_BAUD: u32 = 38_400;
/// The longest time the executor can be blocked: a 128 KiB sector erase, up to 4 s (data
/// sheet; typically 1 to 2 s), during which the CPU stalls on every fetch from flash while
/// the DMA goes on writing the receive rings in SRAM. Each ring holds what its link receives
/// at line rate in that time, or as much as the RAM allows (see `README.md`).
const ERASE_STALL_MS: usize = 4_000;
/// Room for the bytes that arrive after the stall, before the reader runs (the executor first
/// polls the tasks woken meanwhile, each for one step), ms.
const DRAIN_MS: usize = 250;
/// Bytes a UART receives in `ms` at `baud` (10 bits a byte: start, 8 data, stop).
const fn bytes_in(baud: u32, ms: usize) -> usize {
    baud as usize / 10 * ms / 1_000
}
/// AEOLUS DMA receive ring: 16 KiB, 178 ms of a continuous stream at 921 600 Bd. 4.25 s at
/// line rate would be 391 680 bytes, three times the 128 KiB of RAM; the AEOLUS uplink is
/// commands, each answered by a TOAST (see `README.md`).
const AEOLUS_RING_LEN: usize = 16 * 1024;
/// AYDP DMA receive ring: 4.25 s at 115 200 Bd (48 960 bytes).
const AYDP_RING_LEN: usize = bytes_in(AYDP_BAUD, ERASE_STALL_MS + DRAIN_MS);
/// AOK DMA receive ring: 4.25 s at 38 400 Bd (16 320 bytes).
const AOK_RING_LEN: usize = bytes_in(AOK_BAUD, ERASE_STALL_MS + DRAIN_MS);
/// The settings store, in offsets from the start of flash (the map's and the old store's
/// ranges, as the blocking STM32 board lays them out from its sector 5): the settings map on
/// sectors 5 and 6 (0x0802_0000, 2 x 128 KiB), the format 1-3 store it migrates from on
/// sectors 6 and 7, where this board kept it before the map. The program is linked into
/// sectors 0-4 (`firmware-example/src/board/stm32f411.x`).
fn store_layout() -> Layout {
    Layout {
        map: Some(0x2_0000..0x6_0000),
        legacy: 0x4_0000..0x8_0000,
    }
}

bind_interrupts!(struct Irqs {
    FLASH => flash::InterruptHandler;
    USART1 => usart::InterruptHandler<peripherals::USART1>;
    USART2 => usart::InterruptHandler<peripherals::USART2>;
    USART6 => usart::InterruptHandler<peripherals::USART6>;
    DMA1_STREAM5 => dma::InterruptHandler<peripherals::DMA1_CH5>;
    DMA1_STREAM6 => dma::InterruptHandler<peripherals::DMA1_CH6>;
    DMA2_STREAM1 => dma::InterruptHandler<peripherals::DMA2_CH1>;
    DMA2_STREAM2 => dma::InterruptHandler<peripherals::DMA2_CH2>;
    DMA2_STREAM6 => dma::InterruptHandler<peripherals::DMA2_CH6>;
    DMA2_STREAM7 => dma::InterruptHandler<peripherals::DMA2_CH7>;
});

static AEOLUS_READY: TxReady = TxReady::new();
static AYDP_READY: TxReady = TxReady::new();
static AOK_READY: TxReady = TxReady::new();
static AEOLUS_RX_ERRORS: RxErrors = RxErrors::new();
static AYDP_RX_ERRORS: RxErrors = RxErrors::new();
static AOK_RX_ERRORS: RxErrors = RxErrors::new();
static STATS: [PortStats; 3] = [const { PortStats::new() }; 3];
static AEOLUS_RING: ConstStaticCell<[u8; AEOLUS_RING_LEN]> =
    ConstStaticCell::new([0; AEOLUS_RING_LEN]);
static AYDP_RING: ConstStaticCell<[u8; AYDP_RING_LEN]> = ConstStaticCell::new([0; AYDP_RING_LEN]);
static AOK_RING: ConstStaticCell<[u8; AOK_RING_LEN]> = ConstStaticCell::new([0; AOK_RING_LEN]);
/// The tick's hand-over of stores to the store task.
static STORE_JOB: StoreJob = StoreJob::new();
static AEOLUS_QUEUE: ConstStaticCell<Ring<TX_QUEUE>> = ConstStaticCell::new(Ring::new());
static AYDP_QUEUE: ConstStaticCell<Ring<TX_QUEUE>> = ConstStaticCell::new(Ring::new());
static AOK_QUEUE: ConstStaticCell<Ring<TX_QUEUE>> = ConstStaticCell::new(Ring::new());
/// The ports' RX rings are unused: the readers take the UARTs' bytes directly.
static UNUSED_RX: ConstStaticCell<[Ring<UNUSED_RX_LEN>; 3]> =
    ConstStaticCell::new([const { Ring::new() }; 3]);
static SHARED: StaticCell<Shared> = StaticCell::new();
/// The heartbeats the watchdog's supervisor checks: the tick, the AEOLUS, AYDP and AOK
/// pumps, the AOK task.
static HEARTS: [Heartbeat; 5] = [const { Heartbeat::new() }; 5];

/// The IWDG's time-out at the LSI's nominal 32 kHz, µs: above the longest stall (a 128 KiB
/// sector erase, up to 4 s) plus the supervisor's [`links::FEED_MS`] even at
/// the LSI's fastest.
const WATCHDOG_US: u32 = 8_000_000;
/// RCC_CSR (RCC at 0x4002_3800, offset 0x74): the reset flags.
const RCC_CSR: usize = 0x4002_3874;
/// RCC_CSR's IWDGRSTF: the last reset was the IWDG's.
const CSR_IWDGRSTF: u32 = 1 << 29;
/// RCC_CSR's RMVF: clears the reset flags.
const CSR_RMVF: u32 = 1 << 24;

/// HSI (16 MHz) / 8 * 100 / 2 = 100 MHz, the F411's maximum; APB1 (USART2) at 50 MHz, APB2
/// (USART1) at 100 MHz. The blocking board runs the same clocks.
fn clocks() -> embassy_stm32::Config {
    let mut config = embassy_stm32::Config::default();
    config.rcc.hsi = true;
    config.rcc.pll_src = rcc::PllSource::HSI;
    config.rcc.pll = Some(rcc::Pll {
        prediv: rcc::PllPreDiv::DIV8,
        mul: rcc::PllMul::MUL100,
        divp: Some(rcc::PllPDiv::DIV2),
        divq: None,
        divr: None,
    });
    config.rcc.sys = rcc::Sysclk::PLL1_P;
    config.rcc.ahb_pre = rcc::AHBPrescaler::DIV1;
    config.rcc.apb1_pre = rcc::APBPrescaler::DIV2;
    config.rcc.apb2_pre = rcc::APBPrescaler::DIV1;
    config
}

fn uart_config(baud: u32) -> usart::Config {
    let mut config = usart::Config::default();
    config.baudrate = baud;
    config
}

#[embassy_executor::main]
async fn main(spawner: Spawner) {
    let p = embassy_stm32::init(clocks());
    defmt::info!(
        "sensor-box-embassy {=str} on stm32f411 (embassy): booting",
        env!("CARGO_PKG_VERSION")
    );
    // SAFETY: RCC_CSR is the F411's reset-flag register; only its RMVF bit is written, which
    // clears the flags and touches no clock.
    let csr = unsafe {
        let csr = core::ptr::read_volatile(RCC_CSR as *const u32);
        core::ptr::write_volatile(RCC_CSR as *mut u32, csr | CSR_RMVF);
        csr
    };
    defmt::info!(
        "reset cause: RCC_CSR {=u32:#x}, watchdog {=bool}",
        csr,
        csr & CSR_IWDGRSTF != 0
    );
    let mut watchdog = IndependentWatchdog::new(p.IWDG, WATCHDOG_US);
    watchdog.unleash();

    let (Ok(aeolus), Ok(aydp), Ok(aok)) = (
        Uart::new(
            p.USART2,
            p.PA3,
            p.PA2,
            p.DMA1_CH6,
            p.DMA1_CH5,
            Irqs,
            uart_config(AEOLUS_BAUD),
        ),
        Uart::new(
            p.USART1,
            p.PA10,
            p.PA9,
            p.DMA2_CH7,
            p.DMA2_CH2,
            Irqs,
            uart_config(AYDP_BAUD),
        ),
        Uart::new(
            p.USART6,
            p.PA12,
            p.PA11,
            p.DMA2_CH6,
            p.DMA2_CH1,
            Irqs,
            uart_config(AOK_BAUD),
        ),
    ) else {
        defmt::error!("UART set-up failed (baud rate out of range): resetting");
        cortex_m::peripheral::SCB::sys_reset();
    };
    let (aeolus_tx, aeolus_rx) = aeolus.split();
    let (aydp_tx, aydp_rx) = aydp.split();
    let (aok_tx, aok_rx) = aok.split();
    let aeolus_rx = aeolus_rx.into_ring_buffered(AEOLUS_RING.take());
    let aydp_rx = aydp_rx.into_ring_buffered(AYDP_RING.take());
    let aok_rx = aok_rx.into_ring_buffered(AOK_RING.take());

    // The flash in async mode (its FLASH interrupt bound above): the store task awaits its
    // programs and erases; the boot below uses the same driver's blocking side.
    let mut flash = Flash::new(p.FLASH, Irqs);

    let [rx0, rx1, rx2] = UNUSED_RX.take();
    let [st0, st1, st2] = &STATS;
    let (aeolus_port, aeolus_isr) =
        QueuedSerial::split(rx0, AEOLUS_QUEUE.take(), st0, || AEOLUS_READY.signal(()));
    let (aydp_port, aydp_isr) =
        QueuedSerial::split(rx1, AYDP_QUEUE.take(), st1, || AYDP_READY.signal(()));
    let (aok_port, aok_isr) =
        QueuedSerial::split(rx2, AOK_QUEUE.take(), st2, || AOK_READY.signal(()));

    // The boot is blocking, before any other task exists: the App that the tasks share is
    // built from what it loads (`App::with_layout`), and sensor-box's boot (the torn-word
    // guard, the map's load, the format 1-3 reader and the migration) is one blocking
    // implementation, shared with the blocking boards. It logs where the settings came from
    // and any corrupt item, and restores the store policy's debt.
    let app = App::with_layout(&mut flash, store_layout(), links::now_ms());
    defmt::info!(
        "booted: App {=usize} bytes, {=u32} corrupt settings items",
        core::mem::size_of::<App>(),
        app.shared.counters.corrupt_items
    );
    let shared: &'static Shared = SHARED.init(Shared::new(Application {
        app,
        aeolus_tx: aeolus_port,
        aydp_tx: aydp_port,
        aok_tx: aok_port,
        aeolus_rx: aeolus_proto::Stats::default(),
        aydp_rx: aydp_proto::Stats::default(),
    }));

    spawn(&spawner, aeolus_rx_task(aeolus_rx, shared));
    spawn(&spawner, aydp_rx_task(aydp_rx, shared));
    let [
        tick_heart,
        aeolus_heart,
        aydp_heart,
        aok_pump_heart,
        aok_heart,
    ] = &HEARTS;
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
    links::run(
        shared,
        [&AEOLUS_RX_ERRORS, &AYDP_RX_ERRORS, &AOK_RX_ERRORS],
        tick_heart,
        &STORE_JOB,
        links::BoardReport {
            stack: None,
            port_rx: false,
        },
    )
    .await;
    cortex_m::peripheral::SCB::sys_reset();
}

/// The watchdog's supervisor ([`links::supervise`]): feeds the IWDG while the tick, the TX
/// pumps and the AOK task show progress, each within its limit.
#[embassy_executor::task]
async fn watchdog_task(mut watchdog: IndependentWatchdog<'static, peripherals::IWDG>) {
    links::supervise(&HEARTS, || watchdog.pet()).await
}

/// The settings store: the stores the tick hands over, into the settings map on the async
/// flash driver ([`links::store`]).
#[embassy_executor::task]
async fn store_task(flash: Flash<'static, flash::Async>, shared: &'static Shared) {
    links::store(flash, shared, &STORE_JOB).await
}

/// AEOLUS receive: the USART2 DMA ring into the AEOLUS link ([`links::aeolus_rx`]).
#[embassy_executor::task]
async fn aeolus_rx_task(uart: RingBufferedUartRx<'static>, shared: &'static Shared) {
    links::aeolus_rx(uart, shared, &AEOLUS_RX_ERRORS).await
}

/// AYDP receive: the USART1 DMA ring into the AYDP link ([`links::aydp_rx`]).
#[embassy_executor::task]
async fn aydp_rx_task(uart: RingBufferedUartRx<'static>, shared: &'static Shared) {
    links::aydp_rx(uart, shared, &AYDP_RX_ERRORS).await
}

/// AOK: the USART6 DMA ring into the AOK link, polled on bytes and at its wake ([`aok::aok`]).
#[embassy_executor::task]
async fn aok_task(
    uart: RingBufferedUartRx<'static>,
    shared: &'static Shared,
    heart: &'static Heartbeat,
) {
    aok::aok(uart, shared, &AOK_RX_ERRORS, heart).await
}

/// The DMA ring has no clock of its own per byte: the AOK link observes silence itself, by
/// polling ([`aok::Bursts`]).
impl aok::Bursts for RingBufferedUartRx<'_> {
    fn began_burst(&self) -> bool {
        false
    }
}

/// Transmit: one port's TX queue to its UART by DMA ([`links::pump_tx`]); one per UART.
#[embassy_executor::task(pool_size = 3)]
async fn tx_task(
    isr: PortIsr,
    uart: UartTx<'static, Async>,
    ready: &'static TxReady,
    heart: &'static Heartbeat,
) {
    links::pump_tx(isr, uart, ready, heart).await
}
