//! Every entry point of the decoder returns, whatever the stream: each of its loops consumes
//! a byte or hands out an event per turn; and the encoder's byte iterator ends. Unit tests
//! rather than integration tests because the library's unit tests run first: a rule that
//! stops consuming (a loop that makes no progress) fails here, at a deadline far above the
//! microseconds the work takes, instead of hanging the integration tests behind it.

extern crate std;

use super::*;
use std::vec::Vec;

#[path = "../../../frame-io/tests/support/deadline.rs"]
mod deadline;
use deadline::returns;

/// Noise; a false candidate as long as the decoder, whose last two bytes start a heartbeat
/// (held at the end of the buffer, so the decoder moves them to its front); a run of starts,
/// a heartbeat, a copy with its checksum broken, a message with one data byte, and a
/// candidate cut short by the end of the stream.
const STREAM: &[u8] = &[
    0x00, 0x12, 0xFF, 0x80, 0x10, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0xFF, 0x80, 0x07, 0, 0, 0, 0x78,
    0xFF, 0xFF, 0xFF, 0x80, 0x07, 0, 0, 0, 0x78, 0xFF, 0x80, 0x07, 0, 0, 0, 0x79, 0xFF, 0x89, 0x08,
    0, 0, 0, 0x02, 0x7C, 0xFF, 0x89, 0x08, 0,
];

/// What an event is, without the borrow: the frame's bytes, or the error.
type Seen = Result<Vec<u8>>;

fn seen(ev: Result<Frame<'_>>) -> Seen {
    ev.map(|f| f.as_bytes().to_vec())
}

/// A decoder of 16 bytes: the held candidates are moved to the front (`compact`) on the way.
type Small = Decoder<16>;

/// The reference: one byte a `feed`, then `finish`.
fn by_byte() -> Vec<Seen> {
    let mut dec = Small::new(Profile::Spec);
    let mut got = Vec::new();
    for byte in STREAM {
        dec.feed(core::slice::from_ref(byte), |ev| got.push(seen(ev)));
    }
    dec.finish(|ev| got.push(seen(ev)));
    got
}

/// The pull form at every cut of the stream in two: `decode` on what each call left, until it
/// returns `(0, None)`, then `end` until `None`. Every call uses a byte or gives an event.
fn by_decode_at_every_cut() -> Vec<Vec<Seen>> {
    (0..=STREAM.len())
        .map(|cut| {
            let (a, b) = STREAM.split_at(cut);
            let mut dec = Small::new(Profile::Spec);
            let mut got = Vec::new();
            for piece in [a, b] {
                let mut rest = piece;
                loop {
                    let (used, event) = dec.decode(rest);
                    let input = rest;
                    rest = rest.get(used..).unwrap_or(&[]);
                    match event {
                        None => break,
                        Some(Event::Found(found)) => got.push(seen(Ok(dec.item(input, found)))),
                        Some(Event::Error(e)) => got.push(Err(e)),
                        Some(Event::Truncated(_)) => got.push(Err(Error::Truncated)),
                    }
                }
            }
            while let Some(event) = dec.end() {
                match event {
                    Event::Found(found) => got.push(seen(Ok(dec.item(&[], found)))),
                    Event::Error(e) => got.push(Err(e)),
                    Event::Truncated(_) => got.push(Err(Error::Truncated)),
                }
            }
            got
        })
        .collect()
}

fn by_feed_at_every_cut() -> Vec<Vec<Seen>> {
    (0..=STREAM.len())
        .map(|cut| {
            let (a, b) = STREAM.split_at(cut);
            let mut dec = Small::new(Profile::Spec);
            let mut got = Vec::new();
            dec.feed(a, |ev| got.push(seen(ev)));
            dec.feed(b, |ev| got.push(seen(ev)));
            dec.finish(|ev| got.push(seen(ev)));
            got
        })
        .collect()
}

#[test]
fn feed_byte_by_byte_and_finish_return_with_the_streams_events() {
    let got = returns("feed byte by byte and finish", by_byte);
    let frames: Vec<_> = got.iter().filter_map(|e| e.as_ref().ok()).collect();
    assert_eq!(
        frames,
        [
            &[0xFF, 0x80, 0x07, 0, 0, 0, 0x78][..],
            &[0xFF, 0x80, 0x07, 0, 0, 0, 0x78][..],
            &[0xFF, 0x89, 0x08, 0, 0, 0, 0x02, 0x7C][..],
        ]
    );
    assert!(got.contains(&Err(Error::Truncated)), "{got:?}");
}

