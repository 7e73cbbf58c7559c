//! Every event's place in its stream, through `Stream` (`frame_io::Stream`, re-exported), for
//! both decoders (`CommandDecoder`, `MessageDecoder`), on hostile streams (the pieces of
//! `bulk.rs`: frames of every kind, garbage, frames cut short or with a byte changed, mixed):
//!
//! - the events and their places are the same whether the stream is fed whole, byte by byte,
//!   in two pieces split at every point, or pulled one event a call, `finish` at the end;
//! - events come in the order of their first bytes, and items do not overlap;
//! - an item lies inside the stream, and its bytes alone give a fresh decoder (set up as the
//!   decoder was) that item and nothing else;
//! - an error lies inside the stream and its bytes alone give that error first; a frame cut
//!   short by the end of the stream ends where the stream ends;
//! - frames of every kind put back to back, with noise that starts none between them, come at
//!   exactly the offsets where they were put.
//!
//! And a few streams of literal bytes with their places.

use aok_proto::command::WAYPOINT;
use aok_proto::message::{DEBUG, PARAMETER_REPLY};
use aok_proto::{Ack, Command, CommandDecoder, DebugValue, Decode, Error, Expect};
use aok_proto::{FirmwareVersion, Message, MessageDecoder};
use aok_proto::{ParameterValue, Place, ReplyForm, Stream};
use proptest::prelude::*;

use crate::bulk::{command_frame, expect, firmware, message_frame, piece};
use crate::roundtrip::{command, waypoint};

/// An event with its place, its item owned.
type Placed<T> = (Place, Result<T, Error>);

/// Either decoder, for the helpers below.
trait Side: Decode<Error = Error> + Clone {
    /// What an item is, owned.
    type Owned: Clone + PartialEq + core::fmt::Debug;
    /// The item, owned.
    fn own(item: Self::Item<'_>) -> Self::Owned;
    /// A new decoder set up as this one is (reply form, pending request), holding nothing.
    fn fresh(&self) -> Self;
}

impl Side for CommandDecoder {
    type Owned = Command;
    fn own(item: Command) -> Command {
        item
    }
    fn fresh(&self) -> Self {
        CommandDecoder::new()
    }
}

impl Side for MessageDecoder {
    type Owned = Message;
    fn own(item: Message) -> Message {
        item
    }
    fn fresh(&self) -> Self {
        let firmware = match self.reply_form() {
            ReplyForm::Headerless => FirmwareVersion::new(0, 30),
            ReplyForm::Headed => FirmwareVersion::LATEST,
        };
        let mut fresh = MessageDecoder::new(firmware);
        fresh.expect(self.expecting());
        fresh
    }
}

/// Every event of `pieces` fed in turn through a `Stream`, then of its end, with its place.
fn fed<'a, D: Side>(
    decoder: D,
    pieces: impl IntoIterator<Item = &'a [u8]>,
) -> Vec<Placed<D::Owned>> {
    let mut stream = Stream::new(decoder);
    let mut out = Vec::new();
    for piece in pieces {
        stream.feed(piece, |place, event| out.push((place, event.map(D::own))));
    }
    stream.finish(|place, event| out.push((place, event.map(D::own))));
    out
}

/// The pull form through a `Stream` (`next_event` until it finds nothing, then `end_event`):
/// every event with its place, and a fresh decoder set up as the decoder was before the call
/// that gave the event (a call gives one event, and only that event, an item, can settle the
/// pending request).
fn pulled<D: Side>(decoder: D, bytes: &[u8]) -> Vec<(Placed<D::Owned>, D)> {
    let mut stream = Stream::new(decoder);
    let mut out = Vec::new();
    let mut rest = bytes;
    loop {
        let before = stream.decoder().fresh();
        let (used, event) = stream.next_event(rest);
        let event = event.map(|(place, event)| (place, event.map(D::own)));
        rest = &rest[used..];
        match event {
            Some(event) => out.push((event, before)),
            None => break,
        }
    }
    assert!(rest.is_empty(), "the pull form stopped with bytes left");
    loop {
        let before = stream.decoder().fresh();
        match stream.end_event() {
            Some((place, event)) => out.push(((place, event.map(D::own)), before)),
            None => break,
        }
    }
    assert_eq!(stream.used(), bytes.len() as u64);
    out
}

