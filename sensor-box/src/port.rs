//! What every link does with its serial port: read what has arrived in slices, and queue whole
//! frames for transmit.
//!
//! The links take their ports through `embedded_io`'s non-blocking pair of traits:
//! [`ReadReady`] + [`Read`] to receive and [`WriteReady`] + [`Write`] to send. `read` and
//! `write` may wait in `embedded_io` (until one byte has arrived, or there is room for one);
//! the links never let them: they call `read` only after `read_ready()` said `true`, and
//! `write` only after `write_ready()` did. A port that has bytes hands them over as one slice
//! (a `QueuedSerial` drains its RX queue in one pass), and a frame goes to the port in one
//! `write` of the whole frame.
//!
//! * [`Received`]: the bytes of one read, held by the link until it has decoded them. A link
//!   that stops decoding in the middle of a read (its TX queue cannot take one more longest
//!   answer) keeps the rest here and decodes it first on the next poll, so no byte is lost
//!   and the port keeps the bytes after them (back-pressure).
//! * [`TxQueue`]: encoded frames waiting for room in the port; whole frames in, any number
//!   of bytes out.
//!
//! A port error on either side is counted by the link and ends that side of the poll.

use embedded_io::{Read, ReadReady, Write, WriteReady};

/// The most bytes one read takes from a port (a stack buffer's worth).
pub const RX_CHUNK: usize = 64;

/// Bytes read from a port and not yet decoded (at most [`RX_CHUNK`]).
#[derive(Debug, Clone)]
pub struct Received {
    buf: [u8; RX_CHUNK],
    at: usize,
    end: usize,
}

impl Default for Received {
    fn default() -> Self {
        Self::new()
    }
}

impl Received {
    /// Nothing held.
    pub const fn new() -> Self {
        Received {
            buf: [0; RX_CHUNK],
            at: 0,
            end: 0,
        }
    }

    /// The bytes read and not yet decoded.
    ///
    /// ```
    /// let r = sensor_box::port::Received::new();
    /// assert!(r.pending().is_empty());
    /// ```
    pub fn pending(&self) -> &[u8] {
        self.buf.get(self.at..self.end).unwrap_or(&[])
    }

    /// Marks the first `n` pending bytes decoded.
    pub fn consume(&mut self, n: usize) {
        self.at = self.at.saturating_add(n).min(self.end);
    }

    /// When nothing is pending, reads what `port` has received (at most `max` bytes, and
    /// [`RX_CHUNK`]) without waiting; the count read (0: something was still pending, or
    /// nothing had arrived).
    pub fn refill<P: Read + ReadReady>(
        &mut self,
        port: &mut P,
        max: usize,
    ) -> Result<usize, P::Error> {
        if self.at < self.end || max == 0 || !port.read_ready()? {
            return Ok(0);
        }
        let buf = self.buf.get_mut(..max.min(RX_CHUNK)).unwrap_or(&mut []);
        let n = port.read(buf)?.min(buf.len());
        self.at = 0;
        self.end = n;
        Ok(n)
    }
}

/// Encoded frames waiting for room in a port: a ring of `N` bytes. Frames go in whole or not
/// at all ([`TxQueue::push`]); [`TxQueue::drain`] hands the port as much as it takes.
#[derive(Debug, Clone)]
pub struct TxQueue<const N: usize> {
    buf: [u8; N],
    head: usize,
    len: usize,
}

impl<const N: usize> Default for TxQueue<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> TxQueue<N> {
    /// An empty queue.
    pub const fn new() -> Self {
        TxQueue {
            buf: [0; N],
            head: 0,
            len: 0,
        }
    }

    /// Bytes waiting.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether nothing is waiting.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Room left, bytes.
    pub fn free(&self) -> usize {
        N.saturating_sub(self.len)
    }