#[test]
fn feed_at_every_cut_returns_with_the_same_events() {
    let by_byte = returns("feed byte by byte and finish", by_byte);
    for (cut, got) in returns("feed", by_feed_at_every_cut).iter().enumerate() {
        assert_eq!(got, &by_byte, "cut at {cut}");
    }
}

#[test]
fn decode_and_end_at_every_cut_return_with_the_same_events() {
    let by_byte = returns("feed byte by byte and finish", by_byte);
    for (cut, got) in returns("decode and end", by_decode_at_every_cut)
        .iter()
        .enumerate()
    {
        assert_eq!(got, &by_byte, "cut at {cut}");
    }
}

/// A position report as the encoder's byte iterator gives it, and as `encode` writes it.
fn encoded_both_ways() -> (Vec<u8>, Vec<u8>) {
    use crate::{Encoder, Position, Timestamp};
    let pos = Position {
        latitude: 50.5,
        longitude: -1.25,
        altitude: 12.5,
    };
    let enc = Encoder::new(Profile::Spec);
    let stamp = Some(Timestamp::new(1_700_000_000, 250));
    let by_iter: Vec<u8> = enc
        .iter(&pos, stamp)
        .map(|b| b.collect())
        .unwrap_or_default();
    let mut buf = [0u8; 64];
    let n = enc.encode(&pos, stamp, &mut buf).unwrap_or(0);
    (by_iter, buf[..n].to_vec())
}

#[test]
fn the_encoders_byte_iterator_ends_with_the_message() {
    let (by_iter, by_encode) = returns("Encoder::iter", encoded_both_ways);
    assert!(!by_encode.is_empty());
    assert_eq!(by_iter, by_encode);
}

/// The satellites of a two-satellite fix detail and the entries of a two-entry direct output,
/// counted: each iterator ends after its message's count.
fn list_lengths() -> (usize, usize) {
    use crate::{DirectOutput, FixDetail, OutputEntry, Satellite};
    let fix = [[2u8].as_slice(), &[0u8; 2 * Satellite::LEN]].concat();
    let out = [[2u8, 0].as_slice(), &[0u8; 2 * OutputEntry::LEN]].concat();
    let sats = FixDetail::parse(&fix).map_or(0, |f| f.satellites().count());
    let entries = DirectOutput::parse(&out).map_or(0, |d| d.entries().count());
    (sats, entries)
}

#[test]
fn the_message_lists_iterators_end_with_their_count() {
    assert_eq!(returns("Satellites and Entries", list_lengths), (2, 2));
}

/// The frames the blocking reader returns over the stream, read `R` bytes at a time, up to its
/// end (at most 64 reads: the test fails rather than spins if the end is never reported), and
/// whether it reported the end.
#[cfg(feature = "embedded-io")]
fn reader_frames<const R: usize>() -> (Vec<Vec<u8>>, bool) {
    // `frame_io`'s reader itself, which `embedded_io::FrameReader` names: the decoder module
    // does not import the module above it (tests/tests/all/module_layers.rs).
    let mut reader =
        frame_io::embedded_io::Reader::<_, Small, R>::new(STREAM, Small::new(Profile::Spec));
    let mut frames = Vec::new();
    for _ in 0..64 {
        match reader.read() {
            Ok(f) => frames.push(f.as_bytes().to_vec()),
            Err(frame_io::IoError::Eof) => return (frames, true),
            Err(_) => {}
        }
    }
    (frames, false)
}

#[cfg(feature = "embedded-io")]
#[test]
fn the_reader_returns_the_streams_frames_and_its_end() {
    let by_byte: Vec<Vec<u8>> = by_byte().into_iter().filter_map(|s| s.ok()).collect();
    assert!(!by_byte.is_empty());
    for got in [
        returns("FrameReader::read, 1 byte a read", reader_frames::<1>),
        returns("FrameReader::read, 3 bytes a read", reader_frames::<3>),
        returns("FrameReader::read, 64 bytes a read", reader_frames::<64>),
    ] {
        assert_eq!(got, (by_byte.clone(), true));
    }
}
