//! What every link does with its serial port: decode what has arrived in place, a contiguous
//! slice at a time, and queue whole frames for transmit.
//!
//! The links take their ports through two traits: [`Receive`] to take received bytes in
//! place (a ring-buffered port lends the run of its ring that holds them: no copy, no call
//! per byte), and `embedded_io`'s [`WriteReady`] + [`Write`] to send; the AEOLUS link's port
//! also lends its free transmit bytes ([`Transmit`]), so telemetry is encoded straight into
//! it while the link has nothing queued. `write` may wait in
//! `embedded_io` (until there is room for one byte); the links never let it: they call `write`
//! only after `write_ready()` said `true`. A frame goes to the port in one `write` of the
//! whole frame, from the link's [`TxQueue`] (encoded frames waiting for room in the port;
//! whole frames in, any number of bytes out), the one TX path of every link.
//!
//! **Back-pressure.** A link decodes received bytes only while its TX queue has room for the
//! longest answer they could complete; the bytes it did not decode stay in the port (which
//! holds them in its ring, and then in the UART), so no answer is dropped for want of room and
//! no received byte is lost in the link.
//!
//! **Receive errors, one policy for the three links.** Every link counts, under the same
//! names in its counters:
//! * `rx_errors`: every `Err` event its decoder delivers (a candidate frame dropped: bad
//!   check, bad length, bad escape, a frame cut short, ...). The decoder's own `Stats` say
//!   which; the link counts events, never differences of counters.
//! * `port_errors`: every error the port itself reports, on either side. A port error ends
//!   that side of the poll; the next poll tries again.
//! * Line faults ([`Receive::receive_faults`]: a UART receive error, a byte dropped for want
//!   of room) are counted by the port. The AOK link, which frames commands by silence, reads
//!   them as line activity: a fault spoils the burst it falls in, so a command with a
//!   damaged or lost byte is never obeyed (its counters: `line_faults`).
//!
//! A frame whose check is good but whose data does not parse as its type is not a receive
//! error: the AEOLUS and AYDP links count it as `malformed`.

use embedded_io::{ErrorType, Write, WriteReady};

/// A port that lends the bytes it has received, in place: the receive side of every link.
///
/// A ring-buffered port (`serial::QueuedSerial`) lends the contiguous run of its ring that
/// holds the oldest received bytes; the bytes after a wrap of the ring come with the next call.
pub trait Receive: ErrorType {
    /// Calls `take` with the oldest received bytes not yet taken (one contiguous slice, not
    /// empty) and drops from the port as many of them as `take` returns; the count dropped.
    /// When nothing has arrived, `take` is not called and the count is 0. Never waits.
    ///
    /// ```
    /// use sensor_box::port::Receive;
    /// use sensor_box::serial::{PortStats, QueuedSerial, Ring};
    /// let (rxq, txq) = (Ring::<8>::new(), Ring::<8>::new());
    /// let stats = PortStats::new();
    /// let (mut port, mut isr) = QueuedSerial::split(&rxq, &txq, &stats, || {});
    /// for b in *b"abc" {
    ///     isr.received(b);
    /// }
    /// assert_eq!(port.receive(|bytes| {
    ///     assert_eq!(bytes, b"abc");
    ///     2 // "c" stays in the port
    /// }), Ok(2));
    /// assert_eq!(port.receive(|bytes| bytes.len()), Ok(1));
    /// assert_eq!(port.receive(|_| unreachable!()), Ok(0));
    /// ```
    fn receive(&mut self, take: impl FnOnce(&[u8]) -> usize) -> Result<usize, Self::Error>;

    /// The bytes the line lost or damaged since the port was made, a wrapping count: receive
    /// errors the UART reported (framing, noise, overrun, parity, break) and bytes dropped
    /// for want of room. A link that frames commands by silence compares it from poll to
    /// poll: a change is line activity that spoils the burst it falls in (see "Receive
    /// errors" above). The default, for a port that cannot lose or damage a byte (a socket,
    /// a test's port), is 0 for ever.
    ///
    /// ```
    /// use sensor_box::port::Receive;
    /// use sensor_box::serial::{PortStats, QueuedSerial, Ring};
    /// let (rxq, txq) = (Ring::<1>::new(), Ring::<8>::new());
    /// let stats = PortStats::new();
    /// let (port, mut isr) = QueuedSerial::split(&rxq, &txq, &stats, || {});
    /// isr.receive_error(); // a framing error
    /// isr.received(1);
    /// isr.received(2); // the ring is full: dropped
    /// assert_eq!(port.receive_faults(), 2);
    /// ```
    fn receive_faults(&self) -> u32 {
        0
    }

    /// Whether the next byte to take begins a burst: the receive side saw the line silent
    /// before it by its own clock ([`crate::burst_marks`]), however late the application takes
    /// it. A port lends no slice across such a point. The default, for a port with no such
    /// clock, is `false`: the link observes silence itself.
    fn burst_starts(&self) -> bool {
        false
    }
}

