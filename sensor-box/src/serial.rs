//! The serial port the application sees on every board.
//!
//! A UART is split in two halves joined by two [`Ring`]s (`bbqueue` byte queues, which lend
//! contiguous slices of their storage, so every path copies slices, not bytes):
//!
//! ```text
//!   application (main loop)                      UART interrupt handler
//!   QueuedSerial::receive(|bytes| ..) <-- RX ring <--  SerialIsr::receive_while(next) / received(byte)
//!                                                      / receive_batched(at, publish, next)
//!   (or read(&mut buf), a copy)
//!   QueuedSerial::write(&frame)  --> TX ring -->  SerialIsr::send_while(room, put) / take_to_send
//!                                --> kick() (pends the interrupt)
//! ```
//!
//! The application's half speaks three interfaces: [`Receive`](crate::port::Receive) (the
//! links' RX: the received bytes lent in place, a run of the ring at a time, straight to the
//! decoders), `embedded_io`'s `Read`, `ReadReady`, `Write` and `WriteReady` (slices: the links
//! hand whole frames to the TX ring), and `embedded_hal_nb`'s
//! byte-at-a-time `serial::Read<u8>` / `Write<u8>` (whose non-blocking `flush` the main
//! loop calls after every poll).
//!
//! * RX: the interrupt moves every received byte into the RX ring at once, so
//!   nothing is lost while the main loop is busy (telemetry at full rate). A
//!   full ring drops the byte and counts it in [`PortStats`] ([`SerialIsr::received`]), or
//!   leaves it in the UART ([`SerialIsr::receive_while`]: back-pressure).
//! * TX: `write` queues the bytes and calls the board's `kick`, which pends the
//!   UART interrupt (a [`QueuedSerial::batched`] port kicks once per burst,
//!   on `flush`); the handler moves queued bytes into the UART while it has room, and keeps its TX interrupt enabled only while bytes are
//!   waiting. The TX ring being full is the only thing a writer waits for: `write_ready`
//!   says so (and the `nb` `write` returns `nb::WouldBlock`), so the main loop never waits
//!   for the wire.
//!
//! A [`Ring`] of `N` bytes holds `N - 1` to `N` bytes (a bip buffer: which one depends on
//! where its read and write positions stand). The same types run in host tests: the test
//! plays the interrupt handler.

use crate::burst_marks::BurstMarks;
use crate::port::copy_prefix;
use bbqueue::prod_cons::stream::{StreamConsumer, StreamGrantW, StreamProducer};
use bbqueue::traits::{coordination::cs::CsCoord, notifier::polling::Polling, storage::Inline};
use core::convert::Infallible;
use core::sync::atomic::{AtomicBool, AtomicU32, Ordering};
use embedded_hal_nb::serial::{ErrorType, Read, Write};

/// A byte queue of `N` bytes between the main loop and an interrupt handler: `bbqueue`'s
/// inline storage, coordination in a critical section (on a single-core part, interrupts
/// masked for a few instructions: cheaper than compare-and-swap loops and barriers), no async
/// notifier. `Ring::new()` is `const`, so a board keeps its rings in `static`s.
pub type Ring<const N: usize> = bbqueue::BBQueue<Inline<N>, CsCoord, Polling>;

/// Counters shared by both halves of a port (wrapping `u32`s), and whether the handler holds
/// received bytes back in the UART.
#[derive(Debug, Default)]
pub struct PortStats {
    rx_bytes: AtomicU32,
    rx_dropped: AtomicU32,
    rx_errors: AtomicU32,
    tx_bytes: AtomicU32,
    /// The handler found the RX ring full and left bytes in the UART: the next read kicks it.
    rx_held: AtomicBool,
    /// Where the handler saw the line fall silent ([`SerialIsr::at`]).
    marks: BurstMarks,
}

/// A copy of the counters at one instant.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(all(feature = "defmt", target_os = "none"), derive(defmt::Format))]
pub struct PortCounters {
    /// Bytes received and queued.
    pub rx_bytes: u32,
    /// Bytes received but dropped because the RX queue was full.
    pub rx_dropped: u32,
    /// UART receive errors (overrun, framing, parity, break) reported by the board.
    pub rx_errors: u32,
    /// Bytes handed to the UART.
    pub tx_bytes: u32,
}

impl PortStats {
    /// All counters at zero (usable in a `static`).
    ///
    /// ```
    /// static STATS: sensor_box::serial::PortStats = sensor_box::serial::PortStats::new();
    /// assert_eq!(STATS.snapshot().rx_bytes, 0);
    /// ```
    pub const fn new() -> Self {
        Self {
            rx_bytes: AtomicU32::new(0),
            rx_dropped: AtomicU32::new(0),
            rx_errors: AtomicU32::new(0),
            tx_bytes: AtomicU32::new(0),
            rx_held: AtomicBool::new(false),
            marks: BurstMarks::new(),
        }
    }

    /// Reads all counters.
    ///
    /// ```
    /// let s = sensor_box::serial::PortStats::new();
    /// assert_eq!(s.snapshot(), Default::default());
    /// ```
    pub fn snapshot(&self) -> PortCounters {
        PortCounters {
            rx_bytes: self.rx_bytes.load(Ordering::Relaxed),
            rx_dropped: self.rx_dropped.load(Ordering::Relaxed),
            rx_errors: self.rx_errors.load(Ordering::Relaxed),
            tx_bytes: self.tx_bytes.load(Ordering::Relaxed),
        }
    }
}

fn bump(counter: &AtomicU32) {
    add(counter, 1);
}

/// Adds `n` to a counter only one side writes. Single-core targets: load/store is enough and
/// works on every Cortex-M.
fn add(counter: &AtomicU32, n: usize) {
    counter.store(
        counter
            .load(Ordering::Relaxed)
            .wrapping_add(u32::try_from(n).unwrap_or(u32::MAX)),
        Ordering::Relaxed,
    );
}

