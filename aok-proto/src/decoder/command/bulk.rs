//! The contract: [`CommandDecoder`]'s [`Decode`] implementation, on the paths of `../byte.rs`.
//! `feed` and `decode` run the step over the input itself while nothing is held.

use frame_io::{Decode, Event, Span};

use super::*;
use crate::decoder::byte::Rules;
use crate::decoder::{end_of_stream, event};

/// The contract ([`Decode`]): `feed` every slice of the stream, `finish` when the line goes
/// quiet; `decode`, `end` and `item` are the pull form, for a caller that must act between
/// two commands (the readers of `embedded_io`, a firmware checking its TX room). A found
/// command is the [`Command`] itself.
///
/// `feed` is the bulk path: it gives exactly the events of feeding the bytes one at a time
/// (same events in the same order, same counters, same bytes held: the same step decides),
/// but while the decoder holds nothing the step runs on `bytes` itself, without copying, and
/// a false start's rescan is simply the next position in `bytes`. Bytes held from an earlier
/// call go through the byte-by-byte path, and so does a one-byte slice (an interrupt
/// handler's); a command cut by the end of the slice (at most 18 bytes) is copied into the
/// buffer.
///
/// ```
/// use aok_proto::{Command, CommandDecoder, Decode, Error, Event};
/// let mut dec = CommandDecoder::new();
/// let mut got = Vec::new();
/// // Noise, a motor-test start whose checksum fails, a read, and half a read.
/// dec.feed(&[0x00, 0x31, 0x67, 0x0c, 0x67], |event| got.push(event));
/// let mismatch = Error::ChecksumMismatch { id: 0x31, computed: 0x56, received: 0x0c };
/// assert_eq!(got, [Err(mismatch), Ok(Command::ReadParameter(12))]);
/// assert_eq!(dec.held_bytes(), 1);
/// dec.feed(&[0x0d], |event| got.push(event));
/// assert_eq!(got[2], Ok(Command::ReadParameter(13)));
/// assert_eq!(dec.stats().unknown_bytes, 1);
///
/// // The pull form: up to the first event, then the end of the stream.
/// assert_eq!(dec.decode(&[0x67, 0x0c, 0x31]), (2, Some(Event::Found(Command::ReadParameter(12)))));
/// assert_eq!(dec.decode(&[0x31]), (1, None));
/// assert_eq!(dec.end(), Some(Event::Truncated(1)));
/// assert_eq!(dec.end(), None);
/// ```
///
/// # Where each event lies
///
/// [`Decode::span`] says where the event that `decode` or `end` last returned lies, counted
/// back from the end of the bytes used (a [`Stream`](crate::Stream) turns it into the event's
/// [`Place`](crate::Place) in the stream):
///
/// - a command: its frame (`len` its [`Command::buffer_len`], 2 to 19 bytes);
/// - a checksum failure ([`Error::ChecksumMismatch`]) or a good checksum with an out-of-range
///   field: the whole candidate command it condemns (the length its first bytes give), though
///   only its first byte is dropped and the bytes after it are read again;
/// - the end of the stream inside a command ([`Event::Truncated`]): every byte of the command
///   cut short, so that it ends where the stream ends (and so does the next one a rescan
///   gives up);
///
/// and `after` is the bytes used after the event's last byte: 0, or the bytes that follow a
/// command or error that a rescan found inside a condemned candidate. `decode` uses a
/// condemned candidate's bytes whole (those after its first are held for the rescan, whose
/// events come with no byte used); `feed` records no span.
///
/// ```
/// use aok_proto::{Command, CommandDecoder, Decode, Error, Event, Place, Span, Stream};
/// let mut dec = CommandDecoder::new();
/// assert_eq!(dec.decode(&[0x67, 0x0c]), (2, Some(Event::Found(Command::ReadParameter(12)))));
/// assert_eq!(dec.span(), Span { len: 2, after: 0 });
/// // A parameter set whose checksum fails condemns its 7 bytes; the rescan finds the read
/// // inside it, with 4 bytes used after it.
/// let wire = [0x73, 0x67, 0x0c, 0, 0, 0, 0];
/// let (used, event) = dec.decode(&wire);
/// assert!(matches!(event, Some(Event::Error(Error::ChecksumMismatch { id: 0x73, .. }))));
/// assert_eq!((used, dec.span()), (7, Span { len: 7, after: 0 }));
/// assert_eq!(dec.decode(&[]), (0, Some(Event::Found(Command::ReadParameter(12)))));
/// assert_eq!(dec.span(), Span { len: 2, after: 4 });
///
/// // Through a `Stream`: the same bytes, then half a parameter set, with their places.
/// let mut stream = Stream::new(CommandDecoder::new());
/// let mut got = Vec::new();
/// stream.feed(&wire, |place, event| got.push((place, event.is_ok())));
/// stream.feed(&[0x73, 0x01], |place, event| got.push((place, event.is_ok())));
/// stream.finish(|place, event| got.push((place, event.is_ok())));
/// assert_eq!(got, [
///     (Place { offset: 0, len: 7 }, false), // the condemned parameter set
///     (Place { offset: 1, len: 2 }, true),  // the read inside it
///     (Place { offset: 7, len: 2 }, false), // cut short by the end of the stream
/// ]);
/// ```
impl Decode for CommandDecoder {
    type Error = Error;
    type Found = Command;
    type Item<'a> = Command;
    const TRUNCATED: Error = Error::Truncated;

