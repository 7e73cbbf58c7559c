//! The byte-at-a-time decoder of a UART stream (spec section 4.2): [`Decoder`] and its [`Stats`].

#[cfg(not(target_pointer_width = "64"))]
use crate::scan::special_bytes;
#[cfg(target_pointer_width = "64")]
use crate::scan::{WORD, special_in_word};
use frame_io::{Decode, Event, Span};

use crate::{
    ESCAPE, Error, FLAG, Frame, crc,
    scan::{SPECIAL, find_flag, is_special},
};

/// Counters kept by a [`Decoder`], MAVLink style. They wrap on overflow.
///
/// Every byte pushed ends up in exactly one of `bytes_discarded`, `frame_bytes` or `flags`,
/// or is still held by the decoder ([`Decoder::held_bytes`]).
///
/// ```
/// use aeolus_proto::{Decode, Decoder};
/// let mut decoder = Decoder::<16>::new();
/// // Two noise bytes, a good TOAST "hi", then one with a bad CRC.
/// let wire = [
///     0x00, 0x13, 0x7E, 0x52, b'h', b'i', 0, 0x73, 0xEC, 0x7E, 0x52, b'h', b'i', 0, 0x74, 0xEC,
///     0x7E,
/// ];
/// decoder.feed(&wire, |_| {});
/// let stats = decoder.stats();
/// assert_eq!((stats.frames_ok, stats.checksum_errors), (1, 1));
/// assert_eq!((stats.bytes_discarded, stats.frame_bytes, stats.flags), (2 + 6, 6, 3));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Stats {
    /// Frames delivered with a good CRC.
    pub frames_ok: u32,
    /// Frames delivered without a CRC (`00 00`, not in strict mode).
    pub frames_no_crc: u32,
    /// Frames dropped for a CRC mismatch.
    pub checksum_errors: u32,
    /// Frames dropped in strict mode because they carried no CRC.
    pub missing_crc: u32,
    /// Frames dropped because they outgrew the capacity.
    pub overflows: u32,
    /// Frames dropped because they were too short for an ID and a CRC.
    pub too_short: u32,
    /// Frames dropped for a bad escape sequence (invalid byte after 0x7D, or 0x7D before a flag).
    pub bad_escapes: u32,
    /// Bytes dropped: noise before a flag, and the wire bytes of every dropped frame.
    pub bytes_discarded: u32,
    /// Wire bytes (escapes included, flags excluded) of the frames delivered.
    pub frame_bytes: u32,
    /// Flag bytes seen.
    pub flags: u32,
}

impl Stats {
    /// Frames delivered, with or without CRC.
    ///
    /// ```
    /// use aeolus_proto::Stats;
    /// let stats = Stats { frames_ok: 3, frames_no_crc: 2, ..Stats::default() };
    /// assert_eq!(stats.frames_delivered(), 5);
    /// ```
    pub const fn frames_delivered(&self) -> u32 {
        self.frames_ok.wrapping_add(self.frames_no_crc)
    }