/// The application's half of a UART with an `RX`-byte and a `TX`-byte [`Ring`]: `embedded_io`
/// `Read`, `ReadReady`, `Write` and `WriteReady` (slices), and `embedded_hal_nb` `Read<u8>`
/// and `Write<u8>` (bytes).
pub struct QueuedSerial<'q, const RX: usize, const TX: usize> {
    rx: StreamConsumer<&'q Ring<RX>>,
    tx: StreamProducer<&'q Ring<TX>>,
    stats: &'q PortStats,
    kick: fn(),
    /// Kick only on `flush` and when the TX queue is full (see [`QueuedSerial::batched`]).
    batched: bool,
    /// Bytes read from the RX ring since the split (wrapping; against `stats.rx_bytes`).
    rx_taken: u32,
    /// Bytes queued into the TX ring since the split (wrapping; against `stats.tx_bytes`).
    tx_queued: u32,
}

/// The interrupt handler's half of a UART.
pub struct SerialIsr<'q, const RX: usize, const TX: usize> {
    rx: StreamProducer<&'q Ring<RX>>,
    tx: StreamConsumer<&'q Ring<TX>>,
    stats: &'q PortStats,
    /// The run of free RX ring that [`SerialIsr::receive_batched`] keeps open across
    /// interrupts (a write grant, never full) and how many of its bytes are filled.
    open: Option<(StreamGrantW<&'q Ring<RX>>, usize)>,
    /// The millisecond the board last gave ([`SerialIsr::at`]); [`NEVER`]: no marks. (Plain
    /// `u64`s, not `Option`s: an `Option` would give a board's `static` of
    /// `Option<SerialIsr>` a non-zero `None`, in `.data` instead of `.bss`.)
    now_ms: u64,
    /// The millisecond of the last byte (or receive error) taken, by that clock; [`NEVER`].
    last_rx_ms: u64,
}

impl<'q, const RX: usize, const TX: usize> QueuedSerial<'q, RX, TX> {
    /// Splits an RX and a TX ring into the application's port and the interrupt handler's
    /// half. `kick` is called after every write (see [`QueuedSerial::batched`]); a board makes
    /// it pend the UART interrupt. Split each ring once: a second split would make a second
    /// writer (whose grants then fail while the first holds one).
    ///
    /// ```
    /// use sensor_box::serial::{QueuedSerial, Ring};
    /// let (rxq, txq) = (Ring::<16>::new(), Ring::<16>::new());
    /// let stats = sensor_box::serial::PortStats::new();
    /// let (port, isr) = QueuedSerial::split(&rxq, &txq, &stats, || {});
    /// # let _ = (port, isr);
    /// ```
    pub fn split(
        rx_queue: &'q Ring<RX>,
        tx_queue: &'q Ring<TX>,
        stats: &'q PortStats,
        kick: fn(),
    ) -> (QueuedSerial<'q, RX, TX>, SerialIsr<'q, RX, TX>) {
        (
            QueuedSerial {
                rx: rx_queue.stream_consumer(),
                tx: tx_queue.stream_producer(),
                stats,
                kick,
                batched: false,
                rx_taken: 0,
                tx_queued: 0,
            },
            SerialIsr {
                rx: rx_queue.stream_producer(),
                tx: tx_queue.stream_consumer(),
                stats,
                open: None,
                now_ms: NEVER,
                last_rx_ms: NEVER,
            },
        )
    }

    /// The same port, kicking the interrupt per burst instead of per write: `write` only
    /// queues (it kicks when the TX queue is full, then tries once more), and `flush` kicks.
    /// The owner must call `flush` after each burst of writes (the firmware's main loop does,
    /// after every poll), or the bytes wait. One interrupt then moves a whole burst into the
    /// UART's FIFO instead of one interrupt per byte.
    ///
    /// ```
    /// use embedded_hal_nb::serial::Write;
    /// use sensor_box::serial::{QueuedSerial, Ring};
    /// use core::sync::atomic::{AtomicU32, Ordering};
    /// static KICKS: AtomicU32 = AtomicU32::new(0);
    /// let (a, b) = (Ring::<4>::new(), Ring::<8>::new());
    /// let stats = sensor_box::serial::PortStats::new();
    /// let (port, _isr) = QueuedSerial::split(&a, &b, &stats, || {
    ///     KICKS.fetch_add(1, Ordering::Relaxed);
    /// });
    /// let mut port = port.batched();
    /// for byte in b"hello" {
    ///     port.write(*byte).unwrap();
    /// }
    /// assert_eq!(KICKS.load(Ordering::Relaxed), 0);
    /// assert!(port.flush().is_err()); // bytes wait: the interrupt is kicked once
    /// assert_eq!(KICKS.load(Ordering::Relaxed), 1);
    /// ```
    pub fn batched(self) -> Self {
        QueuedSerial {
            batched: true,
            ..self
        }
    }

    /// Received bytes waiting to be read.
    ///
    /// ```
    /// # use sensor_box::serial::{QueuedSerial, Ring};
    /// # let (a, b) = (Ring::<4>::new(), Ring::<4>::new());
    /// # let stats = sensor_box::serial::PortStats::new();
    /// let (port, mut isr) = QueuedSerial::split(&a, &b, &stats, || {});
    /// isr.received(1);
    /// assert_eq!(port.rx_pending(), 1);
    /// ```
    pub fn rx_pending(&self) -> usize {
        let received = self.stats.rx_bytes.load(Ordering::Relaxed);
        received.wrapping_sub(self.rx_taken) as usize
    }

    /// Room left in the TX ring, bytes (at most `TX`; one byte less may fit, see [`Ring`]).
    ///
    /// ```
    /// # use sensor_box::serial::{QueuedSerial, Ring};
    /// # let (a, b) = (Ring::<4>::new(), Ring::<4>::new());
    /// # let stats = sensor_box::serial::PortStats::new();
    /// let (port, _isr) = QueuedSerial::split(&a, &b, &stats, || {});
    /// assert_eq!(port.tx_space(), 4);
    /// ```
    pub fn tx_space(&self) -> usize {
        TX.saturating_sub(self.tx_waiting())
    }

