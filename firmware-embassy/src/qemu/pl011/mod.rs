//! An interrupt-driven async driver for the LM3S6965's three PL011 UARTs: `embedded-io-async`
//! [`Rx`] (with `ReadReady`) and [`Tx`], each woken by the UART's interrupt.
//!
//! * **Receive.** The interrupt moves what the RX FIFO holds into a [`RX_RING`]-byte ring
//!   (`sensor-box`'s `SerialIsr::receive_while`, the blocking boards' ring) and wakes the
//!   reader. While the ring is full it leaves the bytes in the FIFO and masks its RX
//!   interrupts; the reader's next read kicks the interrupt (pends it), which takes them then.
//!   QEMU stops reading a UART's socket while the FIFO is full, so nothing is lost; on a real
//!   part the FIFO overruns, which the UART reports (counted below). A receive error (the
//!   error bits of a DR read: overrun, break, parity, framing) takes no slot and is counted in
//!   the port's [`PortStats`] (`rx_errors`), and the reader's next read returns one error for
//!   the errors counted since its last.
//! * **Transmit.** [`Tx::write`] fills the TX FIFO while it has room and returns the count;
//!   with the FIFO full it enables the TX interrupt and waits for it.
//! * **Interrupt levels.** RX at half full with the receive-timeout interrupt for the rest of
//!   a burst, TX at one-eighth full, as a real PL011 wants them. QEMU 7.2's model ignores the
//!   levels: it raises RX at the first byte and never the receive timeout (so every byte it
//!   hands over raises RX), and sends a written byte at once, so its TX FIFO is never full.
//!
//! Every buffer is bounded ([`RX_RING`], the 16-byte FIFOs); no path panics.

use core::cell::RefCell;
use core::future::poll_fn;
use core::ptr::{read_volatile, write_volatile};
use core::task::Poll;

use cortex_m::peripheral::NVIC;
use critical_section::Mutex;
use embassy_sync::waitqueue::AtomicWaker;
use embedded_io::ErrorKind;
use firmware_example::serial::Ring;
use firmware_example::{PortStats, QueuedSerial, SerialIsr};
use sensor_box::budget::{self, Category};
use sensor_box::port::Receive;

use firmware_example::lm3s6965::uart::{
    self, CTL, CTL_UARTEN_TXE_RXE, DR, DR_ERRORS, FBRD, FR, IBRD, ICR, IFLS,
    IFLS_RX_HALF_TX_EIGHTH, IMSC, INT_ALL, LCRH, LCRH_WLEN8_FEN,
};

use super::chip::{CORE_HZ, Irq};
use wake::{FR_RXFE, FR_TXFF, INT_RT, INT_RX, INT_TX};

pub mod wake;

/// Bytes of each UART's receive ring.
pub const RX_RING: usize = 512;
/// The receive ring's TX side: unused (the receive split sends nothing).
const NO_TX: usize = 1;

/// The UARTs' baud rate (QEMU ignores it; a real part needs it).
const BAUD: u32 = 115_200;
/// The baud divisor in 64ths.
const BAUD_DIV_64THS: u32 = uart::baud_div_64ths(CORE_HZ, BAUD);

// `wake` keeps its own copy of the bits it decides on (it is compiled on the host alone, in
// tests/tests/all/harness/pl011_wake.rs); they are the register map's.
const _: () = assert!(
    FR_RXFE == uart::FR_RXFE
        && FR_TXFF == uart::FR_TXFF
        && wake::FR_TXFE == uart::FR_TXFE
        && INT_RX == uart::INT_RX
        && INT_TX == uart::INT_TX
        && INT_RT == uart::INT_RT
);

/// The UARTs' interrupt priority (below SysTick's, which is the highest).
const PRIORITY: u8 = 0x40;

/// One UART: its registers, its interrupt line, the wakers of its reader and writer, and the
/// interrupt's half of its receive ring.
struct Uart {
    base: usize,
    irq: Irq,
    /// Whether the interrupt marks where the line fell silent (`SerialIsr::at`): the UART of
    /// a link that frames commands by silence (AOK).
    marks_bursts: bool,
    rx_waker: AtomicWaker,
    tx_waker: AtomicWaker,
    isr: Mutex<RefCell<Option<RxIsr>>>,
}

/// The interrupt's half of a receive ring, and the port's counters.
type RxIsr = (SerialIsr<'static, RX_RING, NO_TX>, &'static PortStats);

impl Uart {
    const fn new(base: usize, irq: Irq, marks_bursts: bool) -> Self {
        Uart {
            base,
            irq,
            marks_bursts,
            rx_waker: AtomicWaker::new(),
            tx_waker: AtomicWaker::new(),
            isr: Mutex::new(RefCell::new(None)),
        }
    }

    fn read(&self, offset: usize) -> u32 {
        // SAFETY: `base` is one of the LM3S6965's PL011s and `offset` one of its registers.
        unsafe { read_volatile((self.base + offset) as *const u32) }
    }

