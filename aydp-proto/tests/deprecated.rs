//! The names before the shared vocabulary (`docs/architecture.md`) still compile, as
//! deprecated aliases, and behave exactly as the new ones.
#![allow(deprecated)]

use aydp_proto::{Decoder, Error, Profile};

#[test]
fn bad_checksum_is_checksum_mismatch() {
    assert_eq!(Error::BadChecksum, Error::ChecksumMismatch);
    // A heartbeat with a wrong checksum, then a good one.
    let mut dec = Decoder::<64>::new(Profile::Spec);
    let mut seen = Vec::new();
    dec.feed(
        &[
            0xFF, 0x80, 0x07, 0, 0, 0, 0x77, 0xFF, 0x80, 0x07, 0, 0, 0, 0x78,
        ],
        |ev| {
            seen.push(match ev {
                Err(Error::BadChecksum) => "old name",
                Err(_) => "other error",
                Ok(_) => "frame",
            })
        },
    );
    assert_eq!(seen, ["old name", "frame"]);
    assert_eq!(dec.stats().checksum_errors, 1);
    assert_eq!(dec.stats().frames_ok, 1);
}
