//! The three ways through the contract of both decoders (`CommandDecoder`, `MessageDecoder`):
//! `feed` with whole chunks (the bulk path), `feed` with one-byte slices (the byte-by-byte
//! reference) and the pull form (`decode` until it finds nothing): on any byte stream, split
//! at any chunk boundaries, with the pending request and the firmware changed between chunks,
//! all give the same items in the same order, the same counters, the same pending request and
//! the same buffered bytes after every chunk, and the same result from `finish` at the end.

use crate::events;
use events::{feed_bytes, finish_all};

use aok_proto::{Command, CommandDecoder, Decode, Error, Event, Expect, FirmwareVersion};
use aok_proto::{Message, MessageDecoder, WaypointSlot};
use proptest::prelude::*;

fn xor(bytes: &[u8]) -> u8 {
    bytes.iter().fold(0, |a, &b| a ^ b)
}

/// One frame the PC sends, from raw bytes (fields may be out of range: that is the point).
pub(crate) fn command_frame(kind: u8, v: &[u8; 18]) -> Vec<u8> {
    match kind % 9 {
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
            // Sticks mostly in range (-200..=200 as i16 LE), sometimes not.
            let mut f = vec![0x53];
            for i in 0..3 {
                let s = (v[i] as i16 - 128) * if v[3].is_multiple_of(4) { 3 } else { 1 };
                f.extend_from_slice(&s.to_le_bytes());
            }
            f.extend_from_slice(&v[4..8]);
            f.push(xor(&f[1..]));
            f
        }
        7 => vec![0x63, v[0]],
        _ => vec![v[0]],
    }
}

/// One frame the device sends.
pub(crate) fn message_frame(kind: u8, v: &[u8; 18]) -> Vec<u8> {
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
            // Headerless reply (firmware <= 0.30); with a 1C first byte now and then.
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

/// A piece of a stream: a frame, perhaps with one byte changed or cut short, or garbage.
pub(crate) fn piece(frame: fn(u8, &[u8; 18]) -> Vec<u8>) -> impl Strategy<Value = Vec<u8>> {
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
    prop_oneof![
        4 => prop::collection::vec(piece(frame), 0..40).prop_map(|p| p.concat()),
        1 => prop::collection::vec(any::<u8>(), 0..400),
    ]
}

fn chunk_sizes() -> impl Strategy<Value = Vec<usize>> {
    prop::collection::vec(
        prop_oneof![3 => 0usize..8, 2 => 0usize..40, 1 => 0usize..400],
        1..16,
    )
}

pub(crate) fn expect() -> impl Strategy<Value = Expect> {
    prop_oneof![
        Just(Expect::Nothing),
        Just(Expect::Ack),
        (0u8..4).prop_map(Expect::Parameter),
        any::<u8>().prop_map(Expect::Parameter),
        (0u8..4).prop_map(|n| Expect::Bulk(n.wrapping_sub(15))),
        prop_oneof![Just(0u8), Just(5), Just(31), Just(254), Just(255)]
            .prop_map(|b| Expect::Waypoint(WaypointSlot::from_wire(b).unwrap())),
    ]
}

pub(crate) fn firmware() -> impl Strategy<Value = FirmwareVersion> {
    prop_oneof![
        Just(FirmwareVersion::new(0, 30)),
        Just(FirmwareVersion::new(0, 31)),
        Just(FirmwareVersion::LATEST),
    ]
}

/// What happens at a chunk boundary on the PC side.
#[derive(Debug, Clone)]
enum Between {
    Nothing,
    Expect(Expect),
    Firmware(FirmwareVersion),
}

fn between() -> impl Strategy<Value = Between> {
    prop_oneof![
        4 => Just(Between::Nothing),
        3 => expect().prop_map(Between::Expect),
        1 => firmware().prop_map(Between::Firmware),
    ]
}

fn pc_bytewise(dec: &mut MessageDecoder, bytes: &[u8], out: &mut Vec<Result<Message, Error>>) {
    out.extend(feed_bytes(dec, bytes));
}

fn device_bytewise(dec: &mut CommandDecoder, bytes: &[u8], out: &mut Vec<Result<Command, Error>>) {
    out.extend(feed_bytes(dec, bytes));
}

/// Chunk sizes, cycled; the extra 1 makes every round consume a byte.
fn chunks<'a>(stream: &'a [u8], sizes: &'a [usize]) -> impl Iterator<Item = &'a [u8]> + 'a {
    let mut sizes = sizes.iter().chain(&[1]).cycle();
    let mut rest = stream;
    std::iter::from_fn(move || {
        if rest.is_empty() {
            return None;
        }
        let n = (*sizes.next().unwrap()).min(rest.len());
        let (chunk, tail) = rest.split_at(n);
        rest = tail;
        Some(chunk)
    })
}

