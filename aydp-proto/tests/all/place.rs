//! Every event's place (`Decode::span` through `Stream`): the same whatever slices the stream
//! comes in (every split point) and in the pull form, each frame's place holding exactly its
//! wire bytes, frames put at known offsets found there, and every error's place inside the
//! stream: a failed candidate's from its 0xFF start, a candidate cut short by the end of the
//! stream up to that end.

use crate::bulk::{Reach, biased_stream_of, piece, profile};
use crate::streamgen;

use aydp_proto::{Decoder, Error, Place, Profile, Stream};
use proptest::prelude::*;
use streamgen::{Rng, random_message};

/// An event as owned data, with its place: the frame's wire bytes, or the error.
type Placed = (Place, Result<Vec<u8>, Error>);

/// Feeds the pieces between `cuts` (sorted offsets into `bytes`, its ends included) through a
/// `Stream`, then finishes: every event with its place.
fn placed<const N: usize>(profile: Profile, bytes: &[u8], cuts: &[usize]) -> Vec<Placed> {
    let mut stream = Stream::new(Decoder::<N>::new(profile));
    let mut out = Vec::new();
    for pair in cuts.windows(2) {
        stream.feed(&bytes[pair[0]..pair[1]], |place, ev| {
            out.push((place, ev.map(|f| f.as_bytes().to_vec())))
        });
    }
    stream.finish(|place, ev| out.push((place, ev.map(|f| f.as_bytes().to_vec()))));
    assert_eq!(stream.used(), bytes.len() as u64);
    // Every byte used is in a frame or discarded (an error's 0xFF start among them).
    let framed: usize = out
        .iter()
        .filter_map(|(p, ev)| ev.as_ref().ok().map(|_| p.len))
        .sum();
    let discarded = stream.decoder().stats().bytes_discarded as usize;
    assert_eq!(framed + discarded, bytes.len());
    out
}

fn whole<const N: usize>(profile: Profile, bytes: &[u8]) -> Vec<Placed> {
    placed::<N>(profile, bytes, &[0, bytes.len()])
}

fn by_byte<const N: usize>(profile: Profile, bytes: &[u8]) -> Vec<Placed> {
    let cuts: Vec<usize> = (0..=bytes.len()).collect();
    placed::<N>(profile, bytes, &cuts)
}

/// The pull form: `next_event` on what each call left of each `piece`-byte slice (one event
/// a call, those a rescan left queued with no byte used), then `end_event` until `None`.
fn pulled<const N: usize>(profile: Profile, bytes: &[u8], piece: usize) -> Vec<Placed> {
    let mut stream = Stream::new(Decoder::<N>::new(profile));
    let mut out = Vec::new();
    for chunk in bytes.chunks(piece.max(1)) {
        let mut rest = chunk;
        loop {
            let (used, ev) = stream.next_event(rest);
            let Some((place, ev)) = ev else { break };
            out.push((place, ev.map(|f| f.as_bytes().to_vec())));
            rest = &rest[used..];
        }
    }
    while let Some((place, ev)) = stream.end_event() {
        out.push((place, ev.map(|f| f.as_bytes().to_vec())));
    }
    assert_eq!(stream.used(), bytes.len() as u64);
    out
}

/// The events of `bytes` fed whole, after checking that byte by byte, cut in two at every
/// point, and the pull form (whole, and a byte at a time) give the same events at the same
/// places.
fn every_way<const N: usize>(profile: Profile, bytes: &[u8]) -> Vec<Placed> {
    let want = whole::<N>(profile, bytes);
    assert_eq!(by_byte::<N>(profile, bytes), want, "N={N}: byte by byte");
    for cut in 0..=bytes.len() {
        let got = placed::<N>(profile, bytes, &[0, cut, bytes.len()]);
        assert_eq!(got, want, "N={N}: cut at {cut}");
    }
    let pull = pulled::<N>(profile, bytes, bytes.len());
    assert_eq!(pull, want, "N={N}: pull form, whole");
    assert_eq!(
        pulled::<N>(profile, bytes, 1),
        want,
        "N={N}: pull form, bytewise"
    );
    want
}

