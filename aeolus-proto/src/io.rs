//! What the `embedded-io` and `embedded-io-async` readers and writers share: the error type,
//! the reader's buffer and decode loop, and the message-to-bytes step of the writers. The two
//! feature modules only add the `read`/`write` calls (blocking or `.await`) around these.

use core::fmt;

use crate::decoder::Found;
use crate::message::Message;
use crate::{CrcMode, Decoder, Error, Frame, FrameBytes, TEXT_CAPACITY};

/// The error of a reader or writer over `embedded-io` or `embedded-io-async`: the transport's
/// error `E` and the protocol's [`Error`] are kept apart.
///
/// After [`IoError::Protocol`] the reader has resynchronised and the next read continues with
/// the next frame; after [`IoError::Transport`] it keeps every byte already read, so reading
/// again is fine if the transport recovers (a UART overrun, say).
///
/// ```
/// use aeolus_proto::{Error, IoError};
/// let e: IoError<core::convert::Infallible> = IoError::Protocol(Error::TooShort);
/// assert!(e.is_protocol());
/// assert_eq!(e.to_string(), "protocol error: frame too short to hold an ID and a CRC");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum IoError<E> {
    /// The transport (the `Read` or `Write` implementation) failed.
    Transport(E),
    /// A frame was dropped (bad CRC, bad escape, overflow...) or could not be encoded.
    Protocol(Error),
    /// The stream ended (a read returned 0 bytes) inside a frame: `pending` wire bytes of it
    /// were received and are dropped. The next read starts afresh.
    UnexpectedEof {
        /// Wire bytes of the unfinished frame.
        pending: usize,
    },
    /// The stream ended between frames.
    Eof,
    /// A `write` accepted no bytes of a non-empty buffer.
    WriteZero,
}

impl<E> IoError<E> {
    /// Whether this is a protocol error (the stream is still usable).
    ///
    /// ```
    /// use aeolus_proto::IoError;
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
                write!(f, "end of stream inside a frame ({pending} bytes dropped)")
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
    Frame { len: usize, has_crc: bool },
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
}

impl<const N: usize, const R: usize> ReaderCore<N, R> {
    pub(crate) const fn new(decoder: Decoder<N>) -> Self {
        const { assert!(R > 0, "the read buffer needs at least one byte") };
        Self {
            decoder,
            buf: [0; R],
            start: 0,
            end: 0,
        }
    }

    /// Decodes the unread bytes up to the first event.
    pub(crate) fn decode(&mut self) -> Option<Token> {
        let unread = self.buf.get(self.start..self.end).unwrap_or(&[]);
        if unread.is_empty() {
            return None;
        }
        let (used, found) = self.decoder.push_until(unread);
        self.start = self.start.saturating_add(used);
        match found {
            Found::Nothing => None,
            Found::Frame { len, has_crc } => Some(Token::Frame { len, has_crc }),
            Found::Error(e) => Some(Token::Error(e)),
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
        let pending = self.decoder.held_bytes();
        if pending == 0 {
            return Some(Token::Eof);
        }
        self.decoder.reset();
        Some(Token::UnexpectedEof(pending))
    }

    /// Turns a token into what the reader returns.
    pub(crate) fn take<E>(&self, token: Token) -> Result<Frame<'_>, IoError<E>> {
        match token {
            Token::Frame { len, has_crc } => Ok(self.decoder.found_frame(len, has_crc)),
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

/// Fills `chunk` from `bytes`; returns how many bytes it holds (0: the frame is out).
pub(crate) fn fill(chunk: &mut [u8; CHUNK], bytes: &mut FrameBytes<'_>) -> usize {
    let mut n = 0;
    for slot in chunk.iter_mut() {
        let Some(b) = bytes.next() else { break };
        *slot = b;
        n += 1;
    }
    n
}

/// The wire bytes of one frame, to be written a chunk at a time.
pub(crate) fn frame_bytes(id: u8, data: &[u8], crc: CrcMode) -> FrameBytes<'_> {
    FrameBytes::new(id, data, crc)
}
