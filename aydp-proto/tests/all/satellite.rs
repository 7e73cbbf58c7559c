//! One satellite of a fix detail is 7 bytes: its ID, then azimuth, elevation and SNR as
//! unsigned uflt16; `parse` reads exactly what `to_bytes` writes, and refuses a sign bit.

use aydp_proto::{Error, Satellite};

#[test]
fn parse_reads_back_the_seven_bytes() {
    let b = [7, 0x34, 0x12, 0x00, 0x3C, 0x21, 0x43];
    let s = Satellite::parse(&b).unwrap();
    assert_eq!(s.id, 7);
    let mut out = [0u8; Satellite::LEN];
    assert_eq!(s.emit(&mut out), Ok(7));
    assert_eq!(out, b);
    assert!(s.azimuth > 0.0 && s.elevation > 0.0 && s.snr > 0.0, "{s:?}");
}

#[test]
fn a_sign_bit_in_any_field_is_refused() {
    for at in [2, 4, 6] {
        let mut b = [7, 0x34, 0x12, 0x00, 0x3C, 0x21, 0x43];
        b[at] |= 0x80;
        assert_eq!(
            Satellite::parse(&b),
            Err(Error::NegativeUflt16),
            "byte {at}"
        );
    }
}

#[test]
fn f16_bits_to_f32_keeps_the_sign_and_the_special_values() {
    use aydp_proto::uflt16::f16_bits_to_f32;
    assert_eq!(f16_bits_to_f32(0xC000), -2.0);
    assert_eq!(f16_bits_to_f32(0x3C00), 1.0);
    assert_eq!(f16_bits_to_f32(0x8001), -(2f32.powi(-24)));
    assert_eq!(f16_bits_to_f32(0x7C00), f32::INFINITY);
    assert_eq!(f16_bits_to_f32(0xFC00), f32::NEG_INFINITY);
    assert!(f16_bits_to_f32(0x7E00).is_nan());
}
