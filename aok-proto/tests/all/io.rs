//! The `embedded-io` and `embedded-io-async` readers deliver exactly what `feed` delivers one
//! byte a call, then what `finish` delivers at the end of the stream (each front given up as
//! `UnexpectedEof` with its bytes),
//! whatever the read sizes (1 byte up to more than the buffer), with pending reads, transport
//! errors in mid-frame and EOF, on both sides; the writers write exactly the encoders' bytes.

use crate::events;
use events::feed_byte;

use crate::transport;

use aok_proto::{
    Ack, Command, CommandDecoder, DebugValue, Error, FirmwareVersion, IoError, Message,
    ParameterValue, ReplyForm, Stats, WaypointSlot, embedded_io as bio, embedded_io_async as aio,
};
use aok_proto::{Decode, Expect, MessageDecoder};
use embedded_io::ErrorKind;
use proptest::prelude::*;
use transport::{Sink, Wire, block_on, sink};

fn xor(bytes: &[u8]) -> u8 {
    bytes.iter().fold(0, |a, &b| a ^ b)
}

#[derive(Debug, Clone, PartialEq, Eq)]
enum Event<T> {
    Item(T),
    Protocol(Error),
    UnexpectedEof(usize),
    Eof,
}

fn pc_reference(
    fw: FirmwareVersion,
    expect: Expect,
    stream: &[u8],
) -> (Vec<Event<Message>>, Stats) {
    let mut d = MessageDecoder::new(fw);
    d.expect(expect);
    let mut out = Vec::new();
    let conv = |r: Result<Message, Error>| match r {
        Ok(m) => Event::Item(m),
        Err(e) => Event::Protocol(e),
    };
    for &b in stream {
        out.extend(feed_byte(&mut d, b).into_iter().map(conv));
    }
    out.extend(end_events(&mut d, conv));
    out.push(Event::Eof);
    (out, d.stats())
}

fn device_reference(stream: &[u8]) -> (Vec<Event<Command>>, Stats) {
    let mut d = CommandDecoder::new();
    let mut out = Vec::new();
    let conv = |r: Result<Command, Error>| match r {
        Ok(c) => Event::Item(c),
        Err(e) => Event::Protocol(e),
    };
    for &b in stream {
        out.extend(feed_byte(&mut d, b).into_iter().map(conv));
    }
    out.extend(end_events(&mut d, conv));
    out.push(Event::Eof);
    (out, d.stats())
}

/// The end of the stream as a reader reports it: the events of the pull form's `end` (those of
/// `finish`), each front given up as `UnexpectedEof` with the bytes it dropped, which must be
/// the bytes `held_bytes` lost with it.
fn end_events<D, T>(d: &mut D, conv: impl Fn(Result<T, Error>) -> Event<T>) -> Vec<Event<T>>
where
    D: for<'a> Decode<Item<'a> = T, Found = T, Error = Error> + HeldBytes,
    T: PartialEq + Copy + core::fmt::Debug,
{
    let mut out = Vec::new();
    loop {
        let held = d.held_bytes();
        match d.end() {
            None => break,
            Some(frame_io::Event::Found(item)) => {
                out.push(conv(Ok(d.item(&[], item))));
            }
            Some(frame_io::Event::Error(e)) => {
                out.push(conv(Err(e)));
            }
            Some(frame_io::Event::Truncated(n)) => {
                assert_eq!(n, held - d.held_bytes(), "the bytes the front dropped");
                out.push(Event::UnexpectedEof(n));
            }
        }
    }
    out
}

/// `held_bytes` of either decoder.
trait HeldBytes {
    fn held_bytes(&self) -> usize;
}
impl HeldBytes for MessageDecoder {
    fn held_bytes(&self) -> usize {
        MessageDecoder::held_bytes(self)
    }
}
impl HeldBytes for CommandDecoder {
    fn held_bytes(&self) -> usize {
        CommandDecoder::held_bytes(self)
    }
}

