//! The stream decoder: bytes in, typed messages or errors out.
//!
//! It is AEOLUS's [`Decoder`] (GDL90 framing is identical: 0x7E flags, 0x7D escapes, the
//! same CRC sent LSB first) plus two GDL90 rules: a frame whose CRC field is `00 00` is
//! checked like any other (AEOLUS alone reads `00 00` as "no CRC"), and every good frame is
//! parsed into a [`Message`] before it is handed over.

use aeolus_proto::{Decode, Decoder as Framing, Event, Frame, Span};

use crate::message::Message;
use crate::{ESCAPE, Error, FLAG};

/// Counters kept by a [`Decoder`], MAVLink style. They wrap on overflow.
///
/// Every byte pushed ends up in exactly one of `bytes_discarded`, `frame_bytes` or `flags`,
/// or is still held by the decoder ([`Decoder::held_bytes`]). Each counted frame was
/// also reported as exactly one event.
///
/// ```
/// use gdl90_proto::{Decode, Decoder};
/// let mut decoder = Decoder::<64>::new();
/// // The ICD's heartbeat, then a geometric altitude frame with a corrupted CRC.
/// decoder.feed(&[0x7E, 0x00, 0x81, 0x41, 0xDB, 0xD0, 0x08, 0x02, 0xB3, 0x8B, 0x7E], |_| {});
/// decoder.feed(&[0x0B, 0x01, 0x2C, 0x00, 0x0A, 0x12, 0x34, 0x7E], |_| {});
/// let stats = decoder.stats();
/// assert_eq!((stats.frames_ok, stats.checksum_errors), (1, 1));
/// assert_eq!((stats.frame_bytes, stats.bytes_discarded, stats.flags), (9, 7, 3));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Stats {
    /// Frames with a good CRC delivered as a [`Message`] (raw ones included).
    pub frames_ok: u32,
    /// Frames with a good CRC whose typed parse failed ([`Error::WrongLength`],
    /// [`Error::OutOfRange`]).
    pub invalid: u32,
    /// Frames dropped for a CRC mismatch (a received `00 00` included).
    pub checksum_errors: u32,
    /// Frames dropped because they outgrew the capacity.
    pub overflows: u32,
    /// Frames dropped because they were too short for an ID and a CRC.
    pub too_short: u32,
    /// Frames dropped for a bad escape sequence (invalid byte after 0x7D, or 0x7D before a
    /// flag).
    pub bad_escapes: u32,
    /// Bytes dropped: noise before a flag, and the wire bytes of every dropped frame.
    pub bytes_discarded: u32,
    /// Wire bytes (escapes included, flags excluded) of the frames with a good CRC.
    pub frame_bytes: u32,
    /// Flag bytes seen.
    pub flags: u32,
}

/// What the decoder counts beyond the AEOLUS decoder's own counters.
#[derive(Debug, Clone, Copy, Default)]
struct Extra {
    /// Good-CRC frames whose typed parse failed.
    invalid: u32,
    /// Wire bytes of the `00 00` frames the AEOLUS decoder delivered unchecked and this
    /// decoder rejected: the AEOLUS decoder counted them as frame bytes.
    zero_crc_bytes: u32,
}

/// A byte-at-a-time GDL90 decoder holding at most `N` unescaped bytes per frame (ID, data,
/// CRC).
///
/// It implements the decoder contract, [`Decode`]: [`Decode::feed`] every slice of the
/// stream (one byte, a datagram, a file), [`Decode::finish`] at its end; each event is
/// `Ok(message)` or `Err(error)`, at most one per byte. After any error it resynchronises on the next flag, so an intact frame
/// after garbage or after a bad CRC is always delivered. Unlike AEOLUS, GDL90 has no "CRC
/// `00 00` means no CRC" rule: such a frame is checked like any other. A capacity of
/// [`crate::TYPED_FRAME`] receives every typed message; [`crate::MAX_FRAME`] receives every
/// ICD message (the UAT uplink is the longest).
///
/// ```
/// use gdl90_proto::{Decode, Decoder, message::Message};
///
/// // Noise, then the ICD's heartbeat example, one byte at a time.
/// let rx = [0x13, 0x37, 0x7E, 0x00, 0x81, 0x41, 0xDB, 0xD0, 0x08, 0x02, 0xB3, 0x8B, 0x7E];
/// let mut decoder = Decoder::<{ gdl90_proto::TYPED_FRAME }>::new();
/// let mut seconds = None;
/// for byte in rx {
///     decoder.feed(&[byte], |event| match event {
///         Ok(Message::Heartbeat(hb)) => seconds = Some(hb.seconds_since_midnight),
///         Ok(other) => println!("{}", other.name()),
///         Err(e) => println!("error: {e}"),
///     });
/// }
/// decoder.finish(|event| println!("cut short: {:?}", event.err()));
/// assert_eq!(seconds, Some(53467));
/// assert_eq!(decoder.stats().bytes_discarded, 2);
/// ```
#[derive(Debug, Clone)]
pub struct Decoder<const N: usize> {
    framing: Framing<N>,
    extra: Extra,
}

