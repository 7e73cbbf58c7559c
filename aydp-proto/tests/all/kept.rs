//! `Stream::next_kept`: a frame found in place in the caller's slice is copied into the
//! decoder (`Decode::keep`), so that it outlives the slice; the events and places are those of
//! `next_event`, over hostile streams cut at every chunk size.

use crate::streamgen::{Rng, garbage, random_message};

use aydp_proto::{Decoder, Error, Place, Profile, Stream};

const CAP: usize = 128;

/// What one pull form gives: every event's place, and its frame's bytes or its error.
type Events = Vec<(Place, Result<Vec<u8>, Error>)>;

/// The stream in chunks of `chunk` bytes, each decoded to its end by `next_kept` (`kept`) or
/// `next_event`: the events, and how many frames lay in the caller's chunk (for `next_kept`,
/// every frame is checked to lie outside it, in the decoder).
fn pull(stream: &[u8], chunk: usize, kept: bool) -> (Events, usize) {
    let mut s = Stream::new(Decoder::<CAP>::new(Profile::Spec));
    let mut out = Vec::new();
    let mut in_place = 0;
    for piece in stream.chunks(chunk) {
        let mut rest = piece;
        loop {
            let (used, event) = if kept {
                s.next_kept(rest)
            } else {
                s.next_event(rest)
            };
            let Some((place, event)) = event else {
                break;
            };
            let event = event.map(|frame| {
                let bytes = frame.as_bytes();
                let inside = piece.as_ptr_range().contains(&bytes.as_ptr());
                assert!(
                    !(kept && inside),
                    "a kept frame at {} still points into the caller's slice",
                    place.offset
                );
                in_place += usize::from(inside);
                bytes.to_vec()
            });
            out.push((place, event));
            rest = &rest[used..];
        }
    }
    while let Some((place, event)) = s.end_event() {
        out.push((place, event.map(|f| f.as_bytes().to_vec())));
    }
    (out, in_place)
}

#[test]
fn kept_frames_are_the_frames_found_in_place_with_the_same_places() {
    let mut rng = Rng(0x4B45_5054);
    let mut stream = Vec::new();
    for _ in 0..300 {
        garbage(&mut rng, Profile::Spec, CAP, (1, 4), &mut stream);
        stream.extend_from_slice(&random_message(&mut rng, Profile::Spec));
    }
    for chunk in [1, 2, 7, 64, 1000, stream.len()] {
        let (want, in_place) = pull(&stream, chunk, false);
        let (got, _) = pull(&stream, chunk, true);
        assert_eq!(got, want, "chunks of {chunk} bytes");
        // Long chunks hand frames in place (those behind no false start): the ones `keep`
        // copies.
        let frames = want.iter().filter(|(_, e)| e.is_ok()).count();
        assert!(frames >= 250, "only {frames} frames of 300 came through");
        if chunk >= 1000 {
            assert!(in_place > 0, "no frame of {frames} in place");
        }
    }
}

#[test]
fn a_kept_frame_outlives_the_bytes_it_came_in() {
    // A heartbeat (normal header) and an expedited one, whole in one buffer that is then
    // overwritten: the frame handed back still holds the bytes received.
    let heartbeat = [0xFF, 0x80, 0x07, 0, 0, 0, 0x78];
    let mut buffer = heartbeat;
    let mut s = Stream::new(Decoder::<CAP>::new(Profile::Spec));
    let (used, event) = s.next_kept(&buffer);
    buffer.fill(0xAA);
    let (place, frame) = event.expect("one event");
    assert_eq!((used, place), (7, Place { offset: 0, len: 7 }));
    assert_eq!(frame.expect("a frame").as_bytes(), &heartbeat[..]);
    assert_eq!(buffer, [0xAA; 7]);
}
