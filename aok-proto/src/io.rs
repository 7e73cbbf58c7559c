//! What the `embedded-io` and `embedded-io-async` readers and writers share: the error type
//! and the writers' encoding. The readers are `frame-io`'s, over the decoders' [`Decode`](crate::Decode)
//! implementations (in `decoder/`); the two feature modules only name them and add the
//! writers' calls (blocking or `.await`) around `frame-io`'s write loop.

use crate::Error;
use crate::command::{Command, MAX_COMMAND_LEN};
use crate::message::Message;
use crate::values::ReplyForm;

/// The error of a reader or writer over `embedded-io` or `embedded-io-async`
/// ([`frame_io::IoError`] with this crate's [`Error`]): the transport's error `E` and the
/// protocol's are kept apart.
///
/// After [`IoError::Protocol`] the reader goes on with the bytes after the failed frame; after
/// [`IoError::Transport`] it keeps every byte already read, so reading again is fine if the
/// transport recovers. At the end of the stream inside a frame,
/// [`IoError::UnexpectedEof`]`{ pending }` counts the bytes buffered; they are then rescanned
/// as by [`Decode::finish`](crate::Decode::finish), so a message hidden in them still follows, then
/// [`IoError::Eof`].
///
/// ```
/// use aok_proto::{Error, IoError};
/// let e: IoError<core::convert::Infallible> = IoError::Protocol(Error::ChecksumMismatch {
///     id: 0x31,
///     computed: 0x56,
///     received: 0x0c,
/// });
/// assert!(e.is_protocol());
/// assert_eq!(e.to_string(), "protocol error: checksum mismatch");
/// ```
pub type IoError<E> = frame_io::IoError<E, Error>;

/// The wire bytes of a command.
pub(crate) fn command_bytes(command: &Command) -> ([u8; MAX_COMMAND_LEN], usize) {
    command.wire()
}

/// The wire bytes of a device message in `form`. Every message is one frame, and the longest
/// frame (a waypoint) is [`MAX_COMMAND_LEN`] bytes, so emitting into the buffer cannot fail.
pub(crate) fn message_bytes(message: &Message, form: ReplyForm) -> ([u8; MAX_COMMAND_LEN], usize) {
    let mut buf = [0u8; MAX_COMMAND_LEN];
    let n = message.emit(&mut buf, form).unwrap_or(0);
    (buf, n)
}

/// The error of a writer over `embedded-io` or `embedded-io-async`: the transport's error `E`
/// ([`frame_io::IoError::Transport`] or [`frame_io::IoError::WriteZero`]). Encoding cannot
/// fail here (every message fits the writer's buffer), so the protocol side is
/// [`Infallible`](core::convert::Infallible) and a `match` needs no arm for it.
///
/// ```
/// use aok_proto::WriteError;
/// let e: WriteError<&str> = WriteError::Transport("reset");
/// let text = match e {
///     WriteError::Transport(t) => t,
///     WriteError::WriteZero | WriteError::Eof | WriteError::UnexpectedEof { .. } => "",
/// };
/// assert_eq!(text, "reset");
/// ```
pub type WriteError<E> = frame_io::IoError<E, core::convert::Infallible>;