    fn write(&self, offset: usize, value: u32) {
        // SAFETY: as in `read`; the writes below keep to the PL011's documented bits.
        unsafe { write_volatile((self.base + offset) as *mut u32, value) }
    }

    /// Rewrites the interrupt mask with `decide`'s new value (`None`: unchanged), and returns
    /// its verdict: a read-modify-write that the task and the interrupt both do, so in a
    /// critical section.
    fn update_mask<T>(&self, decide: impl FnOnce(u32) -> (Option<u32>, T)) -> T {
        critical_section::with(|_| {
            let (imsc, verdict) = decide(self.read(IMSC));
            if let Some(imsc) = imsc {
                self.write(IMSC, imsc);
            }
            verdict
        })
    }

    /// Writes bytes of `buf` into the TX FIFO while it has room; the count.
    fn fill_tx(&self, buf: &[u8]) -> usize {
        let mut n = 0;
        for &b in buf {
            if self.read(FR) & FR_TXFF != 0 {
                break;
            }
            self.write(DR, u32::from(b));
            n += 1;
        }
        n
    }
}

static UARTS: [Uart; 3] = [
    Uart::new(uart::BASE[0], Irq::Uart0, false),
    Uart::new(uart::BASE[1], Irq::Uart1, false),
    Uart::new(uart::BASE[2], Irq::Uart2, true),
];

/// The receive rings, one per UART (split once, in [`init`]).
static RX_RINGS: [Ring<RX_RING>; 3] = [const { Ring::new() }; 3];
/// The unused TX sides of the receive splits.
static NO_TX_RINGS: [Ring<NO_TX>; 3] = [const { Ring::new() }; 3];

/// The reading half of a UART.
pub struct Rx {
    uart: &'static Uart,
    port: QueuedSerial<'static, RX_RING, NO_TX>,
    /// The port's `rx_errors` as of the last error reported.
    errors_seen: u32,
    /// Whether the interrupt saw the line silent before the last read's first byte.
    began_burst: bool,
}

/// The writing half of a UART.
pub struct Tx {
    uart: &'static Uart,
}

/// Sets up UART `index` (0..=2; any other is `None`): 8N1, FIFOs on, the interrupt levels,
/// the RX and receive-timeout interrupts on, its interrupt line unmasked. `stats` counts its
/// received, dropped and errored bytes (the links' TX side counts the sent ones in the same
/// counters). Call once per UART, after the clocks are on.
pub fn init(index: usize, stats: &'static PortStats, nvic: &mut NVIC) -> Option<(Rx, Tx)> {
    let uart = UARTS.get(index)?;
    let kick: fn() = match index {
        0 => || NVIC::pend(Irq::Uart0),
        1 => || NVIC::pend(Irq::Uart1),
        _ => || NVIC::pend(Irq::Uart2),
    };
    let (port, isr) =
        QueuedSerial::split(RX_RINGS.get(index)?, NO_TX_RINGS.get(index)?, stats, kick);
    let placed =
        critical_section::with(|cs| uart.isr.borrow(cs).replace(Some((isr, stats))).is_none());
    if !placed {
        // A second init of the same UART would make a second reader of its ring.
        return None;
    }
    uart.write(CTL, 0);
    uart.write(IBRD, BAUD_DIV_64THS / 64);
    uart.write(FBRD, BAUD_DIV_64THS % 64);
    uart.write(LCRH, LCRH_WLEN8_FEN);
    uart.write(IFLS, IFLS_RX_HALF_TX_EIGHTH);
    uart.write(ICR, INT_ALL);
    uart.write(IMSC, INT_RX | INT_RT);
    uart.write(CTL, CTL_UARTEN_TXE_RXE);
    // SAFETY: the interrupt's state (the ring's half) is in place above; the priority is
    // set before the line is unmasked.
    unsafe {
        nvic.set_priority(uart.irq, PRIORITY);
        NVIC::unmask(uart.irq);
    }
    let errors_seen = stats.snapshot().rx_errors;
    Some((
        Rx {
            uart,
            port,
            errors_seen,
            began_burst: false,
        },
        Tx { uart },
    ))
}