    /// Frames dropped for any reason.
    ///
    /// ```
    /// use aeolus_proto::Stats;
    /// let stats = Stats { checksum_errors: 3, overflows: 1, frames_ok: 9, ..Stats::default() };
    /// assert_eq!(stats.frames_dropped(), 4);
    /// ```
    pub const fn frames_dropped(&self) -> u32 {
        self.checksum_errors
            .wrapping_add(self.missing_crc)
            .wrapping_add(self.overflows)
            .wrapping_add(self.too_short)
            .wrapping_add(self.bad_escapes)
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
enum State {
    /// A new decoder's hunt: the fast path stores what it takes for ordinary bytes (garbage
    /// before the first flag) and `at` counts them (see `Decoder::at`). First, so that a new
    /// decoder is all zeros.
    Fresh,
    /// Dropping bytes until a flag (after the first garbage, and after an error).
    Hunt,
    /// Inside a frame.
    Frame,
    /// Inside a frame, right after an escape byte.
    Escape,
}

/// A byte-at-a-time AEOLUS decoder holding at most `N` unescaped bytes (ID + data + CRC).
///
/// It implements the decoder contract, [`Decode`]: [`Decode::feed`] every slice of the
/// stream (one byte from an ISR queue, a DMA buffer, a datagram: the events are the same),
/// [`Decode::finish`] at its end. Each byte gives at most one event, `Ok(frame)` or
/// `Err(error)`. After any error it resynchronises on the next flag, so an intact frame
/// following garbage is always delivered.
///
/// Decisions (see `docs/protocol-notes.md`):
/// - garbage before the first flag is dropped and counted;
/// - `7E 7E` between frames is an empty frame and is skipped silently;
/// - `7D 7E` aborts the frame ([`Error::EscapedFlag`]) and the flag opens the next one;
/// - `7D` followed by anything but `5D`/`5E` drops the frame at once ([`Error::InvalidEscape`]);
/// - a frame longer than `N` gives [`Error::Overflow`] at the byte that does not fit, then the
///   decoder hunts for the next flag.
///
/// A capacity of [`crate::MAX_FIXED_FRAME`] holds every fixed-size message; use more for long
/// LOG messages.
///
/// Decoding a UART byte stream:
///
/// ```
/// use aeolus_proto::{Decode, Decoder, message::Message};
///
/// // Noise, then a TOAST "hi" frame, as it might arrive from a UART RX queue.
/// let rx = [0x00, 0x13, 0x7E, 0x52, b'h', b'i', 0x00, 0x73, 0xEC, 0x7E];
/// let mut decoder = Decoder::<64>::new();
/// let mut texts = 0;
/// for byte in rx {
///     decoder.feed(&[byte], |event| match event {
///         Ok(frame) => {
///             if let Ok(Message::Toast(text)) = frame.message() {
///                 assert_eq!(text.as_str(), Some("hi"));
///                 texts += 1;
///             }
///         }
///         Err(e) => panic!("unexpected {e}"),
///     });
/// }
/// decoder.finish(|event| panic!("nothing held at the end: {:?}", event.err()));
/// assert_eq!(texts, 1);
/// assert_eq!(decoder.stats().bytes_discarded, 2);
/// ```
#[doc = include_str!("../../PERFORMANCE.md")]
#[derive(Debug, Clone)]
pub struct Decoder<const N: usize> {
    buf: [u8; N],
    /// The fast path's write index. In the `Frame` state it is the number of bytes held; in the
    /// other states it is that number plus [`Self::PARKED`], past the end of `buf`, so that the
    /// fast path's single bounds check also sends every byte of those states to the slow path.
    /// One exception: a new decoder hunts in the `Fresh` state with `at` 0, so that it is all
    /// zeros (a `static` decoder then lives in `.bss`, not in flash); the ordinary bytes the
    /// fast path stores before the first flag or escape are garbage, counted as discarded
    /// when the slow path first sees a byte (the first flag or escape, or the byte past a full
    /// buffer; the slice methods reach it at their first flag), at `reset` and `reset_stats`
    /// (all through `settle`), and by `stats()` before that.
    at: usize,
    /// The CRC run over `buf[..crc_at]` (unescaped bytes of the frame in progress, its two
    /// CRC bytes included once they arrive). The slice path keeps it up to date as it copies;
    /// bytes stored one at a time are caught up later, so `push` pays nothing for it.
    crc: u16,
    crc_at: usize,
    escapes: usize,
    /// The wire length of the last event, both flags included (see [`Decode::span`]): written
    /// once an event, never a byte.
    last: usize,
    state: State,
    strict: bool,
    stats: Stats,
}

impl<const N: usize> Default for Decoder<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> Decoder<N> {
    /// Added to the length outside the `Frame` state (see `at`): never a valid index.
    const PARKED: usize = N + 1;

    /// A decoder that accepts frames without CRC (`00 00`), as the spec allows. Every byte of
    /// it is zero, so a `static` one takes no flash for its buffer.
    ///
    /// ```
    /// let d = aeolus_proto::Decoder::<64>::new();
    /// assert_eq!((d.held_bytes(), d.stats().bytes_discarded), (0, 0));
    /// ```
    pub const fn new() -> Self {
        Decoder {
            buf: [0; N],
            at: 0,
            crc: 0,
            crc_at: 0,
            escapes: 0,
            last: 0,
            state: State::Fresh,
            strict: false,
            stats: STATS0,
        }
    }

    /// A decoder in strict mode: frames without CRC are rejected with [`Error::MissingCrc`].
    ///
    /// ```
    /// use aeolus_proto::{Decode, Decoder, Error};
    /// let mut d = Decoder::<16>::strict();
    /// let mut last = None;
    /// d.feed(&[0x7E, 0x52, b'x', 0x00, 0x00, 0x00, 0x7E], |ev| last = Some(ev.map(|f| f.id())));
    /// assert_eq!(last, Some(Err(Error::MissingCrc { id: 82 })));
    /// ```
    pub const fn strict() -> Self {
        let mut d = Self::new();
        d.strict = true;
        d
    }

    /// Whether frames without CRC are rejected.
    ///
    /// ```
    /// use aeolus_proto::Decoder;
    /// assert!(Decoder::<16>::strict().is_strict());
    /// assert!(!Decoder::<16>::new().is_strict());
    /// ```
    pub const fn is_strict(&self) -> bool {
        self.strict
    }

    /// The counters so far.
    ///
    /// ```
    /// use aeolus_proto::{Decode, Decoder};
    /// let mut decoder = Decoder::<16>::new();
    /// decoder.feed(&[0x7E, 0x52, b'h', b'i', 0, 0x73, 0xEC, 0x7E], |_| {});
    /// assert_eq!(decoder.stats().frames_ok, 1);
    /// ```
    pub const fn stats(&self) -> Stats {
        let mut stats = self.stats;
        stats.bytes_discarded = stats.bytes_discarded.wrapping_add(self.fresh() as u32);
        stats
    }

    /// Zeroes the counters.
    ///
    /// ```
    /// use aeolus_proto::{Decode, Decoder, Stats};
    /// let mut decoder = Decoder::<16>::new();
    /// decoder.feed(&[0x7E, 0x52, b'h', b'i', 0, 0x73, 0xEC, 0x7E], |_| {});
    /// decoder.reset_stats();
    /// assert_eq!(decoder.stats(), Stats::default());
    /// ```
    pub fn reset_stats(&mut self) {
        self.settle();
        self.stats = Stats::default();
    }

    /// The garbage bytes a new decoder's fast path has stored and not yet counted (see `at`).
    #[inline(always)]
    const fn fresh(&self) -> usize {
        match self.state {
            State::Fresh => self.at,
            _ => 0,
        }
    }

    /// Counts the garbage a new decoder's fast path stored (see `at`) as discarded and parks
    /// the write index, as every other hunt has it.
    #[inline(always)]
    fn settle(&mut self) {
        if matches!(self.state, State::Fresh) {
            self.stats.bytes_discarded = self.stats.bytes_discarded.wrapping_add(self.at as u32);
            self.enter(State::Hunt, 0);
        }
    }

    /// Bytes held: the wire bytes of the frame in progress (received, not yet delivered nor
    /// dropped).
    ///
    /// ```
    /// use aeolus_proto::Decode;
    /// let mut d = aeolus_proto::Decoder::<16>::new();
    /// d.feed(&[0x7E, 0x52, 0x7D, 0x5E], |_| {});
    /// assert_eq!(d.held_bytes(), 3);
    /// ```
    pub const fn held_bytes(&self) -> usize {
        match self.state {
            State::Fresh | State::Hunt => 0,
            State::Frame | State::Escape => self.len().wrapping_add(self.escapes),
        }
    }

    /// Unescaped bytes held for the frame in progress.
    #[inline(always)]
    const fn len(&self) -> usize {
        match self.state {
            State::Frame => self.at,
            State::Fresh | State::Hunt | State::Escape => self.at.wrapping_sub(Self::PARKED),
        }
    }

    /// Moves to `state`, holding `len` unescaped bytes.
    #[inline(always)]
    fn enter(&mut self, state: State, len: usize) {
        self.state = state;
        self.at = match state {
            State::Frame => len,
            State::Fresh | State::Hunt | State::Escape => len.wrapping_add(Self::PARKED),
        };
    }

    /// Drops the frame in progress (counting its bytes as discarded) and hunts for a flag.
    ///
    /// ```
    /// use aeolus_proto::{Decode, Decoder};
    /// let mut decoder = Decoder::<16>::new();
    /// decoder.feed(&[0x7E, 0x52, b'h'], |_| {});
    /// decoder.reset();
    /// assert_eq!(decoder.held_bytes(), 0);
    /// assert_eq!(decoder.stats().bytes_discarded, 2);
    /// ```
    pub fn reset(&mut self) {
        self.settle();
        self.drop_frame(0, State::Hunt);
    }

    /// Takes one byte; returns at most one event ([`Decode::feed`]'s path for a one-byte
    /// slice, and the reference its slice path is tested against).
    ///
    /// The common case (an ordinary byte inside a frame that still fits) is a few inlined
    /// instructions; flags, escapes and errors go through an out-of-line slow path.
    #[inline(always)]
    pub(crate) fn push(&mut self, byte: u8) -> Option<Result<Frame<'_>, Error>> {
        // `at` is past the end of `buf` outside the `Frame` state: one bounds check covers both.
        // (Nested rather than a let chain: the crate's MSRV is 1.87.)
        if !SPECIAL[byte as usize] {
            if let Some(slot) = self.buf.get_mut(self.at) {
                *slot = byte;
                self.at += 1;
                return None;
            }
        }
        self.push_slow(byte)
    }

    #[inline(never)]
    fn push_slow(&mut self, byte: u8) -> Option<Result<Frame<'_>, Error>> {
        match self.state {
            State::Frame => {
                if !is_special(byte) {
                    self.store(byte)
                } else if byte == ESCAPE {
                    self.escapes += 1;
                    self.enter(State::Escape, self.at);
                    None
                } else {
                    self.end_frame()
                }
            }
            State::Escape => match byte {
                0x5D | 0x5E => {
                    self.enter(State::Frame, self.len());
                    self.store(byte ^ 0x20)
                }
                FLAG => {
                    self.stats.flags = self.stats.flags.wrapping_add(1);
                    // The opening flag, the bytes held (the escape among them), this flag
                    // (which opens the next frame).
                    self.last = self.held_bytes().wrapping_add(2);
                    self.drop_frame(0, State::Frame);
                    self.stats.bad_escapes = self.stats.bad_escapes.wrapping_add(1);
                    Some(Err(Error::EscapedFlag))
                }
                _ => {
                    self.last = self.held_bytes().wrapping_add(2);
                    self.drop_frame(1, State::Hunt);
                    self.stats.bad_escapes = self.stats.bad_escapes.wrapping_add(1);
                    Some(Err(Error::InvalidEscape))
                }
            },
            State::Fresh | State::Hunt => {
                self.settle();
                if byte == FLAG {
                    self.stats.flags = self.stats.flags.wrapping_add(1);
                    self.enter(State::Frame, 0);
                } else {
                    self.stats.bytes_discarded = self.stats.bytes_discarded.wrapping_add(1);
                }
                None
            }
        }
    }

