//! The contract: [`MessageDecoder`]'s [`Decode`] implementation, on the paths of `../byte.rs`.
//! `feed` and `decode` run the step over the input itself while nothing is held.

use frame_io::{Decode, Event, Span};

use super::*;
use crate::decoder::byte::Rules;
use crate::decoder::{end_of_stream, event};

/// The contract ([`Decode`]): `feed` every slice of the stream, `finish` when the line goes
/// quiet; `decode`, `end` and `item` are the pull form, for a caller that must act between
/// two messages (the readers of `embedded_io`). A found message is the [`Message`] itself.
///
/// `feed` is the bulk path: it gives exactly the events of feeding the bytes one at a time
/// (same events in the same order, same counters, same pending request, same bytes held: the
/// same step decides), but while the decoder holds nothing the step runs on `bytes` itself,
/// without copying, and a false start's rescan is simply the next position in `bytes`. Bytes
/// held from an earlier call go through the byte-by-byte path, and so does a one-byte slice;
/// a frame cut by the end of the slice (at most 18 bytes) is copied into the buffer.
///
/// ```
/// use aok_proto::{Ack, DebugValue, Decode, Event, Expect, FirmwareVersion, Message, MessageDecoder};
/// let mut dec = MessageDecoder::new(FirmwareVersion::LATEST);
/// dec.expect(Expect::Ack);
/// let mut got = Vec::new();
/// // A debug frame, the ack, and the first half of the next debug frame.
/// dec.feed(&[0x1c, 0x56, 0xff, 0xff, 0xff, 0xfe, 0x57, b'O', 0x1c, 0x56], |event| got.push(event));
/// assert_eq!(got, [
///     Ok(Message::Debug(DebugValue { number: 86, value: -2 })),
///     Ok(Message::Ack(Ack::Ok)),
/// ]);
/// assert_eq!(dec.expecting(), Expect::Nothing);
/// assert_eq!(dec.held_bytes(), 2);
/// dec.feed(&[0, 0, 0, 1, 0x57], |event| got.push(event));
/// assert_eq!(got[2], Ok(Message::Debug(DebugValue { number: 86, value: 1 })));
///
/// // The pull form: up to the first event, then the end of the stream.
/// let wire = [0x1c, 0x56, 0xff, 0xff, 0xff, 0xfe, 0x57, 0x1c];
/// let debug = Message::Debug(DebugValue { number: 86, value: -2 });
/// assert_eq!(dec.decode(&wire), (7, Some(Event::Found(debug))));
/// assert_eq!(dec.decode(&wire[7..]), (1, None));
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
/// - a message: its frame (`len` its [`Message::buffer_len`] in the reply form in use: a
///   debug frame 7 bytes, an ack 1, a parameter reply 7 headed or 5 headerless, a waypoint
///   reply 19);
/// - a checksum failure ([`Error::ChecksumMismatch`]) or a good checksum with an out-of-range
///   field: the whole candidate frame it condemns (the length its first byte gives; a
///   headerless reply candidate's 5 bytes), though only its first byte is dropped and the
///   bytes after it are read again;
/// - the end of the stream inside a frame ([`Event::Truncated`]): every byte of the frame cut
///   short, so that it ends where the stream ends (and so does the next one a rescan gives
///   up);
///
/// and `after` is the bytes used after the event's last byte: 0, or the bytes that follow a
/// message or error that a rescan found inside a condemned candidate. `decode` uses a
/// condemned candidate's bytes whole (those after its first are held for the rescan, whose
/// events come with no byte used); `feed` records no span.
///
/// ```
/// use aok_proto::{Ack, DebugValue, Decode, Error, Event, Expect, FirmwareVersion, Message};
/// use aok_proto::{MessageDecoder, Place, Span, Stream};
/// let mut dec = MessageDecoder::new(FirmwareVersion::LATEST);
/// let debug = [0x1c, 0x56, 0xff, 0xff, 0xff, 0xfe, 0x57];
/// let found = Message::Debug(DebugValue { number: 86, value: -2 });
/// assert_eq!(dec.decode(&debug), (7, Some(Event::Found(found))));
/// assert_eq!(dec.span(), Span { len: 7, after: 0 });
/// // A debug frame whose checksum fails condemns its 7 bytes; the rescan finds the ack
/// // inside it, with 5 bytes used after it.
/// dec.expect(Expect::Ack);
/// let wire = [0x1c, b'O', 0, 0, 0, 0, 0];
/// let (used, event) = dec.decode(&wire);
/// assert!(matches!(event, Some(Event::Error(Error::ChecksumMismatch { id: 0x1c, .. }))));
/// assert_eq!((used, dec.span()), (7, Span { len: 7, after: 0 }));
/// assert_eq!(dec.decode(&[]), (0, Some(Event::Found(Message::Ack(Ack::Ok)))));
/// assert_eq!(dec.span(), Span { len: 1, after: 5 });
///
/// // Through a `Stream`: the same bytes, then half a debug frame, with their places.
/// let mut decoder = MessageDecoder::new(FirmwareVersion::LATEST);
/// decoder.expect(Expect::Ack);
/// let mut stream = Stream::new(decoder);
/// let mut got = Vec::new();
/// stream.feed(&wire, |place, event| got.push((place, event.is_ok())));
/// stream.feed(&debug[..2], |place, event| got.push((place, event.is_ok())));
/// stream.finish(|place, event| got.push((place, event.is_ok())));
/// assert_eq!(got, [
///     (Place { offset: 0, len: 7 }, false), // the condemned debug frame
///     (Place { offset: 1, len: 1 }, true),  // the ack inside it
///     (Place { offset: 7, len: 2 }, false), // cut short by the end of the stream
/// ]);
/// ```
impl Decode for MessageDecoder {
    type Error = Error;
    type Found = Message;
    type Item<'a> = Message;
    const TRUNCATED: Error = Error::Truncated;

