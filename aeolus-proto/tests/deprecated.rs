//! The names before the shared vocabulary (`docs/architecture.md`) still compile, as
//! deprecated aliases, and behave exactly as the new ones.
#![allow(deprecated)]

use aeolus_proto::{Decoder, Deframer, Error};

/// Noise, a TOAST "hi", a frame with a bad CRC, and the start of a frame.
const STREAM: &[u8] = &[
    0x00, 0x7E, 0x52, b'h', b'i', 0x00, 0x73, 0xEC, 0x7E, 0x52, b'h', b'i', 0x00, 0x00, 0xEC, 0x7E,
    0x52,
];

fn events<const N: usize>(d: &mut Decoder<N>, use_old: bool) -> Vec<Result<Vec<u8>, Error>> {
    let mut out = Vec::new();
    if use_old {
        d.push_slice(STREAM, |ev| out.push(ev.map(|f| f.raw().to_vec())));
    } else {
        d.feed(STREAM, |ev| out.push(ev.map(|f| f.raw().to_vec())));
    }
    out
}

#[test]
fn deframer_and_push_slice_are_decoder_and_feed() {
    let mut old: Deframer<64> = Deframer::<64>::new();
    let mut new = Decoder::<64>::new();
    let (a, b) = (events(&mut old, true), events(&mut new, false));
    assert_eq!(a, b);
    assert_eq!(a.len(), 2);
    assert_eq!(old.stats(), new.stats());
    assert_eq!(old.stats().checksum_errors, 1);
    let strict: Deframer<16> = Deframer::strict();
    assert!(strict.is_strict());
}

#[cfg(feature = "embedded-io")]
#[test]
fn frame_reader_deframer_is_decoder() {
    use aeolus_proto::embedded_io::FrameReader;
    let mut r = FrameReader::<_, 64, 8>::with_deframer(STREAM, Deframer::new());
    let first = r.read_frame().map(|f| f.id());
    assert_eq!(first, Ok(82));
    assert_eq!(r.deframer().stats(), r.decoder().stats());
    assert_eq!(r.deframer().stats().frames_ok, 1);
}