/// Collects a reader's results until EOF; counts transport errors apart.
fn collect<T>(mut next: impl FnMut() -> Result<T, IoError<ErrorKind>>) -> (Vec<Event<T>>, usize) {
    let (mut out, mut transport) = (Vec::new(), 0);
    loop {
        match next() {
            Ok(t) => out.push(Event::Item(t)),
            Err(IoError::Protocol(e)) => out.push(Event::Protocol(e)),
            Err(IoError::UnexpectedEof { pending }) => out.push(Event::UnexpectedEof(pending)),
            Err(IoError::Eof) => {
                out.push(Event::Eof);
                return (out, transport);
            }
            Err(IoError::Transport(_)) => transport += 1,
            Err(IoError::WriteZero) => panic!("a reader never reports WriteZero"),
        }
    }
}

fn check_pc<const R: usize>(
    fw: FirmwareVersion,
    expect: Expect,
    stream: &[u8],
    sizes: &[usize],
    errors: &[usize],
) {
    let (want, want_stats) = pc_reference(fw, expect, stream);
    let injected = errors.iter().filter(|&&e| e <= stream.len()).count();

    let mut r = bio::MessageReader::<_, R>::new(
        Wire::new(stream, sizes, errors),
        aok_proto::MessageDecoder::new(fw),
    );
    r.decoder_mut().expect(expect);
    let (got, transport) = collect(|| r.read());
    assert_eq!(
        got, want,
        "blocking R={R}, sizes {sizes:?}, errors {errors:?}"
    );
    assert_eq!(r.decoder().stats(), want_stats);
    assert_eq!(transport, injected);

    let mut r = aio::MessageReader::<_, R>::new(
        Wire::new(stream, sizes, errors),
        aok_proto::MessageDecoder::new(fw),
    );
    r.decoder_mut().expect(expect);
    let (got, transport) = collect(|| block_on(r.read()));
    assert_eq!(got, want, "async R={R}, sizes {sizes:?}, errors {errors:?}");
    assert_eq!(r.decoder().stats(), want_stats);
    assert_eq!(transport, injected);
}

fn check_device<const R: usize>(stream: &[u8], sizes: &[usize], errors: &[usize]) {
    let (want, want_stats) = device_reference(stream);
    let injected = errors.iter().filter(|&&e| e <= stream.len()).count();

    let mut r = bio::CommandReader::<_, R>::new(
        Wire::new(stream, sizes, errors),
        aok_proto::CommandDecoder::new(),
    );
    let (got, transport) = collect(|| r.read());
    assert_eq!(
        got, want,
        "blocking R={R}, sizes {sizes:?}, errors {errors:?}"
    );
    assert_eq!(r.decoder().stats(), want_stats);
    assert_eq!(transport, injected);

    let mut r = aio::CommandReader::<_, R>::new(
        Wire::new(stream, sizes, errors),
        aok_proto::CommandDecoder::new(),
    );
    let (got, transport) = collect(|| block_on(r.read()));
    assert_eq!(got, want, "async R={R}, sizes {sizes:?}, errors {errors:?}");
    assert_eq!(r.decoder().stats(), want_stats);
    assert_eq!(transport, injected);
}

