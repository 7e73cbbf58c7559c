//! A reader's `unread()` is the exact number of bytes it read from the transport and has not
//! decoded yet: 0 before the first read, the bytes after each frame of a read.

use crate::transport;

use aydp_proto::{Profile, embedded_io as bio, embedded_io_async as aio};
use transport::block_on;

/// A frame of type 0x09 (flag 0x80) with one data byte, 0x02, twice, then a start byte.
const WIRE: [u8; 17] = [
    0xFF, 0x89, 0x08, 0, 0, 0, 0x02, 0x7C, 0xFF, 0x89, 0x08, 0, 0, 0, 0x02, 0x7C, 0xFF,
];

#[test]
fn the_blocking_reader_counts_the_bytes_after_each_frame() {
    let mut r = bio::FrameReader::<_, 32>::new(&WIRE[..], aydp_proto::Decoder::new(Profile::Spec));
    assert_eq!(r.unread(), 0);
    assert_eq!(r.read().map(|f| f.data().to_vec()), Ok(vec![0x02]));
    assert_eq!(r.unread(), 9);
    assert_eq!(r.read().map(|f| f.data().to_vec()), Ok(vec![0x02]));
    assert_eq!(r.unread(), 1);
}

#[test]
fn the_async_reader_counts_the_bytes_after_each_frame() {
    let mut r = aio::FrameReader::<_, 32>::new(&WIRE[..], aydp_proto::Decoder::new(Profile::Spec));
    assert_eq!(r.unread(), 0);
    let first = block_on(r.read()).map(|f| f.data().to_vec());
    assert_eq!((first, r.unread()), (Ok(vec![0x02]), 9));
    let second = block_on(r.read()).map(|f| f.data().to_vec());
    assert_eq!((second, r.unread()), (Ok(vec![0x02]), 1));
}