/// The events of `bytes` with their places, the same fed whole, byte by byte and pulled.
fn all_ways<D: Side>(decoder: D, bytes: &[u8]) -> Vec<Placed<D::Owned>> {
    let whole = fed(decoder.clone(), [bytes]);
    assert_eq!(fed(decoder.clone(), bytes.chunks(1)), whole, "byte by byte");
    let pulled: Vec<_> = pulled(decoder, bytes).into_iter().map(|(e, _)| e).collect();
    assert_eq!(pulled, whole, "pulled");
    whole
}

/// The properties of the places of every event of `stream` (see the module's documentation).
fn check_places<D: Side>(decoder: D, stream: &[u8]) -> Result<(), TestCaseError> {
    let whole = fed(decoder.clone(), [stream]);
    prop_assert_eq!(
        &fed(decoder.clone(), stream.chunks(1)),
        &whole,
        "byte by byte"
    );
    for k in 0..=stream.len() {
        let (a, b) = stream.split_at(k);
        prop_assert_eq!(&fed(decoder.clone(), [a, b]), &whole, "split at {}", k);
    }
    let pulled = pulled(decoder, stream);
    let events: Vec<_> = pulled.iter().map(|(e, _)| e.clone()).collect();
    prop_assert_eq!(&events, &whole, "pulled one event a call");

    let end = stream.len() as u64;
    let (mut first, mut items_end) = (None, 0);
    for ((place, event), before) in pulled {
        prop_assert!(
            place.len > 0 && place.end() <= end,
            "{:?} outside the stream",
            place
        );
        prop_assert!(
            first.is_none_or(|f| place.offset > f),
            "{:?} out of order",
            place
        );
        first = Some(place.offset);
        let bytes = &stream[place.offset as usize..place.end() as usize];
        let alone = fed(before, [bytes]);
        let at_start = Place {
            offset: 0,
            len: place.len,
        };
        match event {
            Ok(item) => {
                prop_assert!(place.offset >= items_end, "{:?} overlaps an item", place);
                items_end = place.end();
                prop_assert_eq!(alone, vec![(at_start, Ok(item))], "alone: {:02x?}", bytes);
            }
            Err(e) => {
                prop_assert_eq!(alone.first(), Some(&(at_start, Err(e))), "{:02x?}", bytes);
                if e == Error::Truncated {
                    prop_assert_eq!(place.end(), end, "a frame cut short ends the stream");
                }
            }
        }
    }
    Ok(())
}

/// A hostile stream of at most 160 bytes (every split point is tried).
fn hostile(frame: fn(u8, &[u8; 18]) -> Vec<u8>) -> impl Strategy<Value = Vec<u8>> {
    prop_oneof![
        4 => prop::collection::vec(piece(frame), 0..12).prop_map(|p| {
            let mut s = p.concat();
            s.truncate(160);
            s
        }),
        1 => prop::collection::vec(any::<u8>(), 0..160),
    ]
}

fn parameter() -> impl Strategy<Value = ParameterValue> {
    (any::<u8>(), any::<i32>()).prop_map(|(number, value)| ParameterValue { number, value })
}

/// A valid message of any kind, in the reply form it is sent in (headerless replies too).
fn message() -> impl Strategy<Value = (Message, ReplyForm)> {
    prop_oneof![
        (any::<u8>(), any::<i32>()).prop_map(|(number, value)| (
            Message::Debug(DebugValue { number, value }),
            ReplyForm::Headed
        )),
        prop_oneof![Just(Ack::Ok), Just(Ack::Error), Just(Ack::InFlight)]
            .prop_map(|a| (Message::Ack(a), ReplyForm::Headed)),
        parameter().prop_map(|p| (Message::Parameter(p), ReplyForm::Headed)),
        parameter().prop_map(|p| (Message::Parameter(p), ReplyForm::Headerless)),
        waypoint().prop_map(|w| (Message::Waypoint(w), ReplyForm::Headed)),
    ]
}

/// A byte that starts no command: an unknown command by the crate's own parse.
fn command_noise() -> impl Strategy<Value = u8> {
    any::<u8>().prop_filter("starts a command", |&b| {
        Command::parse(&[b]) == Err(Error::UnknownCommand(b))
    })
}

