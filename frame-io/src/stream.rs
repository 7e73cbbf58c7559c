//! [`Stream`]: a decoder and the count of the bytes it has used, so that every event comes
//! with its [`Place`].

use crate::{Decode, Event, Place};

/// A decoder over one stream: the one adapter every face drives a decoder through. It counts
/// the bytes the decoder uses and gives every event with its [`Place`] in the stream (from the
/// decoder's [`Decode::span`]), whatever slices the bytes come in, the end of the stream
/// included. The forms are those of [`Decode`]: [`Stream::feed`] and [`Stream::finish`] (the
/// one loop), [`Stream::next_event`] and [`Stream::end_event`] (one event a call), and
/// [`Stream::next_kept`] for a caller that keeps an item after its bytes are gone.
///
/// ```
/// # use frame_io::{Decode, Event, Span};
/// # /// Every byte but 0 is an item; 0 is an error.
/// # struct Bytes;
/// # impl Decode for Bytes {
/// #     type Error = &'static str; type Found = u8; type Item<'a> = u8;
/// #     const TRUNCATED: &'static str = "cut short";
/// #     fn decode(&mut self, b: &[u8]) -> (usize, Option<Event<u8, &'static str>>) {
/// #         match b.first() { None => (0, None), Some(0) => (1, Some(Event::Error("zero"))), Some(&x) => (1, Some(Event::Found(x))) }
/// #     }
/// #     fn end(&mut self) -> Option<Event<u8, &'static str>> { None }
/// #     fn item(&self, _: &[u8], x: u8) -> u8 { x }
/// #     fn span(&self) -> Span { Span { len: 1, after: 0 } }
/// # }
/// use frame_io::{Place, Stream};
///
/// // `Bytes` (hidden): every byte but 0 is an item, 0 an error.
/// let mut stream = Stream::new(Bytes);
/// let mut seen = Vec::new();
/// for piece in [&[7u8, 0][..], &[8]] {
///     stream.feed(piece, |place, event| seen.push((place.offset, event)));
/// }
/// stream.finish(|place, event| seen.push((place.offset, event)));
/// assert_eq!(seen, [(0, Ok(7)), (1, Err("zero")), (2, Ok(8))]);
/// assert_eq!(stream.used(), 3);
/// ```
#[derive(Debug, Clone, Default)]
pub struct Stream<D> {
    decoder: D,
    used: u64,
}

impl<D: Decode> Stream<D> {
    /// `decoder` at the start of a stream: offsets count from its next byte.
    ///
    /// ```
    /// # use frame_io::{Decode, Event, Span};
    /// # struct Bytes; impl Decode for Bytes { type Error = u8; type Found = u8; type Item<'a> = u8; const TRUNCATED: u8 = 0;
    /// # fn decode(&mut self, b: &[u8]) -> (usize, Option<Event<u8, u8>>) { match b.first() { Some(&0) => (1, Some(Event::Error(0))), Some(&x) => (1, Some(Event::Found(x))), None => (0, None) } }
    /// # fn end(&mut self) -> Option<Event<u8, u8>> { None }
    /// # fn item(&self, _: &[u8], x: u8) -> u8 { x }
    /// # fn span(&self) -> Span { Span { len: 1, after: 0 } } }
    /// let stream = frame_io::Stream::new(Bytes);
    /// assert_eq!(stream.used(), 0);
    /// ```
    pub const fn new(decoder: D) -> Self {
        Self { decoder, used: 0 }
    }

    /// The decoder (its counters, its settings).
    ///
    /// ```
    /// # use frame_io::{Decode, Event, Span};
    /// # struct Bytes; impl Decode for Bytes { type Error = u8; type Found = u8; type Item<'a> = u8; const TRUNCATED: u8 = 0;
    /// # fn decode(&mut self, b: &[u8]) -> (usize, Option<Event<u8, u8>>) { match b.first() { Some(&0) => (1, Some(Event::Error(0))), Some(&x) => (1, Some(Event::Found(x))), None => (0, None) } }
    /// # fn end(&mut self) -> Option<Event<u8, u8>> { None }
    /// # fn item(&self, _: &[u8], x: u8) -> u8 { x }
    /// # fn span(&self) -> Span { Span { len: 1, after: 0 } } }
    /// let stream = frame_io::Stream::new(Bytes);
    /// let _decoder: &Bytes = stream.decoder();
    /// ```
    pub const fn decoder(&self) -> &D {
        &self.decoder
    }

