//! `write_normal` and `write_expedited` write exactly the encoder's normal and expedited
//! frames and return their length, blocking and async; in the Reference profile, which has
//! no expedited header, `write_expedited` is refused and writes nothing.

use crate::transport;

use aydp_proto::{Encoder, Profile, Raw, Timestamp, embedded_io as bio, embedded_io_async as aio};
use transport::block_on;

const PAYLOAD: Raw<'static> = Raw {
    msg_type: 9,
    data: &[0x02, 0x7F],
};

fn expected(normal: bool) -> Vec<u8> {
    let e = Encoder::new(Profile::Spec);
    let mut out = [0u8; 64];
    let n = if normal {
        e.encode(&PAYLOAD, Some(Timestamp::new(7, 250)), &mut out)
    } else {
        e.encode(&PAYLOAD, None, &mut out)
    };
    out[..n.unwrap()].to_vec()
}

#[test]
fn the_blocking_writer_writes_both_forms() {
    let (normal_bytes, expedited_bytes) = (expected(true), expected(false));
    let (a, b) = (normal_bytes.len(), expedited_bytes.len());
    assert_eq!((a, b), (25, 9));
    let mut wire = [0u8; 64];
    let mut w = bio::FrameWriter::new(&mut wire[..], Profile::Spec);
    let normal = w.write_normal(&PAYLOAD, Timestamp::new(7, 250));
    let expedited = w.write_expedited(&PAYLOAD);
    assert_eq!((normal, expedited), (Ok(a), Ok(b)));
    assert_eq!(wire[..a], normal_bytes[..]);
    assert_eq!(wire[a..a + b], expedited_bytes[..]);
}

#[test]
fn the_async_writer_writes_both_forms() {
    let (normal_bytes, expedited_bytes) = (expected(true), expected(false));
    let (a, b) = (normal_bytes.len(), expedited_bytes.len());
    let mut wire = [0u8; 64];
    let mut w = aio::FrameWriter::new(&mut wire[..], Profile::Spec);
    let normal = block_on(w.write_normal(&PAYLOAD, Timestamp::new(7, 250)));
    let expedited = block_on(w.write_expedited(&PAYLOAD));
    assert_eq!((normal, expedited), (Ok(a), Ok(b)));
    assert_eq!(wire[..a], normal_bytes[..]);
    assert_eq!(wire[a..a + b], expedited_bytes[..]);
}

#[test]
fn the_reference_writers_refuse_the_expedited_form() {
    let refused = Err(aydp_proto::WriteError::Protocol(
        aydp_proto::EncodeError::ExpeditedInReference,
    ));
    let mut wire = [0u8; 16];
    let mut w = bio::FrameWriter::new(&mut wire[..], Profile::Reference);
    assert_eq!(w.write_expedited(&PAYLOAD), refused);
    let mut w = aio::FrameWriter::new(&mut wire[..], Profile::Reference);
    assert_eq!(block_on(w.write_expedited(&PAYLOAD)), refused);
    assert_eq!(wire, [0u8; 16]);
}
