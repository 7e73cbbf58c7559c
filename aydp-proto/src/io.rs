//! What the `embedded-io` and `embedded-io-async` readers and writers share: the error type,
//! the reader's buffer and decode loop, and the chunking of the writers. The two feature
//! modules only add the `read`/`write` calls (blocking or `.await`) around these.

use core::fmt;

use crate::decoder::{Decoder, Found};
use crate::encoder::{Bytes, Payload};
use crate::error::Error;
use crate::frame::Frame;

/// The error of a reader or writer over `embedded-io` or `embedded-io-async`: the transport's
/// error `E` and the protocol's [`Error`] are kept apart.
///
/// After [`IoError::Protocol`] the reader goes on with the bytes after the failed candidate
/// (the decoder's rescan); after [`IoError::Transport`] it keeps every byte already read, so
/// reading again is fine if the transport recovers.
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
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum IoError<E> {
    /// The transport (the `Read` or `Write` implementation) failed.
    Transport(E),
    /// A candidate failed (bad length or checksum), or a message could not be encoded.
    Protocol(Error),
    /// The stream ended (a read returned 0 bytes) inside a message: an incomplete candidate
    /// of `pending` bytes was given up. Its bytes are rescanned, so messages hidden in it
    /// still follow, then [`IoError::Eof`].
    UnexpectedEof {
        /// Bytes of the incomplete candidate.
        pending: usize,
    },
    /// The stream ended and the decoder is empty.
    Eof,
    /// A `write` accepted no bytes of a non-empty buffer.
    WriteZero,
}

impl<E> IoError<E> {
    /// Whether this is a protocol error (the stream is still usable).
    ///
    /// ```
    /// use aydp_proto::IoError;
    /// assert!(!IoError::<()>::Eof.is_protocol());
    /// ```
    pub const fn is_protocol(&self) -> bool {
        matches!(self, IoError::Protocol(_))
    }
}

impl<E: fmt::Debug> fmt::Display for IoError<E> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            IoError::Transport(e) => write!(f, "transport error: {e:?}"),
            IoError::Protocol(e) => write!(f, "protocol error: {e}"),
            IoError::UnexpectedEof { pending } => {
                write!(
                    f,
                    "end of stream inside a message ({pending} bytes given up)"
                )
            }
            IoError::Eof => f.write_str("end of stream"),
            IoError::WriteZero => f.write_str("the transport accepted no bytes"),
        }
    }
}

impl<E: fmt::Debug> core::error::Error for IoError<E> {}

/// What the reader found, without borrowing it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Token {
    /// A frame of this many bytes in the decoder's buffer.
    Held(usize),
    InPlace {
        from: usize,
        len: usize,
    },
    Error(Error),
    UnexpectedEof(usize),
    Eof,
}

/// The reader's state: the decoder, the read buffer and the unread part of it.
#[derive(Debug, Clone)]
pub(crate) struct ReaderCore<const N: usize, const R: usize> {
    pub(crate) decoder: Decoder<N>,
    buf: [u8; R],
    start: usize,
    end: usize,
    /// The stream ended: hand out what `flush` would, then [`Token::Eof`].
    ending: bool,
}

impl<const N: usize, const R: usize> ReaderCore<N, R> {
    pub(crate) const fn new(decoder: Decoder<N>) -> Self {
        const { assert!(R > 0, "the read buffer needs at least one byte") };
        Self {
            decoder,
            buf: [0; R],
            start: 0,
            end: 0,
            ending: false,
        }
    }

    /// Decodes the unread bytes (and events a rescan left queued) up to the first event.
    pub(crate) fn decode(&mut self) -> Option<Token> {
        if self.ending {
            return Some(self.end_step());
        }
        let unread = self.buf.get(self.start..self.end).unwrap_or(&[]);
        let (used, found) = self.decoder.feed_until(unread);
        let base = self.start;
        self.start = self.start.saturating_add(used);
        Some(match found {
            Found::Nothing => return None,
            Found::Held(len) => Token::Held(len),
            Found::InPlace { at, len } => Token::InPlace {
                from: base.saturating_add(at),
                len,
            },
            Found::Error(e) => Token::Error(e),
            Found::Truncated(n) => Token::UnexpectedEof(n),
        })
    }

    fn end_step(&mut self) -> Token {
        match self.decoder.flush_until() {
            None => {
                self.ending = false;
                Token::Eof
            }
            Some(Found::Truncated(n)) => Token::UnexpectedEof(n),
            Some(Found::Error(e)) => Token::Error(e),
            Some(Found::Held(len)) => Token::Held(len),
            // `flush_until` never reports these (nothing is fed).
            Some(Found::Nothing | Found::InPlace { .. }) => Token::Eof,
        }
    }

    /// The buffer to read into; only called once every byte was decoded.
    pub(crate) fn space(&mut self) -> &mut [u8] {
        self.start = 0;
        self.end = 0;
        &mut self.buf
    }

    /// `n` bytes were read into [`Self::space`]; 0 is the end of the stream.
    pub(crate) fn filled(&mut self, n: usize) -> Option<Token> {
        if n != 0 {
            self.end = n.min(R);
            return None;
        }
        self.ending = true;
        Some(self.end_step())
    }

    /// Turns a token into what the reader returns.
    pub(crate) fn take<E>(&self, token: Token) -> Result<Frame<'_>, IoError<E>> {
        match token {
            Token::Held(len) => Ok(self.decoder.held_frame(len)),
            Token::InPlace { from, len } => {
                let end = from.saturating_add(len);
                let bytes = self.buf.get(from..end).unwrap_or(&[]);
                Ok(Frame::new_unchecked(bytes, self.decoder.profile()))
            }
            Token::Error(e) => Err(IoError::Protocol(e)),
            Token::UnexpectedEof(pending) => Err(IoError::UnexpectedEof { pending }),
            Token::Eof => Err(IoError::Eof),
        }
    }

    /// The bytes read from the transport but not decoded yet.
    pub(crate) fn unread(&self) -> usize {
        self.end.saturating_sub(self.start)
    }
}

/// The writers hand the transport at most this many bytes at a time.
pub(crate) const CHUNK: usize = 32;

/// Fills `chunk` from `bytes`; returns how many bytes it holds (0: the message is out).
pub(crate) fn fill<P: Payload + ?Sized>(
    chunk: &mut [u8; CHUNK],
    bytes: &mut Bytes<'_, P>,
) -> usize {
    let mut n = 0;
    for slot in chunk.iter_mut() {
        let Some(b) = bytes.next() else { break };
        *slot = b;
        n += 1;
    }
    n
}