    /// The port's counters.
    ///
    /// ```
    /// # use sensor_box::serial::{QueuedSerial, Ring};
    /// # let (a, b) = (Ring::<4>::new(), Ring::<4>::new());
    /// # let stats = sensor_box::serial::PortStats::new();
    /// let (port, _isr) = QueuedSerial::split(&a, &b, &stats, || {});
    /// assert_eq!(port.counters().rx_dropped, 0);
    /// ```
    pub fn counters(&self) -> PortCounters {
        self.stats.snapshot()
    }

    /// Bytes queued and not yet handed to the UART.
    fn tx_waiting(&self) -> usize {
        let sent = self.stats.tx_bytes.load(Ordering::Relaxed);
        self.tx_queued.wrapping_sub(sent) as usize
    }

    /// Moves received bytes into `buf`, a slice copy per contiguous run of the ring (two at
    /// most), as many as are waiting and fit; the count. Kicks the interrupt when it had left
    /// bytes in the UART for want of room (see [`SerialIsr::receive_while`]).
    fn take_received(&mut self, buf: &mut [u8]) -> usize {
        let n = drain(&self.rx, buf);
        add_local(&mut self.rx_taken, n);
        if n > 0 && self.stats.rx_held.swap(false, Ordering::Relaxed) {
            (self.kick)();
        }
        n
    }

    /// Copies as much of `bytes` into the TX ring as it has room for, a slice copy per
    /// contiguous run (two at most); the count.
    fn queue_to_send(&mut self, bytes: &[u8]) -> usize {
        let mut n = 0;
        while let Some(rest) = bytes.get(n..).filter(|r| !r.is_empty()) {
            let Ok(mut grant) = self.tx.grant_max_remaining(rest.len()) else {
                break;
            };
            let k = grant.len().min(rest.len());
            copy_prefix(&mut grant, rest.get(..k).unwrap_or(&[]));
            grant.commit(k);
            n += k;
        }
        add_local(&mut self.tx_queued, n);
        n
    }

    /// Whether the TX ring has room for one more byte.
    fn tx_room(&self) -> bool {
        // The count first: the TX ring only ever wraps when its write position is at the end
        // (`queue_to_send` asks for what remains up to the end), so it always has room while
        // two bytes are free. `tx_waiting` can only be too high (the handler counts the bytes
        // after releasing them), never too low.
        if self.tx_waiting().saturating_add(2) <= TX {
            return true;
        }
        // Near full: ask the ring (a grant of one byte, dropped at once: nothing committed).
        self.tx.grant_max_remaining(1).is_ok()
    }
}

/// Hands `block` to `put` four bytes a step (the loop's test and branch once per four calls):
/// the FIFO fill of the TX interrupt.
#[inline(always)]
fn put_block(block: &[u8], put: &mut impl FnMut(u8)) {
    let mut quads = block.chunks_exact(4);
    for q in &mut quads {
        if let [a, b, c, d] = *q {
            put(a);
            put(b);
            put(c);
            put(d);
        }
    }
    for &byte in quads.remainder() {
        put(byte);
    }
}

/// Stores the UART's bytes (`next`, as [`SerialIsr::receive_while`] takes them) into `run`
/// from its start, until the UART has none left (`true`) or the run is full (`false`), and the
/// bytes stored; receive errors are counted in `errors` and take no slot. The end of the run
/// is tested after each store (the slot in hand is filled, then the next one asked for), so a
/// byte costs the UART's reads, the store and one compare.
#[inline(always)]
fn fill_run(
    run: &mut [u8],
    next: &mut impl FnMut() -> Option<Result<u8, ()>>,
    errors: &mut usize,
) -> (bool, usize) {
    let len = run.len();
    let mut slots = run.iter_mut();
    let mut bad = 0;
    let stored = match slots.next() {
        None => (false, 0),
        Some(mut slot) => loop {
            match next() {
                Some(Ok(byte)) => {
                    *slot = byte;
                    match slots.next() {
                        Some(free) => slot = free,
                        None => break (false, len),
                    }
                }
                Some(Err(())) => bad += 1,
                // The slot in hand and those after it stay free.
                None => break (true, len - 1 - slots.len()),
            }
        },
    };
    *errors += bad;
    stored
}

/// `next` (the UART's bytes, as [`SerialIsr::receive_while`] takes them), noting in `active`
/// whether it gave anything and, with `mark`, leaving the burst mark at the given position
/// before the first thing it gives.
#[inline(always)]
fn marking<'a>(
    active: &'a mut bool,
    mark: Option<(&'a PortStats, u32)>,
    mut next: impl FnMut() -> Option<Result<u8, ()>> + 'a,
) -> impl FnMut() -> Option<Result<u8, ()>> + 'a {
    move || {
        let item = next();
        if item.is_some() && !*active {
            *active = true;
            if let Some((stats, position)) = mark {
                stats.marks.push(position);
            }
        }
        item
    }
}

/// "No such millisecond" in [`SerialIsr`]'s clock fields.
const NEVER: u64 = u64::MAX;

/// Adds `n` to a wrapping count one side keeps to itself.
fn add_local(counter: &mut u32, n: usize) {
    *counter = counter.wrapping_add(u32::try_from(n).unwrap_or(u32::MAX));
}

/// Moves bytes from `ring` into `buf`, a slice copy per contiguous run (two at most), as
/// many as are waiting and fit; the count.
fn drain<const N: usize>(ring: &StreamConsumer<&Ring<N>>, buf: &mut [u8]) -> usize {
    let mut n = 0;
    while let Some(rest) = buf.get_mut(n..).filter(|r| !r.is_empty()) {
        let Ok(grant) = ring.read() else { break };
        let k = grant.len().min(rest.len());
        copy_prefix(rest, grant.get(..k).unwrap_or(&[]));
        let whole = k == grant.len();
        grant.release(k);
        n += k;
        if !whole {
            break;
        }
    }
    n
}

impl<const RX: usize, const TX: usize> ErrorType for QueuedSerial<'_, RX, TX> {
    type Error = Infallible;
}

