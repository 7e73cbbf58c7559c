//! The serial port the application sees on every board.
//!
//! A UART is split in two halves joined by two `heapless::spsc` queues:
//!
//! ```text
//!   application (main loop)                      UART interrupt handler
//!   QueuedSerial::read(&mut buf) <-- RX queue <--  SerialIsr::received(byte)
//!   QueuedSerial::write(&frame)  --> TX queue -->  SerialIsr::next_to_send()
//!                                --> kick() (pends the interrupt)
//! ```
//!
//! The application's half speaks two interfaces: `embedded_io`'s `Read`, `ReadReady`,
//! `Write` and `WriteReady` (slices: what the `sensor-box` links use, so the main loop drains
//! the RX queue in bursts and hands whole frames to the TX queue), and `embedded_hal_nb`'s
//! byte-at-a-time `serial::Read<u8>` / `Write<u8>` (whose non-blocking `flush` the main
//! loop calls after every poll).
//!
//! * RX: the interrupt moves every received byte into the RX queue at once, so
//!   nothing is lost while the main loop is busy (telemetry at full rate). A
//!   full queue drops the byte and counts it in [`PortStats`].
//! * TX: `write` queues the bytes and calls the board's `kick`, which pends the
//!   UART interrupt (a [`QueuedSerial::batched`] port kicks once per burst,
//!   on `flush`); the handler moves queued bytes into the UART while it has room, and keeps its TX interrupt enabled only while bytes are
//!   waiting. The TX queue being full is the only thing a writer waits for: `write_ready`
//!   says so (and the `nb` `write` returns `nb::WouldBlock`), so the main loop never waits
//!   for the wire.
//!
//! The same type runs in host tests: the test plays the interrupt handler.

use core::convert::Infallible;
use core::sync::atomic::{AtomicU32, Ordering};
use embedded_hal_nb::serial::{ErrorType, Read, Write};
use heapless::spsc::{Consumer, Producer, Queue};

/// Counters shared by both halves of a port. Wrapping `u32`s.
#[derive(Debug, Default)]
pub struct PortStats {
    rx_bytes: AtomicU32,
    rx_dropped: AtomicU32,
    rx_errors: AtomicU32,
    tx_bytes: AtomicU32,
}

/// A copy of the counters at one instant.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
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
    /// static STATS: firmware_example::PortStats = firmware_example::PortStats::new();
    /// assert_eq!(STATS.snapshot().rx_bytes, 0);
    /// ```
    pub const fn new() -> Self {
        Self {
            rx_bytes: AtomicU32::new(0),
            rx_dropped: AtomicU32::new(0),
            rx_errors: AtomicU32::new(0),
            tx_bytes: AtomicU32::new(0),
        }
    }

    /// Reads all counters.
    ///
    /// ```
    /// let s = firmware_example::PortStats::new();
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
    // Single-core targets: load/store is enough and works on every Cortex-M;
    // only the interrupt handler writes the counters it bumps.
    counter.store(
        counter.load(Ordering::Relaxed).wrapping_add(1),
        Ordering::Relaxed,
    );
}

/// The application's half of a UART: `embedded_io` `Read`, `ReadReady`, `Write` and
/// `WriteReady` (slices), and `embedded_hal_nb` `Read<u8>` and `Write<u8>` (bytes).
pub struct QueuedSerial<'q> {
    rx: Consumer<'q, u8>,
    tx: Producer<'q, u8>,
    stats: &'q PortStats,
    kick: fn(),
    /// Kick only on `flush` and when the TX queue is full (see [`QueuedSerial::batched`]).
    batched: bool,
}

/// The interrupt handler's half of a UART.
pub struct SerialIsr<'q> {
    rx: Producer<'q, u8>,
    tx: Consumer<'q, u8>,
    stats: &'q PortStats,
}

