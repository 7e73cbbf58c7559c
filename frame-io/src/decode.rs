//! The decoder trait the readers are generic over, and what a decoder reports.

use crate::Span;

/// What a decoder reports to a reader: an item found, a protocol error, or the end of the
/// stream inside a frame.
///
/// ```
/// use frame_io::Event;
/// let found: Event<usize, ()> = Event::Found(5);
/// assert_ne!(found, Event::Truncated(5));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Event<F, P> {
    /// An item, as [`Decode::Found`]: where it is (a length, an offset), or the item itself
    /// when it borrows nothing. The reader turns it into [`Decode::Item`] with
    /// [`Decode::item`].
    Found(F),
    /// The protocol's error (a bad checksum, an overflow, ...); the decoder has resynchronised.
    Error(P),
    /// The stream ended inside a frame: `pending` bytes of it were given up.
    Truncated(usize),
}

/// **The decoder contract**: what every decoder of this workspace implements, and the one
/// loop a user writes with it.
///
/// ```text
/// decoder.feed(bytes, |event| ...)   // every slice of the stream, of any length (one byte too)
/// decoder.finish(|event| ...)        // the stream ended (a file, a datagram, a quiet line)
/// ```
///
/// Each `event` is `Ok(item)` (a frame, a message or a command) or `Err(error)` (the decoder
/// has resynchronised and goes on). The events depend only on the bytes, never on how they
/// were cut into slices: feeding a stream whole, byte by byte or in any other pieces gives
/// the same events in the same order (every crate property-tests and fuzzes this). After
/// `finish` the decoder starts afresh, as if new.
///
/// A caller that must act between two events (the firmware checks its TX room before it reads
/// on; the C library returns one event per call) uses the **pull form** instead:
/// [`Decode::next_event`] decodes a slice up to and including the byte that gives the first
/// event and returns how many bytes it used and the event; called again on the rest (and
/// once with an empty slice, for events a rescan left queued), it gives the events of `feed`.
///
/// An implementation writes three methods, on which all of the above is built (the readers of
/// this crate use them directly, to return one item per call without holding a borrow):
///
/// - [`Decode::decode`]: like `next_event`, but the event is an [`Event`] whose
///   [`Event::Found`] says where the item is rather than borrowing it;
/// - [`Decode::end`]: the events of the end of the stream, one a call, until `None`;
/// - [`Decode::item`]: the item an [`Event::Found`] stands for (it may borrow the decoder or
///   the slice given to `decode`).
///
/// A decoder may override `feed` with a faster loop that gives the same events.
///
/// ```
/// use frame_io::{Decode, Event, Span, Stream};
///
/// /// Lines of up to 8 bytes, each ended by `\n`; a longer line is an error.
/// struct Lines {
///     buf: [u8; 8],
///     len: usize,
///     /// The wire length of the last event.
///     last: usize,
/// }
///
/// impl Decode for Lines {
///     type Error = &'static str;
///     type Found = usize;
///     type Item<'a> = &'a [u8];
///     const TRUNCATED: &'static str = "line cut short";
///
///     fn decode(&mut self, bytes: &[u8]) -> (usize, Option<Event<usize, &'static str>>) {
///         for (i, &b) in bytes.iter().enumerate() {
///             if b == b'\n' {
///                 self.last = self.len + 1;
///                 return (i + 1, Some(Event::Found(core::mem::take(&mut self.len))));
///             }
///             let Some(slot) = self.buf.get_mut(self.len) else {
///                 self.last = core::mem::take(&mut self.len) + 1;
///                 return (i + 1, Some(Event::Error("line too long")));
///             };
///             *slot = b;
///             self.len += 1;
///         }
///         (bytes.len(), None)
///     }
///
///     fn end(&mut self) -> Option<Event<usize, &'static str>> {
///         let pending = core::mem::take(&mut self.len);
///         self.last = pending;
///         (pending > 0).then_some(Event::Truncated(pending))
///     }
///
///     fn item<'a>(&'a self, _input: &'a [u8], len: usize) -> &'a [u8] {
///         self.buf.get(..len).unwrap_or(&[])
///     }
///
///     fn span(&self) -> Span {
///         // The line and its `\n`, the nine bytes of a line too long, or what was pending at
///         // the end of the stream; nothing is held after an event.
///         Span { len: self.last, after: 0 }
///     }
/// }
///
/// // The one loop: any slices, then the end of the stream.
/// let mut lines = Lines { buf: [0; 8], len: 0, last: 0 };
/// let mut seen = Vec::new();
/// for piece in [&b"hi\nth"[..], b"ere\n", b"1234567890\n", b"tail"] {
///     lines.feed(piece, |event| seen.push(event.map(|line| line.to_vec())));
/// }
/// lines.finish(|event| seen.push(event.map(|line| line.to_vec())));
/// assert_eq!(
///     seen,
///     [Ok(b"hi".to_vec()), Ok(b"there".to_vec()), Err("line too long"), Ok(b"0".to_vec()), Err("line cut short")]
/// );
///
/// // The pull form underneath.
/// assert_eq!(lines.decode(b"hi\nthere"), (3, Some(Event::Found(2))));
/// assert_eq!(lines.span(), Span { len: 3, after: 0 });
/// assert_eq!(lines.decode(b"there"), (5, None));
/// assert_eq!(lines.end(), Some(Event::Truncated(5)));
/// assert_eq!(lines.end(), None);
///
/// // Through a `Stream`: every event with its place (offset, length on the wire).
/// let mut stream = Stream::new(lines);
/// let mut places = Vec::new();
/// for piece in [&b"hi\nth"[..], b"ere\n", b"1234567890\n", b"tail"] {
///     stream.feed(piece, |place, _| places.push((place.offset, place.len)));
/// }
/// stream.finish(|place, _| places.push((place.offset, place.len)));
/// assert_eq!(places, [(0, 3), (3, 6), (9, 9), (18, 2), (20, 4)]);
/// ```
pub trait Decode {
    /// The protocol's error.
    type Error;
    /// What [`Event::Found`] carries: where the item is, without borrowing anything (a
    /// length, an offset), or the item itself when it is a small `Copy` value.
    type Found;
    /// What the reader returns for an item: it may borrow the decoder or the read buffer.
    type Item<'a>
    where
        Self: 'a;
    /// The error [`Decode::finish`] reports for an [`Event::Truncated`]: the stream ended
    /// inside a frame (each protocol crate's `Error::Truncated`).
    const TRUNCATED: Self::Error;

