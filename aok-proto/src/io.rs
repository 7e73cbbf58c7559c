//! What the `embedded-io` and `embedded-io-async` readers and writers share: the error type,
//! the readers' buffer and decode loop (one for both decoders), and the writers' encoding. The
//! two feature modules only add the `read`/`write` calls (blocking or `.await`) around these.

use core::fmt;

use crate::Error;
use crate::command::{Command, MAX_COMMAND_LEN};
use crate::device::DeviceDecoder;
use crate::message::Message;
use crate::pc::PcDecoder;
use crate::values::ReplyForm;

/// The error of a reader or writer over `embedded-io` or `embedded-io-async`: the transport's
/// error `E` and the protocol's [`Error`] are kept apart.
///
/// After [`IoError::Protocol`] the reader goes on with the bytes after the failed frame; after
/// [`IoError::Transport`] it keeps every byte already read, so reading again is fine if the
/// transport recovers.
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
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum IoError<E> {
    /// The transport (the `Read` or `Write` implementation) failed.
    Transport(E),
    /// A frame failed (checksum, out-of-range field), or a message could not be encoded.
    Protocol(Error),
    /// The stream ended (a read returned 0 bytes) inside a frame: `pending` bytes were
    /// buffered. They are then rescanned as after [`PcDecoder::idle`], so a message hidden
    /// in them still follows, then [`IoError::Eof`].
    UnexpectedEof {
        /// Bytes buffered when the stream ended.
        pending: usize,
    },
    /// The stream ended and nothing is buffered.
    Eof,
    /// A `write` accepted no bytes of a non-empty buffer.
    WriteZero,
}

impl<E> IoError<E> {
    /// Whether this is a protocol error (the stream is still usable).
    ///
    /// ```
    /// use aok_proto::IoError;
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
                write!(f, "end of stream inside a frame ({pending} bytes buffered)")
            }
            IoError::Eof => f.write_str("end of stream"),
            IoError::WriteZero => f.write_str("the transport accepted no bytes"),
        }
    }
}

impl<E: fmt::Debug> core::error::Error for IoError<E> {}

/// A decoder a reader can drive: [`PcDecoder`] or [`DeviceDecoder`].
pub(crate) trait Stream {
    /// A message or a command.
    type Item: Copy;
    /// `feed_until` of the decoder, with protocol errors as `Err`.
    fn feed_until(&mut self, bytes: &[u8]) -> (usize, Option<Result<Self::Item, Error>>);
    /// The next item of `idle`, without the `Truncated` of frames cut by the end.
    fn idle_next(&mut self) -> Option<Result<Self::Item, Error>>;
    /// Bytes buffered.
    fn held_bytes(&self) -> usize;
}

impl Stream for PcDecoder {
    type Item = Message;
    fn feed_until(&mut self, bytes: &[u8]) -> (usize, Option<Result<Message, Error>>) {
        PcDecoder::feed_until(self, bytes)
    }
    fn idle_next(&mut self) -> Option<Result<Message, Error>> {
        // The reader reports a frame cut by the end of the stream as `UnexpectedEof`.
        loop {
            match PcDecoder::idle_next(self)? {
                Err(Error::Truncated) => {}
                other => return Some(other),
            }
        }
    }
    fn held_bytes(&self) -> usize {
        PcDecoder::held_bytes(self)
    }
}

impl Stream for DeviceDecoder {
    type Item = Command;
    fn feed_until(&mut self, bytes: &[u8]) -> (usize, Option<Result<Command, Error>>) {
        DeviceDecoder::feed_until(self, bytes)
    }
    fn idle_next(&mut self) -> Option<Result<Command, Error>> {
        // The reader reports a frame cut by the end of the stream as `UnexpectedEof`.
        loop {
            match DeviceDecoder::idle_next(self)? {
                Err(Error::Truncated) => {}
                other => return Some(other),
            }
        }
    }
    fn held_bytes(&self) -> usize {
        DeviceDecoder::held_bytes(self)
    }
}

/// The reader's state: the decoder, the read buffer and the unread part of it.
#[derive(Debug, Clone)]
pub(crate) struct ReaderCore<D, const R: usize> {
    pub(crate) decoder: D,
    buf: [u8; R],
    start: usize,
    end: usize,
    /// The stream ended: hand out what `idle` finds, then [`IoError::Eof`].
    ending: bool,
}

/// What one step of the reader gives.
pub(crate) type Step<T, E> = Option<Result<T, IoError<E>>>;

impl<D: Stream, const R: usize> ReaderCore<D, R> {
    pub(crate) const fn new(decoder: D) -> Self {
        const { assert!(R > 0, "the read buffer needs at least one byte") };
        Self {
            decoder,
            buf: [0; R],
            start: 0,
            end: 0,
            ending: false,
        }
    }

    /// Decodes the unread bytes (and items left buffered) up to the first item.
    pub(crate) fn decode<E>(&mut self) -> Step<D::Item, E> {
        if self.ending {
            return Some(self.end_step());
        }
        let unread = self.buf.get(self.start..self.end).unwrap_or(&[]);
        let (used, item) = self.decoder.feed_until(unread);
        self.start = self.start.saturating_add(used);
        Some(item?.map_err(IoError::Protocol))
    }

    fn end_step<E>(&mut self) -> Result<D::Item, IoError<E>> {
        match self.decoder.idle_next() {
            Some(item) => item.map_err(IoError::Protocol),
            None => {
                self.ending = false;
                Err(IoError::Eof)
            }
        }
    }

    /// The buffer to read into; only called once every byte was decoded.
    pub(crate) fn space(&mut self) -> &mut [u8] {
        self.start = 0;
        self.end = 0;
        &mut self.buf
    }

    /// `n` bytes were read into [`Self::space`]; 0 is the end of the stream.
    pub(crate) fn filled<E>(&mut self, n: usize) -> Step<D::Item, E> {
        if n != 0 {
            self.end = n.min(R);
            return None;
        }
        self.ending = true;
        let pending = self.decoder.held_bytes();
        if pending == 0 {
            return Some(self.end_step());
        }
        Some(Err(IoError::UnexpectedEof { pending }))
    }

    /// The bytes read from the transport but not decoded yet.
    pub(crate) fn unread(&self) -> usize {
        self.end.saturating_sub(self.start)
    }
}

/// The wire bytes of a command.
pub(crate) fn command_bytes(command: &Command) -> ([u8; MAX_COMMAND_LEN], usize) {
    command.to_bytes()
}

/// The wire bytes of a device message in `form`.
pub(crate) fn message_bytes(
    message: &Message,
    form: ReplyForm,
) -> Result<([u8; MAX_COMMAND_LEN], usize), Error> {
    let mut buf = [0u8; MAX_COMMAND_LEN];
    let n = message.emit(form, &mut buf)?;
    Ok((buf, n))
}
