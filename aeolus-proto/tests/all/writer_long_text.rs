//! The writers take a text of the full `TEXT_CAPACITY` (120 bytes and its NUL) and write
//! exactly the bytes `Message::encode` gives.

use crate::transport;

use aeolus_proto::message::{Message, Text};
use aeolus_proto::{CrcMode, TEXT_CAPACITY, embedded_io as bio, embedded_io_async as aio};
use transport::block_on;

fn longest() -> (Message<'static>, Vec<u8>) {
    let text: String = (0..TEXT_CAPACITY)
        .map(|i| (b'a' + (i % 26) as u8) as char)
        .collect();
    let m = Message::Toast(Text::new(&text).unwrap());
    let mut want = vec![0u8; 300];
    let n = m.encode(&mut want, CrcMode::Compute).unwrap();
    want.truncate(n);
    (m, want)
}

#[test]
fn the_blocking_writer_writes_the_longest_text() {
    let (m, want) = longest();
    let mut wire = [0u8; 300];
    let n = bio::FrameWriter::new(&mut wire[..]).write_message(&m, CrcMode::Compute);
    assert_eq!(n, Ok(want.len()));
    assert_eq!(&wire[..want.len()], &want[..]);
    assert_eq!(want.len(), 126);
}

#[test]
fn the_async_writer_writes_the_longest_text() {
    let (m, want) = longest();
    let mut wire = [0u8; 300];
    let n = block_on(aio::FrameWriter::new(&mut wire[..]).write_message(&m, CrcMode::Compute));
    assert_eq!(n, Ok(want.len()));
    assert_eq!(&wire[..want.len()], &want[..]);
}