    /// The decoder, to change a setting or reset its counters. Dropping what it holds moves no
    /// offset: the count of bytes used goes on.
    ///
    /// ```
    /// # use frame_io::{Decode, Event, Span};
    /// # struct Bytes; impl Decode for Bytes { type Error = u8; type Found = u8; type Item<'a> = u8; const TRUNCATED: u8 = 0;
    /// # fn decode(&mut self, b: &[u8]) -> (usize, Option<Event<u8, u8>>) { match b.first() { Some(&0) => (1, Some(Event::Error(0))), Some(&x) => (1, Some(Event::Found(x))), None => (0, None) } }
    /// # fn end(&mut self) -> Option<Event<u8, u8>> { None }
    /// # fn item(&self, _: &[u8], x: u8) -> u8 { x }
    /// # fn span(&self) -> Span { Span { len: 1, after: 0 } } }
    /// let mut stream = frame_io::Stream::new(Bytes);
    /// let _decoder: &mut Bytes = stream.decoder_mut();
    /// ```
    pub fn decoder_mut(&mut self) -> &mut D {
        &mut self.decoder
    }

    /// The decoder, given back.
    ///
    /// ```
    /// # use frame_io::{Decode, Event, Span};
    /// # struct Bytes; impl Decode for Bytes { type Error = u8; type Found = u8; type Item<'a> = u8; const TRUNCATED: u8 = 0;
    /// # fn decode(&mut self, b: &[u8]) -> (usize, Option<Event<u8, u8>>) { match b.first() { Some(&0) => (1, Some(Event::Error(0))), Some(&x) => (1, Some(Event::Found(x))), None => (0, None) } }
    /// # fn end(&mut self) -> Option<Event<u8, u8>> { None }
    /// # fn item(&self, _: &[u8], x: u8) -> u8 { x }
    /// # fn span(&self) -> Span { Span { len: 1, after: 0 } } }
    /// let _decoder: Bytes = frame_io::Stream::new(Bytes).into_inner();
    /// ```
    pub fn into_inner(self) -> D {
        self.decoder
    }

    /// The bytes the decoder has used since the stream began (wrapping): the offset of the
    /// next byte.
    ///
    /// ```
    /// # use frame_io::{Decode, Event, Span};
    /// # struct Bytes; impl Decode for Bytes { type Error = u8; type Found = u8; type Item<'a> = u8; const TRUNCATED: u8 = 0;
    /// # fn decode(&mut self, b: &[u8]) -> (usize, Option<Event<u8, u8>>) { match b.first() { Some(&0) => (1, Some(Event::Error(0))), Some(&x) => (1, Some(Event::Found(x))), None => (0, None) } }
    /// # fn end(&mut self) -> Option<Event<u8, u8>> { None }
    /// # fn item(&self, _: &[u8], x: u8) -> u8 { x }
    /// # fn span(&self) -> Span { Span { len: 1, after: 0 } } }
    /// let mut stream = frame_io::Stream::new(Bytes);
    /// stream.feed(&[1, 2, 3], |_, _| {});
    /// assert_eq!(stream.used(), 3);
    /// ```
    pub const fn used(&self) -> u64 {
        self.used
    }