    /// Decodes `bytes` up to the first event: returns how many of them were used and the
    /// event, if any (`None`: every byte was used and nothing was found). Events left queued
    /// by an earlier call come first, with no byte used.
    ///
    /// ```
    /// # struct Bytes; impl frame_io::Decode for Bytes { type Error = u8; type Found = u8; type Item<'a> = u8; const TRUNCATED: u8 = 0;
    /// # fn decode(&mut self, b: &[u8]) -> (usize, Option<frame_io::Event<u8, u8>>) { match b.first() { Some(&0) => (1, Some(frame_io::Event::Error(0))), Some(&x) => (1, Some(frame_io::Event::Found(x))), None => (0, None) } }
    /// # fn end(&mut self) -> Option<frame_io::Event<u8, u8>> { None }
    /// # fn item(&self, _: &[u8], x: u8) -> u8 { x }
    /// # fn span(&self) -> frame_io::Span { frame_io::Span { len: 1, after: 0 } } }
    /// use frame_io::{Decode, Event};
    /// // `Bytes`: every non-zero byte is an item, a zero byte an error.
    /// assert_eq!(Bytes.decode(&[7, 8]), (1, Some(Event::Found(7))));
    /// assert_eq!(Bytes.decode(&[]), (0, None));
    /// ```
    #[allow(clippy::type_complexity)] // spelt out: it is what an implementation writes
    fn decode(&mut self, bytes: &[u8]) -> (usize, Option<Event<Self::Found, Self::Error>>);