/// An event of the pull form as `feed` hands it over (the items of both decoders are the
/// found values themselves).
fn result<T>(event: Event<T, Error>) -> Result<T, Error> {
    match event {
        Event::Found(item) => Ok(item),
        Event::Error(e) => Err(e),
        Event::Truncated(_) => Err(Error::Truncated),
    }
}

/// `decode` again and again on what each call left, until it finds nothing in what is
/// left; every call consumes a byte or more, or hands out an event.
fn until_all<T>(
    mut decode: impl FnMut(&[u8]) -> (usize, Option<Event<T, Error>>),
    bytes: &[u8],
) -> Vec<Result<T, Error>> {
    let (mut rest, mut out) = (bytes, Vec::new());
    loop {
        let (n, ev) = decode(rest);
        let ev = ev.map(result);
        assert!(n <= rest.len());
        let found = ev.is_some();
        out.extend(ev);
        assert!(found || n == rest.len(), "stopped without an event");
        rest = &rest[n..];
        if !found && rest.is_empty() {
            return out;
        }
    }
}

fn check_pc(fw: FirmwareVersion, first: Expect, stream: &[u8], sizes: &[usize], steps: &[Between]) {
    let mut slow = MessageDecoder::new(fw);
    let mut fast = MessageDecoder::new(fw);
    let mut until = MessageDecoder::new(fw);
    slow.expect(first);
    fast.expect(first);
    until.expect(first);
    let mut steps = steps.iter().cycle();
    for (i, chunk) in chunks(stream, sizes).enumerate() {
        let (mut want, mut got) = (Vec::new(), Vec::new());
        pc_bytewise(&mut slow, chunk, &mut want);
        fast.feed(chunk, |m| got.push(m));
        assert_eq!(got, want, "chunk {i}");
        assert_eq!(fast.stats(), slow.stats(), "chunk {i}");
        assert_eq!(fast.expecting(), slow.expecting(), "chunk {i}");
        assert_eq!(fast.held_bytes(), slow.held_bytes(), "chunk {i}");
        assert_eq!(
            until_all(|b| until.decode(b), chunk),
            want,
            "decode, chunk {i}"
        );
        assert_eq!(until.stats(), slow.stats(), "decode, chunk {i}");
        assert_eq!(until.expecting(), slow.expecting(), "decode, chunk {i}");
        assert_eq!(until.held_bytes(), slow.held_bytes(), "decode, chunk {i}");
        match steps.next() {
            Some(Between::Expect(e)) => {
                slow.expect(*e);
                fast.expect(*e);
                until.expect(*e);
            }
            Some(Between::Firmware(f)) => {
                slow.set_firmware(*f);
                fast.set_firmware(*f);
                until.set_firmware(*f);
            }
            _ => {}
        }
    }
    let want = finish_all(&mut slow);
    let got = finish_all(&mut fast);
    assert_eq!(got, want, "finish");
    assert_eq!(fast.stats(), slow.stats(), "after finish");
    assert_eq!(finish_all(&mut until), want, "finish after decode");
    assert_eq!(until.stats(), slow.stats(), "after finish after decode");
    assert_eq!(fast.expecting(), slow.expecting());
}

