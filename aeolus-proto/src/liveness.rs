//! The loops over a datagram and over a frame's bytes end, whatever the input: each turn
//! consumes input or ends. A unit test rather than an integration test because the library's
//! unit tests run first: a loop that stops making progress fails here, at a deadline far above
//! the microseconds the work takes, instead of hanging the integration tests behind it.

extern crate std;

use crate::{CrcMode, FrameBytes, decode_datagram, encode_frame, max_encoded_len};
use std::vec::Vec;

#[path = "../../frame-io/tests/support/deadline.rs"]
mod deadline;
use deadline::returns;

/// A frame whose data holds both bytes that are escaped.
fn frame(id: u8) -> Vec<u8> {
    let mut out = std::vec![0u8; max_encoded_len(4)];
    let n = encode_frame(id, &[0x7D, 1, 0x7E, 2], &[], CrcMode::Compute, &mut out).unwrap_or(0);
    out.truncate(n);
    out
}

/// The IDs (or the error) of the frames of a datagram of two frames and a cut one.
fn datagram_ids() -> Vec<Result<u8, crate::Error>> {
    let mut datagram = [frame(82), frame(83), std::vec![0x7E, 0x52, 0x01]].concat();
    decode_datagram(&mut datagram, false)
        .map(|f| f.map(|f| f.id()))
        .collect()
}

/// The bytes `FrameBytes` gives for the frame of ID 82.
fn frame_bytes() -> Vec<u8> {
    FrameBytes::new(82, &[0x7D, 1, 0x7E, 2], CrcMode::Compute).collect()
}

#[test]
fn a_datagram_is_read_to_its_end() {
    let got = returns("decode_datagram", datagram_ids);
    assert_eq!(got, [Ok(82), Ok(83), Err(crate::Error::Truncated)]);
}

#[test]
fn frame_bytes_ends_after_the_frame() {
    assert_eq!(returns("FrameBytes", frame_bytes), frame(82));
}

/// What the blocking reader returns over two frames and a cut one, up to the end of the stream
/// (at most 8 reads: the test fails rather than spins if the end is never reported).
#[cfg(feature = "embedded-io")]
fn reader_results() -> Vec<Result<u8, crate::IoError<core::convert::Infallible>>> {
    let wire = [frame(82), frame(83), std::vec![0x7E, 0x52, 0x01]].concat();
    let mut reader =
        crate::embedded_io::FrameReader::<_, 64>::new(&wire[..], crate::Decoder::new());
    let mut got = Vec::new();
    for _ in 0..8 {
        let r = reader.read().map(|f| f.id());
        let end = r == Err(crate::IoError::Eof);
        got.push(r);
        if end {
            break;
        }
    }
    got
}

#[cfg(feature = "embedded-io")]
#[test]
fn the_reader_reports_the_end_of_the_stream_once() {
    use crate::IoError;
    let got = returns("FrameReader::read", reader_results);
    assert_eq!(
        got,
        [
            Ok(82),
            Ok(83),
            Err(IoError::UnexpectedEof { pending: 2 }),
            Err(IoError::Eof)
        ]
    );
}