    /// Decodes `bytes` up to and including the first message or error, with the bulk path of
    /// `feed`; events a rescan left queued come first. Calling it until it finds nothing in
    /// an empty slice gives exactly the events of `feed`.
    ///
    /// ```
    /// use aok_proto::{DebugValue, Decode, Event, FirmwareVersion, Message, MessageDecoder};
    /// let mut dec = MessageDecoder::new(FirmwareVersion::LATEST);
    /// let two = [0x1c, 0x56, 0xff, 0xff, 0xff, 0xfe, 0x57, 0x1c, 0x56, 0, 0, 0, 1, 0x57];
    /// let (n, event) = dec.decode(&two);
    /// assert_eq!((n, event), (7, Some(Event::Found(Message::Debug(DebugValue { number: 86, value: -2 })))));
    /// let (m, event) = dec.decode(&two[n..]);
    /// assert_eq!((m, event), (7, Some(Event::Found(Message::Debug(DebugValue { number: 86, value: 1 })))));
    /// assert_eq!(dec.decode(&[]), (0, None));
    /// ```
    fn decode(&mut self, bytes: &[u8]) -> (usize, Option<Event<Message, Error>>) {
        // Only after an event out of the buffer: a drained decoder is not asked again, since
        // a pending request changed since (`expect`) could decide its held bytes otherwise
        // than the next byte will.
        if self.unpolled {
            if let Some(item) = self.poll() {
                return (0, event(Some(item)));
            }
            self.unpolled = false;
        }
        // One byte (a caller that acts after every byte): the byte path alone, so such a
        // caller links no slice path.
        match *bytes {
            [] => return (0, None),
            [byte] => {
                let found = self.push(byte);
                self.unpolled = found.is_some();
                return (1, event(found));
            }
            _ => {}
        }
        let (used, found) = self.decode_slice(bytes);
        (used, event(found))
    }