impl<'q> QueuedSerial<'q> {
    /// Splits an RX and a TX queue into the application's port and the
    /// interrupt handler's half. `kick` is called after every queued TX byte;
    /// a board makes it pend the UART interrupt.
    ///
    /// ```
    /// use firmware_example::QueuedSerial;
    /// let (mut rxq, mut txq) = (heapless::spsc::Queue::<u8, 16>::new(), heapless::spsc::Queue::<u8, 16>::new());
    /// let stats = firmware_example::PortStats::new();
    /// let (port, isr) = QueuedSerial::split(&mut rxq, &mut txq, &stats, || {});
    /// # let _ = (port, isr);
    /// ```
    pub fn split<const RX: usize, const TX: usize>(
        rx_queue: &'q mut Queue<u8, RX>,
        tx_queue: &'q mut Queue<u8, TX>,
        stats: &'q PortStats,
        kick: fn(),
    ) -> (QueuedSerial<'q>, SerialIsr<'q>) {
        let (rx_prod, rx_cons) = rx_queue.split();
        let (tx_prod, tx_cons) = tx_queue.split();
        (
            QueuedSerial {
                rx: rx_cons,
                tx: tx_prod,
                stats,
                kick,
                batched: false,
            },
            SerialIsr {
                rx: rx_prod,
                tx: tx_cons,
                stats,
            },
        )
    }

    /// The same port, kicking the interrupt per burst instead of per byte: `write` only
    /// queues (it kicks when the TX queue is full, then tries once more), and `flush` kicks.
    /// The owner must call `flush` after each burst of writes (the firmware's main loop does,
    /// after every poll), or the bytes wait. One interrupt then moves a whole burst into the
    /// UART's FIFO instead of one interrupt per byte.
    ///
    /// ```
    /// use embedded_hal_nb::serial::Write;
    /// use firmware_example::QueuedSerial;
    /// use core::sync::atomic::{AtomicU32, Ordering};
    /// static KICKS: AtomicU32 = AtomicU32::new(0);
    /// let (mut a, mut b) = (heapless::spsc::Queue::<u8, 4>::new(), heapless::spsc::Queue::<u8, 8>::new());
    /// let stats = firmware_example::PortStats::new();
    /// let (port, _isr) = QueuedSerial::split(&mut a, &mut b, &stats, || {
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
    /// # use firmware_example::QueuedSerial;
    /// # let (mut a, mut b) = (heapless::spsc::Queue::<u8, 4>::new(), heapless::spsc::Queue::<u8, 4>::new());
    /// # let stats = firmware_example::PortStats::new();
    /// let (port, mut isr) = QueuedSerial::split(&mut a, &mut b, &stats, || {});
    /// isr.received(1);
    /// assert_eq!(port.rx_pending(), 1);
    /// ```
    pub fn rx_pending(&self) -> usize {
        self.rx.len()
    }

    /// Room left in the TX queue, bytes.
    ///
    /// ```
    /// # use firmware_example::QueuedSerial;
    /// # let (mut a, mut b) = (heapless::spsc::Queue::<u8, 4>::new(), heapless::spsc::Queue::<u8, 4>::new());
    /// # let stats = firmware_example::PortStats::new();
    /// let (port, _isr) = QueuedSerial::split(&mut a, &mut b, &stats, || {});
    /// assert_eq!(port.tx_space(), 3); // a heapless queue of N holds N - 1
    /// ```
    pub fn tx_space(&self) -> usize {
        self.tx.capacity().saturating_sub(self.tx.len())
    }

    /// The port's counters.
    ///
    /// ```
    /// # use firmware_example::QueuedSerial;
    /// # let (mut a, mut b) = (heapless::spsc::Queue::<u8, 4>::new(), heapless::spsc::Queue::<u8, 4>::new());
    /// # let stats = firmware_example::PortStats::new();
    /// let (port, _isr) = QueuedSerial::split(&mut a, &mut b, &stats, || {});
    /// assert_eq!(port.counters().rx_dropped, 0);
    /// ```
    pub fn counters(&self) -> PortCounters {
        self.stats.snapshot()
    }
}

