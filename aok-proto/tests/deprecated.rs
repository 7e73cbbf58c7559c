//! The names before the shared vocabulary (`docs/architecture.md`) still compile, as
//! deprecated aliases, and behave exactly as the new ones.
#![allow(deprecated)]

use aok_proto::pc::{Expect, PcDecoder};
use aok_proto::{
    Ack, Command, DecoderStats, DeviceDecoder, Error, FirmwareVersion, Message, Stats,
};

#[test]
fn decoder_stats_is_stats() {
    let dec = DeviceDecoder::new();
    let s: &DecoderStats = dec.stats();
    let t: &Stats = s;
    assert_eq!(*t, Stats::default());
}

#[test]
fn checksum_is_checksum_mismatch() {
    assert_eq!(Error::Checksum, Error::ChecksumMismatch);
    let mut dec = DeviceDecoder::new();
    let mut seen = Vec::new();
    dec.feed(&[0x31, 0x67, 0x0c], |ev| {
        seen.push(match ev {
            Err(Error::Checksum) => "old name",
            Err(_) => "other error",
            Ok(_) => "command",
        })
    });
    assert_eq!(seen, ["old name", "command"]);
}

#[test]
fn drain_iterates_what_poll_returns() {
    // A `73` start swallows a read: the checksum fails on its 7th byte, and the read follows.
    let bytes = [0x73, 0x67, 0x0c, 0x00, 0x00, 0x00, 0x00];
    let (mut old, mut new) = (DeviceDecoder::new(), DeviceDecoder::new());
    let (mut a, mut b) = (Vec::new(), Vec::new());
    for &byte in &bytes {
        a.extend(old.push(byte));
        a.extend(old.drain());
        let mut event = new.push(byte);
        while let Some(ev) = event {
            b.push(ev);
            event = new.poll();
        }
    }
    assert_eq!(a, b);
    assert_eq!(
        a,
        [Err(Error::ChecksumMismatch), Ok(Command::ReadParameter(12))]
    );
    assert_eq!(old.stats(), new.stats());
}

#[test]
fn pc_drain_iterates_the_messages_poll_returns() {
    // A debug start whose checksum fails holds the ack: the old iterator yields only messages.
    let bytes = [0x1c, b'O', 0, 0, 0, 0, 0];
    let mut old = PcDecoder::new(FirmwareVersion::LATEST);
    old.expect(Expect::Ack);
    let mut messages = Vec::new();
    for &byte in &bytes {
        messages.extend(old.push(byte).and_then(Result::ok));
        messages.extend(old.drain());
    }
    assert_eq!(messages, [Message::Ack(Ack::Ok)]);
    assert_eq!(old.stats().checksum_errors, 1);
}
