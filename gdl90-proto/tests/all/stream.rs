//! The decoder on streams: every split point, garbage between frames, a bad CRC followed by a
//! good frame, the byte accounting, and `feed` against `push` on hostile input.

use gdl90_proto::{Decode, Decoder, Error, Event, Stats, TYPED_FRAME};
use proptest::prelude::*;

/// Frames from `vectors.rs`: ICD heartbeat, ownship, AHRS with an escaped data byte,
/// heartbeat with an escaped CRC, geometric altitude, ForeFlight ID capture, unknown ID 7.
pub(crate) const FRAMES: &[&[u8]] = &[
    &[
        0x7E, 0x00, 0x81, 0x41, 0xDB, 0xD0, 0x08, 0x02, 0xB3, 0x8B, 0x7E,
    ],
    &[
        0x7E, 0x0A, 0x00, 0xA1, 0xB2, 0xC3, 0x20, 0x00, 0x00, 0xC0, 0x00, 0x00, 0x08, 0xC9, 0x9A,
        0x07, 0x8F, 0xFE, 0x40, 0x01, 0x4E, 0x31, 0x32, 0x33, 0x34, 0x35, 0x20, 0x20, 0x00, 0x58,
        0x4B, 0x7E,
    ],
    &[
        0x7E, 0x65, 0x01, 0x00, 0x64, 0xFF, 0xCE, 0x07, 0x08, 0x00, 0x78, 0x00, 0x7D, 0x5E, 0x5A,
        0xBF, 0x7E,
    ],
    &[
        0x7E, 0x00, 0x81, 0x01, 0x2C, 0x0A, 0x00, 0x00, 0x7D, 0x5D, 0x7D, 0x5E, 0x7E,
    ],
    &[0x7E, 0x0B, 0x01, 0x2C, 0x00, 0x0A, 0x24, 0x26, 0x7E],
    &[
        0x7E, 0x65, 0x00, 0x01, 0x00, 0x00, 0x00, 0x00, 0x27, 0x0F, 0xAE, 0x2D, 0x53, 0x6B, 0x79,
        0x45, 0x63, 0x68, 0x6F, 0x00, 0x53, 0x6B, 0x79, 0x45, 0x63, 0x68, 0x6F, 0x00, 0x00, 0x00,
        0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x2D, 0xF0, 0x7E,
    ],
];

/// An owned, comparable event.
type Ev = Result<String, Error>;

fn byte_by_byte<const N: usize>(d: &mut Decoder<N>, bytes: &[u8], out: &mut Vec<Ev>) {
    for &b in bytes {
        d.feed(&[b], |ev| {
            out.push(ev.map(|m| format!("{m:?}")));
        });
    }
}

fn slice_all<const N: usize>(d: &mut Decoder<N>, bytes: &[u8], out: &mut Vec<Ev>) {
    d.feed(bytes, |ev| out.push(ev.map(|m| format!("{m:?}"))));
}

fn by_bytes(bytes: &[u8]) -> (Vec<Ev>, Stats) {
    let mut d = Decoder::<TYPED_FRAME>::new();
    let mut out = Vec::new();
    byte_by_byte(&mut d, bytes, &mut out);
    (out, d.stats())
}

fn check_accounting(s: &Stats, pending: usize, total: usize) {
    let accounted = s.flags as usize + s.frame_bytes as usize + s.bytes_discarded as usize;
    assert_eq!(accounted + pending, total, "{s:?}");
}

fn stream() -> Vec<u8> {
    FRAMES.concat()
}

#[test]
fn a_clean_stream_gives_every_frame() {
    let (events, stats) = by_bytes(&stream());
    assert_eq!(events.len(), FRAMES.len());
    assert!(events.iter().all(Result::is_ok), "{events:?}");
    assert_eq!(stats.frames_ok as usize, FRAMES.len());
    assert_eq!(stats.bytes_discarded, 0);
}

#[test]
fn every_split_point_gives_the_same_events() {
    let wire = stream();
    let (want, want_stats) = by_bytes(&wire);
    for i in 0..=wire.len() {
        for j in i..=wire.len() {
            let mut d = Decoder::<TYPED_FRAME>::new();
            let mut got = Vec::new();
            slice_all(&mut d, &wire[..i], &mut got);
            // The middle piece byte by byte, so both paths hand over to each other.
            byte_by_byte(&mut d, &wire[i..j], &mut got);
            slice_all(&mut d, &wire[j..], &mut got);
            assert_eq!(got, want, "split at {i}, {j}");
            assert_eq!(d.stats(), want_stats, "split at {i}, {j}");
        }
    }
}

#[test]
fn garbage_between_frames_costs_nothing_but_itself() {
    let garbage: &[&[u8]] = &[
        &[0x00, 0x13, 0x37],
        &[0x7D],                               // escape before the next opening flag
        &[0x7D, 0x00, 0xFF],                   // invalid escape
        &[0x41],                               // too short
        &[0x01, 0x02, 0x03, 0x04, 0x05, 0x06], // bad CRC
        &[0x7E, 0x7E, 0x7E],                   // empty frames
    ];
    let mut wire = vec![0xAA, 0x55]; // before the first flag
    for (i, f) in FRAMES.iter().enumerate() {
        wire.extend_from_slice(f);
        wire.extend_from_slice(garbage[i % garbage.len()]);
    }
    let (events, stats) = by_bytes(&wire);
    let oks = events.iter().filter(|e| e.is_ok()).count();
    assert_eq!(oks, FRAMES.len(), "{events:?}");
    let errors: Vec<_> = events.iter().filter_map(|e| e.clone().err()).collect();
    assert!(errors.contains(&Error::EscapedFlag), "{errors:?}");
    assert!(errors.contains(&Error::InvalidEscape), "{errors:?}");
    assert!(errors.contains(&Error::TooShort), "{errors:?}");
    assert!(
        errors
            .iter()
            .any(|e| matches!(e, Error::ChecksumMismatch { id: 0x01, .. })),
        "{errors:?}"
    );
    assert_eq!(stats.bad_escapes, 2);
    check_accounting(&stats, 0, wire.len());
}

