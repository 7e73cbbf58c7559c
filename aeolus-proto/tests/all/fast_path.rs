//! Property tests of the slice path's word-at-a-time copy and running CRC: `feed` over whole
//! slices must give exactly the events and counters of `feed` one byte a call (the per-byte
//! path), on streams dense in the bytes
//! that end a run (0x7D, 0x7E) and those that follow an escape (0x5D, 0x5E), at every word
//! offset, for capacities around the word size, and when one-byte and longer slices take
//! turns within one frame (the running CRC then has bytes to catch up with); and the pull
//! form, `decode` called again on what each call left, gives the same events as well.

use aeolus_proto::{CrcMode, Decode, Decoder, Error, Event, Stats, encode_frame};
use proptest::prelude::*;

type Events = Vec<Result<Vec<u8>, Error>>;

/// A byte that is often one with a rule of its own.
fn hostile_byte() -> impl Strategy<Value = u8> {
    prop_oneof![
        3 => any::<u8>(),
        1 => Just(0x7D),
        1 => Just(0x7E),
        1 => Just(0x5D),
        1 => Just(0x5E),
    ]
}

/// Valid frames (random IDs and data, escapes wherever the bytes fall, CRC or none), with
/// hostile bytes between some of them and a random number of leading bytes, so every frame
/// starts at every offset of a word.
fn stream() -> impl Strategy<Value = Vec<u8>> {
    stream_of(8, 40)
}

/// [`stream`]'s streams of fewer than `frames` frames of fewer than `data` data bytes each
/// (`data` at most 43).
pub(crate) fn stream_of(frames: usize, data: usize) -> impl Strategy<Value = Vec<u8>> {
    let frame = (
        any::<u8>(),
        prop::collection::vec(hostile_byte(), 0..data),
        any::<bool>(),
        prop::collection::vec(hostile_byte(), 0..4),
    );
    (
        prop::collection::vec(hostile_byte(), 0..7),
        prop::collection::vec(frame, 0..frames),
    )
        .prop_map(|(lead, frames)| {
            let mut out = lead;
            for (id, data, omit, noise) in frames {
                let mode = if omit {
                    CrcMode::Omit
                } else {
                    CrcMode::Compute
                };
                let mut buf = [0u8; 2 + 2 * 43];
                let n = encode_frame(id, &data, &[], mode, &mut buf).unwrap();
                out.extend_from_slice(&buf[..n]);
                out.extend_from_slice(&noise);
            }
            out
        })
}

fn record(ev: Result<aeolus_proto::Frame<'_>, Error>) -> Result<Vec<u8>, Error> {
    ev.map(|f| f.raw().to_vec())
}

fn by_byte<const N: usize>(bytes: &[u8]) -> (Events, Stats) {
    let mut d = Decoder::<N>::new();
    let mut ev = Vec::new();
    for &b in bytes {
        d.feed(&[b], |e| ev.push(record(e)));
    }
    (ev, d.stats())
}

/// The split points reduced into `bytes`, with its two ends, in order.
fn cut_points(bytes: &[u8], splits: &[usize]) -> Vec<usize> {
    let mut cuts: Vec<usize> = splits.iter().map(|&s| s % (bytes.len() + 1)).collect();
    cuts.push(0);
    cuts.push(bytes.len());
    cuts.sort_unstable();
    cuts
}

/// Feeds the pieces between the split points in turn; a piece whose index is in `pushed` is
/// fed one byte a call instead.
fn mixed<const N: usize>(bytes: &[u8], splits: &[usize], pushed: u32) -> (Events, Stats) {
    let mut d = Decoder::<N>::new();
    let mut ev = Vec::new();
    let cuts = cut_points(bytes, splits);
    for (i, w) in cuts.windows(2).enumerate() {
        let piece = &bytes[w[0]..w[1]];
        if pushed & (1 << (i % 32)) != 0 {
            for &b in piece {
                d.feed(&[b], |e| ev.push(record(e)));
            }
        } else {
            d.feed(piece, |e| ev.push(record(e)));
        }
    }
    (ev, d.stats())
}