impl<const N: usize> Default for Decoder<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> Decoder<N> {
    /// An empty decoder, waiting for a flag.
    ///
    /// ```
    /// use gdl90_proto::{Decoder, Stats};
    /// let decoder = Decoder::<{ gdl90_proto::TYPED_FRAME }>::new();
    /// assert_eq!((decoder.held_bytes(), decoder.stats()), (0, Stats::default()));
    /// ```
    pub const fn new() -> Self {
        Decoder {
            // Lenient mode, so that a `00 00` frame reaches `accept` whole and its real CRC
            // can be reported; `accept` rejects it.
            framing: Framing::new(),
            extra: Extra {
                invalid: 0,
                zero_crc_bytes: 0,
            },
        }
    }

    /// The counters so far.
    ///
    /// ```
    /// use gdl90_proto::{Decode, Decoder};
    /// let mut d = Decoder::<64>::new();
    /// d.feed(&[0x7E, 0x00, 0x81, 0x41, 0xDB, 0xD0, 0x08, 0x02, 0xB3, 0x8B, 0x7E], |_| {});
    /// assert_eq!((d.stats().frames_ok, d.stats().frame_bytes, d.stats().flags), (1, 9, 2));
    /// ```
    pub fn stats(&self) -> Stats {
        let s = self.framing.stats();
        let zero = self.extra.zero_crc_bytes;
        Stats {
            frames_ok: s.frames_ok.wrapping_sub(self.extra.invalid),
            invalid: self.extra.invalid,
            // Every frame the lenient AEOLUS decoder delivered without CRC was rejected here.
            checksum_errors: s.checksum_errors.wrapping_add(s.frames_no_crc),
            overflows: s.overflows,
            too_short: s.too_short,
            bad_escapes: s.bad_escapes,
            bytes_discarded: s.bytes_discarded.wrapping_add(zero),
            frame_bytes: s.frame_bytes.wrapping_sub(zero),
            flags: s.flags,
        }
    }

    /// Zeroes the counters.
    ///
    /// ```
    /// use gdl90_proto::{Decode, Decoder, Stats};
    /// let mut decoder = Decoder::<64>::new();
    /// decoder.feed(&[0x7E, 0x00, 0x81, 0x41, 0xDB, 0xD0, 0x08, 0x02, 0xB3, 0x8B, 0x7E], |_| {});
    /// decoder.reset_stats();
    /// assert_eq!(decoder.stats(), Stats::default());
    /// ```
    pub fn reset_stats(&mut self) {
        self.framing.reset_stats();
        self.extra = Extra::default();
    }

    /// Drops the frame in progress (counting its bytes as discarded) and waits for a flag.
    ///
    /// ```
    /// use gdl90_proto::{Decode, Decoder};
    /// let mut decoder = Decoder::<64>::new();
    /// decoder.feed(&[0x7E, 0x00, 0x81, 0x41], |_| {});
    /// decoder.reset();
    /// assert_eq!(decoder.held_bytes(), 0);
    /// assert_eq!(decoder.stats().bytes_discarded, 3);
    /// ```
    pub fn reset(&mut self) {
        self.framing.reset();
    }

    /// Bytes held: the wire bytes of the frame in progress (received, not yet delivered nor
    /// dropped).
    ///
    /// ```
    /// use gdl90_proto::Decode;
    /// let mut d = gdl90_proto::Decoder::<16>::new();
    /// d.feed(&[0x7E, 0x00, 0x81], |_| {});
    /// assert_eq!(d.held_bytes(), 2);
    /// ```
    pub const fn held_bytes(&self) -> usize {
        self.framing.held_bytes()
    }
}