#[test]
fn a_bad_crc_is_an_error_and_the_next_frame_is_delivered() {
    for (k, frame) in FRAMES.iter().enumerate() {
        let mut bad = frame.to_vec();
        // Flip a bit of the first data byte (after flag and ID), unless it is an escape.
        let at = if bad[2] == 0x7D { 3 } else { 2 };
        bad[at] ^= 0x01;
        let mut wire = bad;
        wire.extend_from_slice(FRAMES[(k + 1) % FRAMES.len()]);
        let (events, stats) = by_bytes(&wire);
        assert_eq!(events.len(), 2, "{events:?}");
        assert!(
            matches!(events[0], Err(Error::ChecksumMismatch { .. })),
            "{events:?}"
        );
        assert!(events[1].is_ok(), "{events:?}");
        assert_eq!((stats.checksum_errors, stats.frames_ok), (1, 1));
    }
}

#[test]
fn overflow_then_resync() {
    let mut wire = vec![0x7E];
    wire.extend(std::iter::repeat_n(0x11, 100));
    wire.extend_from_slice(FRAMES[0]);
    let mut d = Decoder::<16>::new();
    let mut events = Vec::new();
    byte_by_byte(&mut d, &wire, &mut events);
    assert_eq!(events[0], Err(Error::Overflow));
    assert!(events[1].is_ok(), "{events:?}");
    assert_eq!(d.stats().overflows, 1);
    check_accounting(&d.stats(), d.held_bytes(), wire.len());
}

/// Hostile streams: real frames, corrupted frames and noise (flags and escapes included).
fn hostile() -> impl Strategy<Value = Vec<u8>> {
    let piece = prop_oneof![
        (0..FRAMES.len()).prop_map(|i| FRAMES[i].to_vec()),
        (0..FRAMES.len(), any::<usize>(), any::<u8>()).prop_map(|(i, at, x)| {
            let mut f = FRAMES[i].to_vec();
            let n = f.len();
            f[at % n] ^= x;
            f
        }),
        proptest::collection::vec(
            prop_oneof![
                Just(0x7Eu8),
                Just(0x7D),
                Just(0x5D),
                Just(0x5E),
                any::<u8>()
            ],
            0..24
        ),
    ];
    proptest::collection::vec(piece, 0..12).prop_map(|v| v.concat())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn feed_in_any_chunks_equals_feed_byte_by_byte(wire in hostile(), cuts in proptest::collection::vec(any::<usize>(), 0..6)) {
        let (want, want_stats) = by_bytes(&wire);
        let mut cuts: Vec<usize> = cuts.into_iter().map(|c| c % (wire.len() + 1)).collect();
        cuts.push(0);
        cuts.push(wire.len());
        cuts.sort_unstable();
        let mut d = Decoder::<TYPED_FRAME>::new();
        let mut got = Vec::new();
        for w in cuts.windows(2) {
            slice_all(&mut d, &wire[w[0]..w[1]], &mut got);
        }
        prop_assert_eq!(got, want);
        prop_assert_eq!(d.stats(), want_stats);
        check_accounting(&d.stats(), d.held_bytes(), wire.len());
    }

    /// The pull form (`decode` again and again, `item` for a found frame, `end` at the end)
    /// gives the events and counters of `feed` and `finish`.
    #[test]
    fn the_pull_form_equals_the_loop(wire in hostile(), cut in any::<usize>()) {
        let (mut want, want_stats) = by_bytes(&wire);
        let mut reference = Decoder::<TYPED_FRAME>::new();
        reference.feed(&wire, |_| {});
        reference.finish(|ev| want.push(ev.map(|m| format!("{m:?}"))));
        let cut = cut % (wire.len() + 1);
        let mut d = Decoder::<TYPED_FRAME>::new();
        let mut got = Vec::new();
        for piece in [&wire[..cut], &wire[cut..]] {
            let mut rest = piece;
            loop {
                let (used, event) = d.decode(rest);
                match event {
                    Some(Event::Found(at)) => got.push(Ok(format!("{:?}", d.item(rest, at)))),
                    Some(Event::Error(e)) => got.push(Err(e)),
                    Some(Event::Truncated(n)) => panic!("decode never truncates ({n})"),
                    None => {}
                }
                rest = &rest[used..];
                if event.is_none() {
                    break;
                }
            }
        }
        prop_assert_eq!(d.stats(), want_stats);
        while let Some(event) = d.end() {
            match event {
                Event::Truncated(_) => got.push(Err(Error::Truncated)),
                other => panic!("the end gives up frames, it finds none: {other:?}"),
            }
        }
        prop_assert_eq!(got, want);
        prop_assert_eq!(d.stats(), reference.stats());
    }

    #[test]
    fn accounting_holds_after_every_byte(wire in hostile()) {
        let mut d = Decoder::<TYPED_FRAME>::new();
        let mut events = 0u32;
        for (i, &b) in wire.iter().enumerate() {
            d.feed(&[b], |_| events += 1);
            check_accounting(&d.stats(), d.held_bytes(), i + 1);
        }
        // Every event is counted exactly once.
        let s = d.stats();
        let counted = s.frames_ok + s.invalid + s.checksum_errors + s.overflows + s.too_short + s.bad_escapes;
        prop_assert_eq!(counted, events);
    }
}