/// A byte that starts no message while no request is pending (an ack byte is unknown then).
fn message_noise() -> impl Strategy<Value = u8> {
    any::<u8>().prop_filter("starts a message", |b| {
        ![DEBUG, PARAMETER_REPLY, WAYPOINT].contains(b)
    })
}

proptest! {
    #[test]
    fn device_places_agree_and_hold(s in hostile(command_frame)) {
        check_places(CommandDecoder::new(), &s)?;
    }

    #[test]
    fn pc_places_agree_and_hold(fw in firmware(), first in expect(), s in hostile(message_frame)) {
        let mut decoder = MessageDecoder::new(fw);
        decoder.expect(first);
        check_places(decoder, &s)?;
    }

    /// Commands of every kind back to back, with noise between them and each command cut in
    /// two pieces somewhere: every command at the offset where it was put, and nothing else.
    #[test]
    fn device_commands_come_where_they_were_put(
        sent in prop::collection::vec(
            (command(), prop::collection::vec(command_noise(), 0..4), any::<prop::sample::Index>()),
            0..24,
        ),
    ) {
        let mut stream = Stream::new(CommandDecoder::new());
        let (mut got, mut want, mut at) = (Vec::new(), Vec::new(), 0u64);
        for (command, noise, split) in sent {
            let mut wire = [0u8; aok_proto::command::MAX_COMMAND_LEN];
            let n = command.emit(&mut wire).unwrap();
            let (a, b) = wire[..n].split_at(split.index(n + 1));
            for piece in [a, b, &noise[..]] {
                stream.feed(piece, |place, event| got.push((place, event)));
            }
            want.push((Place { offset: at, len: n }, Ok(command)));
            at += (n + noise.len()) as u64;
        }
        stream.finish(|place, event| got.push((place, event)));
        prop_assert_eq!(got, want);
        prop_assert_eq!(stream.used(), at);
    }

    /// Messages of every kind (acks while one is expected, headerless replies while one is
    /// pending from firmware 0.30) back to back, with noise between them and each message cut
    /// in two pieces somewhere: every message at the offset where it was put.
    #[test]
    fn pc_messages_come_where_they_were_put(
        sent in prop::collection::vec(
            (message(), prop::collection::vec(message_noise(), 0..4), any::<prop::sample::Index>()),
            0..24,
        ),
    ) {
        let mut stream = Stream::new(MessageDecoder::new(FirmwareVersion::LATEST));
        let (mut got, mut want, mut at) = (Vec::new(), Vec::new(), 0u64);
        for ((message, form), noise, split) in sent {
            let decoder = stream.decoder_mut();
            match (message, form) {
                (Message::Ack(_), _) => decoder.expect(Expect::Ack),
                (Message::Parameter(p), ReplyForm::Headerless) => {
                    decoder.set_firmware(FirmwareVersion::new(0, 30));
                    decoder.expect(Expect::Parameter(p.number));
                }
                _ => decoder.set_firmware(FirmwareVersion::LATEST),
            }
            let mut wire = [0u8; 19];
            let n = message.emit(&mut wire, form).unwrap();
            let (a, b) = wire[..n].split_at(split.index(n + 1));
            for piece in [a, b] {
                stream.feed(piece, |place, event| got.push((place, event)));
            }
            prop_assert_eq!(stream.decoder().expecting(), Expect::Nothing);
            stream.feed(&noise, |place, event| got.push((place, event)));
            want.push((Place { offset: at, len: n }, Ok(message)));
            at += (n + noise.len()) as u64;
        }
        stream.finish(|place, event| got.push((place, event)));
        prop_assert_eq!(got, want);
        prop_assert_eq!(stream.used(), at);
    }
}

/// A command after a noise byte: its two bytes at offset 1.
#[test]
fn a_command_lies_where_it_was_sent() {
    let got = all_ways(CommandDecoder::new(), &[0x00, 0x67, 0x0c]);
    assert_eq!(
        got,
        [(Place { offset: 1, len: 2 }, Ok(Command::ReadParameter(12)))]
    );
}

/// A debug frame after two noise bytes: its seven bytes at offset 2.
#[test]
fn a_debug_frame_lies_where_it_was_sent() {
    let wire = [0x00, 0x00, 0x1c, 0x56, 0xff, 0xff, 0xff, 0xfe, 0x57];
    let got = all_ways(MessageDecoder::new(FirmwareVersion::LATEST), &wire);
    let debug = Message::Debug(DebugValue {
        number: 86,
        value: -2,
    });
    assert_eq!(got, [(Place { offset: 2, len: 7 }, Ok(debug))]);
}

