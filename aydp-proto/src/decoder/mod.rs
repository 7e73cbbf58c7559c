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
#[cfg(test)]
mod liveness;
mod state;
mod until;

#[cfg(any(feature = "embedded-io", feature = "embedded-io-async"))]
pub(crate) use until::Found;

use crate::checksum::{ff_run, find_ff, xor};
use crate::error::{Error, Result};
use crate::frame::Frame;
use crate::profile::{EXPEDITED, EXPEDITED_HEADER_LEN, Profile, START};
use state::discard;

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

/// What the rules make of the bytes at the front of a window (see [`Decoder::step`]).
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Step {
    /// Undecided until the window holds this many bytes: they all belong to one candidate.
    Need(usize),
    /// This many bytes of noise were dropped (counted); nothing to report.
    Noise(usize),
    /// A frame of this many bytes, checksum good, is at the front of the window.
    Frame(usize),
    /// The candidate at the front failed: its start byte was dropped (counted), and the
    /// rescan resumes at the byte after it.
    Failed(Error),
    /// The candidate of this many bytes at the front failed its checksum: as `Failed`; the
    /// caller builds the [`Error::ChecksumMismatch`] from those bytes, off the hot path.
    Mismatch(usize),
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
    /// The bytes held are `buf[start..len]`, in stream order.
    start: usize,
    len: usize,
    /// 0: the bytes held have not all been examined. Otherwise every byte held belongs to one
    /// candidate that [`Decoder::step`] can decide only once the bytes held reach
    /// `buf[decide_at - 1]`: a cache of its last answer (`Need`), so that bytes before that
    /// point are only stored.
    decide_at: usize,
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
            start: 0,
            len: 0,
            decide_at: 0,
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

    /// Bytes held: received, and not yet delivered nor dropped (the candidate in progress and
    /// any bytes behind a failed candidate waiting for the rescan). Right after an event they
    /// are the bytes after it, so a caller that counts the bytes it pushed finds where each
    /// event's bytes are: a frame just handed out ends that many bytes before the end of the
    /// input pushed so far, and a failed candidate (length, checksum, truncation) started one
    /// byte before those.
    ///
    /// ```
    /// use aydp_proto::{Decoder, Profile};
    /// let mut dec = Decoder::<64>::new(Profile::Spec);
    /// // A false start whose length (7) takes in a heartbeat's first bytes: it fails, and the
    /// // six bytes after it wait for the rescan.
    /// for &b in &[0xFF, 0x80, 0x07, 0, 0, 0] {
    ///     assert!(dec.push(b).is_none());
    /// }
    /// assert_eq!(dec.held_bytes(), 6);
    /// assert!(dec.push(0xFF).unwrap().is_err());
    /// assert_eq!(dec.held_bytes(), 6); // the candidate started at 7 - 6 - 1 = 0
    /// ```
    pub const fn held_bytes(&self) -> usize {
        self.len.saturating_sub(self.start)
    }

    /// Forget everything held (counters are kept).
    pub fn reset(&mut self) {
        self.start = 0;
        self.len = 0;
        self.decide_at = 0;
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
        // The common case, inlined: the step said it cannot decide before more than one
        // further byte is held, so this byte is only stored.
        let len = self.len;
        if len.wrapping_add(1) < self.decide_at {
            if let Some(slot) = self.buf.get_mut(len) {
                *slot = byte;
                self.len = len + 1;
                return None;
            }
        }
        self.advance(Some(byte))
    }

    /// Stores `byte` (if any) behind the bytes held, then runs the step over them: the one
    /// out-of-line function of `push` and `poll`, so that a byte the fast path of `push` does
    /// not take costs one call.
    #[inline(never)]
    fn advance(&mut self, byte: Option<u8>) -> Option<Result<Frame<'_>>> {
        if let Some(byte) = byte {
            if self.start == self.len {
                self.start = 0;
                self.len = 0;
            } else if self.len >= N {
                self.compact();
            }
            if let Some(slot) = self.buf.get_mut(self.len) {
                *slot = byte;
                self.len += 1;
            } else {
                // Unreachable by construction, as in `append`.
                discard(&mut self.stats, 1);
            }
        }
        let step = self.examine();
        self.event(step)
    }

    /// Take the next event from bytes already held (after a rescan), or `None`.
    ///
    /// ```
    /// use aydp_proto::{Decoder, Profile};
    /// let mut dec = Decoder::<32>::new(Profile::Spec);
    /// assert!(dec.poll().is_none());
    /// ```
    #[inline]
    pub fn poll(&mut self) -> Option<Result<Frame<'_>>> {
        if self.start == self.len {
            // Nothing held (the usual call after an event): nothing to decide.
            return None;
        }
        self.poll_held()
    }

    /// [`Decoder::poll`] when bytes are held: the step runs over them.
    #[inline]
    pub(super) fn poll_held(&mut self) -> Option<Result<Frame<'_>>> {
        self.advance(None)
    }
}