/// Decodes the pieces between the split points with the pull form, `decode` again and again
/// on what each call left, recording its event; every call uses a byte or more, or ends the
/// piece.
fn until<const N: usize>(bytes: &[u8], splits: &[usize]) -> (Events, Stats) {
    let mut d = Decoder::<N>::new();
    let mut ev = Vec::new();
    let cuts = cut_points(bytes, splits);
    for w in cuts.windows(2) {
        let mut piece = &bytes[w[0]..w[1]];
        while !piece.is_empty() {
            let (n, e) = d.decode(piece);
            assert!(n > 0 && n <= piece.len(), "consumed {n} of {}", piece.len());
            let found = e.is_some();
            match e {
                Some(Event::Found(at)) => ev.push(record(Ok(d.item(piece, at)))),
                Some(Event::Error(e)) => ev.push(Err(e)),
                Some(Event::Truncated(n)) => panic!("decode never truncates ({n})"),
                None => {}
            }
            assert!(found || n == piece.len(), "stopped without an event");
            piece = &piece[n..];
        }
    }
    (ev, d.stats())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 3000, ..ProptestConfig::default() })]

    #[test]
    fn decode_again_and_again_is_feed_byte_by_byte(
        bytes in stream(),
        splits in prop::collection::vec(any::<usize>(), 0..6),
    ) {
        prop_assert_eq!(until::<64>(&bytes, &splits), by_byte::<64>(&bytes));
        prop_assert_eq!(until::<5>(&bytes, &splits), by_byte::<5>(&bytes));
        prop_assert_eq!(until::<13>(&bytes, &splits), by_byte::<13>(&bytes));
    }

    #[test]
    fn feed_in_pieces_is_feed_byte_by_byte(
        bytes in stream(),
        splits in prop::collection::vec(any::<usize>(), 0..6),
        pushed in any::<u32>(),
    ) {
        prop_assert_eq!(mixed::<64>(&bytes, &splits, pushed), by_byte::<64>(&bytes));
        prop_assert_eq!(mixed::<64>(&bytes, &splits, 0), by_byte::<64>(&bytes));
        // Capacities around a word, so runs stop for lack of room at every offset.
        prop_assert_eq!(mixed::<5>(&bytes, &splits, pushed), by_byte::<5>(&bytes));
        prop_assert_eq!(mixed::<8>(&bytes, &splits, 0), by_byte::<8>(&bytes));
        prop_assert_eq!(mixed::<13>(&bytes, &splits, pushed), by_byte::<13>(&bytes));
        prop_assert_eq!(mixed::<16>(&bytes, &splits, 0), by_byte::<16>(&bytes));
    }

    #[test]
    fn feed_at_every_split_point_is_push_byte_by_byte(bytes in stream()) {
        let want = by_byte::<48>(&bytes);
        for at in 0..=bytes.len() {
            prop_assert_eq!(&mixed::<48>(&bytes, &[at], 0), &want, "split at {}", at);
        }
    }

    #[test]
    fn a_frame_with_an_escape_at_every_offset_arrives(
        data in prop::collection::vec(any::<u8>().prop_filter("plain", |b| !matches!(b, 0x7D | 0x7E)), 1..24),
        special in prop_oneof![Just(0x7Du8), Just(0x7E)],
        lead in 0usize..4,
    ) {
        for at in 0..data.len() {
            let mut d2 = data.clone();
            d2[at] = special;
            let mut wire = vec![0u8; lead];
            let mut buf = [0u8; 2 + 2 * 27];
            let n = encode_frame(0x3E, &d2, &[], CrcMode::Compute, &mut buf).unwrap();
            wire.extend_from_slice(&buf[..n]);
            let mut d = Decoder::<64>::new();
            let mut got = Vec::new();
            d.feed(&wire, |e| got.push(record(e)));
            prop_assert_eq!(got.len(), 1);
            let raw = got.pop().unwrap().unwrap();
            prop_assert_eq!(&raw[1..raw.len() - 2], &d2[..]);
            prop_assert_eq!(d.stats().frames_ok, 1);
        }
    }
}