fn check_device(stream: &[u8], sizes: &[usize]) {
    let mut slow = CommandDecoder::new();
    let mut fast = CommandDecoder::new();
    let mut until = CommandDecoder::new();
    for (i, chunk) in chunks(stream, sizes).enumerate() {
        let (mut want, mut got) = (Vec::new(), Vec::new());
        device_bytewise(&mut slow, chunk, &mut want);
        fast.feed(chunk, |c| got.push(c));
        assert_eq!(got, want, "chunk {i}");
        assert_eq!(fast.stats(), slow.stats(), "chunk {i}");
        assert_eq!(fast.held_bytes(), slow.held_bytes(), "chunk {i}");
        assert_eq!(
            until_all(|b| until.decode(b), chunk),
            want,
            "decode, chunk {i}"
        );
        assert_eq!(until.stats(), slow.stats(), "decode, chunk {i}");
        assert_eq!(until.held_bytes(), slow.held_bytes(), "decode, chunk {i}");
    }
    let want = finish_all(&mut slow);
    let got = finish_all(&mut fast);
    assert_eq!(got, want, "finish");
    assert_eq!(fast.stats(), slow.stats(), "after finish");
    assert_eq!(finish_all(&mut until), want, "finish after decode");
    assert_eq!(until.stats(), slow.stats(), "after finish after decode");
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 1024, ..ProptestConfig::default() })]

    #[test]
    fn device_bulk_equals_bytewise(s in stream(command_frame), sizes in chunk_sizes()) {
        check_device(&s, &sizes);
    }

    #[test]
    fn pc_bulk_equals_bytewise(
        fw in firmware(),
        first in expect(),
        s in stream(message_frame),
        sizes in chunk_sizes(),
        steps in prop::collection::vec(between(), 1..8),
    ) {
        check_pc(fw, first, &s, &sizes, &steps);
    }

    /// `feed` after a `decode` that stopped at an event with more events queued behind it
    /// (the pull form leaves them for its next call) continues exactly as feeding those
    /// bytes one at a time does: the queued events come first.
    #[test]
    fn device_feed_after_decode(
        s in stream(command_frame),
        ops in prop::collection::vec((any::<bool>(), 0usize..40), 0..20),
    ) {
        let mut slow = CommandDecoder::new();
        let mut fast = CommandDecoder::new();
        let (mut want, mut got) = (Vec::new(), Vec::new());
        let sizes: Vec<usize> = ops.iter().map(|o| o.1).collect();
        for (chunk, pull) in chunks(&s, &sizes).zip(ops.iter().map(|o| o.0).chain([false]).cycle()) {
            device_bytewise(&mut slow, chunk, &mut want);
            let mut rest = chunk;
            if pull {
                // One event at most, then `feed` takes the rest.
                let (n, ev) = fast.decode(rest);
                got.extend(ev.map(result));
                rest = &rest[n..];
            }
            fast.feed(rest, |c| got.push(c));
            if rest.is_empty() {
                // Events the pull form left queued with no byte after them: the end of the
                // stream finds them (as it does for the bytewise decoder).
                continue;
            }
            prop_assert_eq!(&got, &want);
            prop_assert_eq!(fast.stats(), slow.stats());
            prop_assert_eq!(fast.held_bytes(), slow.held_bytes());
        }
        want.extend(finish_all(&mut slow));
        got.extend(finish_all(&mut fast));
        prop_assert_eq!(&got, &want);
        prop_assert_eq!(fast.stats(), slow.stats());
    }

    #[test]
    fn pc_feed_after_decode(
        fw in firmware(),
        first in expect(),
        s in stream(message_frame),
        ops in prop::collection::vec((any::<bool>(), 0usize..40), 0..20),
    ) {
        let mut slow = MessageDecoder::new(fw);
        let mut fast = MessageDecoder::new(fw);
        slow.expect(first);
        fast.expect(first);
        let (mut want, mut got) = (Vec::new(), Vec::new());
        let sizes: Vec<usize> = ops.iter().map(|o| o.1).collect();
        for (chunk, pull) in chunks(&s, &sizes).zip(ops.iter().map(|o| o.0).chain([false]).cycle()) {
            pc_bytewise(&mut slow, chunk, &mut want);
            let mut rest = chunk;
            if pull {
                let (n, ev) = fast.decode(rest);
                got.extend(ev.map(result));
                rest = &rest[n..];
            }
            fast.feed(rest, |m| got.push(m));
            if rest.is_empty() {
                continue;
            }
            prop_assert_eq!(&got, &want);
            prop_assert_eq!(fast.stats(), slow.stats());
            prop_assert_eq!(fast.held_bytes(), slow.held_bytes());
            prop_assert_eq!(fast.expecting(), slow.expecting());
        }
        want.extend(finish_all(&mut slow));
        got.extend(finish_all(&mut fast));
        prop_assert_eq!(&got, &want);
        prop_assert_eq!(fast.stats(), slow.stats());
    }
}

/// Long streams of valid frames in DMA-sized blocks, as the benchmarks feed them.
#[test]
fn long_streams_in_blocks() {
    let mut x = 0x2545_F491_4F6C_DD1Du64;
    let mut next = move || {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        x
    };
    let mut cmds = Vec::new();
    let mut msgs = Vec::new();
    while cmds.len() < 50_000 {
        let v: [u8; 18] = std::array::from_fn(|_| next() as u8);
        cmds.extend(command_frame(next() as u8, &v));
        msgs.extend(message_frame(next() as u8, &v));
    }
    for sizes in [&[4096][..], &[4093, 1, 0, 17]] {
        check_device(&cmds, sizes);
        for fw in [FirmwareVersion::new(0, 30), FirmwareVersion::LATEST] {
            check_pc(fw, Expect::Nothing, &msgs, sizes, &[Between::Nothing]);
            check_pc(
                fw,
                Expect::Parameter(1),
                &msgs,
                sizes,
                &[Between::Expect(Expect::Ack)],
            );
        }
    }
}
