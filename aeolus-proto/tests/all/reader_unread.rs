//! A reader's `unread()` is the exact number of bytes it read from the transport and has not
//! decoded yet: 0 before the first read, the bytes after each frame of a read.

use crate::transport;

use aeolus_proto::{embedded_io as bio, embedded_io_async as aio};
use transport::block_on;

/// TOAST "hi" twice (the closing flag of the first opens the second), then one more flag.
const WIRE: [u8; 16] = [
    0x7E, 0x52, b'h', b'i', 0x00, 0x73, 0xEC, 0x7E, 0x52, b'h', b'i', 0x00, 0x73, 0xEC, 0x7E, 0x7E,
];

#[test]
fn the_blocking_reader_counts_the_bytes_after_each_frame() {
    let mut r = bio::FrameReader::<_, 64>::new(&WIRE[..], aeolus_proto::Decoder::new());
    assert_eq!(r.unread(), 0);
    assert_eq!(r.read().map(|f| f.id()), Ok(0x52));
    assert_eq!(r.unread(), 8);
    assert_eq!(r.read().map(|f| f.id()), Ok(0x52));
    assert_eq!(r.unread(), 1);
}

#[test]
fn the_async_reader_counts_the_bytes_after_each_frame() {
    let mut r = aio::FrameReader::<_, 64>::new(&WIRE[..], aeolus_proto::Decoder::new());
    assert_eq!(r.unread(), 0);
    assert_eq!(block_on(r.read()).map(|f| f.id()), Ok(0x52));
    assert_eq!(r.unread(), 8);
    assert_eq!(block_on(r.read()).map(|f| f.id()), Ok(0x52));
    assert_eq!(r.unread(), 1);
}