/// One frame the PC sends, from raw bytes (fields may be out of range), as in `bulk.rs`.
fn command_frame(kind: u8, v: &[u8; 18]) -> Vec<u8> {
    match kind % 8 {
        0 => vec![0x63, [1, 2, 7, 8, 9][v[0] as usize % 5]],
        1 => vec![0x63, 3 + v[0] % 3, v[1]],
        2 => {
            let mut f = vec![0x73, v[0] % 4, v[1], v[2], v[3], v[4]];
            f.push(xor(&f[1..]));
            f
        }
        3 => vec![[0x67, 0x47, 0x78][v[0] as usize % 3], v[1]],
        4 => {
            let c = [0x31, 0x35, 0x39, 0x41, 0x43][v[0] as usize % 5];
            vec![c, v[1], c ^ v[1]]
        }
        5 => {
            let mut f = vec![0x77];
            f.extend_from_slice(&v[..17]);
            f.push(xor(&f[1..]));
            f
        }
        6 => {
            let mut f = vec![0x53];
            for i in 0..3 {
                let s = (v[i] as i16 - 128) * if v[3].is_multiple_of(4) { 3 } else { 1 };
                f.extend_from_slice(&s.to_le_bytes());
            }
            f.extend_from_slice(&v[4..8]);
            f.push(xor(&f[1..]));
            f
        }
        _ => vec![v[0]],
    }
}

/// One frame the device sends, as in `bulk.rs`.
fn message_frame(kind: u8, v: &[u8; 18]) -> Vec<u8> {
    match kind % 7 {
        0 | 1 => {
            let mut f = vec![0x1c, v[0] % 4, v[1], v[2], v[3], v[4]];
            f.push(xor(&f[1..]));
            f
        }
        2 => {
            let mut f = vec![0xff, v[0] % 4, v[1], v[2], v[3], v[4]];
            f.push(xor(&f[2..]));
            f
        }
        3 => {
            let first = if v[5].is_multiple_of(3) { 0x1c } else { v[1] };
            let mut f = vec![first, v[2], v[3], v[4]];
            f.push(xor(&f));
            f
        }
        4 => {
            let mut f = vec![0x77, [0, 5, 30, 31, 254, 255, v[0]][v[1] as usize % 7]];
            f.extend_from_slice(&v[2..18]);
            f.push(xor(&f[1..]));
            f
        }
        5 => vec![[b'O', b'E', b'I'][v[0] as usize % 3]],
        _ => vec![v[0]],
    }
}

fn piece(frame: fn(u8, &[u8; 18]) -> Vec<u8>) -> impl Strategy<Value = Vec<u8>> {
    prop_oneof![
        6 => (any::<u8>(), any::<[u8; 18]>()).prop_map(move |(k, v)| frame(k, &v)),
        1 => (any::<u8>(), any::<[u8; 18]>(), any::<prop::sample::Index>(), any::<u8>())
            .prop_map(move |(k, v, i, b)| {
                let mut f = frame(k, &v);
                let i = i.index(f.len());
                f[i] = b;
                f
            }),
        1 => (any::<u8>(), any::<[u8; 18]>(), any::<prop::sample::Index>()).prop_map(
            move |(k, v, i)| {
                let f = frame(k, &v);
                f[..i.index(f.len())].to_vec()
            }
        ),
        1 => prop::collection::vec(
            prop_oneof![
                Just(0x1cu8), Just(0xff), Just(0x77), Just(0x63), Just(0x73), Just(0x53),
                Just(b'O'), any::<u8>()
            ],
            0..24
        ),
    ]
}

fn stream(frame: fn(u8, &[u8; 18]) -> Vec<u8>) -> impl Strategy<Value = Vec<u8>> {
    prop::collection::vec(piece(frame), 0..30).prop_map(|p| p.concat())
}

fn expect() -> impl Strategy<Value = Expect> {
    prop_oneof![
        Just(Expect::Nothing),
        Just(Expect::Ack),
        (0u8..4).prop_map(Expect::Parameter),
        (0u8..4).prop_map(|n| Expect::Bulk(n.wrapping_sub(15))),
        prop_oneof![Just(0u8), Just(5), Just(255)]
            .prop_map(|b| Expect::Waypoint(WaypointSlot::from_wire(b).unwrap())),
    ]
}

fn firmware() -> impl Strategy<Value = FirmwareVersion> {
    prop_oneof![
        Just(FirmwareVersion::new(0, 30)),
        Just(FirmwareVersion::LATEST)
    ]
}

