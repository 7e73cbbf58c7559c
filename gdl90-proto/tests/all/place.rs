//! Every event's place through `Stream`: the same whatever slices the stream comes in (every
//! split point), each message's place holding exactly its frame, flag to flag, and every
//! error's place inside the stream.

use gdl90_proto::{Decoder, Error, Place, Stream, TYPED_FRAME};
use proptest::prelude::*;

use crate::stream::FRAMES;

/// An event as owned data, with its place.
type Placed = (Place, Result<String, Error>);

/// The ICD's frames, some corrupted, with hostile bytes around them.
fn hostile_stream() -> impl Strategy<Value = Vec<u8>> {
    let noise = prop::collection::vec(
        prop_oneof![3 => any::<u8>(), 1 => Just(0x7D), 1 => Just(0x7E)],
        0..4,
    );
    let frame = (
        0..FRAMES.len(),
        prop::option::of(any::<(usize, u8)>()),
        noise,
    );
    prop::collection::vec(frame, 0..6).prop_map(|frames| {
        let mut out = Vec::new();
        for (i, flip, noise) in frames {
            let mut f = FRAMES[i].to_vec();
            if let Some((at, bit)) = flip {
                let at = at % f.len();
                f[at] ^= 1 << (bit % 8);
            }
            out.extend(f);
            out.extend(noise);
        }
        out
    })
}

fn placed(bytes: &[u8], cuts: &[usize]) -> Vec<Placed> {
    let mut stream = Stream::new(Decoder::<TYPED_FRAME>::new());
    let mut out = Vec::new();
    for pair in cuts.windows(2) {
        stream.feed(&bytes[pair[0]..pair[1]], |place, ev| {
            out.push((place, ev.map(|m| format!("{m:?}"))))
        });
    }
    stream.finish(|place, ev| out.push((place, ev.map(|m| format!("{m:?}")))));
    out
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Whole, byte by byte, and cut in two at every split point: the same events at the same
    /// places.
    #[test]
    fn places_do_not_depend_on_the_slices(bytes in hostile_stream()) {
        let reference = placed(&bytes, &[0, bytes.len()]);
        let every: Vec<usize> = (0..=bytes.len()).collect();
        prop_assert_eq!(&placed(&bytes, &every), &reference);
        for cut in 0..=bytes.len() {
            prop_assert_eq!(&placed(&bytes, &[0, cut, bytes.len()]), &reference, "cut at {}", cut);
        }
    }

    /// A message's place holds its frame flag to flag (alone, it gives that message and
    /// nothing else); every place lies inside the stream; a frame cut short by the end of the
    /// stream ends where the stream does.
    #[test]
    fn each_place_holds_its_event(bytes in hostile_stream()) {
        for (place, ev) in placed(&bytes, &[0, bytes.len()]) {
            let end = usize::try_from(place.end()).unwrap();
            prop_assert!(end <= bytes.len() && place.len >= 2, "{:?} in {} bytes", place, bytes.len());
            let held = &bytes[place.offset as usize..end];
            prop_assert_eq!(held[0], 0x7E);
            match ev {
                Ok(message) => {
                    let alone = placed(held, &[0, held.len()]);
                    prop_assert_eq!(alone, vec![(Place { offset: 0, len: held.len() }, Ok(message))]);
                }
                Err(Error::Truncated) => prop_assert_eq!(end, bytes.len()),
                Err(_) => {}
            }
        }
    }
}

/// The ICD's frames back to back (each opening flag the last one's closing flag) are found
/// where they were put.
#[test]
fn frames_back_to_back_are_found_where_they_were_put() {
    let mut bytes = vec![0x13, 0x37];
    let mut expected = Vec::new();
    for frame in FRAMES {
        let at = bytes.len().saturating_sub(1).max(2);
        let skip = usize::from(bytes.last() == Some(&0x7E));
        bytes.extend_from_slice(&frame[skip..]);
        expected.push(Place {
            offset: at as u64,
            len: frame.len(),
        });
    }
    let got: Vec<Place> = placed(&bytes, &[0, bytes.len()])
        .into_iter()
        .map(|(p, _)| p)
        .collect();
    assert_eq!(got, expected);
}
