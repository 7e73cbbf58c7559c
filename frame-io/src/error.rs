//! The error of the readers and writers.

use core::fmt;

/// The error of a reader or writer: the transport's error `E` and the protocol's error `P`
/// are kept apart. The protocol crates name it with their own error: `IoError<E>` there is
/// `IoError<E, Error>` here.
///
/// After [`IoError::Protocol`] the reader goes on with the bytes after the failed frame (the
/// decoder has resynchronised); after [`IoError::Transport`] it keeps every byte already
/// read, so reading again is fine if the transport recovers (a UART overrun, say).
///
/// ```
/// use frame_io::IoError;
/// let e: IoError<core::convert::Infallible, &str> = IoError::Protocol("bad checksum");
/// assert!(e.is_protocol());
/// assert_eq!(e.to_string(), "protocol error: bad checksum");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum IoError<E, P> {
    /// The transport (the `Read` or `Write` implementation) failed.
    Transport(E),
    /// A frame was dropped (bad checksum, bad length, overflow, ...), or a message could not
    /// be encoded.
    Protocol(P),
    /// The stream ended (a read returned 0 bytes) inside a frame, of which `pending` bytes
    /// were held. What becomes of them is the protocol's rule (its decoder's `finish`):
    /// dropped, or given up and rescanned, so items hidden in them may still follow;
    /// then [`IoError::Eof`].
    UnexpectedEof {
        /// The bytes of the unfinished frame.
        pending: usize,
    },
    /// The stream ended and nothing is held.
    Eof,
    /// A `write` accepted no bytes of a non-empty buffer.
    WriteZero,
}

impl<E, P> IoError<E, P> {
    /// Whether this is a protocol error (the stream is still usable).
    ///
    /// ```
    /// use frame_io::IoError;
    /// assert!(!IoError::<(), ()>::Eof.is_protocol());
    /// assert!(IoError::<(), ()>::Protocol(()).is_protocol());
    /// ```
    pub const fn is_protocol(&self) -> bool {
        matches!(self, IoError::Protocol(_))
    }
}

impl<E: fmt::Debug, P: fmt::Display> fmt::Display for IoError<E, P> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            IoError::Transport(e) => write!(f, "transport error: {e:?}"),
            IoError::Protocol(e) => write!(f, "protocol error: {e}"),
            IoError::UnexpectedEof { pending } => {
                write!(f, "end of stream inside a frame ({pending} bytes pending)")
            }
            IoError::Eof => f.write_str("end of stream"),
            IoError::WriteZero => f.write_str("the transport accepted no bytes"),
        }
    }
}

impl<E: fmt::Debug, P: fmt::Debug + fmt::Display> core::error::Error for IoError<E, P> {}
