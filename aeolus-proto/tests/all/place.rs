//! Every event's place (`Decode::span` through `Stream`): the same whatever slices the stream
//! comes in (every split point), each frame's place holding exactly its wire bytes, frames put
//! at known offsets found there, and every error's place inside the stream, the end of the
//! stream's included.

use aeolus_proto::{CrcMode, Decoder, Error, FLAG, Place, Stream, encode_frame};
use proptest::prelude::*;

use crate::fast_path::stream_of;

/// An event as owned data: the frame's raw bytes (ID, data, CRC) or the error, with its place.
type Placed = (Place, Result<Vec<u8>, Error>);

/// One frame on the wire: ID, data (escapes where the bytes fall), with or without CRC.
fn wire(id: u8, data: &[u8], omit: bool) -> Vec<u8> {
    let mode = if omit {
        CrcMode::Omit
    } else {
        CrcMode::Compute
    };
    let mut buf = [0u8; 2 + 2 * 60];
    let n = encode_frame(id, data, &[], mode, &mut buf).unwrap();
    buf[..n].to_vec()
}

/// Valid frames with hostile bytes before, between and after them, short enough to be cut at
/// every split point.
fn hostile_stream() -> impl Strategy<Value = Vec<u8>> {
    stream_of(5, 24)
}

/// Feeds the pieces between `cuts` (sorted offsets into `bytes`, its ends included), then
/// finishes: every event with its place.
fn placed<const N: usize>(bytes: &[u8], cuts: &[usize]) -> Vec<Placed> {
    let mut stream = Stream::new(Decoder::<N>::new());
    let mut out = Vec::new();
    for pair in cuts.windows(2) {
        stream.feed(&bytes[pair[0]..pair[1]], |place, ev| {
            out.push((place, ev.map(|f| f.raw().to_vec())))
        });
    }
    stream.finish(|place, ev| out.push((place, ev.map(|f| f.raw().to_vec()))));
    out
}

fn whole<const N: usize>(bytes: &[u8]) -> Vec<Placed> {
    placed::<N>(bytes, &[0, bytes.len()])
}

fn by_byte<const N: usize>(bytes: &[u8]) -> Vec<Placed> {
    let cuts: Vec<usize> = (0..=bytes.len()).collect();
    placed::<N>(bytes, &cuts)
}

/// The pull form: `next_event` on what each call left, then `end_event` until `None`.
fn pulled<const N: usize>(bytes: &[u8]) -> Vec<Placed> {
    let mut stream = Stream::new(Decoder::<N>::new());
    let mut out = Vec::new();
    let mut rest = bytes;
    loop {
        let (used, ev) = stream.next_event(rest);
        rest = &rest[used..];
        match ev {
            Some((place, ev)) => out.push((place, ev.map(|f| f.raw().to_vec()))),
            None if rest.is_empty() => break,
            None => {}
        }
    }
    while let Some((place, ev)) = stream.end_event() {
        out.push((place, ev.map(|f| f.raw().to_vec())));
    }
    out
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Whole, byte by byte, pulled, and cut in two at every split point: the same events at
    /// the same places (a capacity that overflows on long frames too).
    #[test]
    fn places_do_not_depend_on_the_slices(bytes in hostile_stream()) {
        let reference = whole::<64>(&bytes);
        prop_assert_eq!(&by_byte::<64>(&bytes), &reference);
        prop_assert_eq!(&pulled::<64>(&bytes), &reference);
        for cut in 0..=bytes.len() {
            prop_assert_eq!(&placed::<64>(&bytes, &[0, cut, bytes.len()]), &reference, "cut at {}", cut);
        }
        let small = whole::<8>(&bytes);
        prop_assert_eq!(&by_byte::<8>(&bytes), &small);
        for cut in 0..=bytes.len() {
            prop_assert_eq!(&placed::<8>(&bytes, &[0, cut, bytes.len()]), &small, "cut at {}", cut);
        }
    }

    /// A frame's place holds its wire bytes, flag to flag: fed alone to a new decoder they
    /// give that frame and nothing else. Every place lies inside the stream, in order of
    /// their ends; a frame cut short by the end of the stream ends where the stream does.
    #[test]
    fn each_place_holds_its_event(bytes in hostile_stream()) {
        let events = whole::<64>(&bytes);
        let mut last_end = 0;
        for (place, ev) in &events {
            let end = usize::try_from(place.end()).unwrap();
            prop_assert!(end <= bytes.len(), "{:?} past the stream's {} bytes", place, bytes.len());
            prop_assert!(place.len >= 2, "{:?}: a flag and a byte at least", place);
            prop_assert!(end >= last_end, "{:?} ends before the last event's end {}", place, last_end);
            last_end = end;
            let held = &bytes[place.offset as usize..end];
            prop_assert_eq!(held[0], FLAG);
            match ev {
                Ok(raw) => {
                    prop_assert_eq!(held[held.len() - 1], FLAG);
                    let alone = whole::<64>(held);
                    prop_assert_eq!(alone.len(), 1);
                    prop_assert_eq!(alone[0].1.as_ref(), Ok(raw));
                    prop_assert_eq!(alone[0].0, Place { offset: 0, len: held.len() });
                }
                Err(Error::Truncated) => prop_assert_eq!(end, bytes.len()),
                Err(_) => {}
            }
        }
    }

    /// Frames put at known offsets, with short noise (no flag, no escape, too short to be a
    /// frame) between some: each is found exactly where it was put, both flags included, and
    /// each noise run is one error spanning it and the flags around it.
    #[test]
    fn frames_are_found_where_they_were_put(
        frames in prop::collection::vec(
            (any::<u8>(), prop::collection::vec(any::<u8>(), 0..30), any::<bool>(),
             prop::collection::vec(1u8..0x7D, 0..3)),
            1..6,
        ),
    ) {
        let mut bytes = Vec::new();
        let mut expected = Vec::new();
        for (id, data, omit, noise) in &frames {
            // Back to back, a frame's opening flag is the last one's closing flag.
            let frame = wire(*id, data, *omit);
            let shared = bytes.last() == Some(&FLAG);
            let at = bytes.len() - usize::from(shared);
            bytes.extend_from_slice(&frame[usize::from(shared)..]);
            let raw = whole::<64>(&frame).remove(0).1.unwrap();
            expected.push((Place { offset: at as u64, len: frame.len() }, Ok(raw)));
            if !noise.is_empty() {
                expected.push((
                    Place { offset: bytes.len() as u64 - 1, len: noise.len() + 2 },
                    Err(Error::TooShort),
                ));
                bytes.extend_from_slice(noise);
                bytes.push(FLAG);
            }
        }
        prop_assert_eq!(whole::<64>(&bytes), expected);
    }
}