    /// When hunting for a flag (at the start, and after an error: garbage, an overflow, a
    /// bad escape), discards the bytes before the first flag of `bytes` (all of them when it
    /// has none), counted in one addition, a machine word tested a step ([`find_flag`]);
    /// returns the rest, which starts with the flag. Otherwise returns `bytes` as is. In a
    /// flood of random bytes the decoder hunts for about half of them.
    #[inline(always)]
    fn hunt<'b>(&mut self, bytes: &'b [u8]) -> &'b [u8] {
        if !matches!(self.state, State::Fresh | State::Hunt) {
            return bytes;
        }
        self.skip_to_flag(bytes)
    }

    /// The body of [`Decoder::hunt`]: out of line on 32-bit targets, where inlined into
    /// `feed`'s loop it cost the frame path registers (Cortex-M3, deframing through `feed`:
    /// 12.7 -> 13.5 a byte), inlined on 64-bit hosts, where the call cost more (x86-64 under
    /// callgrind: 13.3 -> 13.8).
    #[cfg_attr(target_pointer_width = "64", inline(always))]
    #[cfg_attr(not(target_pointer_width = "64"), inline(never))]
    fn skip_to_flag<'b>(&mut self, bytes: &'b [u8]) -> &'b [u8] {
        let skip = find_flag(bytes).unwrap_or(bytes.len());
        // The counter wraps, as every counter does: the low 32 bits of the count are exact.
        self.stats.bytes_discarded = self.stats.bytes_discarded.wrapping_add(skip as u32);
        bytes.get(skip..).unwrap_or(&[])
    }

    /// Between two frames (in the `Frame` state with nothing held), takes a leading flag, the
    /// next frame's opening flag, at once; returns the rest.
    #[inline(always)]
    fn open<'b>(&mut self, bytes: &'b [u8]) -> &'b [u8] {
        match bytes.split_first() {
            Some((&FLAG, rest)) if self.at == 0 && self.state == State::Frame => {
                self.stats.flags = self.stats.flags.wrapping_add(1);
                rest
            }
            _ => bytes,
        }
    }

    /// Inside a frame, copies the leading run of ordinary bytes of `bytes` that still fits
    /// and returns the rest; outside a frame returns `bytes` as is.
    ///
    /// On 32-bit targets one pass, four bytes a step: a word is loaded, tested for 0x7D/0x7E,
    /// stored, and run through the CRC. The word holding the first special byte is stored
    /// whole (the bytes from the special on lie past the new length and mean nothing); its
    /// leading ordinary bytes are left for the CRC to catch up with later. Fewer than four
    /// bytes of input or of room are left to the byte-at-a-time step.
    ///
    /// On 64-bit hosts two passes: the run is found a machine word a step, copied with one
    /// `copy_from_slice`, and the CRC left to catch up over the whole frame at its closing
    /// flag (`end_frame`). Under callgrind on x86-64 that is 0.75 instructions a byte fewer
    /// than the fused loop (full decode through `feed` 15.4 -> 14.65): the host's `memcpy`
    /// copies faster than eight-byte stores interleaved with the CRC, which Cortex-M3 has no
    /// use for (there the fused loop was measured 12.7 against 16.2 for two passes).
    #[inline(always)]
    fn copy_run<'b>(&mut self, bytes: &'b [u8]) -> &'b [u8] {
        if self.state != State::Frame {
            return bytes;
        }
        let at = self.at;
        let Some((held, room)) = self.buf.split_at_mut_checked(at) else {
            return bytes;
        };
        #[cfg(target_pointer_width = "64")]
        let run = {
            let _ = held;
            let run = ordinary_run(bytes.get(..room.len()).unwrap_or(bytes));
            if let (Some(d), Some(s)) = (room.get_mut(..run), bytes.get(..run)) {
                d.copy_from_slice(s);
            }
            run
        };
        #[cfg(not(target_pointer_width = "64"))]
        let run = {
            let mut c = self.crc;
            if self.crc_at != at {
                c = crc::update_slice(c, held.get(self.crc_at..).unwrap_or(&[]));
            }
            let mut c = (c as u32) << 16;
            let mut src = bytes;
            let mut dst = room;
            let mut covered = 0;
            let mut run = 0;
            // Slice patterns rather than `chunks_exact().zip()`: at opt-level "s" they compile
            // to a plain pointer loop with no bounds checks. Four bytes a step (the
            // machine-word form of the same loop compiles worse here: 13.2 against 12.7 on
            // Cortex-M3).
            while let (Some((s, s_rest)), Some((d, d_rest))) = (
                src.split_first_chunk::<4>(),
                core::mem::take(&mut dst).split_first_chunk_mut::<4>(),
            ) {
                *d = *s;
                let w = u32::from_le_bytes(*s);
                let hits = special_bytes(w);
                if hits != 0 {
                    run = covered + (hits.trailing_zeros() / 8) as usize;
                    break;
                }
                c = crc::update_word(c, w.swap_bytes());
                covered += 4;
                run = covered;
                src = s_rest;
                dst = d_rest;
            }
            self.crc = (c >> 16) as u16;
            self.crc_at = at + covered;
            run
        };
        self.at = at + run;
        bytes.get(run..).unwrap_or(&[])
    }

    /// Takes `bytes` up to and including the first byte that gives an event, with the slice
    /// path of [`Decode::feed`]. Returns how many bytes were consumed and what the
    /// last of them gave, as a [`Found`] that does not borrow the decoder: a reader keeps
    /// looping over reads and asks for the frame ([`Decoder::found_frame`]) afterwards.
    pub(crate) fn push_until(&mut self, bytes: &[u8]) -> (usize, Found) {
        let total = bytes.len();
        // An error ends the call, so a hunt after it starts at the next call.
        let mut rest = self.hunt(bytes);
        rest = self.open(rest);
        loop {
            rest = self.copy_run(rest);
            let Some((&b, after)) = rest.split_first() else {
                return (total, Found::Nothing);
            };
            rest = after;
            let found = match self.push_slow(b) {
                None => continue,
                Some(Ok(frame)) => Found::Frame {
                    len: frame.raw().len(),
                    has_crc: frame.has_crc(),
                },
                Some(Err(e)) => Found::Error(e),
            };
            return (total.saturating_sub(rest.len()), found);
        }
    }

    /// The frame a [`Found::Frame`] from the last [`Decoder::push_until`] stands for: it is
    /// still in the buffer until the next byte is pushed.
    pub(crate) fn found_frame(&self, len: usize, has_crc: bool) -> Frame<'_> {
        Frame::checked(self.buf.get(..len).unwrap_or(&[]), has_crc)
    }

    /// Stores an unescaped byte; only in the `Frame` state (where `at` is the length).
    #[inline(always)]
    fn store(&mut self, byte: u8) -> Option<Result<Frame<'_>, Error>> {
        if let Some(slot) = self.buf.get_mut(self.at) {
            *slot = byte;
            self.at += 1;
            None
        } else {
            // The opening flag, the bytes held, the byte that did not fit.
            self.last = self.held_bytes().wrapping_add(2);
            self.drop_frame(1, State::Hunt);
            self.stats.overflows = self.stats.overflows.wrapping_add(1);
            Some(Err(Error::Overflow))
        }
    }

    /// Counts the frame in progress (plus `extra` bytes) as discarded, empties the buffer and
    /// moves to `next`.
    fn drop_frame(&mut self, extra: usize, next: State) {
        let wire = self.held_bytes().wrapping_add(extra);
        self.stats.bytes_discarded = self.stats.bytes_discarded.wrapping_add(wire as u32);
        self.escapes = 0;
        self.crc = 0;
        self.crc_at = 0;
        self.enter(next, 0);
    }

    fn end_frame(&mut self) -> Option<Result<Frame<'_>, Error>> {
        let stats = &mut self.stats;
        stats.flags = stats.flags.wrapping_add(1);
        // Only reached in the `Frame` state, where `at` is the length; the state stays `Frame`.
        let len = core::mem::take(&mut self.at);
        let wire = (len + core::mem::take(&mut self.escapes)) as u32;
        if len == 0 {
            return None;
        }
        self.last = (wire as usize).wrapping_add(2);
        let raw = self.buf.get(..len).unwrap_or(&[]);
        // The running CRC, caught up over the bytes stored since it last advanced.
        let rest = raw.get(core::mem::take(&mut self.crc_at)..).unwrap_or(&[]);
        let all = crc::update_slice(core::mem::take(&mut self.crc), rest);
        let result = Frame::checked_running(raw, self.strict, all);
        let counter = match result {
            Ok(frame) if frame.has_crc() => &mut stats.frames_ok,
            Ok(_) => &mut stats.frames_no_crc,
            Err(Error::ChecksumMismatch { .. }) => &mut stats.checksum_errors,
            Err(Error::MissingCrc { .. }) => &mut stats.missing_crc,
            Err(_) => &mut stats.too_short,
        };
        *counter = counter.wrapping_add(1);
        if result.is_ok() {
            stats.frame_bytes = stats.frame_bytes.wrapping_add(wire);
        } else {
            stats.bytes_discarded = stats.bytes_discarded.wrapping_add(wire);
        }
        Some(result)
    }
}