/// A motor test whose checksum fails condemns its three bytes; the read inside it, found by
/// the rescan, lies at offset 1. So does a read inside a parameter set whose checksum fails,
/// with four bytes of the set after it.
#[test]
fn a_checksum_failure_condemns_the_whole_command() {
    let got = all_ways(CommandDecoder::new(), &[0x31, 0x67, 0x0c]);
    let mismatch = Error::ChecksumMismatch {
        id: 0x31,
        computed: 0x56,
        received: 0x0c,
    };
    assert_eq!(
        got,
        [
            (Place { offset: 0, len: 3 }, Err(mismatch)),
            (Place { offset: 1, len: 2 }, Ok(Command::ReadParameter(12))),
        ]
    );
    let got = all_ways(CommandDecoder::new(), &[0x73, 0x67, 0x0c, 0, 0, 0, 0]);
    let mismatch = Error::ChecksumMismatch {
        id: 0x73,
        computed: 0x6b,
        received: 0,
    };
    assert_eq!(
        got,
        [
            (Place { offset: 0, len: 7 }, Err(mismatch)),
            (Place { offset: 1, len: 2 }, Ok(Command::ReadParameter(12))),
        ]
    );
}

/// A headerless reply (firmware 0.30) whose checksum fails condemns its five bytes; the
/// four after its first, each the start of a reply still pending, are cut short by the end
/// of the stream one after another, each up to the stream's end.
#[test]
fn a_headerless_reply_with_a_bad_checksum_then_the_end_of_the_stream() {
    let mut decoder = MessageDecoder::new(FirmwareVersion::new(0, 30));
    decoder.expect(Expect::Parameter(12));
    let got = all_ways(decoder, &[0x00, 0x00, 0x05, 0xdc, 0x00]);
    let places: Vec<_> = got.iter().map(|(p, _)| (p.offset, p.len)).collect();
    assert_eq!(places, [(0, 5), (1, 4), (2, 3), (3, 2), (4, 1)]);
    assert!(matches!(got[0].1, Err(Error::ChecksumMismatch { .. })));
    assert!(got[1..].iter().all(|(_, e)| *e == Err(Error::Truncated)));
}

/// A waypoint reply with a good checksum but a slot out of range condemns its 19 bytes.
#[test]
fn a_waypoint_reply_with_a_bad_slot_condemns_the_whole_frame() {
    let mut wire = [0u8; 19];
    (wire[0], wire[1], wire[18]) = (0x77, 100, 100);
    let got = all_ways(MessageDecoder::new(FirmwareVersion::LATEST), &wire);
    assert_eq!(
        got,
        [(Place { offset: 0, len: 19 }, Err(Error::InvalidSlot(100)))]
    );
}

/// A command cut short by the end of the stream: every byte of it, up to the stream's end.
#[test]
fn a_command_cut_short_ends_at_the_end_of_the_stream() {
    let got = all_ways(CommandDecoder::new(), &[0x67, 0x0c, 0x73, 0x01, 0x02]);
    assert_eq!(
        got,
        [
            (Place { offset: 0, len: 2 }, Ok(Command::ReadParameter(12))),
            (Place { offset: 2, len: 3 }, Err(Error::Truncated)),
        ]
    );
}

/// A debug frame cut short by the end of the stream, and the headed reply start the rescan
/// finds inside it, cut short too: both end at the stream's end.
#[test]
fn a_debug_frame_cut_short_ends_at_the_end_of_the_stream() {
    let wire = [0x1c, 0x56, 0xff, 0xff, 0xff, 0xfe, 0x57, 0x1c, 0x56, 0xff];
    let got = all_ways(MessageDecoder::new(FirmwareVersion::LATEST), &wire);
    let debug = Message::Debug(DebugValue {
        number: 86,
        value: -2,
    });
    assert_eq!(
        got,
        [
            (Place { offset: 0, len: 7 }, Ok(debug)),
            (Place { offset: 7, len: 3 }, Err(Error::Truncated)),
            (Place { offset: 9, len: 1 }, Err(Error::Truncated)),
        ]
    );
}