/// What the places must be on any stream, for a decoder that holds a header (`N` >= 6).
fn check_places(bytes: &[u8], events: &[Placed]) {
    let len = bytes.len() as u64;
    let mut last_offset = None;
    for (place, ev) in events {
        let end = place.end();
        assert!(place.len > 0 && end <= len, "{place:?} outside {len} bytes");
        let at = &bytes[place.offset as usize..end as usize];
        // Events come in the order of their first bytes, never two at one.
        assert!(
            last_offset < Some(place.offset),
            "{place:?} after {last_offset:?}"
        );
        last_offset = Some(place.offset);
        // Every event, a frame or a failed candidate, starts at a 0xFF start byte.
        assert_eq!(at[0], 0xFF, "{place:?}: {ev:?}");
        match ev {
            Ok(frame) => assert_eq!(at, &frame[..], "{place:?}"),
            Err(Error::ChecksumMismatch { id, received, .. }) => {
                // The candidate's whole announced length: its XOR is not 0, and its type and
                // checksum bytes are those the error reports.
                assert_ne!(at.iter().fold(0, |x, b| x ^ b), 0, "{place:?}");
                assert_eq!((at[1], u16::from(at[at.len() - 1])), (*id, *received));
            }
            Err(Error::BadLength(field)) => {
                // The six bytes judged: start, type, length field.
                assert_eq!(place.len, 6, "{place:?}");
                assert_eq!(u32::from_le_bytes([at[2], at[3], at[4], at[5]]), *field);
            }
            Err(Error::Truncated) => assert_eq!(end, len, "{place:?}: not at the end"),
            Err(e) => panic!("{e:?} from the decoder"),
        }
    }
}

/// A hostile stream of at most 160 bytes (the pieces cut there): every split point is tried.
fn hostile_stream() -> impl Strategy<Value = (Profile, Vec<u8>)> {
    profile().prop_flat_map(|p| {
        prop::collection::vec(piece(p, Reach::Short), 0..8).prop_map(move |pieces| {
            let mut bytes = pieces.concat();
            bytes.truncate(160);
            (p, bytes)
        })
    })
}

/// A stream, and each message put into it with its offset.
type Known = (Profile, Vec<u8>, Vec<(u64, Vec<u8>)>);