impl<const RX: usize, const TX: usize> embedded_io::ErrorType for QueuedSerial<'_, RX, TX> {
    type Error = Infallible;
}

impl<const RX: usize, const TX: usize> embedded_io::ReadReady for QueuedSerial<'_, RX, TX> {
    /// Whether received bytes are waiting: then [`embedded_io::Read::read`] does not wait.
    fn read_ready(&mut self) -> Result<bool, Infallible> {
        Ok(self.rx_pending() > 0)
    }
}

impl<const RX: usize, const TX: usize> embedded_io::Read for QueuedSerial<'_, RX, TX> {
    /// Moves the received bytes waiting in the RX ring into `buf` (as many as fit), a slice
    /// copy per contiguous run. With nothing waiting it waits for the interrupt to receive a
    /// byte, as `embedded_io` asks: a caller that must not wait asks
    /// [`read_ready`](embedded_io::ReadReady::read_ready) first.
    ///
    /// ```
    /// use embedded_io::{Read, ReadReady};
    /// # use sensor_box::serial::{QueuedSerial, Ring};
    /// # let (a, b) = (Ring::<8>::new(), Ring::<4>::new());
    /// # let stats = sensor_box::serial::PortStats::new();
    /// let (mut port, mut isr) = QueuedSerial::split(&a, &b, &stats, || {});
    /// for byte in b"hello" {
    ///     isr.received(*byte);
    /// }
    /// let mut buf = [0u8; 4];
    /// assert_eq!(port.read(&mut buf), Ok(4));
    /// assert_eq!(&buf, b"hell");
    /// assert_eq!(port.read(&mut buf), Ok(1));
    /// assert_eq!(port.read_ready(), Ok(false));
    /// ```
    fn read(&mut self, buf: &mut [u8]) -> Result<usize, Infallible> {
        if buf.is_empty() {
            return Ok(0);
        }
        loop {
            let n = self.take_received(buf);
            if n > 0 {
                return Ok(n);
            }
        }
    }
}

impl<const RX: usize, const TX: usize> crate::port::Receive for QueuedSerial<'_, RX, TX> {
    /// Lends `take` the oldest run of received bytes in the RX ring, in place (a read grant
    /// up to the ring's end), and releases what it took. Kicks the interrupt when it had left
    /// bytes in the UART for want of room (see [`SerialIsr::receive_while`]).
    fn receive(&mut self, take: impl FnOnce(&[u8]) -> usize) -> Result<usize, Infallible> {
        // Two loads say whether anything waits; the grant (atomics) only when it does.
        if self.rx_pending() == 0 {
            return Ok(0);
        }
        let Ok(grant) = self.rx.read() else {
            return Ok(0);
        };
        // No slice across a burst mark.
        let (_, limit) = self.stats.marks.next(self.rx_taken);
        let len = limit.map_or(grant.len(), |l| l.min(grant.len()));
        let n = take(grant.get(..len).unwrap_or(&grant)).min(len);
        grant.release(n);
        add_local(&mut self.rx_taken, n);
        if n > 0 && self.stats.rx_held.swap(false, Ordering::Relaxed) {
            (self.kick)();
        }
        Ok(n)
    }

    /// Whether the handler left a burst mark before the next byte ([`SerialIsr::at`]).
    fn burst_starts(&self) -> bool {
        self.rx_pending() > 0 && self.stats.marks.next(self.rx_taken).0
    }

    /// [`PortCounters::rx_errors`] plus [`PortCounters::rx_dropped`], wrapping.
    fn receive_faults(&self) -> u32 {
        let errors = self.stats.rx_errors.load(Ordering::Relaxed);
        errors.wrapping_add(self.stats.rx_dropped.load(Ordering::Relaxed))
    }
}

impl<const RX: usize, const TX: usize> crate::port::Transmit for QueuedSerial<'_, RX, TX> {
    /// Lends `fill` the free run of the TX ring from its write position (a write grant, up to
    /// the ring's end, as [`embedded_io::Write::write`] takes it), commits what `fill` wrote
    /// and kicks the interrupt (a [`QueuedSerial::batched`] port only on `flush`). A full ring
    /// lends nothing.
    fn transmit(&mut self, fill: impl FnOnce(&mut [u8]) -> usize) -> Result<usize, Infallible> {
        let Ok(mut grant) = self.tx.grant_max_remaining(TX) else {
            return Ok(0);
        };
        let n = fill(&mut grant).min(grant.len());
        grant.commit(n);
        add_local(&mut self.tx_queued, n);
        if n > 0 && !self.batched {
            (self.kick)();
        }
        Ok(n)
    }
}

impl<const RX: usize, const TX: usize> embedded_io::WriteReady for QueuedSerial<'_, RX, TX> {
    /// Whether the TX ring has room for a byte: then [`embedded_io::Write::write`] does not
    /// wait. When it is full the interrupt is kicked first (a batched port's bytes are
    /// otherwise only kicked on `flush`) and the room checked once more.
    fn write_ready(&mut self) -> Result<bool, Infallible> {
        if self.tx_room() {
            return Ok(true);
        }
        (self.kick)();
        Ok(self.tx_room())
    }
}