    /// Decodes `bytes` up to and including the first command or error, with the bulk path
    /// of `feed`; events a rescan left queued come first. Calling it until it finds nothing
    /// in an empty slice gives exactly the events of `feed`.
    ///
    /// ```
    /// use aok_proto::{Command, CommandDecoder, Decode, Event};
    /// let mut dec = CommandDecoder::new();
    /// // Two reads of parameters 12 and 13.
    /// let (n, event) = dec.decode(&[0x67, 0x0c, 0x67, 0x0d]);
    /// assert_eq!((n, event), (2, Some(Event::Found(Command::ReadParameter(12)))));
    /// let (m, event) = dec.decode(&[0x67, 0x0d]);
    /// assert_eq!((m, event), (2, Some(Event::Found(Command::ReadParameter(13)))));
    /// assert_eq!(dec.decode(&[]), (0, None));
    /// ```
    fn decode(&mut self, bytes: &[u8]) -> (usize, Option<Event<Command, Error>>) {
        if let Some(item) = self.poll() {
            return (0, event(Some(item)));
        }
        // One byte (a caller that acts after every byte, as the box's AOK link): the byte path
        // alone, so such a caller links no slice path.
        match *bytes {
            [] => return (0, None),
            [byte] => return (1, event(self.push(byte))),
            _ => {}
        }
        let (used, found) = self.decode_slice(bytes);
        (used, event(found))
    }

    /// The end of the stream, one event a call, the events of `finish`: each front that cannot
    /// complete given up as [`Event::Truncated`] with the bytes it dropped, and the commands
    /// and errors the rescan of the bytes after it finds.
    ///
    /// ```
    /// use aok_proto::{Command, CommandDecoder, Decode, Event};
    /// let mut dec = CommandDecoder::new();
    /// dec.feed(&[0x73, 0x63, 0x02], |_| {}); // 73 waits for 4 more bytes
    /// assert_eq!(dec.end(), Some(Event::Truncated(1)));
    /// assert_eq!(dec.end(), Some(Event::Found(Command::DebugOn)));
    /// assert_eq!(dec.end(), None);
    /// ```
    ///
    /// `finish`, the trait's loop over `end`, hands out the same events:
    ///
    /// ```
    /// use aok_proto::{Command, CommandDecoder, Decode, Error};
    /// let mut dec = CommandDecoder::new();
    /// dec.feed(&[0x73, 0x63, 0x02], |_| {}); // 73 waits for 4 more bytes
    /// let mut got = Vec::new();
    /// dec.finish(|event| got.push(event));
    /// assert_eq!(got, [Err(Error::Truncated), Ok(Command::DebugOn)]);
    /// assert_eq!(dec.stats().abandoned, 1);
    /// assert_eq!(dec.held_bytes(), 0);
    /// ```
    fn end(&mut self) -> Option<Event<Command, Error>> {
        end_of_stream!(self, self.quiet_next())
    }

    /// Where the event that `decode` or `end` last returned lies (see the implementation's
    /// documentation).
    ///
    /// ```
    /// use aok_proto::{CommandDecoder, Decode, Span};
    /// let mut dec = CommandDecoder::new();
    /// dec.decode(&[0x63, 0x02]); // debug on
    /// assert_eq!(dec.span(), Span { len: 2, after: 0 });
    /// ```
    #[inline]
    fn span(&self) -> Span {
        self.held.span
    }

    /// The command itself.
    ///
    /// ```
    /// use aok_proto::{Command, CommandDecoder, Decode};
    /// assert_eq!(CommandDecoder::new().item(&[], Command::DebugOn), Command::DebugOn);
    /// ```
    #[inline]
    fn item<'a>(&'a self, _input: &'a [u8], found: Command) -> Command {
        found
    }

    /// Feeds a slice and hands every event to `on_event`, in order (the bulk path).
    ///
    /// ```
    /// use aok_proto::{Command, CommandDecoder, Decode};
    /// let mut dec = CommandDecoder::new();
    /// let mut got = Vec::new();
    /// dec.feed(&[0x63, 0x01, 0x63], |event| got.push(event));
    /// dec.feed(&[0x02], |event| got.push(event)); // one byte at a time works the same
    /// assert_eq!(got, [Ok(Command::DebugOff), Ok(Command::DebugOn)]);
    /// ```
    #[inline]
    fn feed<F>(&mut self, bytes: &[u8], mut on_event: F)
    where
        F: FnMut(Result<Command, Error>),
    {
        // One byte (an interrupt handler's): the byte path alone.
        if let [byte] = *bytes {
            return self.feed_byte(byte, &mut on_event);
        }
        self.feed_slice(bytes, on_event);
    }
}