/// Valid messages, each behind noise that cannot start one (no 0xFF), with the offset at
/// which each was put.
fn known_frames() -> impl Strategy<Value = Known> {
    let noise = prop::collection::vec(0u8..0xFF, 0..10);
    profile().prop_flat_map(move |p| {
        (
            prop::collection::vec((noise.clone(), any::<u64>()), 0..8),
            noise.clone(),
        )
            .prop_map(move |(frames, tail)| {
                let mut bytes = Vec::new();
                let mut put = Vec::new();
                for (lead, seed) in frames {
                    bytes.extend(lead);
                    let m = random_message(&mut Rng(seed), p);
                    put.push((bytes.len() as u64, m.clone()));
                    bytes.extend(m);
                }
                bytes.extend(tail);
                (p, bytes, put)
            })
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    /// Whole, byte by byte, cut in two at every point, the pull form: the same events at the
    /// same places, each where the properties of `check_places` say, at three capacities
    /// (a 23-byte decoder turns most headers into length errors).
    #[test]
    fn places_are_the_same_however_the_stream_is_cut((p, bytes) in hostile_stream()) {
        check_places(&bytes, &every_way::<128>(p, &bytes));
        check_places(&bytes, &every_way::<40>(p, &bytes));
        check_places(&bytes, &every_way::<23>(p, &bytes));
        check_places(&bytes, &every_way::<6>(p, &bytes));
    }

    #[test]
    fn places_in_false_starts_are_the_same_however_the_stream_is_cut(
        p in profile(),
        bytes in biased_stream_of(120),
    ) {
        check_places(&bytes, &every_way::<64>(p, &bytes));
        check_places(&bytes, &every_way::<7>(p, &bytes));
        // Just big enough for a header (the smallest decoder with events before the end).
        check_places(&bytes, &every_way::<6>(p, &bytes));
    }

    /// Any chunks (random sizes, empty ones too), not only a cut in two.
    #[test]
    fn places_are_the_same_in_any_chunks(
        (p, bytes) in hostile_stream(),
        sizes in prop::collection::vec(0usize..40, 1..12),
    ) {
        let mut cuts = vec![0];
        for size in sizes.iter().cycle() {
            let at = (cuts[cuts.len() - 1] + size + 1).min(bytes.len());
            cuts.push(at);
            if at == bytes.len() {
                break;
            }
        }
        prop_assert_eq!(placed::<128>(p, &bytes, &cuts), whole::<128>(p, &bytes));
        prop_assert_eq!(placed::<23>(p, &bytes, &cuts), whole::<23>(p, &bytes));
    }

    /// Frames behind noise without a 0xFF: exactly those frames, each at its offset, and no
    /// error.
    #[test]
    fn frames_are_found_where_they_were_put((p, bytes, put) in known_frames()) {
        let want: Vec<Placed> = put
            .into_iter()
            .map(|(offset, m)| (Place { offset, len: m.len() }, Ok(m)))
            .collect();
        prop_assert_eq!(every_way::<128>(p, &bytes), want);
    }

    /// A decoder too small for a header gives nothing but the candidate cut short by the end,
    /// at the bytes it held (the bytes it could not hold come after them), however cut.
    #[test]
    fn a_decoder_too_small_for_a_header_places_its_truncations((p, bytes) in hostile_stream()) {
        for events in [every_way::<4>(p, &bytes), every_way::<1>(p, &bytes)] {
            for (place, ev) in events {
                prop_assert_eq!(ev, Err(Error::Truncated));
                prop_assert!(place.end() <= bytes.len() as u64);
                prop_assert_eq!(bytes[place.offset as usize], 0xFF);
            }
        }
        prop_assert!(every_way::<0>(p, &bytes).is_empty());
    }
}

/// An expedited heartbeat (type 0, no data).
const HEARTBEAT: [u8; 7] = [0xFF, 0x80, 0x07, 0, 0, 0, 0x78];

/// The places (and what each event is) of `bytes` in the `Spec` profile, every way.
fn spec<const N: usize>(bytes: &[u8]) -> Vec<(u64, usize, Result<usize, Error>)> {
    every_way::<N>(Profile::Spec, bytes)
        .into_iter()
        .map(|(place, ev)| (place.offset, place.len, ev.map(|f| f.len())))
        .collect()
}

#[test]
fn a_frame_is_placed_at_its_bytes() {
    let mut bytes = vec![0x13, 0x00];
    bytes.extend(HEARTBEAT);
    bytes.push(0x42);
    assert_eq!(spec::<64>(&bytes), [(2, 7, Ok(7))]);
}

#[test]
fn a_checksum_error_is_placed_at_its_whole_candidate() {
    let mut bytes = vec![0x13];
    let mut bad = HEARTBEAT;
    bad[6] ^= 1;
    bytes.extend(bad);
    let events = spec::<64>(&bytes);
    assert_eq!(events.len(), 1);
    assert_eq!((events[0].0, events[0].1), (1, 7));
    assert!(matches!(
        events[0].2,
        Err(Error::ChecksumMismatch {
            id: 0x80,
            received: 0x79,
            ..
        })
    ));
}

#[test]
fn a_length_error_is_placed_at_the_six_bytes_judged() {
    // A length of 0x7FFF_FFFF; the rescan drops the type byte and two of the three 0xFF, and
    // the last 0xFF with the byte after it is the candidate the end of the stream cuts short.
    let bytes = [0x00, 0xFF, 0x80, 0xFF, 0xFF, 0xFF, 0x7F];
    assert_eq!(
        spec::<64>(&bytes),
        [
            (1, 6, Err(Error::BadLength(0x7FFF_FFFF))),
            (5, 2, Err(Error::Truncated))
        ]
    );
    // Beyond the capacity: the same six bytes.
    let bytes = [0xFF, 0x80, 0x40, 0, 0, 0];
    assert_eq!(spec::<32>(&bytes)[0], (0, 6, Err(Error::BadLength(0x40))));
}

#[test]
fn a_frame_inside_a_failed_candidate_is_placed_inside_it() {
    // A false start (length 14) that takes in a heartbeat and the byte after it: the failed
    // candidate covers all 14 bytes, the heartbeat found by the rescan its own 7.
    let mut bytes = vec![0xFF, 0x80, 0x0E, 0, 0, 0];
    bytes.extend(HEARTBEAT);
    bytes.extend([0x00, 0x55]);
    let events = spec::<64>(&bytes);
    assert!(matches!(
        events[..],
        [(0, 14, Err(Error::ChecksumMismatch { .. })), (6, 7, Ok(7))]
    ));
    // Two false starts in a row, the second inside the first: three events, the frame last.
    let mut bytes = vec![0xFF, 0x80, 0x10, 0, 0, 0, 0xFF, 0x80, 0x08, 0, 0, 0];
    bytes.extend(HEARTBEAT);
    let events = spec::<64>(&bytes);
    assert!(matches!(
        events[..],
        [
            (0, 16, Err(Error::ChecksumMismatch { .. })),
            (6, 8, Err(Error::ChecksumMismatch { .. })),
            (12, 7, Ok(7))
        ]
    ));
}

#[test]
fn a_candidate_cut_short_is_placed_up_to_the_end_of_the_stream() {
    let mut bytes = HEARTBEAT.to_vec();
    bytes.extend([0x00, 0xFF, 0x89, 0x08, 0x00]);
    assert_eq!(
        spec::<64>(&bytes),
        [(0, 7, Ok(7)), (8, 4, Err(Error::Truncated))]
    );
    // The rescan of a candidate cut short finds another inside it, cut short too.
    let bytes = [0xFF, 0x80, 0x20, 0, 0, 0, 0x11, 0xFF, 0x80];
    assert_eq!(
        spec::<64>(&bytes),
        [(0, 9, Err(Error::Truncated)), (7, 2, Err(Error::Truncated))]
    );
}

#[test]
fn a_decoder_too_small_for_a_header_places_the_bytes_it_held() {
    // Four bytes held; the three after them could not be (discarded as they came).
    assert_eq!(spec::<4>(&HEARTBEAT), [(0, 4, Err(Error::Truncated))]);
}