impl<P: Receive> Receive for &mut P {
    fn receive(&mut self, take: impl FnOnce(&[u8]) -> usize) -> Result<usize, Self::Error> {
        (**self).receive(take)
    }

    fn receive_faults(&self) -> u32 {
        (**self).receive_faults()
    }
    fn burst_starts(&self) -> bool {
        (**self).burst_starts()
    }
}

/// A port that lends the free bytes of its transmit buffer, in place: a link encodes a frame
/// straight into it, with no copy out of the link's own queue. The transmit side of a
/// ring-buffered port (`serial::QueuedSerial`, whose TX ring the UART interrupt empties).
///
/// A port with no buffer of its own to lend (a socket, a test's port) implements it with the
/// default, which lends nothing: the link then queues the frame and writes it from there with
/// [`Write`].
pub trait Transmit: ErrorType {
    /// Calls `fill` with the longest contiguous run of free bytes of the port's transmit
    /// buffer (possibly empty) and queues for transmit the first bytes of it, as many as
    /// `fill` returns (at most the run's length; 0 when what it had to write did not fit);
    /// the count queued. Never waits. The default lends nothing: `fill` is not called and
    /// the count is 0.
    ///
    /// ```
    /// use sensor_box::port::Transmit;
    /// use sensor_box::serial::{PortStats, QueuedSerial, Ring};
    /// let (rxq, txq) = (Ring::<2>::new(), Ring::<8>::new());
    /// let stats = PortStats::new();
    /// let (mut port, mut isr) = QueuedSerial::split(&rxq, &txq, &stats, || {});
    /// let queued = port.transmit(|free| {
    ///     free[..3].copy_from_slice(b"abc");
    ///     3
    /// });
    /// assert_eq!(queued, Ok(3));
    /// let sent: Vec<u8> = core::iter::from_fn(|| isr.next_to_send()).collect();
    /// assert_eq!(sent, b"abc");
    /// ```
    fn transmit(&mut self, fill: impl FnOnce(&mut [u8]) -> usize) -> Result<usize, Self::Error> {
        let _ = fill;
        Ok(0)
    }
}

impl<P: Transmit> Transmit for &mut P {
    fn transmit(&mut self, fill: impl FnOnce(&mut [u8]) -> usize) -> Result<usize, Self::Error> {
        (**self).transmit(fill)
    }
}

/// Takes received bytes from `port` in slices, at most `budget` of them, handing each slice
/// to `decode`, which returns how many it decoded (fewer than it was given when the link
/// cannot take on more: the loop stops and the rest stays in the port); the count taken, or
/// the port's error. The RX loop of every link.
///
/// ```
/// use sensor_box::port::receive_slices;
/// use sensor_box::serial::{PortStats, QueuedSerial, Ring};
/// let (rxq, txq) = (Ring::<8>::new(), Ring::<8>::new());
/// let stats = PortStats::new();
/// let (mut port, mut isr) = QueuedSerial::split(&rxq, &txq, &stats, || {});
/// for b in 1..=6 {
///     isr.received(b);
/// }
/// let mut seen = Vec::new();
/// let taken = receive_slices(&mut port, 4, |bytes| {
///     seen.extend_from_slice(bytes);
///     bytes.len()
/// });
/// assert_eq!((taken, seen), (Ok(4), vec![1, 2, 3, 4])); // the budget
/// ```
pub fn receive_slices<P: Receive>(
    port: &mut P,
    mut budget: usize,
    mut decode: impl FnMut(&[u8]) -> usize,
) -> Result<usize, P::Error> {
    let mut total = 0;
    while budget > 0 {
        let mut whole = false;
        let n = port.receive(|bytes| {
            let piece = bytes.get(..budget).unwrap_or(bytes);
            let n = decode(piece).min(piece.len());
            whole = n == piece.len();
            n
        })?;
        total += n;
        budget = budget.saturating_sub(n);
        if n == 0 || !whole {
            break;
        }
    }
    Ok(total)
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
    /// use sensor_box::serial::{PortStats, QueuedSerial, Ring};
    /// let (rxq, txq) = (Ring::<2>::new(), Ring::<3>::new());
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
    if src.len() <= dst.len() {
        copy_prefix(dst, src);
    }
}

/// Copies as many bytes as both slices hold from the start of `src` to the start of `dst`;
/// the count. A byte loop the compiler turns into one `memcpy` call: unlike
/// `copy_from_slice`, it has no length-mismatch panic, whose message formatting (about 1 KiB
/// of `core::fmt`) the firmware would otherwise carry.
pub(crate) fn copy_prefix(dst: &mut [u8], src: &[u8]) -> usize {
    let mut n = 0;
    for (d, s) in dst.iter_mut().zip(src) {
        *d = *s;
        n += 1;
    }
    n
}
