//! The stream decoder with lossless resynchronisation: byte at a time ([`Decoder::push`]) or
//! a slice at a time ([`Decoder::feed`], the fast path for DMA buffers and datagrams; it gives
//! exactly the events and counters of pushing the same bytes one by one).
//!
//! # How it works
//!
//! Bytes before a 0xFF start are discarded. From a start the decoder collects the type and the
//! u32 length; when a start is followed by another 0xFF the first is dropped (Y5). The moment
//! the length field is complete it is checked against the profile's minimum and the capacity
//! `N` (Y5). The message then completes when the announced number of bytes is held, and the
//! XOR checksum (Y4) decides.
//!
//! After a length or checksum failure the decoder does not throw the held bytes away: it drops
//! only the false start byte and **rescans** the bytes it already holds, from the byte after
//! the false start. A message hidden behind a false 0xFF start is therefore still found.
//!
//! # Events, and why there may be more than one per byte
//!
//! A rescan can uncover several complete messages (and further failures) among bytes already
//! held. [`Decoder::push`] stores the byte and returns the *first* event; the caller must then
//! call [`Decoder::poll`] until it returns `None` to take the rest. Bytes that are queued for a
//! rescan are kept in order ahead of any new input, so nothing is lost if the caller pushes
//! again before polling, but events are only handed out one at a time.
//!
//! ```
//! use aydp_proto::{Decoder, Profile};
//! // A false start (FF 00 with length 40) swallows a heartbeat; the rescan finds it.
//! let stream = [0xFF, 0x00, 0x28, 0, 0, 0, 0xFF, 0x80, 0x07, 0, 0, 0, 0x78];
//! let mut dec = Decoder::<64>::new(Profile::Spec);
//! let mut frames = 0;
//! for &byte in &stream {
//!     let mut event = dec.push(byte);
//!     while let Some(ev) = event {
//!         if let Ok(frame) = ev {
//!             assert_eq!(frame.type_byte(), 0x80);
//!             frames += 1;
//!         }
//!         event = dec.poll();
//!     }
//! }
//! // The false start is still waiting for 40 bytes; the heartbeat arrives when the false
//! // candidate fails. Here the stream simply ends: flush reports what is still pending.
//! assert_eq!(frames, 0);
//! dec.flush(|ev| if ev.is_ok() { frames += 1 });
//! assert_eq!(frames, 1);
//! assert_eq!(dec.stats().frames_ok, 1);
//! ```

mod bulk;
mod state;
#[cfg(any(feature = "embedded-io", feature = "embedded-io-async"))]
mod until;

#[cfg(any(feature = "embedded-io", feature = "embedded-io-async"))]
pub(crate) use until::Found;

use crate::checksum::{ff_run, find_ff, xor};
use crate::error::{Error, Result};
use crate::frame::Frame;
use crate::header::array_at;
use crate::profile::{EXPEDITED, EXPEDITED_HEADER_LEN, Profile, START};

/// Decoder counters (MAVLink style). Every counter wraps.
///
/// ```
/// let s = aydp_proto::Stats::default();
/// assert_eq!(s.frames_ok, 0);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Stats {
    /// Frames (whole messages) delivered with a good checksum.
    pub frames_ok: u32,
    /// Candidates that reached their announced length with a bad checksum.
    pub checksum_errors: u32,
    /// Candidates whose length field was below the profile minimum or beyond the capacity.
    pub length_errors: u32,
    /// Bytes dropped: noise before a start, dropped 0xFF starts (Y5), false start bytes.
    pub bytes_discarded: u32,
}

/// What one step produced (small, so it travels in registers).
#[derive(Clone, Copy, PartialEq, Eq)]
enum Outcome {
    More,
    Frame,
    BadLength(u32),
    ChecksumMismatch,
}

/// AYDP stream decoder holding at most `N` bytes (the longest message it accepts).
///
/// Feed it byte by byte with [`Decoder::push`] (then [`Decoder::poll`]), or a slice at a time
/// with [`Decoder::feed`], which is several times faster and otherwise identical. See the
/// [module documentation](self) for the event protocol.
///
/// ```
/// use aydp_proto::{Decoder, Message, Profile};
/// let mut dec = Decoder::<64>::new(Profile::Spec);
/// let mut heartbeats = 0;
/// for &b in &[0xFF, 0x80, 0x07, 0, 0, 0, 0x78] {
///     if let Some(Ok(frame)) = dec.push(b) {
///         // The frame borrows the decoder: use it (or copy it out) before the next push.
///         if frame.message() == Ok(Message::Heartbeat) {
///             heartbeats += 1;
///         }
///     }
/// }
/// assert_eq!(heartbeats, 1);
/// ```
#[derive(Debug, Clone)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Decoder<const N: usize> {
    buf: [u8; N],
    /// Bytes of the current candidate, at `buf[..len]`.
    len: usize,
    /// Announced frame length once the length field is complete, else 0.
    need: usize,
    /// Bytes waiting to be (re)scanned, at `buf[head..head + pending]` (`head >= len`).
    pending: usize,
    /// Start of the bytes waiting to be rescanned.
    head: usize,
    /// `buf[..len]` is a frame handed out last call; drop it before doing anything else.
    delivered: bool,
    xor: u8,
    profile: Profile,
    stats: Stats,
}

impl<const N: usize> Default for Decoder<N> {
    fn default() -> Self {
        Self::new(Profile::default())
    }
}