/// How many leading bytes of `bytes` are ordinary (neither flag nor escape), a machine word a
/// step; a tail shorter than a word is left to the byte-at-a-time step.
#[cfg(target_pointer_width = "64")]
#[inline(always)]
fn ordinary_run(bytes: &[u8]) -> usize {
    let mut run = 0;
    let mut rest = bytes;
    while let Some((w, tail)) = rest.split_first_chunk::<WORD>() {
        let hits = special_in_word(usize::from_le_bytes(*w));
        if hits != 0 {
            return run + (hits.trailing_zeros() / 8) as usize;
        }
        run += WORD;
        rest = tail;
    }
    run
}

const STATS0: Stats = Stats {
    frames_ok: 0,
    frames_no_crc: 0,
    checksum_errors: 0,
    missing_crc: 0,
    overflows: 0,
    too_short: 0,
    bad_escapes: 0,
    bytes_discarded: 0,
    frame_bytes: 0,
    flags: 0,
};

/// **The decoder contract** of `frame-io` ([`Decode`]): the one loop is [`Decode::feed`] for
/// every slice of the stream (one byte included) and [`Decode::finish`] at its end; the events
/// are `Ok(`[`Frame`]`)`, borrowing the decoder until the next call, or `Err(`[`Error`]`)`.
/// `finish` drops a frame still in progress, counts its bytes as discarded and reports it as
/// [`Error::Truncated`]; between frames it reports nothing.
///
/// The pull form: [`Decode::decode`] takes a slice up to the first event (a found frame is
/// `(length, has_crc)` in the decoder's buffer, [`Decode::item`] its [`Frame`]), for a
/// caller that acts between two frames.
///
/// ```
/// use aeolus_proto::{Decode, Decoder, Error, Event, Place};
/// let mut d = Decoder::<64>::new();
/// let mut events = Vec::new();
/// d.feed(&[0x7E, 0x52, b'h', b'i', 0x00, 0x73, 0xEC, 0x7E, 0x52], |ev| events.push(ev.map(|f| f.id())));
/// d.finish(|ev| events.push(ev.map(|f| f.id())));
/// assert_eq!(events, [Ok(0x52), Err(Error::Truncated)]);
///
/// // The same frame through the pull form: 8 bytes used, 6 unescaped (ID, data, CRC).
/// let (used, event) = d.decode(&[0x7E, 0x52, b'h', b'i', 0x00, 0x73, 0xEC, 0x7E, 0x52]);
/// assert_eq!((used, event), (8, Some(Event::Found((6, true)))));
/// assert_eq!(d.item(&[], (6, true)).id(), 0x52);
/// assert_eq!(d.decode(&[0x52]), (1, None));
/// assert_eq!(d.end(), Some(Event::Truncated(1)));
/// assert_eq!(d.end(), None);
///
/// // Through a `Stream`, each event with its place: the frame with both its flags (8 bytes
/// // from 0), then the frame cut short (its flag, shared, and one byte).
/// let mut stream = aeolus_proto::Stream::new(Decoder::<64>::new());
/// let mut places = Vec::new();
/// stream.feed(&[0x7E, 0x52, b'h', b'i', 0x00, 0x73, 0xEC, 0x7E, 0x52], |place, _| places.push(place));
/// stream.finish(|place, _| places.push(place));
/// assert_eq!(places, [Place { offset: 0, len: 8 }, Place { offset: 7, len: 2 }]);
/// ```
impl<const N: usize> Decode for Decoder<N> {
    type Error = Error;
    type Found = (usize, bool);
    type Item<'a> = Frame<'a>;
    const TRUNCATED: Error = Error::Truncated;