    /// The stream ended: the next event of the end of the stream (a frame cut short as
    /// [`Event::Truncated`], then what a protocol that rescans finds in the bytes after it),
    /// or `None` once there is none; call it until `None`, after which the decoder is as new.
    ///
    /// ```
    /// # struct Bytes; impl frame_io::Decode for Bytes { type Error = u8; type Found = u8; type Item<'a> = u8; const TRUNCATED: u8 = 0;
    /// # fn decode(&mut self, b: &[u8]) -> (usize, Option<frame_io::Event<u8, u8>>) { match b.first() { Some(&0) => (1, Some(frame_io::Event::Error(0))), Some(&x) => (1, Some(frame_io::Event::Found(x))), None => (0, None) } }
    /// # fn end(&mut self) -> Option<frame_io::Event<u8, u8>> { None }
    /// # fn item(&self, _: &[u8], x: u8) -> u8 { x }
    /// # fn span(&self) -> frame_io::Span { frame_io::Span { len: 1, after: 0 } } }
    /// use frame_io::Decode;
    /// // `Bytes` holds nothing between calls: the end of the stream finds nothing.
    /// assert_eq!(Bytes.end(), None);
    /// ```
    fn end(&mut self) -> Option<Event<Self::Found, Self::Error>>;

    /// The item that `found` stands for. `input` is the slice given to the
    /// [`Decode::decode`] call that reported it (empty for an event of [`Decode::end`]), so
    /// an item found in place in the read buffer can borrow it.
    ///
    /// ```
    /// # struct Bytes; impl frame_io::Decode for Bytes { type Error = u8; type Found = u8; type Item<'a> = u8; const TRUNCATED: u8 = 0;
    /// # fn decode(&mut self, b: &[u8]) -> (usize, Option<frame_io::Event<u8, u8>>) { match b.first() { Some(&0) => (1, Some(frame_io::Event::Error(0))), Some(&x) => (1, Some(frame_io::Event::Found(x))), None => (0, None) } }
    /// # fn end(&mut self) -> Option<frame_io::Event<u8, u8>> { None }
    /// # fn item(&self, _: &[u8], x: u8) -> u8 { x }
    /// # fn span(&self) -> frame_io::Span { frame_io::Span { len: 1, after: 0 } } }
    /// use frame_io::Decode;
    /// assert_eq!(Bytes.item(&[7, 8], 7), 7);
    /// ```
    fn item<'a>(&'a self, input: &'a [u8], found: Self::Found) -> Self::Item<'a>;

    /// Where the event that the last [`Decode::decode`] or [`Decode::end`] call returned lies
    /// (see [`Span`]): its length on the wire and the bytes used after it. Read it before the
    /// next call; [`crate::Stream`] does, to give every event its [`crate::Place`].
    ///
    /// ```
    /// # struct Bytes; impl frame_io::Decode for Bytes { type Error = u8; type Found = u8; type Item<'a> = u8; const TRUNCATED: u8 = 0;
    /// # fn decode(&mut self, b: &[u8]) -> (usize, Option<frame_io::Event<u8, u8>>) { match b.first() { Some(&0) => (1, Some(frame_io::Event::Error(0))), Some(&x) => (1, Some(frame_io::Event::Found(x))), None => (0, None) } }
    /// # fn end(&mut self) -> Option<frame_io::Event<u8, u8>> { None }
    /// # fn item(&self, _: &[u8], x: u8) -> u8 { x }
    /// # fn span(&self) -> frame_io::Span { frame_io::Span { len: 1, after: 0 } } }
    /// use frame_io::{Decode, Span};
    /// // `Bytes`: every byte is an event of its own.
    /// let mut d = Bytes;
    /// d.decode(&[7, 8]);
    /// assert_eq!(d.span(), Span { len: 1, after: 0 });
    /// ```
    fn span(&self) -> Span;