impl<const N: usize> Decoder<N> {
    /// An empty decoder for `profile`.
    pub const fn new(profile: Profile) -> Self {
        Self {
            buf: [0; N],
            len: 0,
            need: 0,
            pending: 0,
            head: 0,
            delivered: false,
            xor: 0,
            profile,
            stats: Stats {
                frames_ok: 0,
                checksum_errors: 0,
                length_errors: 0,
                bytes_discarded: 0,
            },
        }
    }

    /// The profile this decoder follows.
    pub const fn profile(&self) -> Profile {
        self.profile
    }

    /// The capacity `N`: the longest message accepted.
    pub const fn capacity(&self) -> usize {
        N
    }

    /// The counters.
    pub const fn stats(&self) -> Stats {
        self.stats
    }

    /// Zero the counters.
    pub fn reset_stats(&mut self) {
        self.stats = Stats::default();
    }

    /// Whether bytes are queued for a rescan, i.e. [`Decoder::poll`] may still produce events.
    pub const fn has_pending(&self) -> bool {
        self.pending != 0
    }

    /// Bytes received that the decoder has not examined yet: queued behind a failed candidate
    /// for a rescan. A caller that counts the bytes it pushed finds where an event's bytes
    /// are: a frame just handed out ends that many bytes before the end of the input pushed so
    /// far, and a failed candidate (length, checksum, truncation) started one byte before
    /// those.
    ///
    /// ```
    /// use aydp_proto::{Decoder, Profile};
    /// let mut dec = Decoder::<64>::new(Profile::Spec);
    /// // A false start whose length (7) takes in a heartbeat's first bytes: it fails, and the
    /// // six bytes after it wait for the rescan.
    /// for &b in &[0xFF, 0x80, 0x07, 0, 0, 0] {
    ///     assert!(dec.push(b).is_none());
    /// }
    /// assert!(dec.push(0xFF).unwrap().is_err());
    /// assert_eq!(dec.unscanned_bytes(), 6); // the candidate started at 7 - 6 - 1 = 0
    /// ```
    pub const fn unscanned_bytes(&self) -> usize {
        self.pending
    }

    /// Forget everything held (counters are kept).
    pub fn reset(&mut self) {
        self.len = 0;
        self.need = 0;
        self.pending = 0;
        self.head = 0;
        self.delivered = false;
        self.xor = 0;
    }

    /// Feed one byte. Returns the first event it causes; call [`Decoder::poll`] until `None`
    /// to take any further events a rescan uncovered.
    ///
    /// ```
    /// use aydp_proto::{Decoder, Profile};
    /// let mut dec = Decoder::<32>::new(Profile::Spec);
    /// let ev: Vec<_> = [0xFF, 0x89, 0x08, 0, 0, 0, 0x02, 0x7C]
    ///     .iter()
    ///     .filter_map(|&b| dec.push(b).map(|e| e.map(|f| f.data().to_vec())))
    ///     .collect();
    /// assert_eq!(ev, vec![Ok(vec![0x02])]);
    /// ```
    #[inline]
    pub fn push(&mut self, byte: u8) -> Option<Result<Frame<'_>>> {
        // The common case, inlined: nothing queued, a byte that is only stored and XORed
        // because the candidate stays incomplete after it: inside the body once the length
        // is known (`need >= 7`), or the third to fifth header byte (the length field is not
        // complete yet, and only the second byte has a rule of its own). A frame handed out
        // last call has `len == need`, so it never takes this path.
        let len = self.len;
        let limit = if self.need > EXPEDITED_HEADER_LEN {
            self.need
        } else {
            EXPEDITED_HEADER_LEN
        };
        if self.pending == 0 {
            // (Nested rather than a let chain: the crate's MSRV is 1.87.)
            if len >= 2 && len.wrapping_add(1) < limit {
                if let Some(slot) = self.buf.get_mut(len) {
                    *slot = byte;
                    self.len = len + 1;
                    self.xor ^= byte;
                    return None;
                }
            }
            // Hunting (`len == 0` also means no frame is lent out): a start, or noise.
            if len == 0 {
                if byte == START {
                    if let Some(slot) = self.buf.first_mut() {
                        *slot = START;
                        self.len = 1;
                        self.xor = START;
                        return None;
                    }
                }
                if byte != START {
                    self.discard(1);
                    return None;
                }
            }
        }
        self.push_slow(byte)
    }

    #[inline(never)]
    fn push_slow(&mut self, byte: u8) -> Option<Result<Frame<'_>>> {
        self.release();
        if self.pending != 0 {
            self.enqueue(byte);
            return self.poll();
        }
        let outcome = self.step(byte);
        self.event(outcome)
    }

    /// Take the next event from bytes already held (after a rescan), or `None`.
    ///
    /// ```
    /// use aydp_proto::{Decoder, Profile};
    /// let mut dec = Decoder::<32>::new(Profile::Spec);
    /// assert!(dec.poll().is_none());
    /// ```
    pub fn poll(&mut self) -> Option<Result<Frame<'_>>> {
        self.release();
        let outcome = self.rescan_queued();
        self.event(outcome)
    }

    /// Steps through the queued bytes until one completes or fails a candidate (`More`: none
    /// did, and the queue is empty).
    fn rescan_queued(&mut self) -> Outcome {
        while self.pending != 0 {
            let byte = self.buf.get(self.head).copied().unwrap_or(0);
            self.head = self.head.wrapping_add(1);
            self.pending -= 1;
            match self.step(byte) {
                Outcome::More => {}
                other => return other,
            }
        }
        Outcome::More
    }
}