/// **The decoder contract** of `frame-io` ([`Decode`]): [`Decode::feed`] every slice,
/// [`Decode::finish`] at the end of the stream; the events are `Ok(`[`Message`]`)`,
/// borrowing the decoder during the call, or `Err(`[`Error`]`)`. `finish` drops a frame still
/// in progress, counts its bytes as discarded and reports [`Error::Truncated`]; between
/// frames it reports nothing. The pull form ([`Decode::decode`]) checks and counts a frame
/// when it finds it; [`Decode::item`] parses it (a second time: `feed` parses once).
///
/// ```
/// use gdl90_proto::{Decode, Decoder, Error};
/// // A heartbeat whose CRC field was zeroed (GDL90 has no "no CRC" code), then half a frame.
/// let mut d = Decoder::<64>::new();
/// let mut events = Vec::new();
/// let wire = [0x7E, 0x00, 0x81, 0x41, 0xDB, 0xD0, 0x08, 0x02, 0x00, 0x00, 0x7E, 0x00, 0x81];
/// d.feed(&wire, |ev| events.push(ev.map(|m| m.id())));
/// d.finish(|ev| events.push(ev.map(|m| m.id())));
/// assert_eq!(
///     events,
///     [Err(Error::ChecksumMismatch { id: 0, computed: 0x8BB3, received: 0 }), Err(Error::Truncated)]
/// );
/// assert_eq!(d.stats().bytes_discarded, 11);
///
/// // Each event with its place: the rejected frame with both flags, the frame cut short
/// // (its flag, shared, and two bytes).
/// let mut stream = gdl90_proto::Stream::new(Decoder::<64>::new());
/// let mut places = Vec::new();
/// stream.feed(&wire, |place, _| places.push((place.offset, place.len)));
/// stream.finish(|place, _| places.push((place.offset, place.len)));
/// assert_eq!(places, [(0, 11), (10, 3)]);
/// ```
impl<const N: usize> Decode for Decoder<N> {
    type Error = Error;
    type Found = (usize, bool);
    type Item<'a> = Message<'a>;
    const TRUNCATED: Error = Error::Truncated;

    #[inline]
    fn feed<F>(&mut self, bytes: &[u8], mut on_event: F)
    where
        F: FnMut(Result<Message<'_>, Error>),
    {
        let extra = &mut self.extra;
        self.framing
            .feed(bytes, |event| on_event(accept(extra, event)));
    }

    fn decode(&mut self, bytes: &[u8]) -> (usize, Option<Event<(usize, bool), Error>>) {
        let (used, event) = self.framing.decode(bytes);
        let event = match event {
            Some(Event::Found(found)) => {
                let frame = self.framing.item(&[], found);
                match accept(&mut self.extra, Ok(frame)) {
                    Ok(_) => Some(Event::Found(found)),
                    Err(e) => Some(Event::Error(e)),
                }
            }
            Some(Event::Error(e)) => Some(Event::Error(Error::from_framing(e))),
            Some(Event::Truncated(n)) => Some(Event::Truncated(n)),
            None => None,
        };
        (used, event)
    }

    fn end(&mut self) -> Option<Event<(usize, bool), Error>> {
        match self.framing.end()? {
            Event::Truncated(n) => Some(Event::Truncated(n)),
            Event::Error(e) => Some(Event::Error(Error::from_framing(e))),
            // The framing's end gives up frames, it finds none.
            Event::Found(found) => Some(Event::Found(found)),
        }
    }

    fn item<'a>(&'a self, _input: &'a [u8], found: (usize, bool)) -> Message<'a> {
        let frame = self.framing.item(&[], found);
        // `decode` parsed this frame already and found it good, so this parse succeeds too.
        Message::parse(frame.id(), frame.data()).unwrap_or(Message::Unknown {
            id: frame.id(),
            data: frame.data(),
        })
    }

    /// The framing's: every event's bytes run from a frame's opening flag to the byte that
    /// ended it (its closing flag, the byte that did not fit, the byte after `7D`, or the last
    /// byte held at the end of the stream); nothing used after it is held.
    #[inline]
    fn span(&self) -> Span {
        self.framing.span()
    }
}

/// Turns one event of the AEOLUS decoder into a GDL90 event, counting what it cannot.
fn accept<'a>(
    extra: &mut Extra,
    event: Result<Frame<'a>, aeolus_proto::Error>,
) -> Result<Message<'a>, Error> {
    let frame = event.map_err(Error::from_framing)?;
    if !frame.has_crc() {
        // The lenient AEOLUS decoder passes `00 00` unchecked; a real CRC of 0 would have been
        // recognised as checked, so this CRC is wrong.
        let raw = frame.raw();
        let body = raw.get(..raw.len().saturating_sub(2)).unwrap_or(&[]);
        let escapes = raw.iter().filter(|&&b| b == FLAG || b == ESCAPE).count();
        let wire = raw.len().wrapping_add(escapes) as u32;
        extra.zero_crc_bytes = extra.zero_crc_bytes.wrapping_add(wire);
        return Err(Error::ChecksumMismatch {
            id: frame.id(),
            computed: aeolus_proto::crc::checksum(body),
            received: 0,
        });
    }
    Message::parse(frame.id(), frame.data()).inspect_err(|_| {
        extra.invalid = extra.invalid.wrapping_add(1);
    })
}
