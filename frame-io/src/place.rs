//! Where an event lies: [`Span`], as a decoder states it, and [`Place`], as a caller gets it.

/// Where the event that a decoder's last [`Decode::decode`](crate::Decode::decode) or
/// [`Decode::end`](crate::Decode::end) call returned lies, counted back from the end of every
/// byte the decoder has used so far: its bytes end `after` bytes before that end and are `len`
/// bytes long on the wire (escapes and flags included). A decoder states it
/// ([`Decode::span`](crate::Decode::span)); [`Stream`](crate::Stream) turns it into a
/// [`Place`].
///
/// - an item: the bytes of its frame (for a flag-framed protocol, both flags);
/// - an error: the bytes it gives up or condemns (a frame with a bad check, the bytes of a
///   frame cut short by an overflow up to the byte that did not fit, a false start);
/// - `after`: bytes used after the event that the decoder still holds (a protocol that
///   rescans after an error), 0 otherwise.
///
/// ```
/// use frame_io::Span;
/// // A 7-byte frame, with 2 bytes after it held for a rescan.
/// let span = Span { len: 7, after: 2 };
/// assert_eq!(span.place(20), frame_io::Place { offset: 11, len: 7 });
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Span {
    /// The event's length on the wire.
    pub len: usize,
    /// Bytes used after the event's last byte.
    pub after: usize,
}

impl Span {
    /// The place of this span when the decoder has used `used` bytes since it began
    /// (wrapping, as the count does).
    ///
    /// ```
    /// use frame_io::{Place, Span};
    /// assert_eq!(Span { len: 3, after: 0 }.place(3), Place { offset: 0, len: 3 });
    /// ```
    #[inline]
    pub const fn place(self, used: u64) -> Place {
        Place {
            offset: used
                .wrapping_sub(self.after as u64)
                .wrapping_sub(self.len as u64),
            len: self.len,
        }
    }
}

/// Where an event is in its stream: the offset of its first byte since the decoder began
/// (whatever slices the bytes came in), and its length on the wire. [`Stream`](crate::Stream)
/// gives one with every event.
///
/// ```
/// use frame_io::Place;
/// let place = Place { offset: 10, len: 4 };
/// assert_eq!(place.end(), 14);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Place {
    /// The offset of the event's first byte in the stream.
    pub offset: u64,
    /// Its length on the wire.
    pub len: usize,
}

impl Place {
    /// The offset just past the event's last byte.
    ///
    /// ```
    /// assert_eq!(frame_io::Place { offset: 2, len: 3 }.end(), 5);
    /// ```
    #[inline]
    pub const fn end(self) -> u64 {
        self.offset.wrapping_add(self.len as u64)
    }
}