/// The place of each error kind, on literal bytes.
#[test]
fn the_place_of_each_error() {
    let frame = [0x7E, 0x52, b'h', b'i', 0x00, 0x73, 0xEC, 0x7E];
    // A bad CRC: the frame, flag to flag.
    let mut bad = frame;
    bad[5] ^= 1;
    let got = whole::<64>(&bad);
    assert!(matches!(
        got[..],
        [(
            Place { offset: 0, len: 8 },
            Err(Error::ChecksumMismatch { .. })
        )]
    ));
    // Noise, then an escape before a bad byte: from the flag to the byte after 7D.
    let got = whole::<64>(&[0x11, 0x22, 0x7E, 0x52, 0x7D, 0x41, 0x33]);
    assert_eq!(
        got,
        [(Place { offset: 2, len: 4 }, Err(Error::InvalidEscape))]
    );
    // 7D 7E: from the flag to the flag, which opens the next frame (shared).
    let mut wire = vec![0x7E, 0x52, 0x7D, 0x7E];
    wire.extend_from_slice(&frame[1..]);
    let got = whole::<64>(&wire);
    assert_eq!(
        got[0],
        (Place { offset: 0, len: 4 }, Err(Error::EscapedFlag))
    );
    assert_eq!(got[1].0, Place { offset: 3, len: 8 });
    // An overflow: from the flag to the byte that did not fit (capacity 4).
    let got = whole::<4>(&[0x7E, 1, 2, 3, 4, 5, 6, 0x7E]);
    assert_eq!(got[0], (Place { offset: 0, len: 6 }, Err(Error::Overflow)));
    // The end of the stream: the flag and the bytes held, escape included.
    let got = whole::<64>(&[0x00, 0x7E, 0x52, 0x7D]);
    assert_eq!(got, [(Place { offset: 1, len: 3 }, Err(Error::Truncated))]);
    // A new decoder's garbage and a lone flag give nothing.
    assert_eq!(whole::<64>(&[1, 2, 3, 0x7E]), []);
}

/// Offsets go on across `finish`: a second stream on the same `Stream` counts from where the
/// first ended.
#[test]
fn offsets_go_on_after_the_end_of_a_stream() {
    let frame = [0x7E, 0x52, b'h', b'i', 0x00, 0x73, 0xEC, 0x7E];
    let mut stream = Stream::new(Decoder::<64>::new());
    let mut places = Vec::new();
    stream.feed(&frame, |p, _| places.push(p));
    stream.finish(|p, _| places.push(p));
    // The closing flag opened a frame that the next stream's bytes go into: 55 and a flag
    // are a frame too short, from that flag on.
    stream.feed(&[0x55], |p, _| places.push(p));
    stream.feed(&frame, |p, _| places.push(p));
    assert_eq!(
        places,
        [
            Place { offset: 0, len: 8 },
            Place { offset: 7, len: 3 },
            Place { offset: 9, len: 8 }
        ]
    );
    assert_eq!(stream.used(), 17);
    assert_eq!(stream.decoder().stats().frames_ok, 2);
}
