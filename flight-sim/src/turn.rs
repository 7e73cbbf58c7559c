//! Angles as fractions of a turn, and their sine, cosine and `atan2` in fixed point.
//!
//! [`Flight::state`](crate::Flight::state) runs on cores without an FPU (the sensor box's
//! Cortex-M3), where one `libm::sinf` costs about 1 250 instructions and one soft-float
//! multiplication about 50, but an integer multiplication one. So the per-state maths keeps
//! angles and unit vectors in integers and converts to `f32` only at the end:
//!
//! * an **angle** is a `u32` fraction of a whole turn (2³² = 360°, one unit ≈ 1.5·10⁻⁹ rad):
//!   it wraps for free, so headings never need reducing;
//! * a sine, cosine or unit-vector component is an `i32` in **Q30** (1.0 = 2³⁰, one unit
//!   ≈ 9.3·10⁻¹⁰), a third of an `f32` ulp at 1.0;
//! * [`sin_cos`] evaluates the Taylor series of sin and cos on a half turn (|error| below
//!   4·10⁻⁹, pinned by the tests below against `std`), [`atan2_hypot`] runs 28 CORDIC steps
//!   (angle within 3·10⁻⁸ rad, length within 4·10⁻⁸ relative before its rounding to `f32`), and [`to_f32`] rounds a
//!   fixed-point value to the nearest `f32`.

/// 1.0 in Q30.
pub(crate) const ONE: i32 = 1 << 30;

/// A quarter turn (90°) in angle units; also 1.0 in the quarter-turn units of [`poly`].
const QUARTER: i32 = 1 << 30;

/// `a · b` in Q30, rounded.
#[inline]
pub(crate) fn mul(a: i32, b: i32) -> i32 {
    ((i64::from(a) * i64::from(b) + (1 << 29)) >> 30) as i32
}

/// `a · b + c · d` in Q30, rounded once.
#[inline]
pub(crate) fn dot(a: i32, b: i32, c: i32, d: i32) -> i32 {
    ((i64::from(a) * i64::from(b) + i64::from(c) * i64::from(d) + (1 << 29)) >> 30) as i32
}

/// Taylor coefficients of `sin(x·π/2) / x` in powers of `x²`, Q30 (`round((π/2)^(2k+1) /
/// (2k+1)! · 2³⁰) · (-1)^k`). Through x¹³: the next term is below 7·10⁻¹⁰ on |x| ≤ 1.
const SIN: [i32; 7] = [
    1_686_629_713,
    -693_598_668,
    85_569_306,
    -5_026_995,
    172_272,
    -3_864,
    61,
];

/// Taylor coefficients of `cos(x·π/2)` in powers of `x²`, Q30. Through x¹⁴: the next term is
/// below 7·10⁻¹¹ on |x| ≤ 1.
const COS: [i32; 8] = [
    1_073_741_824,
    -1_324_675_879,
    272_375_560,
    -22_401_992,
    987_048,
    -27_060,
    506,
    -7,
];

/// `Σ c[k]·u^k` by Horner's rule, Q30.
fn horner(c: &[i32], u: i32) -> i32 {
    c.iter().rev().fold(0, |acc, &k| k + mul(acc, u))
}

/// For `x` in quarter turns, Q30, |x| ≤ 1 (|angle| ≤ π/2): `(S, cos)` with
/// `sin(x·π/2) = x · S` (so `S` is π/2 at 0, and a caller holding `x` more precisely than
/// Q30 keeps its relative precision) and the cosine, both Q30.
pub(crate) fn poly(x: i32) -> (i32, i32) {
    let u = mul(x, x);
    (horner(&SIN, u), horner(&COS, u))
}

/// `(sin, cos)` of an angle, Q30.
///
/// The angle is folded into `[-π/2, π/2]` (`sin(a + π) = -sin a`, the same for cos) and the
/// series of [`poly`] evaluated there.
pub(crate) fn sin_cos(angle: u32) -> (i32, i32) {
    let a = angle as i32; // [-π, π)
    let (x, flip) = if !(-QUARTER..=QUARTER).contains(&a) {
        (a.wrapping_sub(i32::MIN), true) // a ± π
    } else {
        (a, false)
    };
    let (s, c) = poly(x);
    let s = mul(x, s);
    if flip { (-s, -c) } else { (s, c) }
}

