//! A reader's `unread()` is the exact number of bytes it read from the transport and has not
//! decoded yet: 0 before the first read, the bytes after each item of a read, 0 at the end.

use crate::transport;

use aok_proto::{Command, FirmwareVersion, embedded_io as bio, embedded_io_async as aio};
use transport::block_on;

/// "control 1", "save set 2", "control 1": 2 + 3 + 2 bytes, all in one read.
const COMMANDS: [u8; 7] = [0x63, 0x01, 0x63, 0x04, 0x02, 0x63, 0x01];

/// A 7-byte parameter reply twice, then one byte of the next frame.
const MESSAGES: [u8; 15] = [
    0x1c, 0x56, 0xff, 0xff, 0xff, 0xfe, 0x57, 0x1c, 0x56, 0xff, 0xff, 0xff, 0xfe, 0x57, 0x00,
];

#[test]
fn command_reader_counts_the_bytes_after_each_command() {
    let mut r = bio::CommandReader::<_>::new(&COMMANDS[..], aok_proto::CommandDecoder::new());
    assert_eq!(r.unread(), 0);
    let mut left = Vec::new();
    for _ in 0..3 {
        r.read().unwrap();
        left.push(r.unread());
    }
    assert_eq!(left, [5, 2, 0]);
}

#[test]
fn async_command_reader_counts_the_bytes_after_each_command() {
    let mut r = aio::CommandReader::<_>::new(&COMMANDS[..], aok_proto::CommandDecoder::new());
    assert_eq!(r.unread(), 0);
    let mut got = Vec::new();
    for _ in 0..3 {
        let c = block_on(r.read()).unwrap();
        got.push((c, r.unread()));
    }
    assert_eq!(got[1], (Command::SaveSet(2), 2));
    assert_eq!(got.iter().map(|g| g.1).collect::<Vec<_>>(), [5, 2, 0]);
}

#[test]
fn message_reader_counts_the_bytes_after_each_message() {
    let mut r = bio::MessageReader::<_>::new(
        &MESSAGES[..],
        aok_proto::MessageDecoder::new(FirmwareVersion::LATEST),
    );
    assert_eq!(r.unread(), 0);
    r.read().unwrap();
    assert_eq!(r.unread(), 8);
    r.read().unwrap();
    assert_eq!(r.unread(), 1);
}

#[test]
fn async_message_reader_counts_the_bytes_after_each_message() {
    let mut r = aio::MessageReader::<_>::new(
        &MESSAGES[..],
        aok_proto::MessageDecoder::new(FirmwareVersion::LATEST),
    );
    assert_eq!(r.unread(), 0);
    block_on(r.read()).unwrap();
    assert_eq!(r.unread(), 8);
    block_on(r.read()).unwrap();
    assert_eq!(r.unread(), 1);
}