    /// The pull form: decodes `bytes` up to and including the byte that gives the first event
    /// and returns how many bytes that used and the event with its place (`None`: every byte
    /// was used and nothing came of it). Call it again on the rest, and once more with an
    /// empty slice after an event, until `(0, None)`, as [`Decode::next_event`].
    ///
    /// ```
    /// # use frame_io::{Decode, Event, Span};
    /// # struct Bytes; impl Decode for Bytes { type Error = u8; type Found = u8; type Item<'a> = u8; const TRUNCATED: u8 = 0;
    /// # fn decode(&mut self, b: &[u8]) -> (usize, Option<Event<u8, u8>>) { match b.first() { Some(&0) => (1, Some(Event::Error(0))), Some(&x) => (1, Some(Event::Found(x))), None => (0, None) } }
    /// # fn end(&mut self) -> Option<Event<u8, u8>> { None }
    /// # fn item(&self, _: &[u8], x: u8) -> u8 { x }
    /// # fn span(&self) -> Span { Span { len: 1, after: 0 } } }
    /// use frame_io::Place;
    /// let mut stream = frame_io::Stream::new(Bytes);
    /// assert_eq!(stream.next_event(&[5, 0]), (1, Some((Place { offset: 0, len: 1 }, Ok(5)))));
    /// assert_eq!(stream.next_event(&[0]), (1, Some((Place { offset: 1, len: 1 }, Err(0)))));
    /// ```
    #[inline]
    #[allow(clippy::type_complexity)] // spelt out: it is what a caller matches on
    pub fn next_event<'a>(
        &'a mut self,
        bytes: &'a [u8],
    ) -> (usize, Option<(Place, Result<D::Item<'a>, D::Error>)>) {
        let (used, event) = self.decoder.decode(bytes);
        self.used = self.used.wrapping_add(used as u64);
        let event = event.map(|event| self.placed(bytes, event));
        (used, event)
    }

    /// [`Stream::next_event`] for a caller that keeps the item after `bytes` are gone: an item
    /// found in place in `bytes` is first copied into the decoder ([`Decode::keep`]), so the
    /// item borrows the stream only. The events and places are those of `next_event`.
    ///
    /// ```
    /// # use frame_io::{Decode, Event, Place, Span};
    /// # struct Bytes; impl Decode for Bytes { type Error = u8; type Found = u8; type Item<'a> = u8; const TRUNCATED: u8 = 0;
    /// # fn decode(&mut self, b: &[u8]) -> (usize, Option<Event<u8, u8>>) { match b.first() { Some(&0) => (1, Some(Event::Error(0))), Some(&x) => (1, Some(Event::Found(x))), None => (0, None) } }
    /// # fn end(&mut self) -> Option<Event<u8, u8>> { None }
    /// # fn item(&self, _: &[u8], x: u8) -> u8 { x }
    /// # fn span(&self) -> Span { Span { len: 1, after: 0 } } }
    /// let mut stream = frame_io::Stream::new(Bytes);
    /// let mut buffer = [5, 0];
    /// let (used, event) = stream.next_kept(&buffer);
    /// buffer = [0; 2]; // the caller's bytes change; the item does not borrow them
    /// assert_eq!((used, event), (1, Some((Place { offset: 0, len: 1 }, Ok(5)))));
    /// # let _ = buffer;
    /// ```
    #[inline]
    #[allow(clippy::type_complexity)] // spelt out: it is what a caller matches on
    pub fn next_kept(
        &mut self,
        bytes: &[u8],
    ) -> (usize, Option<(Place, Result<D::Item<'_>, D::Error>)>) {
        let (used, event) = self.decoder.decode(bytes);
        self.used = self.used.wrapping_add(used as u64);
        let event = event.map(|event| match event {
            Event::Found(found) => Event::Found(self.decoder.keep(bytes, found)),
            other => other,
        });
        let event = event.map(|event| self.placed(&[], event));
        (used, event)
    }

    /// The pull form of the end of the stream: its next event with its place (a frame cut
    /// short is `Err(TRUNCATED)`), `None` once there is none; the decoder is then as new and
    /// the offsets go on counting.
    ///
    /// ```
    /// # use frame_io::{Decode, Event, Span};
    /// # struct Bytes; impl Decode for Bytes { type Error = u8; type Found = u8; type Item<'a> = u8; const TRUNCATED: u8 = 0;
    /// # fn decode(&mut self, b: &[u8]) -> (usize, Option<Event<u8, u8>>) { match b.first() { Some(&0) => (1, Some(Event::Error(0))), Some(&x) => (1, Some(Event::Found(x))), None => (0, None) } }
    /// # fn end(&mut self) -> Option<Event<u8, u8>> { None }
    /// # fn item(&self, _: &[u8], x: u8) -> u8 { x }
    /// # fn span(&self) -> Span { Span { len: 1, after: 0 } } }
    /// let mut stream = frame_io::Stream::new(Bytes);
    /// assert!(stream.end_event().is_none()); // `Bytes` holds nothing
    /// ```
    #[allow(clippy::type_complexity)] // spelt out: it is what a caller matches on
    pub fn end_event(&mut self) -> Option<(Place, Result<D::Item<'_>, D::Error>)> {
        let event = self.decoder.end()?;
        Some(self.placed(&[], event))
    }

    /// The loop for a slice of the stream: calls `on_event` with every event of `bytes` and
    /// its place, in order.
    ///
    /// ```
    /// # use frame_io::{Decode, Event, Span};
    /// # struct Bytes; impl Decode for Bytes { type Error = u8; type Found = u8; type Item<'a> = u8; const TRUNCATED: u8 = 0;
    /// # fn decode(&mut self, b: &[u8]) -> (usize, Option<Event<u8, u8>>) { match b.first() { Some(&0) => (1, Some(Event::Error(0))), Some(&x) => (1, Some(Event::Found(x))), None => (0, None) } }
    /// # fn end(&mut self) -> Option<Event<u8, u8>> { None }
    /// # fn item(&self, _: &[u8], x: u8) -> u8 { x }
    /// # fn span(&self) -> Span { Span { len: 1, after: 0 } } }
    /// let mut stream = frame_io::Stream::new(Bytes);
    /// let mut offsets = Vec::new();
    /// stream.feed(&[1, 0, 2], |place, _| offsets.push(place.offset));
    /// assert_eq!(offsets, [0, 1, 2]);
    /// ```
    #[inline]
    pub fn feed<F>(&mut self, bytes: &[u8], mut on_event: F)
    where
        F: FnMut(Place, Result<D::Item<'_>, D::Error>),
    {
        let mut rest = bytes;
        loop {
            let input = rest;
            let (used, event) = self.decoder.decode(input);
            self.used = self.used.wrapping_add(used as u64);
            rest = input.get(used..).unwrap_or(&[]);
            match event {
                None => return,
                Some(event) => {
                    let (place, event) = self.placed(input, event);
                    on_event(place, event);
                }
            }
        }
    }

    /// The loop for the end of the stream: calls `on_event` with every event of
    /// [`Decode::end`] and its place; the decoder is then as new and the offsets go on.
    ///
    /// ```
    /// # use frame_io::{Decode, Event, Span};
    /// # struct Bytes; impl Decode for Bytes { type Error = u8; type Found = u8; type Item<'a> = u8; const TRUNCATED: u8 = 0;
    /// # fn decode(&mut self, b: &[u8]) -> (usize, Option<Event<u8, u8>>) { match b.first() { Some(&0) => (1, Some(Event::Error(0))), Some(&x) => (1, Some(Event::Found(x))), None => (0, None) } }
    /// # fn end(&mut self) -> Option<Event<u8, u8>> { None }
    /// # fn item(&self, _: &[u8], x: u8) -> u8 { x }
    /// # fn span(&self) -> Span { Span { len: 1, after: 0 } } }
    /// let mut stream = frame_io::Stream::new(Bytes);
    /// let mut seen = 0;
    /// stream.finish(|_, _| seen += 1);
    /// assert_eq!(seen, 0);
    /// ```
    pub fn finish<F>(&mut self, mut on_event: F)
    where
        F: FnMut(Place, Result<D::Item<'_>, D::Error>),
    {
        while let Some(event) = self.decoder.end() {
            let (place, event) = self.placed(&[], event);
            on_event(place, event);
        }
    }

    /// An event of `decode` on `input` (or of `end`, on nothing) with its place: the span is
    /// read before the item borrows the decoder.
    #[inline(always)]
    #[allow(clippy::type_complexity)]
    fn placed<'a>(
        &'a self,
        input: &'a [u8],
        event: Event<D::Found, D::Error>,
    ) -> (Place, Result<D::Item<'a>, D::Error>) {
        let place = self.decoder.span().place(self.used);
        let event = match event {
            Event::Found(found) => Ok(self.decoder.item(input, found)),
            Event::Error(e) => Err(e),
            Event::Truncated(_) => Err(D::TRUNCATED),
        };
        (place, event)
    }
}