impl ErrorType for QueuedSerial<'_> {
    type Error = Infallible;
}

impl QueuedSerial<'_> {
    /// Moves received bytes into `buf` in one pass, as many as are waiting and fit; the
    /// count. Kicks the interrupt when the queue was full (see [`SerialIsr::rx_room`]).
    fn take_received(&mut self, buf: &mut [u8]) -> usize {
        let was_full = self.rx.len() >= self.rx.capacity();
        let mut n = 0;
        for slot in buf.iter_mut() {
            let Some(byte) = self.rx.dequeue() else { break };
            *slot = byte;
            n += 1;
        }
        if was_full && n > 0 {
            (self.kick)();
        }
        n
    }

    /// Copies as much of `bytes` into the TX queue as it has room for, in one pass; the count.
    fn queue_to_send(&mut self, bytes: &[u8]) -> usize {
        let mut n = 0;
        for &byte in bytes {
            if self.tx.enqueue(byte).is_err() {
                break;
            }
            n += 1;
        }
        n
    }
}

impl embedded_io::ErrorType for QueuedSerial<'_> {
    type Error = Infallible;
}

impl embedded_io::ReadReady for QueuedSerial<'_> {
    /// Whether received bytes are waiting: then [`embedded_io::Read::read`] does not wait.
    fn read_ready(&mut self) -> Result<bool, Infallible> {
        Ok(self.rx.ready())
    }
}

impl embedded_io::Read for QueuedSerial<'_> {
    /// Moves the received bytes waiting in the RX queue into `buf` (as many as fit) in one
    /// pass. With nothing waiting it waits for the interrupt to receive a byte, as
    /// `embedded_io` asks: a caller that must not wait asks
    /// [`read_ready`](embedded_io::ReadReady::read_ready) first.
    ///
    /// ```
    /// use embedded_io::{Read, ReadReady};
    /// # use firmware_example::QueuedSerial;
    /// # let (mut a, mut b) = (heapless::spsc::Queue::<u8, 8>::new(), heapless::spsc::Queue::<u8, 4>::new());
    /// # let stats = firmware_example::PortStats::new();
    /// let (mut port, mut isr) = QueuedSerial::split(&mut a, &mut b, &stats, || {});
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

impl embedded_io::WriteReady for QueuedSerial<'_> {
    /// Whether the TX queue has room for a byte: then [`embedded_io::Write::write`] does not
    /// wait. When it is full the interrupt is kicked first (a batched port's bytes are
    /// otherwise only kicked on `flush`) and the room checked once more.
    fn write_ready(&mut self) -> Result<bool, Infallible> {
        if self.tx.ready() {
            return Ok(true);
        }
        (self.kick)();
        Ok(self.tx.ready())
    }
}

impl embedded_io::Write for QueuedSerial<'_> {
    /// Copies as much of `buf` as the TX queue has room for, in one pass, and kicks the
    /// interrupt (a [`QueuedSerial::batched`] port only when the queue is full: its owner's
    /// `flush` kicks). With the queue full it kicks and waits for room, as `embedded_io`
    /// asks: a caller that must not wait asks
    /// [`write_ready`](embedded_io::WriteReady::write_ready) first.
    ///
    /// ```
    /// use embedded_io::{Write, WriteReady};
    /// # use firmware_example::QueuedSerial;
    /// # let (mut a, mut b) = (heapless::spsc::Queue::<u8, 2>::new(), heapless::spsc::Queue::<u8, 4>::new());
    /// # let stats = firmware_example::PortStats::new();
    /// let (mut port, mut isr) = QueuedSerial::split(&mut a, &mut b, &stats, || {});
    /// assert_eq!(port.write(b"hello"), Ok(3)); // a heapless queue of 4 holds 3
    /// assert_eq!(port.write_ready(), Ok(false));
    /// assert_eq!(isr.next_to_send(), Some(b'h'));
    /// assert_eq!(port.write(b"lo"), Ok(1));
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
        while !self.tx.is_empty() {}
        Ok(())
    }
}