    /// Makes the item that `found` stands for the decoder's own when it lies in `input` (an
    /// item found in place in the caller's slice, as AYDP finds a whole frame): the bytes are
    /// copied into the decoder, and the value returned stands for them there, so that
    /// [`Decode::item`] no longer reads `input`. For a caller that keeps an item after its
    /// bytes are gone (a C caller's buffer, which a DMA may write again). The default returns
    /// `found` as it is: for a decoder whose items never borrow the input.
    /// [`crate::Stream::next_kept`] calls it.
    ///
    /// ```
    /// # struct Bytes; impl frame_io::Decode for Bytes { type Error = u8; type Found = u8; type Item<'a> = u8; const TRUNCATED: u8 = 0;
    /// # fn decode(&mut self, b: &[u8]) -> (usize, Option<frame_io::Event<u8, u8>>) { match b.first() { Some(&0) => (1, Some(frame_io::Event::Error(0))), Some(&x) => (1, Some(frame_io::Event::Found(x))), None => (0, None) } }
    /// # fn end(&mut self) -> Option<frame_io::Event<u8, u8>> { None }
    /// # fn item(&self, _: &[u8], x: u8) -> u8 { x }
    /// # fn span(&self) -> frame_io::Span { frame_io::Span { len: 1, after: 0 } } }
    /// use frame_io::Decode;
    /// // `Bytes` carries its items in `Found`: there is nothing to copy.
    /// assert_eq!(Bytes.keep(&[7], 7), 7);
    /// ```
    #[inline(always)]
    fn keep(&mut self, input: &[u8], found: Self::Found) -> Self::Found {
        let _ = input;
        found
    }