    /// Runs of ordinary bytes inside a frame are copied in bulk (a machine word tested a
    /// step), garbage is skipped a word at a time; a one-byte slice takes the per-byte path.
    #[inline]
    fn feed<F>(&mut self, bytes: &[u8], mut on_event: F)
    where
        F: FnMut(Result<Frame<'_>, Error>),
    {
        if let [byte] = bytes {
            // One byte (an ISR, a byte-at-a-time reader): the inlined per-byte path.
            if let Some(event) = self.push(*byte) {
                on_event(event);
            }
            return;
        }
        let mut bytes = self.hunt(bytes);
        loop {
            bytes = self.copy_run(bytes);
            let Some((&b, rest)) = bytes.split_first() else {
                return;
            };
            bytes = rest;
            if let Some(ev) = self.push_slow(b) {
                on_event(ev);
                // Only an error leaves the decoder hunting.
                bytes = self.hunt(bytes);
                bytes = self.open(bytes);
            }
        }
    }

    #[inline]
    fn decode(&mut self, bytes: &[u8]) -> (usize, Option<Event<(usize, bool), Error>>) {
        match bytes {
            [] => return (0, None),
            // One byte (a caller that acts after every byte): the inlined per-byte path.
            [byte] => {
                let event = self.push(*byte).map(|event| match event {
                    Ok(frame) => Event::Found((frame.raw().len(), frame.has_crc())),
                    Err(e) => Event::Error(e),
                });
                return (1, event);
            }
            _ => {}
        }
        let (used, found) = self.push_until(bytes);
        let event = match found {
            Found::Nothing => None,
            Found::Frame { len, has_crc } => Some(Event::Found((len, has_crc))),
            Found::Error(e) => Some(Event::Error(e)),
        };
        (used, event)
    }

    fn end(&mut self) -> Option<Event<(usize, bool), Error>> {
        let pending = self.held_bytes();
        if pending == 0 {
            return None;
        }
        // The opening flag and the bytes held.
        self.last = pending.wrapping_add(1);
        self.reset();
        Some(Event::Truncated(pending))
    }

    #[inline]
    fn item<'a>(&'a self, _input: &'a [u8], (len, has_crc): (usize, bool)) -> Frame<'a> {
        self.found_frame(len, has_crc)
    }

    /// Every event's bytes run from a frame's opening flag to the byte that ended it: its
    /// closing flag (a frame, a bad CRC, a frame too short, `7D 7E`), the byte that did not fit
    /// (an overflow), the byte after `7D` (a bad escape), or the last byte held (the end of
    /// the stream). Nothing used after it is held (`after` 0). Two frames that share a flag
    /// share that byte.
    #[inline]
    fn span(&self) -> Span {
        Span {
            len: self.last,
            after: 0,
        }
    }
}

/// What [`Decoder::push_until`] stopped at.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Found {
    /// Every byte was consumed without an event.
    Nothing,
    /// A frame of `len` unescaped bytes is in the buffer.
    Frame { len: usize, has_crc: bool },
    /// A frame was dropped for this error.
    Error(Error),
}
