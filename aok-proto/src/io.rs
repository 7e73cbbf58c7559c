//! What the `embedded-io` and `embedded-io-async` readers and writers share: the error type,
//! the decoders' [`frame_io::Decode`] implementations that the readers of `frame-io` drive,
//! and the writers' encoding. The two feature modules only name the readers and add the
//! writers' calls (blocking or `.await`) around `frame-io`'s write loop.

use frame_io::{Decode, Event};

use crate::Error;
use crate::command::{Command, MAX_COMMAND_LEN};
use crate::device::DeviceDecoder;
use crate::message::Message;
use crate::pc::PcDecoder;
use crate::values::ReplyForm;

/// The error of a reader or writer over `embedded-io` or `embedded-io-async`
/// ([`frame_io::IoError`] with this crate's [`Error`]): the transport's error `E` and the
/// protocol's are kept apart.
///
/// After [`IoError::Protocol`] the reader goes on with the bytes after the failed frame; after
/// [`IoError::Transport`] it keeps every byte already read, so reading again is fine if the
/// transport recovers. At the end of the stream inside a frame,
/// [`IoError::UnexpectedEof`]`{ pending }` counts the bytes buffered; they are then rescanned
/// as after [`PcDecoder::idle`], so a message hidden in them still follows, then
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

/// The end of the stream of either decoder: first the bytes buffered, as `Truncated`; then
/// what `idle` finds in them, without the `Truncated` of frames it gives up (the reader has
/// reported the end inside a frame once).
fn end<T>(
    first: bool,
    held: usize,
    mut idle_next: impl FnMut() -> Option<Result<T, Error>>,
) -> Option<Event<T, Error>> {
    if first && held > 0 {
        return Some(Event::Truncated(held));
    }
    loop {
        match idle_next()? {
            Ok(item) => return Some(Event::Found(item)),
            Err(Error::Truncated) => {}
            Err(e) => return Some(Event::Error(e)),
        }
    }
}

#[inline]
fn event<T>(found: Option<Result<T, Error>>) -> Option<Event<T, Error>> {
    Some(match found? {
        Ok(item) => Event::Found(item),
        Err(e) => Event::Error(e),
    })
}

/// The PC side's reader decoding: [`PcDecoder::feed`]'s bulk path up to the first message;
/// at the end of the stream, the bytes buffered (`Truncated`), then what [`PcDecoder::idle`]
/// finds in them. A found message is the [`Message`] itself.
///
/// ```
/// use aok_proto::{pc::PcDecoder, DebugValue, FirmwareVersion, Message};
/// use frame_io::{Decode, Event};
/// let mut d = PcDecoder::new(FirmwareVersion::LATEST);
/// let wire = [0x1c, 0x56, 0xff, 0xff, 0xff, 0xfe, 0x57, 0x1c];
/// let debug = Message::Debug(DebugValue { number: 86, value: -2 });
/// assert_eq!(d.decode(&wire), (7, Some(Event::Found(debug))));
/// assert_eq!(d.decode(&wire[7..]), (1, None));
/// assert_eq!(d.end(true), Some(Event::Truncated(1)));
/// ```
impl Decode for PcDecoder {
    type Error = Error;
    type Found = Message;
    type Item<'a> = Message;
    const TRUNCATED: Error = Error::Truncated;

    #[inline]
    fn decode(&mut self, bytes: &[u8]) -> (usize, Option<Event<Message, Error>>) {
        let (used, found) = self.feed_until(bytes);
        (used, event(found))
    }

    fn end(&mut self, first: bool) -> Option<Event<Message, Error>> {
        end(first, self.held_bytes(), || self.idle_next())
    }

    #[inline]
    fn item<'a>(&'a self, _input: &'a [u8], found: Message) -> Message {
        found
    }
}

/// The device side's reader decoding: [`DeviceDecoder::feed`]'s bulk path up to the first
/// command; at the end of the stream, the bytes buffered (`Truncated`), then what
/// [`DeviceDecoder::idle`] finds in them. A found command is the [`Command`] itself.
///
/// ```
/// use aok_proto::{Command, DeviceDecoder};
/// use frame_io::{Decode, Event};
/// let mut d = DeviceDecoder::new();
/// assert_eq!(d.decode(&[0x67, 0x0c, 0x31]), (2, Some(Event::Found(Command::ReadParameter(12)))));
/// assert_eq!(d.decode(&[0x31]), (1, None));
/// assert_eq!(d.end(true), Some(Event::Truncated(1)));
/// ```
impl Decode for DeviceDecoder {
    type Error = Error;
    type Found = Command;
    type Item<'a> = Command;
    const TRUNCATED: Error = Error::Truncated;

    #[inline]
    fn decode(&mut self, bytes: &[u8]) -> (usize, Option<Event<Command, Error>>) {
        let (used, found) = self.feed_until(bytes);
        (used, event(found))
    }

    fn end(&mut self, first: bool) -> Option<Event<Command, Error>> {
        end(first, self.held_bytes(), || self.idle_next())
    }

    #[inline]
    fn item<'a>(&'a self, _input: &'a [u8], found: Command) -> Command {
        found
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

/// Liveness: the end of the stream reports the bytes held once, then rescans. A mutant that
/// reports them again makes the readers of `tests/io.rs` spin (a hang, not a failure); this
/// fails at once instead (unit tests run before the integration tests).
#[cfg(test)]
mod liveness {
    use super::*;

    #[test]
    fn the_end_reports_the_bytes_held_once() {
        let mut d = DeviceDecoder::new();
        assert_eq!(Decode::decode(&mut d, &[0x31]), (1, None));
        assert_eq!(Decode::end(&mut d, true), Some(Event::Truncated(1)));
        assert_eq!(Decode::end(&mut d, false), None);
        assert_eq!(Decode::end(&mut d, true), None);
        let mut p = PcDecoder::new(crate::FirmwareVersion::LATEST);
        assert_eq!(Decode::decode(&mut p, &[0x1c, 0x56]), (2, None));
        assert_eq!(Decode::end(&mut p, true), Some(Event::Truncated(2)));
        assert!(!matches!(
            Decode::end(&mut p, false),
            Some(Event::Truncated(_))
        ));
    }
}