fn sizes() -> impl Strategy<Value = Vec<usize>> {
    prop::collection::vec(
        prop_oneof![3 => 1usize..8, 2 => 1usize..40, 1 => 1usize..200],
        1..6,
    )
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, ..ProptestConfig::default() })]

    #[test]
    fn pc_readers_deliver_what_push_and_idle_deliver(
        fw in firmware(),
        first in expect(),
        stream in stream(message_frame),
        sizes in sizes(),
        errors in prop::collection::vec(0usize..400, 0..3),
    ) {
        check_pc::<32>(fw, first, &stream, &sizes, &errors);
        check_pc::<5>(fw, first, &stream, &sizes, &errors);
        check_pc::<1>(fw, first, &stream, &sizes, &errors);
    }

    #[test]
    fn device_readers_deliver_what_push_and_idle_deliver(
        stream in stream(command_frame),
        sizes in sizes(),
        errors in prop::collection::vec(0usize..400, 0..3),
    ) {
        check_device::<32>(&stream, &sizes, &errors);
        check_device::<5>(&stream, &sizes, &errors);
        check_device::<1>(&stream, &sizes, &errors);
    }
}

/// A debug frame, a headed reply, an ack, a waypoint reply with a bad checksum, half a frame.
fn device_stream() -> Vec<u8> {
    let mut s = vec![0x1c, 0x56, 0xff, 0xff, 0xff, 0xfe, 0x57];
    let mut buf = [0u8; 19];
    let n = Message::Parameter(ParameterValue {
        number: 12,
        value: 1500,
    })
    .emit(&mut buf, ReplyForm::Headed)
    .unwrap();
    s.extend_from_slice(&buf[..n]);
    s.push(b'O');
    let mut wp = vec![0x77, 5];
    wp.extend_from_slice(&[1; 16]);
    wp.push(0x00);
    s.extend(wp);
    s.extend_from_slice(&[0x1c, 0x56]);
    s
}

fn pc_stream() -> Vec<u8> {
    let mut s = vec![0x00];
    for c in [
        Command::DebugOff,
        Command::ReadParameter(12),
        Command::SaveSet(1),
    ] {
        let mut f = [0u8; aok_proto::command::MAX_COMMAND_LEN];
        let n = c.emit(&mut f).unwrap();
        s.extend_from_slice(&f[..n]);
    }
    s.extend_from_slice(&[0x73, 0x63, 0x02]);
    s
}

#[test]
fn every_read_size_from_one_byte_to_the_whole_stream() {
    let s = device_stream();
    for size in 1..=s.len() + 1 {
        check_pc::<32>(FirmwareVersion::LATEST, Expect::Ack, &s, &[size], &[]);
        check_pc::<3>(FirmwareVersion::LATEST, Expect::Nothing, &s, &[size], &[]);
    }
    let s = pc_stream();
    for size in 1..=s.len() + 1 {
        check_device::<32>(&s, &[size], &[]);
        check_device::<3>(&s, &[size], &[]);
    }
}

#[test]
fn transport_errors_in_mid_frame_lose_nothing() {
    let s = device_stream();
    for at in 0..=s.len() {
        check_pc::<8>(FirmwareVersion::LATEST, Expect::Ack, &s, &[3], &[at]);
        check_pc::<8>(
            FirmwareVersion::LATEST,
            Expect::Ack,
            &s,
            &[1, 5],
            &[at, at + 2],
        );
    }
    let s = pc_stream();
    for at in 0..=s.len() {
        check_device::<8>(&s, &[3], &[at]);
    }
}

