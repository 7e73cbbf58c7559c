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

    /// Feed a slice, handing every event (frames and failures) to `on_event` in order.
    ///
    /// This is the bulk path. It behaves exactly like pushing the bytes one at a time with
    /// [`Decoder::push`] and draining [`Decoder::poll`] after each (same events in the same
    /// order, same counters, same rescans), but it is several times faster:
    ///
    /// - while the decoder holds nothing, messages are found and checked **in `bytes` itself**
    ///   (no copy): the 0xFF start is searched a machine word at a time, and once the header
    ///   gives the length the whole message is XORed a word at a time. Frames found this way
    ///   borrow `bytes`;
    /// - a message cut by the end of the slice is copied into the decoder's buffer; the next
    ///   call copies the rest of its body in one go, once its length is known.
    ///
    /// Feed it whole DMA buffers, UART FIFOs or datagrams.
    ///
    /// ```
    /// use aydp_proto::{Decoder, Profile};
    /// let mut dec = Decoder::<32>::new(Profile::Spec);
    /// let mut n = 0;
    /// dec.feed(&[0x00, 0xFF, 0xFF, 0x80, 0x07, 0, 0, 0, 0x78], |ev| n += ev.is_ok() as u32);
    /// assert_eq!(n, 1);
    /// assert_eq!(dec.stats().bytes_discarded, 2);
    ///
    /// // A message split across two calls is delivered by the call that completes it.
    /// dec.feed(&[0xFF, 0x89, 0x08], |_| unreachable!());
    /// dec.feed(&[0, 0, 0, 0x02, 0x7C], |ev| n += ev.is_ok() as u32);
    /// assert_eq!(n, 2);
    /// ```
    pub fn feed<F: FnMut(Result<Frame<'_>>)>(&mut self, bytes: &[u8], mut on_event: F) {
        if N < EXPEDITED_HEADER_LEN {
            // A decoder too small for a header: keep to the byte-at-a-time rules.
            for &b in bytes {
                let mut ev = self.push(b);
                while let Some(e) = ev {
                    on_event(e);
                    ev = self.poll();
                }
            }
            return;
        }
        if bytes.is_empty() {
            // Pushing nothing does nothing, not even hand out events still queued.
            return;
        }
        let mut rest = bytes;
        loop {
            // Events a rescan left queued come first: those bytes precede `rest`.
            while let Some(e) = self.poll() {
                on_event(e);
            }
            if self.len == 0 {
                self.scan_in_place(rest, &mut on_event);
                return;
            }
            let Some((&byte, after)) = rest.split_first() else {
                return;
            };
            if self.need == 0 {
                // The header is still incomplete (at most five bytes): byte by byte.
                rest = after;
                let outcome = self.step(byte);
                if let Some(e) = self.event(outcome) {
                    on_event(e);
                }
                continue;
            }
            // The length is known: copy the rest of the body in one go.
            let want = self.need.saturating_sub(self.len);
            let (body, after) = rest.split_at_checked(want).unwrap_or((rest, &[]));
            rest = after;
            let room = self.buf.get_mut(self.len..).unwrap_or(&mut []);
            if let Some(dst) = room.get_mut(..body.len()) {
                dst.copy_from_slice(body);
                self.xor ^= xor(body);
                self.len += body.len();
            }
            if self.len >= self.need {
                let outcome = self.complete();
                if let Some(e) = self.event(outcome) {
                    on_event(e);
                }
            }
        }
    }

    /// The decoder holds nothing: find and check messages in `bytes` itself, hand every event
    /// to `on_event`, and keep an incomplete last candidate in the buffer. Exactly what
    /// pushing the bytes one by one does: a failed candidate's rescan starts at the byte after
    /// its start, which here is simply the next position in `bytes`.
    fn scan_in_place<F: FnMut(Result<Frame<'_>>)>(&mut self, mut bytes: &[u8], on_event: &mut F) {
        loop {
            // Noise before a start is discarded.
            let noise = if bytes.first() == Some(&START) {
                0
            } else {
                find_ff(bytes)
            };
            let from = bytes.get(noise..).unwrap_or(&[]);
            if from.is_empty() {
                self.discard(noise);
                return;
            }
            // Y5: in a run of 0xFF only the last is the start; the others are discarded.
            let run = if from.get(1) == Some(&START) {
                ff_run(from)
            } else {
                1
            };
            let start = run.saturating_sub(1);
            self.discard(noise.saturating_add(start));
            let candidate = from.get(start..).unwrap_or(&[]);
            let Some(header) = candidate.first_chunk::<EXPEDITED_HEADER_LEN>() else {
                self.hold(candidate, 0);
                return;
            };
            let field = u32::from_le_bytes([header[2], header[3], header[4], header[5]]);
            let expedited = header[1] & EXPEDITED != 0;
            match self.profile.frame_len(field, expedited) {
                Some(total) if total <= N => {
                    let Some(frame) = candidate.get(..total) else {
                        self.hold(candidate, total);
                        return;
                    };
                    if xor(frame) == 0 {
                        self.stats.frames_ok = self.stats.frames_ok.wrapping_add(1);
                        on_event(Ok(Frame::new_unchecked(frame, self.profile)));
                        bytes = candidate.get(total..).unwrap_or(&[]);
                        continue;
                    }
                    self.stats.checksum_errors = self.stats.checksum_errors.wrapping_add(1);
                    on_event(Err(Error::ChecksumMismatch));
                }
                _ => {
                    self.stats.length_errors = self.stats.length_errors.wrapping_add(1);
                    on_event(Err(Error::BadLength(field)));
                }
            }
            // The false start is dropped; scanning resumes at the byte after it.
            self.discard(1);
            bytes = candidate.get(1..).unwrap_or(&[]);
        }
    }

    /// Feed `bytes` up to and including the first event, with the bulk path of
    /// [`Decoder::feed`] (messages found in place in `bytes`, bodies copied in one go), events
    /// still queued by a rescan first. Returns how many bytes were consumed and what the
    /// event was, as a [`Found`] that borrows nothing, so a reader can loop over reads and
    /// build the frame afterwards. Calling it until it finds nothing in an empty slice gives
    /// exactly the events of [`Decoder::push`] and [`Decoder::poll`].
    #[cfg(any(feature = "embedded-io", feature = "embedded-io-async"))]
    pub(crate) fn feed_until(&mut self, bytes: &[u8]) -> (usize, Found) {
        let total = bytes.len();
        if let Some(found) = self.poll_found() {
            return (0, found);
        }
        if N < EXPEDITED_HEADER_LEN {
            // A decoder too small for a header: keep to the byte-at-a-time rules.
            for (i, &b) in bytes.iter().enumerate() {
                let found = match self.push(b) {
                    None => continue,
                    Some(Ok(_)) => Found::Held,
                    Some(Err(e)) => Found::Error(e),
                };
                return (i.saturating_add(1), found);
            }
            return (total, Found::Nothing);
        }
        let mut rest = bytes;
        loop {
            let used = total.saturating_sub(rest.len());
            if let Some(found) = self.poll_found() {
                return (used, found);
            }
            if self.len == 0 {
                let (n, found) = self.scan_until(rest);
                let found = match found {
                    Found::InPlace { at, len } => Found::InPlace {
                        at: at.saturating_add(used),
                        len,
                    },
                    other => other,
                };
                return (used.saturating_add(n), found);
            }
            let Some((&byte, after)) = rest.split_first() else {
                return (total, Found::Nothing);
            };
            let outcome = if self.need == 0 {
                // The header is still incomplete (at most five bytes): byte by byte.
                rest = after;
                self.step(byte)
            } else {
                // The length is known: copy the rest of the body in one go.
                let want = self.need.saturating_sub(self.len);
                let (body, after) = rest.split_at_checked(want).unwrap_or((rest, &[]));
                rest = after;
                let room = self.buf.get_mut(self.len..).unwrap_or(&mut []);
                if let Some(dst) = room.get_mut(..body.len()) {
                    dst.copy_from_slice(body);
                    self.xor ^= xor(body);
                    self.len += body.len();
                }
                if self.len < self.need {
                    continue;
                }
                self.complete()
            };
            if let Some(found) = Found::of(outcome) {
                return (total.saturating_sub(rest.len()), found);
            }
        }
    }

    /// [`Decoder::poll`], as a [`Found`].
    #[cfg(any(feature = "embedded-io", feature = "embedded-io-async"))]
    fn poll_found(&mut self) -> Option<Found> {
        match self.poll()? {
            Ok(_) => Some(Found::Held),
            Err(e) => Some(Found::Error(e)),
        }
    }

    /// [`Decoder::scan_in_place`] up to the first event: returns the bytes consumed and the
    /// event; a frame found is at `bytes[at..at + len]`.
    #[cfg(any(feature = "embedded-io", feature = "embedded-io-async"))]
    fn scan_until(&mut self, bytes: &[u8]) -> (usize, Found) {
        let total = bytes.len();
        let noise = if bytes.first() == Some(&START) {
            0
        } else {
            find_ff(bytes)
        };
        let from = bytes.get(noise..).unwrap_or(&[]);
        if from.is_empty() {
            self.discard(noise);
            return (total, Found::Nothing);
        }
        let run = if from.get(1) == Some(&START) {
            ff_run(from)
        } else {
            1
        };
        let start = run.saturating_sub(1);
        self.discard(noise.saturating_add(start));
        let candidate = from.get(start..).unwrap_or(&[]);
        let at = total.saturating_sub(candidate.len());
        let Some(header) = candidate.first_chunk::<EXPEDITED_HEADER_LEN>() else {
            self.hold(candidate, 0);
            return (total, Found::Nothing);
        };
        let field = u32::from_le_bytes([header[2], header[3], header[4], header[5]]);
        let expedited = header[1] & EXPEDITED != 0;
        let found = match self.profile.frame_len(field, expedited) {
            Some(len) if len <= N => {
                let Some(frame) = candidate.get(..len) else {
                    self.hold(candidate, len);
                    return (total, Found::Nothing);
                };
                if xor(frame) == 0 {
                    self.stats.frames_ok = self.stats.frames_ok.wrapping_add(1);
                    return (at.saturating_add(len), Found::InPlace { at, len });
                }
                self.stats.checksum_errors = self.stats.checksum_errors.wrapping_add(1);
                Found::Error(Error::ChecksumMismatch)
            }
            _ => {
                self.stats.length_errors = self.stats.length_errors.wrapping_add(1);
                Found::Error(Error::BadLength(field))
            }
        };
        // The false start is dropped; the next call resumes at the byte after it.
        self.discard(1);
        (at.saturating_add(1), found)
    }

    /// The end of the stream, one event at a time: what [`Decoder::flush`] hands out, in the
    /// same order, with each incomplete candidate as [`Found::Truncated`] (with its length).
    /// `None` once the decoder is empty.
    #[cfg(any(feature = "embedded-io", feature = "embedded-io-async"))]
    pub(crate) fn flush_until(&mut self) -> Option<Found> {
        if let Some(found) = self.poll_found() {
            return Some(found);
        }
        if self.len == 0 {
            self.reset();
            return None;
        }
        let pending = self.len;
        self.rescan();
        Some(Found::Truncated(pending))
    }

    /// The frame a [`Found::Held`] stands for (until the next call).
    #[cfg(any(feature = "embedded-io", feature = "embedded-io-async"))]
    pub(crate) fn held_frame(&self) -> Frame<'_> {
        Frame::new_unchecked(self.buf.get(..self.len).unwrap_or(&[]), self.profile)
    }

    /// Keep an incomplete candidate (start byte first; `need` = its length once known, else 0).
    fn hold(&mut self, candidate: &[u8], need: usize) {
        if let Some(dst) = self.buf.get_mut(..candidate.len()) {
            dst.copy_from_slice(candidate);
            self.len = candidate.len();
            self.xor = xor(candidate);
            self.need = need;
        }
    }

    #[inline]
    fn discard(&mut self, count: usize) {
        // Counting `count` at once wraps exactly like counting one at a time.
        self.stats.bytes_discarded = self.stats.bytes_discarded.wrapping_add(count as u32);
    }

    /// End of stream: fail the incomplete candidate (if any), rescan what it held, and hand
    /// every resulting event to `on_event`. Afterwards the decoder is empty. An incomplete
    /// candidate is reported as [`Error::Truncated`] and is not counted as a checksum or
    /// length error.
    ///
    /// ```
    /// use aydp_proto::{Decoder, Error, Profile};
    /// let mut dec = Decoder::<32>::new(Profile::Spec);
    /// let mut evs = Vec::new();
    /// dec.feed(&[0xFF, 0x80, 0x07], |e| evs.push(e.map(|_| ())));
    /// dec.flush(|e| evs.push(e.map(|_| ())));
    /// assert_eq!(evs, vec![Err(Error::Truncated)]);
    /// ```
    pub fn flush<F: FnMut(Result<Frame<'_>>)>(&mut self, mut on_event: F) {
        while let Some(e) = self.flush_next() {
            on_event(e);
        }
    }

    /// End of stream, one event at a time: the next event [`Decoder::flush`] would hand over,
    /// or `None` once the decoder is empty (it is then reset). Between calls the caller may
    /// read [`Decoder::unscanned_bytes`] to place each event in the input.
    ///
    /// ```
    /// use aydp_proto::{Decoder, Error, Profile};
    /// let mut dec = Decoder::<32>::new(Profile::Spec);
    /// dec.feed(&[0xFF, 0x80, 0x07], |_| {});
    /// assert!(matches!(dec.flush_next(), Some(Err(Error::Truncated))));
    /// assert!(dec.flush_next().is_none());
    /// ```
    pub fn flush_next(&mut self) -> Option<Result<Frame<'_>>> {
        self.release();
        let outcome = self.rescan_queued();
        if outcome != Outcome::More {
            return self.event(outcome);
        }
        if self.len == 0 {
            self.reset();
            return None;
        }
        self.rescan();
        Some(Err(Error::Truncated))
    }

    /// Drop a frame handed out on the previous call. Queued bytes stay where they are.
    #[inline]
    fn release(&mut self) {
        if self.delivered {
            self.delivered = false;
            self.len = 0;
            self.need = 0;
            self.xor = 0;
        }
    }

    /// Copy `count` bytes from `buf[from..]` to `buf[to..]` (`to <= from`).
    fn move_down(&mut self, from: usize, to: usize, count: usize) {
        let mut i = 0;
        while i < count {
            let v = self.buf.get(from.wrapping_add(i)).copied().unwrap_or(0);
            if let Some(d) = self.buf.get_mut(to.wrapping_add(i)) {
                *d = v;
            }
            i += 1;
        }
    }

    /// Close the gap of consumed bytes between the candidate and the queued bytes.
    fn compact(&mut self) {
        if self.head != self.len {
            self.move_down(self.head, self.len, self.pending);
            self.head = self.len;
        }
    }

    /// The current candidate failed: drop its start byte and queue the rest for a rescan,
    /// ahead of the bytes already queued.
    fn rescan(&mut self) {
        self.stats.bytes_discarded = self.stats.bytes_discarded.wrapping_add(1);
        self.compact();
        let count = self.len.saturating_sub(1).saturating_add(self.pending);
        self.move_down(1, 0, count);
        self.pending = count;
        self.head = 0;
        self.len = 0;
        self.need = 0;
        self.xor = 0;
    }

    /// Queue a byte behind bytes waiting for a rescan.
    fn enqueue(&mut self, byte: u8) {
        if self.pending == 0 {
            self.head = self.len;
        }
        if self.head.saturating_add(self.pending) >= N {
            self.compact();
        }
        let at = self.head.saturating_add(self.pending);
        if let Some(slot) = self.buf.get_mut(at) {
            *slot = byte;
            self.pending += 1;
        } else {
            // Unreachable by construction (a failure or a delivery always frees a byte);
            // count it rather than panic.
            self.stats.bytes_discarded = self.stats.bytes_discarded.wrapping_add(1);
        }
    }

    /// The candidate holds all its announced bytes: the checksum decides.
    fn complete(&mut self) -> Outcome {
        if self.xor == 0 {
            self.stats.frames_ok = self.stats.frames_ok.wrapping_add(1);
            self.delivered = true;
            return Outcome::Frame;
        }
        self.stats.checksum_errors = self.stats.checksum_errors.wrapping_add(1);
        self.rescan();
        Outcome::ChecksumMismatch
    }

    #[inline]
    fn event(&self, outcome: Outcome) -> Option<Result<Frame<'_>>> {
        match outcome {
            Outcome::More => None,
            Outcome::Frame => Some(Ok(Frame::new_unchecked(
                self.buf.get(..self.len).unwrap_or(&[]),
                self.profile,
            ))),
            Outcome::BadLength(field) => Some(Err(Error::BadLength(field))),
            Outcome::ChecksumMismatch => Some(Err(Error::ChecksumMismatch)),
        }
    }

    /// Process the byte that belongs at `buf[len]`.
    #[inline]
    fn step(&mut self, byte: u8) -> Outcome {
        let len = self.len;
        if self.need != 0 {
            if let Some(slot) = self.buf.get_mut(len) {
                *slot = byte;
            }
            let len = len.wrapping_add(1);
            self.len = len;
            self.xor ^= byte;
            if len < self.need {
                return Outcome::More;
            }
            return self.complete();
        }
        match len {
            0 => {
                if byte == START {
                    if let Some(slot) = self.buf.get_mut(0) {
                        *slot = START;
                        self.len = 1;
                        self.xor = START;
                    }
                } else {
                    self.stats.bytes_discarded = self.stats.bytes_discarded.wrapping_add(1);
                }
                Outcome::More
            }
            1 if byte == START => {
                // Y5: FF FF - the first start is dropped, the second becomes the start.
                self.stats.bytes_discarded = self.stats.bytes_discarded.wrapping_add(1);
                Outcome::More
            }
            _ => {
                if let Some(slot) = self.buf.get_mut(len) {
                    *slot = byte;
                }
                let len = len.wrapping_add(1);
                self.len = len;
                self.xor ^= byte;
                if len < EXPEDITED_HEADER_LEN {
                    return Outcome::More;
                }
                let field = u32::from_le_bytes(array_at(&self.buf, 2));
                let expedited = self.buf.get(1).copied().unwrap_or(0) & EXPEDITED != 0;
                match self.profile.frame_len(field, expedited) {
                    Some(total) if total <= N => {
                        self.need = total;
                        Outcome::More
                    }
                    _ => {
                        self.stats.length_errors = self.stats.length_errors.wrapping_add(1);
                        self.rescan();
                        Outcome::BadLength(field)
                    }
                }
            }
        }
    }
}

/// What [`Decoder::feed_until`] or [`Decoder::flush_until`] found.
#[cfg(any(feature = "embedded-io", feature = "embedded-io-async"))]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Found {
    /// Every byte was consumed without an event.
    Nothing,
    /// A frame held in the decoder's buffer ([`Decoder::held_frame`]).
    Held,
    /// A frame at `bytes[at..at + len]` of the slice fed.
    InPlace { at: usize, len: usize },
    /// A failed candidate.
    Error(Error),
    /// End of stream: an incomplete candidate of this many bytes was given up.
    Truncated(usize),
}

#[cfg(any(feature = "embedded-io", feature = "embedded-io-async"))]
impl Found {
    fn of(outcome: Outcome) -> Option<Self> {
        match outcome {
            Outcome::More => None,
            Outcome::Frame => Some(Found::Held),
            Outcome::BadLength(field) => Some(Found::Error(Error::BadLength(field))),
            Outcome::ChecksumMismatch => Some(Found::Error(Error::ChecksumMismatch)),
        }
    }
}