impl Read<u8> for QueuedSerial<'_> {
    /// The next received byte, or `WouldBlock` when none is waiting.
    ///
    /// When the queue was full, the board's interrupt may have stopped taking bytes from the
    /// UART (see [`SerialIsr::rx_room`]); reading then kicks it, so it takes them again.
    fn read(&mut self) -> nb::Result<u8, Self::Error> {
        let byte = self.rx.dequeue().ok_or(nb::Error::WouldBlock)?;
        if self.rx.len() + 1 >= self.rx.capacity() {
            (self.kick)();
        }
        Ok(byte)
    }
}

impl Write<u8> for QueuedSerial<'_> {
    /// Queues a byte; `WouldBlock` when the TX queue is full.
    fn write(&mut self, word: u8) -> nb::Result<(), Self::Error> {
        if !self.batched {
            let queued = self.tx.enqueue(word).map_err(|_| nb::Error::WouldBlock);
            (self.kick)();
            return queued;
        }
        match self.tx.enqueue(word) {
            Ok(()) => Ok(()),
            Err(word) => {
                // Full: start the interrupt on what is queued, and try once more (the
                // handler may have made room at once).
                (self.kick)();
                self.tx.enqueue(word).map_err(|_| nb::Error::WouldBlock)
            }
        }
    }

    /// `Ok` once every queued byte has gone to the UART, else `WouldBlock`.
    fn flush(&mut self) -> nb::Result<(), Self::Error> {
        if self.tx.is_empty() {
            Ok(())
        } else {
            (self.kick)();
            Err(nb::Error::WouldBlock)
        }
    }
}

