//! Each checksum is the XOR the spec gives, not a look-alike: frames whose checksum byte is
//! the OR or the AND of the checked bytes (which the XOR is not) are refused, on both sides
//! and by both paths (`feed` one byte at a time and `feed` with the whole frame). Random corruption seldom lands on those values, so
//! they are written out here.

use aok_proto::{CommandDecoder, Error, FirmwareVersion, Message, MessageDecoder};
use aok_proto::{Decode, Expect};

/// Every motor-test start byte (`1`..`9`, `A`..`C`).
fn motor_bytes() -> impl Iterator<Item = u8> {
    (0x31..=0x39).chain(0x41..=0x43)
}

#[test]
fn a_motor_test_with_an_or_or_and_checksum_is_refused() {
    for first in motor_bytes() {
        // 0xFF shares every bit with the start byte: XOR, OR and AND all differ.
        let value = 0xFF;
        let xor = first ^ value;
        for wrong in [first | value, first & value] {
            assert_ne!(wrong, xor);
            let frame = [first, value, wrong];
            let mismatch = Error::ChecksumMismatch {
                id: first,
                computed: u16::from(xor),
                received: u16::from(wrong),
            };
            let mut pushed = CommandDecoder::new();
            let mut by_push = Vec::new();
            for b in frame {
                pushed.feed(&[b], |ev| by_push.push(ev));
            }
            let mut fed = CommandDecoder::new();
            let mut by_feed = Vec::new();
            fed.feed(&frame, |ev| by_feed.push(ev));
            for (path, got, dec) in [("byte", &by_push, &pushed), ("feed", &by_feed, &fed)] {
                assert_eq!(got.first(), Some(&Err(mismatch)), "{path} {frame:02x?}");
                assert!(
                    got.iter().all(Result::is_err),
                    "{path} {frame:02x?}: {got:?}"
                );
                assert_eq!(dec.stats().frames_ok, 0, "{path} {frame:02x?}");
                assert_eq!(dec.stats().checksum_errors, 1, "{path} {frame:02x?}");
            }
        }
        // The XOR itself is a motor test.
        let mut dec = CommandDecoder::new();
        let mut got = Vec::new();
        dec.feed(&[first, value, xor], |ev| got.push(ev));
        assert_eq!(got.len(), 1, "{first:#04x}");
        assert!(got[0].is_ok(), "{first:#04x}: {got:?}");
    }
}

#[test]
fn a_failed_headerless_reply_is_a_checksum_mismatch_unless_it_may_be_a_debug_frame() {
    // A firmware of the headerless reply form (<= 0.30), waiting for parameter 12: any byte
    // may start the 5-byte reply. These five fail its check and do not start with the debug
    // frame's 0x1C, so they are a checksum mismatch, reported, and only the first is dropped.
    let bad = [0x01, 0x02, 0x03, 0x04, 0x00];
    let mismatch = Error::ChecksumMismatch {
        id: 0x01,
        computed: 0x04, // 0x01 ^ 0x02 ^ 0x03 ^ 0x04
        received: 0,
    };
    for path in ["byte", "feed"] {
        let mut dec = MessageDecoder::new(FirmwareVersion::new(0, 30));
        dec.expect(Expect::Parameter(12));
        let mut got = Vec::new();
        if path == "byte" {
            for b in bad {
                dec.feed(&[b], |ev| got.push(ev));
            }
        } else {
            dec.feed(&bad, |ev| got.push(ev));
        }
        assert_eq!(got, [Err(mismatch)], "{path}");
        let stats = dec.stats();
        assert_eq!(
            (
                stats.checksum_errors,
                stats.unknown_bytes,
                stats.bytes_discarded
            ),
            (1, 0, 1),
            "{path}"
        );
        // The four bytes after it wait as the next candidate; a good reply behind them is
        // found once the rescan reaches it.
        assert_eq!(dec.held_bytes(), 4, "{path}");
        let good = [0x00, 0x00, 0x05, 0xDC, 0x05 ^ 0xDC];
        let mut after = Vec::new();
        dec.feed(&good, |ev| after.push(ev));
        assert_eq!(
            after.last(),
            Some(&Ok(Message::Parameter(aok_proto::ParameterValue {
                number: 12,
                value: 1500
            }))),
            "{path}: {after:?}"
        );
    }
}
