#![cfg(all(feature = "embedded-io", feature = "embedded-io-async"))]
//! `write_normal` and `write_expedited` write exactly the encoder's normal and expedited
//! frames and return their length, blocking and async.

#[path = "../../aeolus-proto/tests/support/transport.rs"]
mod transport;

use aydp_proto::{Encoder, Profile, Raw, Timestamp, embedded_io as bio, embedded_io_async as aio};
use transport::block_on;

const PAYLOAD: Raw<'static> = Raw {
    msg_type: 9,
    data: &[0x02, 0x7F],
};

fn expected(normal: bool) -> Vec<u8> {
    let e = Encoder::new(Profile::Reference);
    let mut out = [0u8; 64];
    let n = if normal {
        e.encode_normal(&PAYLOAD, Timestamp::new(7, 250), &mut out)
    } else {
        e.encode_expedited(&PAYLOAD, &mut out)
    };
    out[..n.unwrap()].to_vec()
}

#[test]
fn the_blocking_writer_writes_both_forms() {
    let mut wire = [0u8; 64];
    let mut w = bio::FrameWriter::new(&mut wire[..], Profile::Reference);
    let normal = w.write_normal(&PAYLOAD, Timestamp::new(7, 250));
    let expedited = w.write_expedited(&PAYLOAD);
    assert_eq!((normal, expedited), (Ok(25), Ok(9)));
    assert_eq!(wire[..25], expected(true)[..]);
    assert_eq!(wire[25..34], expected(false)[..]);
}

#[test]
fn the_async_writer_writes_both_forms() {
    let mut wire = [0u8; 64];
    let mut w = aio::FrameWriter::new(&mut wire[..], Profile::Reference);
    let normal = block_on(w.write_normal(&PAYLOAD, Timestamp::new(7, 250)));
    let expedited = block_on(w.write_expedited(&PAYLOAD));
    assert_eq!((normal, expedited), (Ok(25), Ok(9)));
    assert_eq!(wire[..25], expected(true)[..]);
    assert_eq!(wire[25..34], expected(false)[..]);
}