    /// The pull form for a caller: decodes `bytes` up to and including the byte that gives
    /// the first event, and returns how many bytes that used and the event, as the item (it
    /// may borrow the decoder or `bytes`) or the error. `None`: every byte was used and
    /// nothing came of it. Call it again on the rest, and once more with an empty slice after
    /// an event, until it returns `(0, None)`: a protocol that rescans can hold several events
    /// for one byte. The events are those of [`Decode::feed`] over the same bytes.
    ///
    /// ```
    /// # struct Bytes; impl frame_io::Decode for Bytes { type Error = u8; type Found = u8; type Item<'a> = u8; const TRUNCATED: u8 = 0;
    /// # fn decode(&mut self, b: &[u8]) -> (usize, Option<frame_io::Event<u8, u8>>) { match b.first() { Some(&0) => (1, Some(frame_io::Event::Error(0))), Some(&x) => (1, Some(frame_io::Event::Found(x))), None => (0, None) } }
    /// # fn end(&mut self) -> Option<frame_io::Event<u8, u8>> { None }
    /// # fn item(&self, _: &[u8], x: u8) -> u8 { x }
    /// # fn span(&self) -> frame_io::Span { frame_io::Span { len: 1, after: 0 } } }
    /// use frame_io::Decode;
    /// let mut d = Bytes;
    /// let input = [7, 0, 8];
    /// let mut rest = &input[..];
    /// let mut seen = Vec::new();
    /// loop {
    ///     let (used, event) = d.next_event(rest);
    ///     rest = &rest[used..];
    ///     match event {
    ///         Some(event) => seen.push(event), // act here: the next byte waits
    ///         None => break,
    ///     }
    /// }
    /// assert_eq!(seen, [Ok(7), Err(0), Ok(8)]);
    /// ```
    #[inline]
    #[allow(clippy::type_complexity)] // spelt out: it is what a caller matches on
    fn next_event<'a>(
        &'a mut self,
        bytes: &'a [u8],
    ) -> (usize, Option<Result<Self::Item<'a>, Self::Error>>) {
        let (used, event) = self.decode(bytes);
        let this: &'a Self = self;
        let event = match event {
            None => None,
            Some(Event::Found(found)) => Some(Ok(this.item(bytes, found))),
            Some(Event::Error(error)) => Some(Err(error)),
            Some(Event::Truncated(_)) => Some(Err(Self::TRUNCATED)),
        };
        (used, event)
    }

    /// The loop of the contract for a slice of the stream: calls `on_event` for every event
    /// the bytes give, in order, and returns once every byte is used. Slices of any length,
    /// one byte included, give the events of the whole stream.
    ///
    /// ```
    /// # struct Bytes; impl frame_io::Decode for Bytes { type Error = u8; type Found = u8; type Item<'a> = u8; const TRUNCATED: u8 = 0;
    /// # fn decode(&mut self, b: &[u8]) -> (usize, Option<frame_io::Event<u8, u8>>) { match b.first() { Some(&0) => (1, Some(frame_io::Event::Error(0))), Some(&x) => (1, Some(frame_io::Event::Found(x))), None => (0, None) } }
    /// # fn end(&mut self) -> Option<frame_io::Event<u8, u8>> { None }
    /// # fn item(&self, _: &[u8], x: u8) -> u8 { x }
    /// # fn span(&self) -> frame_io::Span { frame_io::Span { len: 1, after: 0 } } }
    /// use frame_io::Decode;
    /// let mut seen = Vec::new();
    /// Bytes.feed(&[7, 0, 8], |event| seen.push(event));
    /// assert_eq!(seen, [Ok(7), Err(0), Ok(8)]);
    /// ```
    #[inline]
    fn feed<F>(&mut self, bytes: &[u8], mut on_event: F)
    where
        F: FnMut(Result<Self::Item<'_>, Self::Error>),
    {
        let mut rest = bytes;
        loop {
            let input = rest;
            let (used, event) = self.decode(input);
            rest = input.get(used..).unwrap_or(&[]);
            match event {
                None => return,
                Some(Event::Found(found)) => on_event(Ok(self.item(input, found))),
                Some(Event::Error(error)) => on_event(Err(error)),
                Some(Event::Truncated(_)) => on_event(Err(Self::TRUNCATED)),
            }
        }
    }

    /// The loop of the contract for the end of the stream: calls `on_event` for every event
    /// of [`Decode::end`] (a frame cut short is `Err(TRUNCATED)`; what a protocol rescans
    /// after it follows), then the decoder is as new.
    ///
    /// ```
    /// # struct Bytes; impl frame_io::Decode for Bytes { type Error = u8; type Found = u8; type Item<'a> = u8; const TRUNCATED: u8 = 0;
    /// # fn decode(&mut self, b: &[u8]) -> (usize, Option<frame_io::Event<u8, u8>>) { match b.first() { Some(&0) => (1, Some(frame_io::Event::Error(0))), Some(&x) => (1, Some(frame_io::Event::Found(x))), None => (0, None) } }
    /// # fn end(&mut self) -> Option<frame_io::Event<u8, u8>> { None }
    /// # fn item(&self, _: &[u8], x: u8) -> u8 { x }
    /// # fn span(&self) -> frame_io::Span { frame_io::Span { len: 1, after: 0 } } }
    /// use frame_io::Decode;
    /// let mut seen = 0;
    /// Bytes.finish(|_| seen += 1);
    /// assert_eq!(seen, 0); // `Bytes` holds nothing between calls
    /// ```
    fn finish<F>(&mut self, mut on_event: F)
    where
        F: FnMut(Result<Self::Item<'_>, Self::Error>),
    {
        while let Some(event) = self.end() {
            match event {
                Event::Found(found) => on_event(Ok(self.item(&[], found))),
                Event::Error(error) => on_event(Err(error)),
                Event::Truncated(_) => on_event(Err(Self::TRUNCATED)),
            }
        }
    }
}