impl<const RX: usize, const TX: usize> embedded_io::Write for QueuedSerial<'_, RX, TX> {
    /// Copies as much of `buf` as the TX ring has room for, a slice copy per contiguous run,
    /// and kicks the interrupt (a [`QueuedSerial::batched`] port only when the ring is full:
    /// its owner's `flush` kicks). With the ring full it kicks and waits for room, as
    /// `embedded_io` asks: a caller that must not wait asks
    /// [`write_ready`](embedded_io::WriteReady::write_ready) first.
    ///
    /// ```
    /// use embedded_io::{Write, WriteReady};
    /// # use sensor_box::serial::{QueuedSerial, Ring};
    /// # let (a, b) = (Ring::<2>::new(), Ring::<4>::new());
    /// # let stats = sensor_box::serial::PortStats::new();
    /// let (mut port, mut isr) = QueuedSerial::split(&a, &b, &stats, || {});
    /// assert_eq!(port.write(b"hello"), Ok(4)); // a ring of 4, empty, holds 4
    /// assert_eq!(port.write_ready(), Ok(false));
    /// assert_eq!(isr.next_to_send(), Some(b'h'));
    /// assert_eq!(isr.next_to_send(), Some(b'e'));
    /// assert_eq!(port.write(b"o!"), Ok(1)); // wrapped: the ring keeps one byte free
    /// ```
    fn write(&mut self, buf: &[u8]) -> Result<usize, Infallible> {
        if buf.is_empty() {
            return Ok(0);
        }
        let mut n = self.queue_to_send(buf);
        while n == 0 {
            (self.kick)();
            n = self.queue_to_send(buf);
        }
        if !self.batched {
            (self.kick)();
        }
        Ok(n)
    }

    /// Kicks the interrupt and waits until every queued byte has gone to the UART. The main
    /// loop, which must not wait, uses the `embedded_hal_nb` `flush` instead.
    fn flush(&mut self) -> Result<(), Infallible> {
        (self.kick)();
        while self.tx_waiting() > 0 {}
        Ok(())
    }
}

impl<const RX: usize, const TX: usize> Read<u8> for QueuedSerial<'_, RX, TX> {
    /// The next received byte, or `WouldBlock` when none is waiting.
    ///
    /// When the ring was full, the board's interrupt may have stopped taking bytes from the
    /// UART (see [`SerialIsr::receive_while`]); reading then kicks it, so it takes them again.
    fn read(&mut self) -> nb::Result<u8, Self::Error> {
        let mut byte = [0u8];
        if self.take_received(&mut byte) == 0 {
            return Err(nb::Error::WouldBlock);
        }
        Ok(byte[0])
    }
}

impl<const RX: usize, const TX: usize> Write<u8> for QueuedSerial<'_, RX, TX> {
    /// Queues a byte; `WouldBlock` when the TX ring is full.
    fn write(&mut self, word: u8) -> nb::Result<(), Self::Error> {
        let mut queued = self.queue_to_send(&[word]) == 1;
        if !queued && self.batched {
            // Full: start the interrupt on what is queued, and try once more (the
            // handler may have made room at once).
            (self.kick)();
            queued = self.queue_to_send(&[word]) == 1;
        } else if !self.batched {
            (self.kick)();
        }
        if queued {
            Ok(())
        } else {
            Err(nb::Error::WouldBlock)
        }
    }

    /// `Ok` once every queued byte has gone to the UART, else `WouldBlock`.
    fn flush(&mut self) -> nb::Result<(), Self::Error> {
        if self.tx_waiting() == 0 {
            Ok(())
        } else {
            (self.kick)();
            Err(nb::Error::WouldBlock)
        }
    }
}

