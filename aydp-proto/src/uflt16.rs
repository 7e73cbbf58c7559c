//! `uflt16`: an IEEE 754 binary16 value that is never negative, read as `f32` (DECISIONS.md Y7).
//!
//! The conversions are written here (no extra crate) and are `const fn`. Decoding is exact:
//! every binary16 value is representable in `f32`. Encoding rounds to nearest, ties to even,
//! overflows to +infinity, clamps negative values (and -0.0) to +0.0 and keeps a NaN's top ten payload bits
//! (so every binary16 bit pattern without its sign bit survives decode then encode).

use crate::error::{Error, Result};

const SIGN: u16 = 0x8000;

/// Convert binary16 bits to `f32`, whatever the sign bit (exact).
///
/// ```
/// use aydp_proto::uflt16::f16_bits_to_f32;
/// assert_eq!(f16_bits_to_f32(0x3C00), 1.0);
/// assert_eq!(f16_bits_to_f32(0xC000), -2.0);
/// assert_eq!(f16_bits_to_f32(0x0001), 2f32.powi(-24));
/// ```
pub const fn f16_bits_to_f32(bits: u16) -> f32 {
    let sign = ((bits & SIGN) as u32) << 16;
    let exp = ((bits >> 10) & 0x1F) as u32;
    let mant = (bits & 0x03FF) as u32;
    let magnitude = if exp == 0 {
        // Zero or subnormal: mant * 2^-24, exact in f32.
        let v = mant as f32 * (1.0 / 16_777_216.0);
        v.to_bits()
    } else if exp == 0x1F {
        0x7F80_0000 | (mant << 13)
    } else {
        ((exp + 112) << 23) | (mant << 13)
    };
    f32::from_bits(sign | magnitude)
}

/// Decode a `uflt16` field: a set sign bit is a malformed field (Y7).
///
/// ```
/// use aydp_proto::{uflt16::decode, Error};
/// assert_eq!(decode(0x4900), Ok(10.0));
/// assert_eq!(decode(0x8000), Err(Error::NegativeUflt16));
/// ```
pub const fn decode(bits: u16) -> Result<f32> {
    if bits & SIGN != 0 {
        Err(Error::NegativeUflt16)
    } else {
        Ok(f16_bits_to_f32(bits))
    }
}

/// Encode an `f32` as `uflt16` bits: negatives clamp to 0, overflow gives +infinity, rounding
/// is to nearest with ties to even.
///
/// ```
/// use aydp_proto::uflt16::encode;
/// assert_eq!(encode(1.0), 0x3C00);
/// assert_eq!(encode(-3.0), 0x0000);
/// assert_eq!(encode(1.0e6), 0x7C00);
/// assert_eq!(encode(65504.0), 0x7BFF);
/// ```
pub const fn encode(value: f32) -> u16 {
    let bits = value.to_bits();
    let exp32 = (bits >> 23) & 0xFF;
    let mant = bits & 0x007F_FFFF;
    if exp32 == 0xFF {
        return if mant == 0 {
            if bits & 0x8000_0000 != 0 { 0 } else { 0x7C00 }
        } else {
            // NaN: keep the top ten payload bits, so decode -> encode is the identity; a
            // payload that lives only in the low bits becomes the quiet NaN.
            let payload = (mant >> 13) as u16;
            0x7C00 | if payload == 0 { 0x0200 } else { payload }
        };
    }
    if bits & 0x8000_0000 != 0 {
        return 0;
    }
    // Unbiased binary16 exponent.
    let e = exp32 as i32 - 127 + 15;
    if e >= 0x1F {
        return 0x7C00;
    }
    if e <= 0 {
        // Subnormal (or zero) in binary16.
        if e < -10 {
            return 0;
        }
        let m = mant | 0x0080_0000;
        let shift = (14 - e) as u32; // 14..=24
        let h = m >> shift;
        let rem = m & ((1u32 << shift) - 1);
        let half = 1u32 << (shift - 1);
        let up = rem > half || (rem == half && (h & 1) == 1);
        return (h + up as u32) as u16;
    }
    let h = ((e as u32) << 10) | (mant >> 13);
    let rem = mant & 0x1FFF;
    let up = rem > 0x1000 || (rem == 0x1000 && (h & 1) == 1);
    // A carry out of the mantissa correctly bumps the exponent (up to 0x7C00 = infinity).
    (h + up as u32) as u16
}
