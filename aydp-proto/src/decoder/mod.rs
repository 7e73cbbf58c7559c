//! The stream decoder, with lossless resynchronisation: [`Decoder`] implements the decoder
//! contract of this workspace, [`Decode`] (stated once in `frame-io`): the one loop
//!
//! ```text
//! decoder.feed(bytes, |event| ..)   // every slice of the stream, of any length (one byte too)
//! decoder.finish(|event| ..)        // the stream ended: a candidate cut short is Err(Truncated)
//! ```
//!
//! with each event `Ok(frame)` or `Err(error)` (counted; the decoder has resynchronised), and
//! underneath it the pull form, [`Decode::decode`], [`Decode::end`] and [`Decode::item`], for
//! a caller that acts between two events. The events depend only on the bytes, never on how
//! they were cut into slices.
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
//! # Several events from one byte
//!
//! A rescan can uncover several messages (and further failures) among bytes already held, so
//! one byte can give several events: `feed` hands them all out, in order. The pull form
//! returns one a call: events a rescan left queued come first, with no byte used, so its
//! caller calls [`Decode::decode`] again on the rest, and once with an empty slice, until it
//! returns `(0, None)`. No event is lost either way.
//!
//! ```
//! use aydp_proto::{Decode, Decoder, Error, Event, Profile};
//! // A false start (FF 00, length 40) swallows a heartbeat: when its 40 bytes are in, its
//! // checksum fails and the rescan finds the heartbeat. The 40th byte gives two events.
//! let mut stream = vec![0xFF, 0x00, 0x28, 0, 0, 0, 0xFF, 0x80, 0x07, 0, 0, 0, 0x78];
//! stream.resize(40, 0);
//!
//! // The one loop, here a byte at a time.
//! let mut dec = Decoder::<64>::new(Profile::Spec);
//! let mut seen = Vec::new();
//! for byte in &stream {
//!     dec.feed(core::slice::from_ref(byte), |event| seen.push(event.map(|f| f.type_byte())));
//! }
//! dec.finish(|event| seen.push(event.map(|f| f.type_byte())));
//! assert!(matches!(seen[..], [Err(Error::ChecksumMismatch { .. }), Ok(0x80)]));
//!
//! // The pull form: the heartbeat comes with no byte used, from the bytes held.
//! let mut dec = Decoder::<64>::new(Profile::Spec);
//! assert_eq!(dec.decode(&stream[..39]), (39, None));
//! let (used, event) = dec.decode(&stream[39..]);
//! assert!(used == 1 && matches!(event, Some(Event::Error(Error::ChecksumMismatch { .. }))));
//! let (used, event) = dec.decode(&[]);
//! assert_eq!((used, event), (0, Some(Event::Found((None, 7)))));
//! assert_eq!(dec.item(&[], (None, 7)).type_byte(), 0x80);
//! assert_eq!(dec.decode(&[]), (0, None));
//! assert_eq!(dec.stats().frames_ok, 1);
//! ```

// The files: `step.rs`, the rules, once, and their reports made events; `byte.rs`, the
// per-byte path (`feed` of one byte); `bulk.rs`, the slice fast path; `buffer.rs`, the bytes
// held between calls; `span.rs`, where each event of the pull form lies. Every path decides
// through the one step, and the property tests prove them equal on every split of hostile
// streams.
mod buffer;
mod bulk;
mod byte;
#[cfg(test)]
mod liveness;
mod span;
mod step;

use frame_io::{Decode, Event, Span};

