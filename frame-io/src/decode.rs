//! The decoder trait the readers are generic over, and what a decoder reports.

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

/// A stream decoder that the readers can drive: the slice fast path, the end of the stream,
/// and the item a [`Event::Found`] stands for.
///
/// The reader calls [`Decode::decode`] on every byte it reads (and once more with an empty
/// slice before each read, for events a rescan left queued); when a read returns 0 bytes, it
/// calls [`Decode::end`] until that returns `None`, then reports
/// [`IoError::Eof`](crate::IoError::Eof) and reads on. The events must be those of the
/// decoder's byte-at-a-time `push` (and `poll`) over the same bytes, and at the end those of
/// its `flush` or `idle`.
///
/// ```
/// use frame_io::{Decode, Event};
///
/// /// Lines of up to 8 bytes, each ended by `\n`; a longer line is an error.
/// struct Lines {
///     buf: [u8; 8],
///     len: usize,
/// }
///
/// impl Decode for Lines {
///     type Error = &'static str;
///     type Found = usize;
///     type Item<'a> = &'a [u8];
///
///     fn decode(&mut self, bytes: &[u8]) -> (usize, Option<Event<usize, &'static str>>) {
///         for (i, &b) in bytes.iter().enumerate() {
///             if b == b'\n' {
///                 return (i + 1, Some(Event::Found(core::mem::take(&mut self.len))));
///             }
///             let Some(slot) = self.buf.get_mut(self.len) else {
///                 self.len = 0;
///                 return (i + 1, Some(Event::Error("line too long")));
///             };
///             *slot = b;
///             self.len += 1;
///         }
///         (bytes.len(), None)
///     }
///
///     fn end(&mut self, _first: bool) -> Option<Event<usize, &'static str>> {
///         let pending = core::mem::take(&mut self.len);
///         (pending > 0).then_some(Event::Truncated(pending))
///     }
///
///     fn item<'a>(&'a self, _input: &'a [u8], len: usize) -> &'a [u8] {
///         self.buf.get(..len).unwrap_or(&[])
///     }
/// }
///
/// let mut lines = Lines { buf: [0; 8], len: 0 };
/// assert_eq!(lines.decode(b"hi\nthere"), (3, Some(Event::Found(2))));
/// assert_eq!(lines.decode(b"there"), (5, None));
/// assert_eq!(lines.end(true), Some(Event::Truncated(5)));
/// assert_eq!(lines.end(false), None);
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

    /// Decodes `bytes` up to the first event: returns how many of them were used and the
    /// event, if any (`None`: every byte was used and nothing was found). Events left queued
    /// by an earlier call come first, with no byte used.
    ///
    /// ```
    /// # struct Bytes; impl frame_io::Decode for Bytes { type Error = u8; type Found = u8; type Item<'a> = u8;
    /// # fn decode(&mut self, b: &[u8]) -> (usize, Option<frame_io::Event<u8, u8>>) { match b.first() { Some(&0) => (1, Some(frame_io::Event::Error(0))), Some(&x) => (1, Some(frame_io::Event::Found(x))), None => (0, None) } }
    /// # fn end(&mut self, _: bool) -> Option<frame_io::Event<u8, u8>> { None }
    /// # fn item(&self, _: &[u8], x: u8) -> u8 { x } }
    /// use frame_io::{Decode, Event};
    /// // `Bytes`: every non-zero byte is an item, a zero byte an error.
    /// assert_eq!(Bytes.decode(&[7, 8]), (1, Some(Event::Found(7))));
    /// assert_eq!(Bytes.decode(&[]), (0, None));
    /// ```
    #[allow(clippy::type_complexity)] // spelt out: it is what an implementation writes
    fn decode(&mut self, bytes: &[u8]) -> (usize, Option<Event<Self::Found, Self::Error>>);

    /// The stream ended: the next event of the end of the stream (the decoder's `flush` or
    /// `idle`), or `None` once there is none. `first` is true on the first call after the
    /// read that returned 0 bytes.
    ///
    /// ```
    /// # struct Bytes; impl frame_io::Decode for Bytes { type Error = u8; type Found = u8; type Item<'a> = u8;
    /// # fn decode(&mut self, b: &[u8]) -> (usize, Option<frame_io::Event<u8, u8>>) { match b.first() { Some(&0) => (1, Some(frame_io::Event::Error(0))), Some(&x) => (1, Some(frame_io::Event::Found(x))), None => (0, None) } }
    /// # fn end(&mut self, _: bool) -> Option<frame_io::Event<u8, u8>> { None }
    /// # fn item(&self, _: &[u8], x: u8) -> u8 { x } }
    /// use frame_io::Decode;
    /// // `Bytes` holds nothing between calls: the end of the stream finds nothing.
    /// assert_eq!(Bytes.end(true), None);
    /// ```
    fn end(&mut self, first: bool) -> Option<Event<Self::Found, Self::Error>>;

    /// The item that `found` stands for. `input` is the slice given to the
    /// [`Decode::decode`] call that reported it (empty for an event of [`Decode::end`]), so
    /// an item found in place in the read buffer can borrow it.
    ///
    /// ```
    /// # struct Bytes; impl frame_io::Decode for Bytes { type Error = u8; type Found = u8; type Item<'a> = u8;
    /// # fn decode(&mut self, b: &[u8]) -> (usize, Option<frame_io::Event<u8, u8>>) { match b.first() { Some(&0) => (1, Some(frame_io::Event::Error(0))), Some(&x) => (1, Some(frame_io::Event::Found(x))), None => (0, None) } }
    /// # fn end(&mut self, _: bool) -> Option<frame_io::Event<u8, u8>> { None }
    /// # fn item(&self, _: &[u8], x: u8) -> u8 { x } }
    /// use frame_io::Decode;
    /// assert_eq!(Bytes.item(&[7, 8], 7), 7);
    /// ```
    fn item<'a>(&'a self, input: &'a [u8], found: Self::Found) -> Self::Item<'a>;
}
