//! What the `embedded-io` and `embedded-io-async` readers and writers share: the error type
//! and the decoder's [`frame_io::Decode`] implementation that the readers of `frame-io`
//! drive. The two feature modules only name the readers and add the writers' calls (blocking
//! or `.await`) around `frame-io`'s write loop.

use frame_io::{Decode, Event};

use crate::decoder::{Decoder, Found};
use crate::error::Error;
use crate::frame::Frame;

/// The error of a reader or writer over `embedded-io` or `embedded-io-async`
/// ([`frame_io::IoError`] with this crate's [`Error`]): the transport's error `E` and the
/// protocol's are kept apart.
///
/// After [`IoError::Protocol`] the reader goes on with the bytes after the failed candidate
/// (the decoder's rescan); after [`IoError::Transport`] it keeps every byte already read, so
/// reading again is fine if the transport recovers. At the end of the stream inside a
/// message, the incomplete candidate is given up ([`IoError::UnexpectedEof`]`{ pending }`, its
/// bytes) and its bytes rescanned as [`Decoder::flush`] does, so messages hidden in it still
/// follow, then [`IoError::Eof`].
///
/// ```
/// use aydp_proto::{Error, IoError};
/// let e: IoError<core::convert::Infallible> = IoError::Protocol(Error::ChecksumMismatch {
///     id: 3,
///     computed: 0xE2,
///     received: 0x55,
/// });
/// assert!(e.is_protocol());
/// assert_eq!(e.to_string(), "protocol error: checksum mismatch");
/// ```
pub type IoError<E> = frame_io::IoError<E, Error>;

/// The readers' decoding: [`Decoder::feed`]'s bulk path up to the first event (messages
/// checked in place in the input when nothing is held); at the end of the stream,
/// [`Decoder::flush`]'s events one at a time. A found message is `(Some(at), len)`, in place
/// at `at` in the input, or `(None, len)`, the last `len` bytes delivered from the decoder's
/// buffer.
///
/// ```
/// use aydp_proto::{Decoder, Profile};
/// use frame_io::{Decode, Event};
/// // An expedited heartbeat (type 0), then the start of another.
/// let wire = [0xFF, 0x80, 0x07, 0, 0, 0, 0x78, 0xFF, 0x89];
/// let mut d = Decoder::<32>::new(Profile::Spec);
/// let (used, event) = d.decode(&wire);
/// assert_eq!((used, event), (7, Some(Event::Found((Some(0), 7)))));
/// assert_eq!(d.item(&wire, (Some(0), 7)).as_bytes(), &wire[..7]);
/// assert_eq!(d.decode(&wire[7..]), (2, None));
/// assert_eq!(d.end(true), Some(Event::Truncated(2)));
/// assert_eq!(d.end(false), None);
/// ```
impl<const N: usize> Decode for Decoder<N> {
    type Error = Error;
    type Found = (Option<usize>, usize);
    type Item<'a> = Frame<'a>;
    const TRUNCATED: Error = Error::Truncated;

    #[inline]
    fn decode(&mut self, bytes: &[u8]) -> (usize, Option<Event<(Option<usize>, usize), Error>>) {
        let (used, found) = self.find_until(bytes);
        (used, event(found))
    }

    fn end(&mut self, _first: bool) -> Option<Event<(Option<usize>, usize), Error>> {
        // `flush_until` feeds nothing: it never reports `Nothing` or `InPlace`.
        event(self.flush_until()?)
    }

    #[inline]
    fn item<'a>(&'a self, input: &'a [u8], (at, len): (Option<usize>, usize)) -> Frame<'a> {
        match at {
            None => self.held_frame(len),
            Some(at) => {
                let bytes = input.get(at..at.saturating_add(len)).unwrap_or(&[]);
                Frame::new_unchecked(bytes, self.profile())
            }
        }
    }
}

#[inline]
fn event(found: Found) -> Option<Event<(Option<usize>, usize), Error>> {
    Some(match found {
        Found::Nothing => return None,
        Found::Held(len) => Event::Found((None, len)),
        Found::InPlace { at, len } => Event::Found((Some(at), len)),
        Found::Error(e) => Event::Error(e),
        Found::Truncated(n) => Event::Truncated(n),
    })
}