#[test]
fn eof_mid_frame_is_reported_then_what_finish_finds() {
    let s = device_stream();
    let mut r = bio::MessageReader::<_, 16>::new(
        Wire::new(&s, &[4], &[]),
        aok_proto::MessageDecoder::new(FirmwareVersion::LATEST),
    );
    r.decoder_mut().expect(Expect::Ack);
    let (got, _) = collect(|| r.read());
    assert_eq!(
        got,
        [
            Event::Item(Message::Debug(DebugValue {
                number: 86,
                value: -2
            })),
            Event::Item(Message::Parameter(ParameterValue {
                number: 12,
                value: 1500
            })),
            Event::Item(Message::Ack(Ack::Ok)),
            // The waypoint reply with a bad checksum: the PC decoder reports its failures too.
            Event::Protocol(Error::ChecksumMismatch {
                id: 0x77,
                computed: 0x05,
                received: 0
            }),
            // Two bytes held at the end: the front that cannot complete is given up (1 byte);
            // the byte after it starts no frame and is discarded (counted, no event).
            Event::UnexpectedEof(1),
            Event::Eof,
        ]
    );
    let s = pc_stream();
    let mut r = aio::CommandReader::<_, 16>::new(
        Wire::new(&s, &[4], &[]),
        aok_proto::CommandDecoder::new(),
    );
    let (got, _) = collect(|| block_on(r.read()));
    assert_eq!(
        &got[got.len() - 3..],
        [
            // Three bytes held: the front given up (1 byte), then the rescan finds the
            // command in the two after it.
            Event::UnexpectedEof(1),
            Event::Item(Command::DebugOn),
            Event::Eof
        ]
    );
}

fn arb_command() -> impl Strategy<Value = Command> {
    (any::<u8>(), any::<[u8; 18]>()).prop_filter_map("a command", |(k, v)| {
        Command::parse(&command_frame(k, &v)).ok().map(|c| c.0)
    })
}

fn arb_message() -> impl Strategy<Value = (Message, ReplyForm)> {
    (any::<u8>(), any::<[u8; 18]>(), any::<bool>()).prop_filter_map(
        "a message",
        |(k, v, headed)| {
            let form = if headed {
                ReplyForm::Headed
            } else {
                ReplyForm::Headerless
            };
            Message::parse(&message_frame(k, &v))
                .ok()
                .map(|m| (m.0, form))
        },
    )
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    #[test]
    fn writers_write_what_the_encoders_write(
        cmd in arb_command(),
        (msg, form) in arb_message(),
        max in 1usize..8,
    ) {
        let mut f = [0u8; aok_proto::command::MAX_COMMAND_LEN];
        let n = cmd.emit(&mut f).unwrap();
        let mut w = bio::Writer::new(sink(max));
        prop_assert_eq!(w.write_command(&cmd), Ok(n));
        prop_assert_eq!(&w.into_inner().out[..], &f[..n]);
        let mut w = aio::Writer::new(sink(max));
        prop_assert_eq!(block_on(w.write_command(&cmd)), Ok(n));
        prop_assert_eq!(&w.into_inner().out[..], &f[..n]);

        let mut want = [0u8; 19];
        let n = msg.emit(&mut want, form).unwrap();
        let mut w = bio::Writer::new(sink(max));
        prop_assert_eq!(w.write_message(&msg, form), Ok(n));
        prop_assert_eq!(&w.into_inner().out[..], &want[..n]);
        let mut w = aio::Writer::new(sink(max));
        prop_assert_eq!(block_on(w.write_message(&msg, form)), Ok(n));
        prop_assert_eq!(&w.into_inner().out[..], &want[..n]);
    }
}

#[test]
fn writer_errors_are_the_transports() {
    let mut w = bio::Writer::new(Sink {
        fail_at: Some(0),
        ..sink(8)
    });
    assert_eq!(
        w.write_command(&Command::DebugOn),
        Err(aok_proto::WriteError::Transport(ErrorKind::BrokenPipe))
    );
    let mut w = aio::Writer::new(Sink {
        zero: true,
        ..sink(8)
    });
    assert_eq!(
        block_on(w.write_command(&Command::DebugOn)),
        Err(aok_proto::WriteError::WriteZero)
    );
}
