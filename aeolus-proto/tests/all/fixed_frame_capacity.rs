//! `MAX_FIXED_FRAME` is the unescaped length of DEBUGINFO, the longest fixed-size message
//! (ID + 208 data bytes + CRC = 211): a decoder of that capacity receives it, and a frame one
//! data byte longer overflows it at the byte that does not fit.

use aeolus_proto::{
    CrcMode, Decode, Decoder, Error, MAX_FIXED_FRAME, encode_frame, max_encoded_len,
    message::{DEBUGINFO_LEN, Message, id},
};

#[test]
fn max_fixed_frame_is_id_debuginfo_data_and_crc() {
    assert_eq!(DEBUGINFO_LEN, 208);
    assert_eq!(MAX_FIXED_FRAME, 211);
}

/// The frame of ID 76 with `len` data bytes 0x00, 0x01, ... (no byte needs an escape).
fn frame(len: usize) -> Vec<u8> {
    let data: Vec<u8> = (0..len).map(|i| (i % 0x70) as u8).collect();
    let mut out = vec![0; max_encoded_len(len)];
    let n = encode_frame(id::DEBUGINFO, &data, &[], CrcMode::Compute, &mut out).unwrap();
    out.truncate(n);
    out
}

#[test]
fn a_decoder_of_max_fixed_frame_receives_debuginfo() {
    let wire = frame(DEBUGINFO_LEN);
    let mut d = Decoder::<MAX_FIXED_FRAME>::new();
    let mut got = Vec::new();
    d.feed(&wire, |ev| {
        got.push(ev.map(|f| {
            (
                f.id(),
                f.raw().len(),
                matches!(f.message(), Ok(Message::DebugInfo(_))),
            )
        }))
    });
    assert_eq!(got, [Ok((76, 211, true))]);
    assert_eq!(d.stats().frames_ok, 1);
    assert_eq!(d.stats().overflows, 0);
}

#[test]
fn one_data_byte_more_overflows_a_decoder_of_max_fixed_frame() {
    let wire = frame(DEBUGINFO_LEN + 1);
    let mut d = Decoder::<MAX_FIXED_FRAME>::new();
    let mut got = Vec::new();
    d.feed(&wire, |ev| got.push(ev.map(|f| f.id())));
    assert_eq!(got, [Err(Error::Overflow)]);
    assert_eq!(d.stats().overflows, 1);
    assert_eq!(d.stats().frames_ok, 0);
}