impl SerialIsr<'_> {
    /// Stores a received byte; when the RX queue is full the byte is dropped
    /// and counted. Returns whether it was stored.
    ///
    /// ```
    /// # use firmware_example::QueuedSerial;
    /// # let (mut a, mut b) = (heapless::spsc::Queue::<u8, 2>::new(), heapless::spsc::Queue::<u8, 2>::new());
    /// # let stats = firmware_example::PortStats::new();
    /// let (port, mut isr) = QueuedSerial::split(&mut a, &mut b, &stats, || {});
    /// assert!(isr.received(1));
    /// assert!(!isr.received(2)); // the queue holds one byte
    /// assert_eq!(port.counters().rx_dropped, 1);
    /// ```
    pub fn received(&mut self, byte: u8) -> bool {
        match self.rx.enqueue(byte) {
            Ok(()) => {
                bump(&self.stats.rx_bytes);
                true
            }
            Err(_) => {
                bump(&self.stats.rx_dropped);
                false
            }
        }
    }

    /// Counts a receive error reported by the UART hardware.
    ///
    /// ```
    /// # use firmware_example::QueuedSerial;
    /// # let (mut a, mut b) = (heapless::spsc::Queue::<u8, 2>::new(), heapless::spsc::Queue::<u8, 2>::new());
    /// # let stats = firmware_example::PortStats::new();
    /// let (port, mut isr) = QueuedSerial::split(&mut a, &mut b, &stats, || {});
    /// isr.receive_error();
    /// assert_eq!(port.counters().rx_errors, 1);
    /// ```
    pub fn receive_error(&mut self) {
        bump(&self.stats.rx_errors);
    }

    /// The next byte to hand to the UART, if any.
    ///
    /// ```
    /// # use firmware_example::QueuedSerial;
    /// # let (mut a, mut b) = (heapless::spsc::Queue::<u8, 2>::new(), heapless::spsc::Queue::<u8, 2>::new());
    /// # let stats = firmware_example::PortStats::new();
    /// let (_port, mut isr) = QueuedSerial::split(&mut a, &mut b, &stats, || {});
    /// assert_eq!(isr.next_to_send(), None);
    /// ```
    pub fn next_to_send(&mut self) -> Option<u8> {
        let byte = self.tx.dequeue();
        if byte.is_some() {
            bump(&self.stats.tx_bytes);
        }
        byte
    }

    /// Hands queued bytes to `put` one by one while `room()` says the UART takes another (its
    /// FIFO is not full), for an interrupt handler that fills the FIFO; the count. The bytes
    /// are counted as handed to the UART once, at the end.
    ///
    /// ```
    /// use embedded_io::Write;
    /// # use firmware_example::QueuedSerial;
    /// # let (mut a, mut b) = (heapless::spsc::Queue::<u8, 2>::new(), heapless::spsc::Queue::<u8, 8>::new());
    /// # let stats = firmware_example::PortStats::new();
    /// let (mut port, mut isr) = QueuedSerial::split(&mut a, &mut b, &stats, || {});
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
        let mut n = 0;
        while room() {
            let Some(byte) = self.tx.dequeue() else { break };
            put(byte);
            n += 1;
        }
        self.count_sent(n);
        n
    }

    fn count_sent(&self, n: usize) {
        let sent = &self.stats.tx_bytes;
        sent.store(
            sent.load(Ordering::Relaxed)
                .wrapping_add(u32::try_from(n).unwrap_or(u32::MAX)),
            Ordering::Relaxed,
        );
    }

    /// Moves queued bytes into `buf` (as many as are queued and fit), for a UART that takes a
    /// block at a time (a DMA transfer); the count. The bytes are counted as handed to the
    /// UART.
    ///
    /// ```
    /// use embedded_io::Write;
    /// # use firmware_example::QueuedSerial;
    /// # let (mut a, mut b) = (heapless::spsc::Queue::<u8, 2>::new(), heapless::spsc::Queue::<u8, 8>::new());
    /// # let stats = firmware_example::PortStats::new();
    /// let (mut port, mut isr) = QueuedSerial::split(&mut a, &mut b, &stats, || {});
    /// port.write(b"hello").unwrap();
    /// let mut block = [0u8; 4];
    /// assert_eq!(isr.take_to_send(&mut block), 4);
    /// assert_eq!(&block, b"hell");
    /// assert_eq!(port.counters().tx_bytes, 4);
    /// ```
    pub fn take_to_send(&mut self, buf: &mut [u8]) -> usize {
        let mut n = 0;
        for slot in buf.iter_mut() {
            let Some(byte) = self.tx.dequeue() else { break };
            *slot = byte;
            n += 1;
        }
        self.count_sent(n);
        n
    }

    /// Whether the RX queue has room for another byte. A board whose UART can hold bytes back
    /// (a FIFO, and a peer that waits for it, as QEMU's sockets do) stops reading the UART
    /// while this is false instead of dropping bytes; the application's next read kicks the
    /// interrupt again.
    ///
    /// ```
    /// # use firmware_example::QueuedSerial;
    /// # let (mut a, mut b) = (heapless::spsc::Queue::<u8, 2>::new(), heapless::spsc::Queue::<u8, 2>::new());
    /// # let stats = firmware_example::PortStats::new();
    /// let (_port, mut isr) = QueuedSerial::split(&mut a, &mut b, &stats, || {});
    /// assert!(isr.rx_room());
    /// isr.received(7); // the queue holds one byte
    /// assert!(!isr.rx_room());
    /// ```
    pub fn rx_room(&self) -> bool {
        self.rx.ready()
    }

    /// Whether bytes are waiting to be sent (keep the TX interrupt enabled).
    ///
    /// ```
    /// # use firmware_example::QueuedSerial;
    /// # let (mut a, mut b) = (heapless::spsc::Queue::<u8, 2>::new(), heapless::spsc::Queue::<u8, 2>::new());
    /// # let stats = firmware_example::PortStats::new();
    /// let (_port, isr) = QueuedSerial::split(&mut a, &mut b, &stats, || {});
    /// assert!(!isr.tx_pending());
    /// ```
    pub fn tx_pending(&self) -> bool {
        self.tx.ready()
    }
}