use crate::checksum::{ff_run, find_ff, xor};
use crate::error::{Error, Result};
use crate::frame::Frame;
use crate::profile::{EXPEDITED, EXPEDITED_HEADER_LEN, Profile, START};
use step::discard;

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
/// It implements [`Decode`]: `feed` every slice of the stream (whole DMA buffers, UART
/// FIFOs, datagrams, or one byte from an interrupt handler), `finish` when the stream ends.
/// See the [module documentation](self) for how it resynchronises and the pull form.
///
/// ```
/// use aydp_proto::{Decode, Decoder, Error, Message, Profile};
/// let mut decoder = Decoder::<64>::new(Profile::Spec);
/// let (mut heartbeats, mut errors) = (0, 0);
/// // Noise, a heartbeat cut across two reads, then a message cut short by the end.
/// for bytes in [&[0x13, 0xFF, 0x80, 0x07][..], &[0, 0, 0, 0x78, 0xFF, 0x89]] {
///     decoder.feed(bytes, |event| match event {
///         // The frame borrows the decoder or `bytes`: use it (or copy it out) here.
///         Ok(frame) => heartbeats += u32::from(frame.message() == Ok(Message::Heartbeat)),
///         Err(_) => errors += 1, // counted; the decoder resynchronised
///     });
/// }
/// decoder.finish(|event| {
///     assert_eq!(event.err(), Some(Error::Truncated)); // the end of the stream
///     errors += 1;
/// });
/// assert_eq!((heartbeats, errors), (1, 1));
/// assert_eq!(decoder.stats().bytes_discarded, 3); // the noise byte, the cut message's two
/// ```
#[doc = include_str!("../../PERFORMANCE.md")]
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
    /// Where the event the pull form last returned lies (see [`Decode::span`]): written once an
    /// event, never a byte. In a decoder too small for a header (`N` < 6), which gives no event
    /// before the end of the stream, `after` counts the bytes `decode` could not hold behind
    /// its candidate (discarded as they came) until `end` has reported it.
    span: Span,
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
    ///
    /// ```
    /// use aydp_proto::{Decoder, Profile};
    /// let dec = Decoder::<64>::new(Profile::Reference);
    /// assert_eq!((dec.profile(), dec.held_bytes()), (Profile::Reference, 0));
    /// ```
    pub const fn new(profile: Profile) -> Self {
        Self {
            buf: [0; N],
            start: 0,
            len: 0,
            decide_at: 0,
            span: Span { len: 0, after: 0 },
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
    ///
    /// ```
    /// use aydp_proto::{Decoder, Profile};
    /// assert_eq!(Decoder::<64>::new(Profile::Spec).profile(), Profile::Spec);
    /// ```
    pub const fn profile(&self) -> Profile {
        self.profile
    }

    /// The capacity `N`: the longest message accepted.
    ///
    /// ```
    /// use aydp_proto::{Decoder, Profile};
    /// assert_eq!(Decoder::<64>::new(Profile::Spec).capacity(), 64);
    /// ```
    pub const fn capacity(&self) -> usize {
        N
    }

    /// The counters.
    ///
    /// ```
    /// use aydp_proto::{Decode, Decoder, Profile};
    /// let mut dec = Decoder::<64>::new(Profile::Spec);
    /// dec.feed(&[0x00, 0xFF, 0x80, 0x07, 0, 0, 0, 0x78], |_| {});
    /// assert_eq!((dec.stats().frames_ok, dec.stats().bytes_discarded), (1, 1));
    /// ```
    pub const fn stats(&self) -> Stats {
        self.stats
    }

    /// Zero the counters.
    ///
    /// ```
    /// use aydp_proto::{Decode, Decoder, Profile, Stats};
    /// let mut dec = Decoder::<64>::new(Profile::Spec);
    /// dec.feed(&[0x00], |_| {});
    /// dec.reset_stats();
    /// assert_eq!(dec.stats(), Stats::default());
    /// ```
    pub fn reset_stats(&mut self) {
        self.stats = Stats::default();
    }

    /// Bytes held: received, and not yet delivered nor dropped (the candidate in progress and
    /// any bytes behind a failed candidate waiting for the rescan). Right after an event of
    /// the pull form they are the bytes after it, so a caller that counts the bytes
    /// [`Decode::decode`] used finds where each event's bytes are: a frame just handed out
    /// ends that many bytes before the end of the input used so far, and a failed candidate
    /// (length, checksum, truncation) started one byte before those. [`Decode::span`] says
    /// where every event lies, and [`Stream`](crate::Stream) counts the bytes used.
    ///
    /// ```
    /// use aydp_proto::{Decode, Decoder, Event, Profile};
    /// let mut dec = Decoder::<64>::new(Profile::Spec);
    /// // A false start whose length (7) takes in a heartbeat's first bytes: it fails, and the
    /// // six bytes after it wait for the rescan.
    /// assert_eq!(dec.decode(&[0xFF, 0x80, 0x07, 0, 0, 0]), (6, None));
    /// assert_eq!(dec.held_bytes(), 6);
    /// let (used, event) = dec.decode(&[0xFF]);
    /// assert!(used == 1 && matches!(event, Some(Event::Error(_))));
    /// assert_eq!(dec.held_bytes(), 6); // the candidate started at 7 - 6 - 1 = 0
    /// ```
    pub const fn held_bytes(&self) -> usize {
        self.len.saturating_sub(self.start)
    }

    /// Forget everything held (counters are kept).
    ///
    /// ```
    /// use aydp_proto::{Decode, Decoder, Profile};
    /// let mut dec = Decoder::<64>::new(Profile::Spec);
    /// dec.feed(&[0xFF, 0x80, 0x07], |_| {});
    /// dec.reset();
    /// assert_eq!(dec.held_bytes(), 0);
    /// ```
    pub fn reset(&mut self) {
        self.start = 0;
        self.len = 0;
        self.decide_at = 0;
    }

    /// The next event a rescan left queued in the bytes held, in the pull form, or `None`.
    #[inline]
    fn queued(&mut self) -> Option<Event<(Option<usize>, usize), Error>> {
        Some(match self.examine() {
            Step::Frame(total) => {
                self.frame_span(total);
                Event::Found((None, total))
            }
            Step::Failed(e) => {
                // A length error: the step judged the header's first six bytes.
                self.failed_span(EXPEDITED_HEADER_LEN);
                Event::Error(e)
            }
            Step::Mismatch(total) => {
                self.failed_span(total);
                Event::Error(self.mismatch_held(total))
            }
            Step::Need(_) | Step::Noise(_) => return None,
        })
    }
}

/// The contract (see [`Decode`]). An item is a [`Frame`], its length and checksum checked. What
/// [`Event::Found`] carries says where the frame is: `(Some(at), len)`, in place at `at` in
/// the slice given to `decode` (checked there, not copied), or `(None, len)`, the last `len`
/// bytes the decoder delivered from its own buffer. [`Decode::finish`] gives exactly the
/// events of the end of the stream: the candidate cut short is `Err(Error::Truncated)` (not
/// counted as a checksum or length error), then what the rescan of its bytes finds; after it
/// the decoder holds nothing.
///
/// **Where each event lies** ([`Decode::span`], which [`Stream`](crate::Stream) turns into
/// every event's [`Place`](crate::Place) in the stream):
///
/// - a frame: its bytes, [`Frame::as_bytes`], from the 0xFF start to the checksum;
/// - [`Error::ChecksumMismatch`]: the candidate from its 0xFF start for its whole announced
///   length (the bytes whose XOR failed, checksum byte included);
/// - [`Error::BadLength`]: the six bytes the step judged: the 0xFF start, the type byte and
///   the four bytes of the length field;
/// - [`Error::Truncated`] (of `end`): the candidate's bytes that were pending
///   ([`Event::Truncated`]'s count), from its 0xFF start to the end of the stream.
///
/// Only an error's first byte, its 0xFF start, is counted in
/// [`Stats::bytes_discarded`]: its other bytes are rescanned, and are dropped as noise
/// (counted then) or belong to later events, so a frame can lie inside a failed candidate.
/// Every byte used is in exactly one of: a frame, a discarded byte, the bytes held. Events
/// come in the order of their first bytes. A rescan's events come with no byte used, so the
/// span's `after` counts the bytes used after the event's last byte: those held, less a failed
/// candidate's own. On the slice path of `decode` a failed candidate is used whole, and its
/// bytes after the 0xFF held for the rescan (as the per-byte path holds them), so that its
/// span lies in the bytes used. A decoder too small for a header (`N` < 6) gives no event
/// before `end`; there the bytes it could not hold follow the pending ones.
///
/// ```
/// use aydp_proto::{Decode, Decoder, Error, Event, Place, Profile, Span, Stream};
/// // An expedited heartbeat (type 0), then the start of another.
/// let wire = [0xFF, 0x80, 0x07, 0, 0, 0, 0x78, 0xFF, 0x89];
/// let mut d = Decoder::<32>::new(Profile::Spec);
/// let (used, event) = d.decode(&wire);
/// assert_eq!((used, event), (7, Some(Event::Found((Some(0), 7)))));
/// assert_eq!(d.item(&wire, (Some(0), 7)).as_bytes(), &wire[..7]);
/// assert_eq!(d.span(), Span { len: 7, after: 0 });
/// assert_eq!(d.decode(&wire[7..]), (2, None));
/// assert_eq!(d.end(), Some(Event::Truncated(2)));
/// assert_eq!(d.span(), Span { len: 2, after: 0 });
/// assert_eq!(d.end(), None);
///
/// // A false start (FF 80, length 14) that takes in a heartbeat and the byte after it: its
/// // checksum fails, and the rescan of its bytes finds the heartbeat, the 0x00 held behind it.
/// let wire = [0xFF, 0x80, 0x0E, 0, 0, 0, 0xFF, 0x80, 0x07, 0, 0, 0, 0x78, 0x00];
/// let (used, event) = d.decode(&wire);
/// assert!(used == 14 && matches!(event, Some(Event::Error(Error::ChecksumMismatch { .. }))));
/// assert_eq!(d.span(), Span { len: 14, after: 0 });
/// assert_eq!(d.decode(&[]), (0, Some(Event::Found((None, 7)))));
/// assert_eq!(d.span(), Span { len: 7, after: 1 });
///
/// // Through a `Stream`, in any slices: every event with its place.
/// let mut stream = Stream::new(Decoder::<32>::new(Profile::Spec));
/// let mut places = Vec::new();
/// for byte in &wire {
///     stream.feed(core::slice::from_ref(byte), |place, _| places.push(place));
/// }
/// stream.finish(|place, _| places.push(place));
/// assert_eq!(places, [Place { offset: 0, len: 14 }, Place { offset: 6, len: 7 }]);
/// ```
impl<const N: usize> Decode for Decoder<N> {
    type Error = Error;
    type Found = (Option<usize>, usize);
    type Item<'a> = Frame<'a>;
    const TRUNCATED: Error = Error::Truncated;

    /// Up to the first event, with the slice fast path (the step runs on `bytes` itself while
    /// nothing is held), events a rescan left queued first. A candidate that fails on the
    /// slice path is used whole, its bytes after the 0xFF held for the rescan.
    fn decode(&mut self, bytes: &[u8]) -> (usize, Option<Event<(Option<usize>, usize), Error>>) {
        let total = bytes.len();
        if N < EXPEDITED_HEADER_LEN || total <= 1 {
            // A decoder too small for a header, or one byte (a caller that acts after every
            // byte, as the box's AYDP link, which then links no slice path): the
            // byte-at-a-time path.
            if let Some(event) = self.queued() {
                return (0, Some(event));
            }
            for (i, &b) in bytes.iter().enumerate() {
                if N < EXPEDITED_HEADER_LEN {
                    // Too small for a header (no event before the end of the stream): count
                    // the bytes `push` cannot hold, behind the candidate, for its span.
                    self.span.after = if self.held_bytes() >= N {
                        self.span.after.wrapping_add(1)
                    } else {
                        0
                    };
                }
                let event = match self.push(b) {
                    None => continue,
                    Some(Ok(frame)) => Event::Found((None, frame.as_bytes().len())),
                    Some(Err(e)) => Event::Error(e),
                };
                // The held bytes were one undecided candidate (or none) before this byte, so
                // the event ends at it: a frame is followed by nothing held, and a failed
                // candidate is its start byte and every byte held.
                match event {
                    Event::Found((_, len)) => self.frame_span(len),
                    _ => self.failed_span(self.held_bytes().saturating_add(1)),
                }
                return (i.saturating_add(1), Some(event));
            }
            return (total, None);
        }
        let mut rest = bytes;
        loop {
            let used = total.saturating_sub(rest.len());
            if let Some(event) = self.queued() {
                return (used, Some(event));
            }
            if self.len == self.start {
                let (n, step) = self.scan_in_place(rest);
                let end = used.saturating_add(n);
                // A failed candidate started at the byte before `end`: the six bytes of its
                // header that the step judged (a length error), or its whole announced length.
                let at = end.saturating_sub(1);
                let (len, error) = match step {
                    Step::Frame(len) => {
                        self.frame_span(len);
                        return (
                            end,
                            Some(Event::Found((Some(end.saturating_sub(len)), len))),
                        );
                    }
                    Step::Failed(e) => (EXPEDITED_HEADER_LEN, Some(e)),
                    Step::Mismatch(len) => (len, None),
                    Step::Need(_) | Step::Noise(_) => return (end, None),
                };
                let candidate = bytes.get(at..at.saturating_add(len)).unwrap_or(&[]);
                let error = error.unwrap_or_else(|| Error::mismatch(candidate));
                self.hold_failed(candidate);
                return (
                    at.saturating_add(candidate.len()),
                    Some(Event::Error(error)),
                );
            }
            if rest.is_empty() {
                return (total, None);
            }
            rest = self.take_needed(rest);
        }
    }

    /// The events of the end of the stream, one a call: those a rescan left queued, then the
    /// candidate cut short as [`Event::Truncated`] (its bytes then rescanned), until `None`.
    fn end(&mut self) -> Option<Event<(Option<usize>, usize), Error>> {
        if let Some(event) = self.queued() {
            return Some(event);
        }
        // The candidate's bytes held are the last used, but in a decoder too small for a
        // header, where the bytes it could not hold (discarded as they came) follow them.
        let after = if N < EXPEDITED_HEADER_LEN {
            self.span.after
        } else {
            0
        };
        let Some(pending) = self.give_up() else {
            self.span = Span::default();
            return None;
        };
        self.span = Span {
            len: pending,
            after,
        };
        Some(Event::Truncated(pending))
    }

    #[inline]
    fn item<'a>(&'a self, input: &'a [u8], (at, len): (Option<usize>, usize)) -> Frame<'a> {
        let bytes = match at {
            // The last `len` bytes delivered from the buffer end where the bytes held begin.
            None => self.buf.get(self.start.saturating_sub(len)..self.start),
            Some(at) => input.get(at..at.saturating_add(len)),
        };
        Frame::new_unchecked(bytes.unwrap_or(&[]), self.profile)
    }

    /// A frame found in place (`(Some(at), len)`) is copied to the front of the buffer, where
    /// a frame the decoder held would be; nothing is held after a frame found in place, so
    /// nothing is overwritten. A frame always fits: the step takes none longer than `N`.
    #[inline]
    fn keep(&mut self, input: &[u8], found: (Option<usize>, usize)) -> (Option<usize>, usize) {
        let (Some(at), len) = found else {
            return found;
        };
        let (Some(frame), Some(to)) = (
            input.get(at..at.saturating_add(len)),
            self.buf.get_mut(..len),
        ) else {
            return found;
        };
        for (d, s) in to.iter_mut().zip(frame) {
            *d = *s;
        }
        (self.start, self.len) = (len, len);
        (None, len)
    }

    /// Recorded once an event, never a byte: see above for each event's bytes.
    #[inline]
    fn span(&self) -> Span {
        self.span
    }

    /// The loop of the contract, overridden with the fast paths (same events as the pull
    /// form): one byte goes the per-byte path (stored; the step runs only where it can
    /// decide), a longer slice the bulk path.
    #[inline]
    fn feed<F>(&mut self, bytes: &[u8], on_event: F)
    where
        F: FnMut(Result<Frame<'_>>),
    {
        if let [byte] = *bytes {
            self.feed_byte(byte, on_event);
        } else {
            self.feed_bulk(bytes, on_event);
        }
    }
}
