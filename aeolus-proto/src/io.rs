//! What the `embedded-io` and `embedded-io-async` readers and writers share: the error type,
//! the decoder's [`frame_io::Decode`] implementation that the readers of `frame-io` drive,
//! and the message-to-bytes step of the writers. The two feature modules only name the
//! readers and add the writers' calls (blocking or `.await`) around these.

use frame_io::{Decode, Event};

use crate::decoder::Found;
use crate::message::Message;
use crate::{CrcMode, Decoder, Error, Frame, FrameBytes, TEXT_CAPACITY};

/// The error of a reader or writer over `embedded-io` or `embedded-io-async`
/// ([`frame_io::IoError`] with this crate's [`Error`]): the transport's error `E` and the
/// protocol's are kept apart.
///
/// After [`IoError::Protocol`] the reader has resynchronised and the next read continues with
/// the next frame; after [`IoError::Transport`] it keeps every byte already read, so reading
/// again is fine if the transport recovers (a UART overrun, say). At the end of the stream
/// inside a frame, the frame's bytes are dropped and counted in
/// [`IoError::UnexpectedEof`]`{ pending }` (as [`Decoder::flush`] does), then comes
/// [`IoError::Eof`].
///
/// ```
/// use aeolus_proto::{Error, IoError};
/// let e: IoError<core::convert::Infallible> = IoError::Protocol(Error::TooShort);
/// assert!(e.is_protocol());
/// assert_eq!(e.to_string(), "protocol error: frame too short to hold an ID and a CRC");
/// ```
pub type IoError<E> = frame_io::IoError<E, Error>;

/// The readers' decoding: [`Decoder::feed`]'s fast path up to the first event; at the end of
/// the stream, the frame in progress is dropped (`Truncated` with its wire bytes). A found
/// frame is `(length, has_crc)` in the decoder's buffer.
///
/// ```
/// use aeolus_proto::Decoder;
/// use frame_io::{Decode, Event};
/// let mut d = Decoder::<64>::new();
/// let (used, event) = d.decode(&[0x7E, 0x52, b'h', b'i', 0x00, 0x73, 0xEC, 0x7E, 0x52]);
/// // The frame: ID, data and CRC, 6 bytes unescaped.
/// assert_eq!((used, event), (8, Some(Event::Found((6, true)))));
/// assert_eq!(d.item(&[], (6, true)).id(), 0x52);
/// assert_eq!(d.decode(&[0x52]), (1, None));
/// assert_eq!(d.end(true), Some(Event::Truncated(1)));
/// assert_eq!(d.end(false), None);
/// ```
impl<const N: usize> Decode for Decoder<N> {
    type Error = Error;
    type Found = (usize, bool);
    type Item<'a> = Frame<'a>;
    const TRUNCATED: Error = Error::Truncated;

    #[inline]
    fn decode(&mut self, bytes: &[u8]) -> (usize, Option<Event<(usize, bool), Error>>) {
        if bytes.is_empty() {
            return (0, None);
        }
        let (used, found) = self.push_until(bytes);
        let event = match found {
            Found::Nothing => None,
            Found::Frame { len, has_crc } => Some(Event::Found((len, has_crc))),
            Found::Error(e) => Some(Event::Error(e)),
        };
        (used, event)
    }

    fn end(&mut self, _first: bool) -> Option<Event<(usize, bool), Error>> {
        let pending = self.held_bytes();
        if pending == 0 {
            return None;
        }
        self.reset();
        Some(Event::Truncated(pending))
    }

    #[inline]
    fn item<'a>(&'a self, _input: &'a [u8], (len, has_crc): (usize, bool)) -> Frame<'a> {
        self.found_frame(len, has_crc)
    }
}

/// Enough for the data of every typed message: the longest text with its NUL, or the longest
/// fixed layout.
const SCRATCH: usize = TEXT_CAPACITY + 1;
const _: () = assert!(crate::message::Compass::LEN <= SCRATCH);

/// Message data, emitted into `scratch` unless the message holds its bytes already.
pub(crate) fn message_data<'m>(
    message: &'m Message<'_>,
    scratch: &'m mut [u8; SCRATCH],
) -> Result<&'m [u8], Error> {
    match message {
        Message::CalibInfo(d) | Message::DebugInfo(d) | Message::Log(d) => Ok(d),
        Message::Unknown { data, .. } => Ok(data),
        other => {
            let n = other.emit(scratch)?;
            Ok(scratch.get(..n).unwrap_or(&[]))
        }
    }
}

/// A zeroed scratch buffer for [`message_data`].
pub(crate) const fn scratch() -> [u8; SCRATCH] {
    [0; SCRATCH]
}

/// The wire bytes of one frame, to be written a chunk at a time.
pub(crate) fn frame_bytes(id: u8, data: &[u8], crc: CrcMode) -> FrameBytes<'_> {
    FrameBytes::new(id, data, crc)
}