/// CORDIC angles `atan(2^-i)` in angle units, i = 0..28.
const ATAN: [u32; 28] = [
    536_870_912,
    316_933_406,
    167_458_907,
    85_004_756,
    42_667_331,
    21_354_465,
    10_679_838,
    5_340_245,
    2_670_163,
    1_335_087,
    667_544,
    333_772,
    166_886,
    83_443,
    41_722,
    20_861,
    10_430,
    5_215,
    2_608,
    1_304,
    652,
    326,
    163,
    81,
    41,
    20,
    10,
    5,
];

/// 1 / (the CORDIC gain of [`ATAN`]'s 28 steps), Q30.
const INV_GAIN: i64 = 652_032_874;

/// The angle of the vector `(x, y)` (`atan2(y, x)`, 0 along +x, a quarter turn along +y) and
/// its length, where `x` and `y` are fixed point with `frac_bits` fractional bits. The zero
/// vector gives `(0, 0.0)`.
pub(crate) fn atan2_hypot(y: i32, x: i32, frac_bits: i32) -> (u32, f32) {
    let largest = x.unsigned_abs().max(y.unsigned_abs());
    if largest == 0 {
        return (0, 0.0);
    }
    // Scale so that the larger component is in [2^28, 2^29): the steps grow the vector by
    // at most √2 · 1.65, which stays below 2^31 (i32 arithmetic: on a 32-bit core a 64-bit
    // shift by a variable amount costs ten instructions), and the shifts' rounding stays
    // small.
    let shift = largest.leading_zeros() as i32 - 3;
    let (mut x, mut y) = if shift >= 0 {
        (x << shift, y << shift)
    } else {
        (x >> -shift, y >> -shift)
    };
    // Into the right half-plane by a quarter turn, then rotate y to zero.
    let mut angle: u32 = 0;
    if x < 0 {
        (x, y, angle) = if y >= 0 {
            (y, -x, QUARTER as u32)
        } else {
            (-y, x, QUARTER.wrapping_neg() as u32)
        };
    }
    for (i, &step) in ATAN.iter().enumerate() {
        let (dx, dy) = (y >> i, x >> i);
        if y >= 0 {
            (x, y, angle) = (x + dx, y - dy, angle.wrapping_add(step));
        } else {
            (x, y, angle) = (x - dx, y + dy, angle.wrapping_sub(step));
        }
    }
    (
        angle,
        to_f32(i64::from(x) * INV_GAIN, 30 + shift + frac_bits),
    )
}

/// The `f32` nearest to `v · 2^-frac_bits` (ties to even; below the normal range 0,
/// above it infinity).
pub(crate) fn to_f32(v: i64, frac_bits: i32) -> f32 {
    if v == 0 {
        return 0.0;
    }
    let sign = if v < 0 { 1 << 31 } else { 0 };
    let magnitude = v.unsigned_abs();
    let zeros = magnitude.leading_zeros();
    let normalised = magnitude << zeros; // the leading 1 at bit 63
    let mut mantissa = (normalised >> 40) as u32; // 24 bits, the leading 1 at bit 23
    let rest = normalised & ((1 << 40) - 1);
    const HALF: u64 = 1 << 39;
    if rest > HALF || (rest == HALF && mantissa & 1 == 1) {
        mantissa += 1; // 2^24 carries into the exponent below
    }
    let exponent = 63 - zeros as i32 - frac_bits + 127;
    if exponent <= 0 {
        return f32::from_bits(sign);
    }
    if exponent >= 255 {
        return f32::from_bits(sign | 0x7F80_0000);
    }
    f32::from_bits(sign | (((exponent as u32) << 23) + mantissa - (1 << 23)))
}

/// The `f64` nearest to `v · 2^-frac_bits` (ties to even), for results in the normal range.
pub(crate) fn to_f64(v: i64, frac_bits: i32) -> f64 {
    if v == 0 {
        return 0.0;
    }
    let sign = if v < 0 { 1 << 63 } else { 0 };
    let magnitude = v.unsigned_abs();
    let zeros = magnitude.leading_zeros();
    let normalised = magnitude << zeros; // the leading 1 at bit 63
    let mut mantissa = normalised >> 11; // 53 bits, the leading 1 at bit 52
    let rest = normalised & 0x7FF;
    if rest > 0x400 || (rest == 0x400 && mantissa & 1 == 1) {
        mantissa += 1; // 2^53 carries into the exponent below
    }
    let exponent = (63 - zeros as i32 - frac_bits + 1023).clamp(1, 2046) as u64;
    f64::from_bits(sign | ((exponent << 52) + mantissa - (1 << 52)))
}

