//! `Stats::frames_delivered` and `Stats::frames_dropped` are the sums of their counters, on a
//! stream with one frame of every outcome.

use aeolus_proto::Decode;
use aeolus_proto::{Decoder, Error, Stats};

/// TOAST "hi" with its CRC, then with `00 00` (no CRC), then with a wrong CRC, then a frame
/// too long for 8 bytes, a 2-byte frame, and a bad escape.
const STREAM: &[u8] = &[
    0x7E, 0x52, b'h', b'i', 0x00, 0x73, 0xEC, 0x7E, // ok
    0x52, b'h', b'i', 0x00, 0x00, 0x00, 0x7E, // no CRC
    0x52, b'h', b'i', 0x00, 0x73, 0xED, 0x7E, // CRC mismatch
    0x52, 1, 2, 3, 4, 5, 6, 7, 8, 0x7E, // overflow (then hunts for the flag)
    0x7E, 0x52, 0x00, 0x7E, // too short
    0x52, 0x7D, 0x00, 0x7E, // bad escape (then hunts for the flag)
];

const MISMATCH: Error = Error::ChecksumMismatch {
    id: 0x52,
    computed: 0xEC73,
    received: 0xED73,
};

fn run(mut d: Decoder<8>) -> (Vec<Result<u8, Error>>, Stats) {
    let mut events = Vec::new();
    d.feed(STREAM, |ev| events.push(ev.map(|f| f.id())));
    (events, d.stats())
}

#[test]
fn delivered_and_dropped_are_the_sums_of_their_counters() {
    let (events, s) = run(Decoder::new());
    let want = [
        Ok(0x52),
        Ok(0x52),
        Err(MISMATCH),
        Err(Error::Overflow),
        Err(Error::TooShort),
        Err(Error::InvalidEscape),
    ];
    assert_eq!(events, want);
    assert_eq!((s.frames_ok, s.frames_no_crc), (1, 1));
    assert_eq!(s.frames_delivered(), 2);
    assert_eq!(
        (
            s.checksum_errors,
            s.missing_crc,
            s.overflows,
            s.too_short,
            s.bad_escapes
        ),
        (1, 0, 1, 1, 1)
    );
    assert_eq!(s.frames_dropped(), 4);
}

#[test]
fn in_strict_mode_a_frame_without_crc_is_dropped_as_missing_crc() {
    let (events, s) = run(Decoder::strict());
    let want = [
        Ok(0x52),
        Err(Error::MissingCrc { id: 0x52 }),
        Err(MISMATCH),
        Err(Error::Overflow),
        Err(Error::TooShort),
        Err(Error::InvalidEscape),
    ];
    assert_eq!(events, want);
    assert_eq!((s.frames_ok, s.frames_no_crc), (1, 0));
    assert_eq!(s.frames_delivered(), 1);
    assert_eq!(
        (
            s.checksum_errors,
            s.missing_crc,
            s.overflows,
            s.too_short,
            s.bad_escapes
        ),
        (1, 1, 1, 1, 1)
    );
    assert_eq!(s.frames_dropped(), 5);
}