    /// Queues all of `bytes`, or nothing when they do not fit; whether they were queued.
    ///
    /// ```
    /// let mut q = sensor_box::port::TxQueue::<4>::new();
    /// assert!(q.push(b"abc"));
    /// assert!(!q.push(b"de"));
    /// assert_eq!(q.len(), 3);
    /// ```
    pub fn push(&mut self, bytes: &[u8]) -> bool {
        if bytes.len() > self.free() {
            return false;
        }
        let tail = self.head.saturating_add(self.len) % N.max(1);
        // Up to the end of the ring, then the rest from its start.
        let (to_end, wrapped) = bytes.split_at(bytes.len().min(N.saturating_sub(tail)));
        copy(self.buf.get_mut(tail..).unwrap_or(&mut []), to_end);
        copy(&mut self.buf, wrapped);
        self.len = self.len.saturating_add(bytes.len());
        true
    }

    /// Queues the frame `encode` writes, whole, if it fits with `reserve` bytes to spare;
    /// whether it was queued. `encode` writes into the slice it is given and returns the
    /// frame's length, or `None` when the slice is too short. The frame is encoded straight
    /// into the ring's free bytes when they are contiguous; only a frame that would wrap
    /// around the ring's end goes through a stack buffer of `M` bytes (at most `M` bytes
    /// then).
    ///
    /// ```
    /// let mut q = sensor_box::port::TxQueue::<8>::new();
    /// let frame = |out: &mut [u8]| {
    ///     out.get_mut(..3)?.copy_from_slice(b"abc");
    ///     Some(3)
    /// };
    /// assert!(q.push_with::<8>(0, frame));
    /// assert!(!q.push_with::<8>(3, frame)); // 5 free, 3 of them kept
    /// assert_eq!(q.len(), 3);
    /// ```
    pub fn push_with<const M: usize>(
        &mut self,
        reserve: usize,
        mut encode: impl FnMut(&mut [u8]) -> Option<usize>,
    ) -> bool {
        let room = self.free().saturating_sub(reserve);
        let tail = self.head.saturating_add(self.len) % N.max(1);
        let contiguous = N.saturating_sub(tail).min(room);
        let end = tail.saturating_add(contiguous);
        if let Some(slot) = self.buf.get_mut(tail..end)
            && let Some(n) = encode(slot).filter(|&n| n <= contiguous)
        {
            self.len = self.len.saturating_add(n);
            return true;
        }
        if contiguous >= room {
            // Nothing more past the ring's end: it does not fit.
            return false;
        }
        let mut scratch = [0u8; M];
        let limit = room.min(M);
        match scratch.get_mut(..limit).and_then(&mut encode) {
            Some(n) if n <= limit => self.push(scratch.get(..n).unwrap_or(&[])),
            _ => false,
        }
    }

    /// Hands queued bytes to `port` until the queue is empty or the port has no room; the
    /// port's error, if it reported one (the bytes stay queued).
    ///
    /// ```
    /// use sensor_box::serial::{PortStats, QueuedSerial};
    /// let (rxq, txq) = (sensor_box::serial::Ring::<2>::new(), sensor_box::serial::Ring::<3>::new());
    /// let stats = PortStats::new();
    /// let (mut port, mut isr) = QueuedSerial::split(&rxq, &txq, &stats, || {});
    /// let mut q = sensor_box::port::TxQueue::<8>::new();
    /// q.push(b"hello");
    /// q.drain(&mut port).unwrap(); // the port holds 3
    /// assert_eq!(q.len(), 2);
    /// let sent: Vec<u8> = core::iter::from_fn(|| isr.next_to_send()).collect();
    /// assert_eq!(sent, b"hel");
    /// q.drain(&mut port).unwrap();
    /// assert!(q.is_empty());
    /// ```
    pub fn drain<P: Write + WriteReady>(&mut self, port: &mut P) -> Result<(), P::Error> {
        while self.len > 0 && port.write_ready()? {
            let end = self.head.saturating_add(self.len).min(N);
            let front = self.buf.get(self.head..end).unwrap_or(&[]);
            let n = port.write(front)?.min(front.len());
            if n == 0 {
                break;
            }
            self.len -= n;
            self.head = if self.len == 0 {
                0
            } else {
                self.head.saturating_add(n) % N.max(1)
            };
        }
        Ok(())
    }
}

/// Copies `src` to the start of `dst` (nothing if it does not fit).
fn copy(dst: &mut [u8], src: &[u8]) {
    if let Some(d) = dst.get_mut(..src.len()) {
        d.copy_from_slice(src);
    }
}