/// 2^k as an `f64`, for |k| < 1000.
fn pow2(k: i32) -> f64 {
    f64::from_bits(((1023 + k) as u64) << 52)
}

/// `x · 2^frac_bits` rounded to the nearest integer (saturating).
pub(crate) fn from_f64(x: f64, frac_bits: i32) -> i64 {
    let v = x * pow2(frac_bits);
    (if v < 0.0 { v - 0.5 } else { v + 0.5 }) as i64
}

/// The angle of `deg` degrees (any finite value; wrapped into one turn).
pub(crate) fn from_deg(deg: f64) -> u32 {
    let turns = deg * (1.0 / 360.0);
    let fraction = turns - (turns as i64) as f64; // (-1, 1)
    from_f64(fraction, 32) as u32
}

/// The angle in degrees, `[0, 360)`.
pub(crate) fn to_deg(angle: u32) -> f32 {
    let d = to_f32(i64::from(angle) * 360, 32);
    if d >= 360.0 { 0.0 } else { d }
}

/// The angle in degrees, `(-180, 180]`.
pub(crate) fn to_deg_signed(angle: u32) -> f32 {
    to_f32(signed(angle) * 360, 32)
}

/// The angle in radians, `(-π, π]`.
pub(crate) fn to_rad(angle: u32) -> f32 {
    /// 2π in Q29.
    const TAU_Q29: i64 = 3_373_259_426;
    to_f32(signed(angle) * TAU_Q29, 32 + 29)
}

/// The angle as a signed count of units in `(-2^31, 2^31]` (a half turn is positive).
fn signed(angle: u32) -> i64 {
    if angle == 1 << 31 {
        1 << 31
    } else {
        i64::from(angle as i32)
    }
}

/// A vector of `f32` components as Q30 integers with one shared binary scale:
/// component `i` is `q[i] · 2^-frac_bits`, and every `|q[i]| <= 2^30`, so that a rotation of
/// the vector still fits an `i32`. The zero vector (or one without a finite largest
/// component) is all zeros.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct Fixed3 {
    /// The components.
    pub q: [i32; 3],
    /// Fractional bits of the components.
    pub frac_bits: i32,
}