impl<const RX: usize, const TX: usize> SerialIsr<'_, RX, TX> {
    /// Stores a received byte; when the RX ring is full the byte is dropped
    /// and counted. Returns whether it was stored. For a UART that cannot hold bytes back;
    /// [`SerialIsr::receive_while`] takes a FIFO's worth at once.
    ///
    /// ```
    /// # use sensor_box::serial::{QueuedSerial, Ring};
    /// # let (a, b) = (Ring::<1>::new(), Ring::<2>::new());
    /// # let stats = sensor_box::serial::PortStats::new();
    /// let (port, mut isr) = QueuedSerial::split(&a, &b, &stats, || {});
    /// assert!(isr.received(1));
    /// assert!(!isr.received(2)); // the ring holds one byte
    /// assert_eq!(port.counters().rx_dropped, 1);
    /// ```
    pub fn received(&mut self, byte: u8) -> bool {
        self.publish();
        if self.silent() {
            let position = self.stats.rx_bytes.load(Ordering::Relaxed);
            self.stats.marks.push(position);
        }
        self.heard(true);
        match self.rx.grant_exact(1) {
            Ok(mut grant) => {
                copy_prefix(&mut grant, &[byte]);
                grant.commit(1);
                bump(&self.stats.rx_bytes);
                true
            }
            Err(_) => {
                bump(&self.stats.rx_dropped);
                false
            }
        }
    }

    /// Moves received bytes from the UART into the RX ring while the ring has room: `next`
    /// gives the UART's next byte (`Some(Ok(byte))`), a receive error (`Some(Err(()))`,
    /// counted) or `None` when the UART has nothing more; the bytes stored. Each contiguous
    /// run of free ring is filled in place and committed once, and the count updated once.
    /// When the ring is full `next` is not called again and the bytes stay in the UART (a
    /// FIFO, and a peer that waits for it, as QEMU's sockets do): the application's next
    /// read kicks the interrupt, which takes them then.
    ///
    /// ```
    /// # use sensor_box::serial::{QueuedSerial, Ring};
    /// # let (a, b) = (Ring::<4>::new(), Ring::<2>::new());
    /// # let stats = sensor_box::serial::PortStats::new();
    /// let (port, mut isr) = QueuedSerial::split(&a, &b, &stats, || {});
    /// let mut uart = [Ok(1), Err(()), Ok(2), Ok(3), Ok(4), Ok(5)].into_iter();
    /// assert_eq!(isr.receive_while(|| uart.next()), 4); // the ring is full
    /// assert_eq!(uart.next(), Some(Ok(5))); // still in the UART
    /// assert_eq!((port.rx_pending(), port.counters().rx_errors), (4, 1));
    /// ```
    pub fn receive_while(&mut self, next: impl FnMut() -> Option<Result<u8, ()>>) -> usize {
        // Bytes a `receive_batched` left unpublished come first.
        self.publish();
        let position = self.stats.rx_bytes.load(Ordering::Relaxed);
        let mark = self.silent().then_some((self.stats, position));
        let mut active = false;
        let mut next = marking(&mut active, mark, next);
        // Errors are counted in a register, added to the shared counter once at the end (and
        // only when there were any).
        let (mut total, mut errors) = (0, 0);
        loop {
            let Ok(mut grant) = self.rx.grant_max_remaining(usize::MAX) else {
                self.stats.rx_held.store(true, Ordering::Relaxed);
                break;
            };
            let (empty, n) = fill_run(&mut grant, &mut next, &mut errors);
            grant.commit(n);
            total += n;
            if empty {
                break;
            }
        }
        drop(next);
        self.heard(active);
        self.count_received(total, errors);
        total
    }

    /// Moves received bytes from the UART into the RX ring as [`SerialIsr::receive_while`]
    /// does, but keeps the run of free ring it fills open from one call to the next: its bytes
    /// become the application's (committed, and counted in `rx_bytes`) only once `publish_at`
    /// of them wait, when the run is full, or when `publish` is true; the count of bytes this
    /// call published. An interrupt handler that takes a few bytes at a time pays for the
    /// ring's grant and commit once per `publish_at` bytes instead of once per interrupt; it
    /// calls again with `publish` true (with or without new bytes) when the application must
    /// see what waits, such as once a millisecond while [`SerialIsr::unpublished`] is not 0.
    /// When the ring is full `next` is not called again and the bytes stay in the UART, as in
    /// `receive_while`.
    ///
    /// ```
    /// # use sensor_box::serial::{QueuedSerial, Ring};
    /// # let (a, b) = (Ring::<64>::new(), Ring::<2>::new());
    /// # let stats = sensor_box::serial::PortStats::new();
    /// let (port, mut isr) = QueuedSerial::split(&a, &b, &stats, || {});
    /// let mut uart = [1, 2, 3].into_iter().map(Ok);
    /// assert_eq!(isr.receive_batched(8, false, || uart.next()), 0); // held in the ring
    /// assert_eq!((isr.unpublished(), port.rx_pending()), (3, 0));
    /// let mut more = [4, 5, 6, 7, 8].into_iter().map(Ok);
    /// assert_eq!(isr.receive_batched(8, false, || more.next()), 8); // 8 wait: published
    /// assert_eq!(isr.receive_batched(8, true, || None), 0); // nothing left to publish
    /// assert_eq!((isr.unpublished(), port.rx_pending()), (0, 8));
    /// ```
    pub fn receive_batched(
        &mut self,
        publish_at: usize,
        publish: bool,
        next: impl FnMut() -> Option<Result<u8, ()>>,
    ) -> usize {
        let (mut published, mut errors) = (0, 0);
        let unpublished = u32::try_from(self.unpublished()).unwrap_or(u32::MAX);
        let position = self.stats.rx_bytes.load(Ordering::Relaxed);
        let mark = self
            .silent()
            .then_some((self.stats, position.wrapping_add(unpublished)));
        let mut active = false;
        let mut next = marking(&mut active, mark, next);
        loop {
            if self.open.is_none() {
                match self.rx.grant_max_remaining(usize::MAX) {
                    Ok(grant) => self.open = Some((grant, 0)),
                    Err(_) => {
                        self.stats.rx_held.store(true, Ordering::Relaxed);
                        break;
                    }
                }
            }
            let Some((grant, filled)) = self.open.as_mut() else {
                break;
            };
            let len = grant.len();
            let free = grant.get_mut(*filled..).unwrap_or_default();
            let (empty, n) = fill_run(free, &mut next, &mut errors);
            *filled += n;
            let waiting = *filled;
            if waiting >= len || waiting >= publish_at || (empty && publish && waiting > 0) {
                published += self.commit_open();
            }
            if empty {
                break;
            }
        }
        drop(next);
        self.heard(active);
        self.count_received(published, errors);
        published
    }

    /// Adds bytes made the application's and receive errors to the shared counters (the
    /// errors only when there were any).
    #[inline(always)]
    fn count_received(&self, bytes: usize, errors: usize) {
        add(&self.stats.rx_bytes, bytes);
        if errors > 0 {
            add(&self.stats.rx_errors, errors);
        }
    }

    /// Received bytes that [`SerialIsr::receive_batched`] holds in the ring and has not
    /// published yet (the application does not see them).
    ///
    /// ```
    /// # use sensor_box::serial::{QueuedSerial, Ring};
    /// # let (a, b) = (Ring::<8>::new(), Ring::<2>::new());
    /// # let stats = sensor_box::serial::PortStats::new();
    /// let (_port, mut isr) = QueuedSerial::split(&a, &b, &stats, || {});
    /// let mut uart = [7].into_iter().map(Ok);
    /// isr.receive_batched(4, false, || uart.next());
    /// assert_eq!(isr.unpublished(), 1);
    /// ```
    pub fn unpublished(&self) -> usize {
        self.open.as_ref().map_or(0, |(_, filled)| *filled)
    }

    /// Publishes what [`SerialIsr::receive_batched`] holds (see there), counted.
    fn publish(&mut self) {
        let n = self.commit_open();
        add(&self.stats.rx_bytes, n);
    }

    /// Commits the open run's filled bytes, if a run is open, and closes it; the count (not
    /// yet added to `rx_bytes`).
    #[inline(always)]
    fn commit_open(&mut self) -> usize {
        let Some((grant, filled)) = self.open.take() else {
            return 0;
        };
        grant.commit(filled);
        filled
    }

    /// Counts a receive error reported by the UART hardware.
    ///
    /// ```
    /// # use sensor_box::serial::{QueuedSerial, Ring};
    /// # let (a, b) = (Ring::<2>::new(), Ring::<2>::new());
    /// # let stats = sensor_box::serial::PortStats::new();
    /// let (port, mut isr) = QueuedSerial::split(&a, &b, &stats, || {});
    /// isr.receive_error();
    /// assert_eq!(port.counters().rx_errors, 1);
    /// ```
    pub fn receive_error(&mut self) {
        bump(&self.stats.rx_errors);
        self.heard(true);
    }

    /// Tells the handler the board's millisecond (its SysTick count) before it takes the
    /// UART's bytes. From the first call on, the first byte after [`GAP_MS`] of silence by
    /// this clock (no byte and no receive error since) leaves a burst mark
    /// ([`crate::burst_marks`]): a link that frames commands by silence then tells apart the
    /// commands that waited in the ring while the main loop stalled. A board that never calls
    /// it leaves no mark.
    ///
    /// ```
    /// use sensor_box::port::Receive;
    /// # use sensor_box::serial::{QueuedSerial, Ring};
    /// # let (a, b) = (Ring::<16>::new(), Ring::<2>::new());
    /// # let stats = sensor_box::serial::PortStats::new();
    /// let (mut port, mut isr) = QueuedSerial::split(&a, &b, &stats, || {});
    /// for (ms, byte) in [(0, 0x67), (0, 0x01), (5, 0x67), (5, 0x02)] {
    ///     isr.at(ms);
    ///     isr.received(byte);
    /// }
    /// // The main loop comes late: the port lends the first command alone, then says that the
    /// // next byte begins a burst.
    /// assert!(port.burst_starts());
    /// assert_eq!(port.receive(|bytes| bytes.len()), Ok(2));
    /// assert!(port.burst_starts());
    /// assert_eq!(port.receive(|bytes| bytes.len()), Ok(2));
    /// ```
    ///
    /// [`GAP_MS`]: crate::aok_link::GAP_MS
    pub fn at(&mut self, now_ms: u64) {
        self.now_ms = now_ms.min(NEVER - 1);
    }

    /// Whether, by the board's clock, the line has been silent long enough for the next byte
    /// to begin a burst.
    fn silent(&self) -> bool {
        match (self.now_ms, self.last_rx_ms) {
            (NEVER, _) => false,
            (_, NEVER) => true,
            (now, last) => now.saturating_sub(last) >= crate::aok_link::GAP_MS,
        }
    }

    /// The line was active now (`active`: a byte or a receive error was taken).
    fn heard(&mut self, active: bool) {
        if active && self.now_ms != NEVER {
            self.last_rx_ms = self.now_ms;
        }
    }

    /// The next byte to hand to the UART, if any.
    ///
    /// ```
    /// # use sensor_box::serial::{QueuedSerial, Ring};
    /// # let (a, b) = (Ring::<2>::new(), Ring::<2>::new());
    /// # let stats = sensor_box::serial::PortStats::new();
    /// let (_port, mut isr) = QueuedSerial::split(&a, &b, &stats, || {});
    /// assert_eq!(isr.next_to_send(), None);
    /// ```
    pub fn next_to_send(&mut self) -> Option<u8> {
        let mut byte = [0u8];
        (self.take_to_send(&mut byte) == 1).then_some(byte[0])
    }

    /// Hands queued bytes to `put` one by one while `room()` says the UART takes another (its
    /// FIFO is not full), for an interrupt handler that fills the FIFO; the count. The bytes
    /// come from the ring's contiguous runs (one slice each, released once) and are counted as
    /// handed to the UART once, at the end.
    ///
    /// ```
    /// use embedded_io::Write;
    /// # use sensor_box::serial::{QueuedSerial, Ring};
    /// # let (a, b) = (Ring::<2>::new(), Ring::<8>::new());
    /// # let stats = sensor_box::serial::PortStats::new();
    /// let (mut port, mut isr) = QueuedSerial::split(&a, &b, &stats, || {});
    /// port.write(b"hello").unwrap();
    /// let (room, mut fifo) = (core::cell::Cell::new(3), Vec::new()); // a FIFO with room for 3
    /// let put = |b| {
    ///     room.set(room.get() - 1);
    ///     fifo.push(b);
    /// };
    /// assert_eq!(isr.send_while(|| room.get() > 0, put), 3);
    /// assert_eq!(fifo, b"hel");
    /// assert_eq!(port.counters().tx_bytes, 3);
    /// ```
    pub fn send_while(&mut self, mut room: impl FnMut() -> bool, mut put: impl FnMut(u8)) -> usize {
        let mut total = 0;
        while let Ok(grant) = self.tx.read() {
            let mut n = 0;
            for &byte in grant.iter() {
                if !room() {
                    break;
                }
                put(byte);
                n += 1;
            }
            let whole = n == grant.len();
            grant.release(n);
            total += n;
            if !whole {
                break;
            }
        }
        add(&self.stats.tx_bytes, total);
        total
    }

    /// Hands queued bytes to `put` a block of `block` bytes at a time while `empty()` says the
    /// UART takes a whole block (its FIFO is empty: one register read per block instead of
    /// one per byte), for an interrupt handler that fills the FIFO; the count. The last block
    /// may be shorter (the queue ran dry). One release per contiguous run of the ring, one
    /// counter update at the end. A FIFO that is neither empty nor full is left to
    /// [`SerialIsr::send_while`].
    ///
    /// ```
    /// use embedded_io::Write;
    /// # use sensor_box::serial::{QueuedSerial, Ring};
    /// # let (a, b) = (Ring::<2>::new(), Ring::<64>::new());
    /// # let stats = sensor_box::serial::PortStats::new();
    /// let (mut port, mut isr) = QueuedSerial::split(&a, &b, &stats, || {});
    /// port.write(&[7; 40]).unwrap();
    /// let (mut fifo, empties) = (Vec::new(), core::cell::Cell::new(2u32)); // empties twice
    /// let empty = || empties.replace(empties.get().saturating_sub(1)) > 0;
    /// assert_eq!(isr.send_blocks(16, empty, |b| fifo.push(b)), 32);
    /// assert_eq!(port.counters().tx_bytes, 32);
    /// ```
    pub fn send_blocks(
        &mut self,
        block: usize,
        empty: impl FnMut() -> bool,
        put: impl FnMut(u8),
    ) -> usize {
        self.fill(block, empty, || false, put).0
    }

    /// Fills a UART's transmit FIFO from the TX ring, for an interrupt handler: a block of
    /// `block` bytes at a time while `empty()` says the FIFO takes a whole one (one register
    /// read per block), then byte by byte while `room()` says it takes one more; whether bytes
    /// are still queued (the handler keeps its TX interrupt on for them). The work of
    /// [`SerialIsr::send_blocks`], [`SerialIsr::send_while`] and [`SerialIsr::tx_pending`] in
    /// one pass, which reads the ring once per contiguous run and once more to find it empty.
    ///
    /// ```
    /// use embedded_io::Write;
    /// # use sensor_box::serial::{QueuedSerial, Ring};
    /// # let (a, b) = (Ring::<2>::new(), Ring::<64>::new());
    /// # let stats = sensor_box::serial::PortStats::new();
    /// let (mut port, mut isr) = QueuedSerial::split(&a, &b, &stats, || {});
    /// port.write(&[7; 40]).unwrap();
    /// let mut fifo = Vec::new();
    /// // An empty FIFO takes 16, then 3 more fit one by one: 19 of 40 go, 21 wait.
    /// let empty = core::cell::Cell::new(true);
    /// let left = core::cell::Cell::new(3u32);
    /// let pending = isr.send_fifo(
    ///     16,
    ///     || empty.replace(false),
    ///     || left.replace(left.get().saturating_sub(1)) > 0,
    ///     |b| fifo.push(b),
    /// );
    /// assert!(pending);
    /// assert_eq!(fifo.len(), 19);
    /// ```
    pub fn send_fifo(
        &mut self,
        block: usize,
        empty: impl FnMut() -> bool,
        room: impl FnMut() -> bool,
        put: impl FnMut(u8),
    ) -> bool {
        self.fill(block, empty, room, put).1
    }

    /// The FIFO fill of [`SerialIsr::send_fifo`] and [`SerialIsr::send_blocks`]: the bytes
    /// handed over, and whether bytes are still queued.
    #[inline(always)]
    fn fill(
        &mut self,
        block: usize,
        mut empty: impl FnMut() -> bool,
        mut room: impl FnMut() -> bool,
        mut put: impl FnMut(u8),
    ) -> (usize, bool) {
        let block = block.max(1);
        let mut total = 0;
        let pending = loop {
            let Ok(grant) = self.tx.read() else {
                break false;
            };
            let len = grant.len();
            let mut n = 0;
            while n < len && empty() {
                let chunk = grant.get(n..len.min(n + block)).unwrap_or_default();
                put_block(chunk, &mut put);
                n += chunk.len();
            }
            while let Some(&byte) = grant.get(n) {
                if !room() {
                    break;
                }
                put(byte);
                n += 1;
            }
            grant.release(n);
            total += n;
            if n < len {
                break true;
            }
        };
        add(&self.stats.tx_bytes, total);
        (total, pending)
    }

    /// Moves queued bytes into `buf` (as many as are queued and fit), a slice copy per
    /// contiguous run, for a UART that takes a block at a time (a DMA transfer); the count.
    /// The bytes are counted as handed to the UART.
    ///
    /// ```
    /// use embedded_io::Write;
    /// # use sensor_box::serial::{QueuedSerial, Ring};
    /// # let (a, b) = (Ring::<2>::new(), Ring::<8>::new());
    /// # let stats = sensor_box::serial::PortStats::new();
    /// let (mut port, mut isr) = QueuedSerial::split(&a, &b, &stats, || {});
    /// port.write(b"hello").unwrap();
    /// let mut block = [0u8; 4];
    /// assert_eq!(isr.take_to_send(&mut block), 4);
    /// assert_eq!(&block, b"hell");
    /// assert_eq!(port.counters().tx_bytes, 4);
    /// ```
    pub fn take_to_send(&mut self, buf: &mut [u8]) -> usize {
        let n = drain(&self.tx, buf);
        add(&self.stats.tx_bytes, n);
        n
    }

    /// Whether the RX ring has room for another byte. A board whose UART can hold bytes back
    /// stops taking them while this is false ([`SerialIsr::receive_while`] does so itself);
    /// the application's next read then kicks the interrupt.
    ///
    /// ```
    /// # use sensor_box::serial::{QueuedSerial, Ring};
    /// # let (a, b) = (Ring::<1>::new(), Ring::<2>::new());
    /// # let stats = sensor_box::serial::PortStats::new();
    /// let (_port, mut isr) = QueuedSerial::split(&a, &b, &stats, || {});
    /// assert!(isr.rx_room());
    /// isr.received(7); // the ring holds one byte
    /// assert!(!isr.rx_room());
    /// ```
    pub fn rx_room(&self) -> bool {
        // An open run always has a free slot (`receive_batched` publishes a full one).
        if self.open.is_some() {
            return true;
        }
        // A grant of one byte, dropped at once: nothing is committed.
        let room = self.rx.grant_max_remaining(1).is_ok();
        if !room {
            // The board holds bytes back from here on: the next read kicks it.
            self.stats.rx_held.store(true, Ordering::Relaxed);
        }
        room
    }

    /// Whether the RX ring was found full and bytes were left in the UART, until the
    /// application's next read takes some (and kicks the interrupt): a board stops its RX
    /// interrupts meanwhile. One load, for the interrupt's RX-only path.
    ///
    /// ```
    /// # use sensor_box::serial::{QueuedSerial, Ring};
    /// # let (a, b) = (Ring::<2>::new(), Ring::<2>::new());
    /// # let stats = sensor_box::serial::PortStats::new();
    /// let (_port, mut isr) = QueuedSerial::split(&a, &b, &stats, || {});
    /// let mut uart = [1, 2, 3].into_iter().map(Ok);
    /// isr.receive_while(|| uart.next());
    /// assert!(isr.rx_held()); // the third byte is still in the UART
    /// ```
    pub fn rx_held(&self) -> bool {
        self.stats.rx_held.load(Ordering::Relaxed)
    }

    /// Whether bytes are waiting to be sent (keep the TX interrupt enabled).
    ///
    /// ```
    /// # use sensor_box::serial::{QueuedSerial, Ring};
    /// # let (a, b) = (Ring::<2>::new(), Ring::<2>::new());
    /// # let stats = sensor_box::serial::PortStats::new();
    /// let (_port, isr) = QueuedSerial::split(&a, &b, &stats, || {});
    /// assert!(!isr.tx_pending());
    /// ```
    pub fn tx_pending(&self) -> bool {
        // A read grant, dropped at once: nothing is released.
        self.tx.read().is_ok()
    }
}
