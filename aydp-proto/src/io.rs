//! What the `embedded-io` and `embedded-io-async` readers and writers share: the error type.
//! The readers are `frame-io`'s, driving the decoder's [`Decode`](crate::Decode)
//! implementation; the two feature modules only name them and add the writers' calls
//! (blocking or `.await`) around `frame-io`'s write loop.

use crate::error::{EncodeError, Error};

/// The error of a reader or writer over `embedded-io` or `embedded-io-async`
/// ([`frame_io::IoError`] with this crate's [`Error`]): the transport's error `E` and the
/// protocol's are kept apart.
///
/// After [`IoError::Protocol`] the reader goes on with the bytes after the failed candidate
/// (the decoder's rescan); after [`IoError::Transport`] it keeps every byte already read, so
/// reading again is fine if the transport recovers. At the end of the stream inside a
/// message, the incomplete candidate is given up ([`IoError::UnexpectedEof`]`{ pending }`, its
/// bytes) and its bytes rescanned as [`Decode::finish`](crate::Decode::finish) does, so
/// messages hidden in it still follow, then [`IoError::Eof`].
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

/// The error of a writer over `embedded-io` or `embedded-io-async` ([`frame_io::IoError`] with
/// this crate's [`EncodeError`]): the transport's error `E`, or the message could not be
/// encoded (nothing was written).
///
/// ```
/// use aydp_proto::{EncodeError, WriteError};
/// let e: WriteError<core::convert::Infallible> = WriteError::Protocol(EncodeError::TooLong);
/// assert_eq!(e.to_string(), "protocol error: message too long for the length field");
/// ```
pub type WriteError<E> = frame_io::IoError<E, EncodeError>;