impl Fixed3 {
    /// `v` in fixed point.
    pub(crate) fn new(v: [f32; 3]) -> Fixed3 {
        let largest = v.iter().fold(0.0f32, |m, c| m.max(c.abs()));
        if !(largest > 0.0 && largest.is_finite()) {
            return Fixed3 {
                q: [0; 3],
                frac_bits: 0,
            };
        }
        // largest < 2^e, from the exponent field (subnormals: e = -126).
        let e = ((largest.to_bits() >> 23) & 0xFF) as i32 - 126;
        let frac_bits = 30 - e.max(-126);
        Fixed3 {
            q: v.map(|c| from_f64(f64::from(c), frac_bits) as i32),
            frac_bits,
        }
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use std::f64::consts::{PI, TAU};

    /// Angles over the whole turn, dense near the quadrant boundaries and zero.
    fn angles() -> impl Iterator<Item = u32> {
        (0..200_000u32)
            .map(|i| i.wrapping_mul(21_475)) // about 0.0018° apart
            .chain((0..4u32).flat_map(|q| {
                (0..2_000u32).map(move |d| (q << 30).wrapping_add(d).wrapping_sub(1_000))
            }))
    }

    fn rad(angle: u32) -> f64 {
        f64::from(angle as i32) / 4_294_967_296.0 * TAU
    }

    #[test]
    fn sin_cos_within_4e_9() {
        let mut worst = 0.0f64;
        for a in angles() {
            let (s, c) = sin_cos(a);
            let r = rad(a);
            worst = worst
                .max((f64::from(s) / f64::from(ONE) - r.sin()).abs())
                .max((f64::from(c) / f64::from(ONE) - r.cos()).abs());
        }
        assert!(worst < 4e-9, "{worst:e}");
        assert_eq!(sin_cos(0), (0, ONE));
    }

    #[test]
    fn atan2_hypot_within_3e_8_rad_and_1e_7_relative() {
        let mut worst = (0.0f64, 0.0f64);
        for a in angles().step_by(7) {
            for len in [1.0f64, 7.5, 49.9, 300.0] {
                let r = rad(a);
                let (x, y) = (len * r.cos(), len * r.sin());
                let (xq, yq) = (from_f64(x, 21) as i32, from_f64(y, 21) as i32);
                let (angle, h) = atan2_hypot(yq, xq, 21);
                let want = f64::from(yq).atan2(f64::from(xq));
                let da = (rad(angle) - want + PI).rem_euclid(TAU) - PI;
                let dh = f64::from(h) / f64::from(xq).hypot(f64::from(yq)) * 2_097_152.0 - 1.0;
                worst = (worst.0.max(da.abs()), worst.1.max(dh.abs()));
            }
        }
        // The length is rounded to f32 (up to 6e-8 relative) after the CORDIC's 4e-8.
        assert!(worst.0 < 3e-8 && worst.1 < 1e-7, "{worst:?}");
        assert_eq!(atan2_hypot(0, 0, 0), (0, 0.0));
        // The extremes of i32 do not overflow.
        let (a, h) = atan2_hypot(i32::MIN, i32::MIN, 0);
        assert!(a.abs_diff(0xA000_0000) < 32, "{a:#x}"); // -135°
        assert!((f64::from(h) / (2f64.sqrt() * 2_147_483_648.0) - 1.0).abs() < 1e-7);
    }

    #[test]
    fn to_f32_rounds_to_nearest() {
        for v in [
            1i64,
            -1,
            3,
            (1 << 24) + 1,
            (1 << 25) + 3,
            i64::MAX,
            i64::MIN,
            123_456_789_012,
        ] {
            for frac in [-20, 0, 30, 61] {
                let want = (v as f64 * (2f64).powi(-frac)) as f32; // f64 is exact enough here
                let got = to_f32(v, frac);
                let tie_ok = (v as f64) == ((v as f64) as i64) as f64;
                assert!(got == want || !tie_ok, "{v} {frac}: {got} vs {want}");
            }
        }
        assert_eq!(to_f32((1 << 24) + 1, 0), 16_777_216.0); // tie to even
        assert_eq!(to_f32((1 << 24) + 3, 0), 16_777_220.0);
        assert_eq!(to_f32(1, 200), 0.0);
        for v in [
            1i64,
            -7,
            360 << 40,
            (1 << 53) + 1,
            (1 << 54) + 3,
            i64::MAX,
            i64::MIN,
        ] {
            assert_eq!(to_f64(v, 55), v as f64 / 36_028_797_018_963_968.0, "{v}");
        }
        assert_eq!(to_f32(-1, -200), f32::NEG_INFINITY);
    }

    #[test]
    fn degrees_and_radians() {
        assert_eq!(from_deg(90.0), 1 << 30);
        assert_eq!(from_deg(-90.0), 3 << 30);
        assert_eq!(from_deg(450.0), 1 << 30);
        assert_eq!(to_deg(u32::MAX), 0.0); // rounds to 360: wrapped
        assert_eq!(to_deg(1 << 31), 180.0);
        assert_eq!(to_deg_signed(1 << 31), 180.0);
        assert_eq!(to_deg_signed(3 << 30), -90.0);
        assert_eq!(to_rad(1 << 31), core::f32::consts::PI);
        assert_eq!(to_rad(1 << 30), core::f32::consts::FRAC_PI_2);
    }

    #[test]
    fn fixed3_scales_the_largest_component_below_one() {
        let f = Fixed3::new([0.21, 0.01, -0.43]);
        assert_eq!(f.frac_bits, 31);
        assert!(f.q.iter().all(|q| q.unsigned_abs() <= 1 << 30));
        assert_eq!(to_f32(i64::from(f.q[2]), f.frac_bits), -0.43);
        assert_eq!(Fixed3::new([0.0; 3]).q, [0; 3]);
        let big = Fixed3::new([f32::MAX, 1.0, 0.0]);
        assert_eq!(to_f32(i64::from(big.q[0]), big.frac_bits), f32::MAX);
    }
}