    /// The end of the stream, one event a call, the events of `finish`: each front that cannot
    /// complete given up as [`Event::Truncated`] with the bytes it dropped, and the messages
    /// and errors the rescan of the bytes after it finds.
    ///
    /// ```
    /// use aok_proto::{Ack, Decode, Event, Expect, FirmwareVersion, Message, MessageDecoder};
    /// let mut dec = MessageDecoder::new(FirmwareVersion::LATEST);
    /// dec.expect(Expect::Ack);
    /// dec.feed(&[0x1c, 0x56, b'O'], |_| {}); // the ack inside a debug frame cut short
    /// assert_eq!(dec.end(), Some(Event::Truncated(1))); // 0x1c; then 0x56 starts no frame
    /// assert_eq!(dec.end(), Some(Event::Found(Message::Ack(Ack::Ok))));
    /// assert_eq!(dec.end(), None);
    /// ```
    ///
    /// `finish`, the trait's loop over `end`, hands out the same events:
    ///
    /// ```
    /// use aok_proto::{Ack, Decode, Error, Expect, FirmwareVersion, Message, MessageDecoder};
    /// let mut dec = MessageDecoder::new(FirmwareVersion::LATEST);
    /// dec.expect(Expect::Ack);
    /// // A debug frame cut short, then the ack: the ack is inside the debug candidate...
    /// let mut got = Vec::new();
    /// dec.feed(&[0x1c, 0x56, b'O'], |event| got.push(event));
    /// assert!(got.is_empty());
    /// // ...until the line goes quiet.
    /// dec.finish(|event| got.push(event));
    /// assert_eq!(got, [Err(Error::Truncated), Ok(Message::Ack(Ack::Ok))]);
    /// ```
    fn end(&mut self) -> Option<Event<Message, Error>> {
        self.unpolled = false;
        end_of_stream!(self, self.quiet_next())
    }

    /// Where the event that `decode` or `end` last returned lies (see the implementation's
    /// documentation).
    ///
    /// ```
    /// use aok_proto::{Decode, Expect, FirmwareVersion, MessageDecoder, Span};
    /// let mut dec = MessageDecoder::new(FirmwareVersion::LATEST);
    /// dec.expect(Expect::Ack);
    /// dec.decode(b"O");
    /// assert_eq!(dec.span(), Span { len: 1, after: 0 });
    /// ```
    #[inline]
    fn span(&self) -> Span {
        self.held.span
    }

    /// The message itself.
    ///
    /// ```
    /// use aok_proto::{Ack, Decode, FirmwareVersion, Message, MessageDecoder};
    /// let dec = MessageDecoder::new(FirmwareVersion::LATEST);
    /// assert_eq!(dec.item(&[], Message::Ack(Ack::Ok)), Message::Ack(Ack::Ok));
    /// ```
    #[inline]
    fn item<'a>(&'a self, _input: &'a [u8], found: Message) -> Message {
        found
    }

    /// Feeds a slice and hands every event (messages and failures) to `on_event`, in order
    /// (the bulk path).
    ///
    /// ```
    /// use aok_proto::{Ack, Decode, Expect, FirmwareVersion, Message, MessageDecoder};
    /// let mut dec = MessageDecoder::new(FirmwareVersion::LATEST);
    /// dec.expect(Expect::Ack);
    /// let mut got = Vec::new();
    /// dec.feed(b"O", |event| got.push(event));
    /// assert_eq!(got, [Ok(Message::Ack(Ack::Ok))]);
    /// ```
    #[inline]
    fn feed<F>(&mut self, bytes: &[u8], mut on_event: F)
    where
        F: FnMut(Result<Message, Error>),
    {
        // One byte (an interrupt handler's): the byte path alone.
        if let [byte] = *bytes {
            return self.feed_byte(byte, &mut on_event);
        }
        self.feed_slice(bytes, on_event);
    }
}
