//! What the `embedded-io` and `embedded-io-async` readers and writers share: the error type,
//! and the message-to-bytes step of the writers. The two feature modules only name the
//! readers and add the writers' calls (blocking or `.await`) around these.

use crate::message::Message;
use crate::{CrcMode, Error, FrameBytes, TEXT_CAPACITY};

/// The error of a reader or writer over `embedded-io` or `embedded-io-async`
/// ([`frame_io::IoError`] with this crate's [`Error`]): the transport's error `E` and the
/// protocol's are kept apart.
///
/// After [`IoError::Protocol`] the reader has resynchronised and the next read continues with
/// the next frame; after [`IoError::Transport`] it keeps every byte already read, so reading
/// again is fine if the transport recovers (a UART overrun, say). At the end of the stream
/// inside a frame, the frame's bytes are dropped and counted in
/// [`IoError::UnexpectedEof`]`{ pending }` (as [`crate::Decode::finish`] does), then comes
/// [`IoError::Eof`].
///
/// ```
/// use aeolus_proto::{Error, IoError};
/// let e: IoError<core::convert::Infallible> = IoError::Protocol(Error::TooShort);
/// assert!(e.is_protocol());
/// assert_eq!(e.to_string(), "protocol error: frame too short to hold an ID and a CRC");
/// ```
pub type IoError<E> = frame_io::IoError<E, Error>;

/// Enough for the data of every typed message: the longest text with its NUL, or the longest
/// fixed layout.
const SCRATCH: usize = TEXT_CAPACITY + 1;
const _: () = assert!(crate::message::Compass::LEN <= SCRATCH);

/// Message data, emitted into `scratch` unless the message holds its bytes already. `scratch`
/// holds every typed message's data (checked above), so emitting into it cannot fail.
pub(crate) fn message_data<'m>(
    message: &'m Message<'_>,
    scratch: &'m mut [u8; SCRATCH],
) -> &'m [u8] {
    match message {
        Message::CalibInfo(d) | Message::DebugInfo(d) | Message::Log(d) => d,
        Message::Unknown { data, .. } => data,
        other => {
            let n = other.emit(scratch).unwrap_or(0);
            scratch.get(..n).unwrap_or(&[])
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

/// The error of a writer over `embedded-io` or `embedded-io-async`: the transport's error `E`
/// ([`frame_io::IoError::Transport`] or [`frame_io::IoError::WriteZero`]). Encoding cannot
/// fail here (every message fits the writer's buffer), so the protocol side is
/// [`Infallible`](core::convert::Infallible) and a `match` needs no arm for it.
///
/// ```
/// use aeolus_proto::WriteError;
/// let e: WriteError<&str> = WriteError::Transport("reset");
/// let text = match e {
///     WriteError::Transport(t) => t,
///     WriteError::WriteZero | WriteError::Eof | WriteError::UnexpectedEof { .. } => "",
/// };
/// assert_eq!(text, "reset");
/// ```
pub type WriteError<E> = frame_io::IoError<E, core::convert::Infallible>;