/// UART `index`'s interrupt: takes what the RX FIFO holds (while the ring has room) and wakes
/// the reader; on TX room, masks the TX interrupt and wakes the writer. Also runs when the
/// reader pends it after it made room in a ring that was full.
pub fn on_interrupt(index: usize) {
    let Some(uart) = UARTS.get(index) else {
        return;
    };
    let previous = budget::enter(Category::RxIrq);
    // The TX interrupt stays raised while the FIFO has room (QEMU: after every byte), so it
    // is cleared with the RX ones; the writer enables it again when it needs to wait.
    uart.write(ICR, INT_RX | INT_RT | INT_TX);
    let (moved, new_errors, held) = critical_section::with(|cs| {
        // Only this interrupt borrows it after `init` (a failed borrow is not a panic).
        let Ok(mut isr) = uart.isr.borrow(cs).try_borrow_mut() else {
            return (0, false, false);
        };
        let Some((isr, stats)) = isr.as_mut() else {
            return (0, false, false);
        };
        let before = stats.snapshot().rx_errors;
        if uart.marks_bursts {
            isr.at(embassy_time::Instant::now().as_millis());
        }
        let n = isr.receive_while(|| {
            if uart.read(FR) & FR_RXFE != 0 {
                return None;
            }
            let dr = uart.read(DR);
            Some(if dr & DR_ERRORS != 0 {
                Err(())
            } else {
                Ok(dr as u8)
            })
        });
        (n, stats.snapshot().rx_errors != before, isr.rx_held())
    });
    // A full ring: the bytes wait in the FIFO, and its interrupts stay off until the reader
    // makes room (its read pends this interrupt).
    let wake_reader = uart.update_mask(|imsc| {
        let after = wake::after_receive(imsc, moved, new_errors, held);
        (Some(after.imsc), after.wake_reader)
    });
    if wake_reader {
        uart.rx_waker.wake();
    }
    budget::leave(previous);
    let previous = budget::enter(Category::TxIrq);
    // Only a writer that waits for room is woken (not the idle pump on every received byte).
    let wake_writer = uart.update_mask(|imsc| {
        let after = wake::after_transmit(imsc, uart.read(FR));
        (Some(after.imsc), after.wake_writer)
    });
    if wake_writer {
        uart.tx_waker.wake();
    }
    budget::leave(previous);
}

impl embedded_io::ErrorType for Rx {
    type Error = ErrorKind;
}

impl Rx {
    /// What a read does now ([`wake::read`]), with the port's receive-error count.
    fn next_read(&self) -> (wake::Read, u32) {
        let errors = self.port.counters().rx_errors;
        (
            wake::read(self.port.rx_pending(), errors, self.errors_seen),
            errors,
        )
    }
}

impl embedded_io_async::Read for Rx {
    /// Waits until received bytes wait in the ring, then moves as many as fit into `buf`. A
    /// receive error counted since the last read is returned first, as one
    /// [`ErrorKind::Other`] (the bytes read on).
    async fn read(&mut self, buf: &mut [u8]) -> Result<usize, ErrorKind> {
        if buf.is_empty() {
            return Ok(0);
        }
        poll_fn(|cx| {
            self.uart.rx_waker.register(cx.waker());
            match self.next_read() {
                (wake::Read::Error, errors) => {
                    self.errors_seen = errors;
                    Poll::Ready(Err(ErrorKind::Other))
                }
                (wake::Read::Wait, _) => Poll::Pending,
                // No read across a burst mark: a burst's bytes begin a read.
                (wake::Read::Take, _) => {
                    self.began_burst = self.port.burst_starts();
                    Poll::Ready(
                        self.port
                            .receive(|bytes| {
                                buf.iter_mut()
                                    .zip(bytes)
                                    .map(|(to, &from)| *to = from)
                                    .count()
                            })
                            .map_err(|e| match e {}),
                    )
                }
            }
        })
        .await
    }
}

impl embedded_io_async::ReadReady for Rx {
    /// Whether a read returns at once: bytes wait in the ring, or an error to report.
    fn read_ready(&mut self) -> Result<bool, ErrorKind> {
        Ok(self.next_read().0 != wake::Read::Wait)
    }
}

impl crate::aok::Bursts for Rx {
    /// Whether the interrupt saw the line silent before the last read's first byte (AOK's
    /// UART only).
    fn began_burst(&self) -> bool {
        self.began_burst
    }
}

impl embedded_io::ErrorType for Tx {
    type Error = ErrorKind;
}

impl embedded_io_async::Write for Tx {
    /// Writes what the TX FIFO has room for (at least one byte, waiting for the TX interrupt
    /// while the FIFO is full); the count.
    async fn write(&mut self, buf: &[u8]) -> Result<usize, ErrorKind> {
        if buf.is_empty() {
            return Ok(0);
        }
        poll_fn(|cx| {
            self.uart.tx_waker.register(cx.waker());
            let taken = self.uart.fill_tx(buf);
            self.uart
                .update_mask(|imsc| match wake::write(imsc, taken) {
                    wake::Write::Done(n) => (None, Poll::Ready(Ok(n))),
                    wake::Write::Wait(imsc) => (Some(imsc), Poll::Pending),
                })
        })
        .await
    }

    /// Waits until the TX FIFO is empty (woken by the TX interrupt as it drains).
    async fn flush(&mut self) -> Result<(), ErrorKind> {
        poll_fn(|cx| {
            self.uart.tx_waker.register(cx.waker());
            self.uart
                .update_mask(|imsc| match wake::flush(imsc, self.uart.read(FR)) {
                    wake::Write::Done(_) => (None, Poll::Ready(Ok(()))),
                    wake::Write::Wait(imsc) => (Some(imsc), Poll::Pending),
                })
        })
        .await
    }
}
