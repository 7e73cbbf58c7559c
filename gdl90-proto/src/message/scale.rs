//! Rounding physical values to wire steps without `std` (no `f32::round` in `core`), and
//! without wrapping: every result saturates.

/// `x` rounded to the nearest integer, halves away from zero; `None` for NaN. Infinities and
/// values beyond `i64` saturate.
pub(crate) fn round_f32(x: f32) -> Option<i64> {
    round_f64(x as f64)
}

/// `x` rounded to the nearest integer, halves away from zero; `None` for NaN. Infinities and
/// values beyond `i64` saturate.
pub(crate) fn round_f64(x: f64) -> Option<i64> {
    if x.is_nan() {
        None
    } else if x >= 0.0 {
        Some((x + 0.5) as i64)
    } else {
        Some((x - 0.5) as i64)
    }
}

/// `x / step` rounded to the nearest integer, halves up.
pub(crate) const fn div_round(x: i64, step: i64) -> i64 {
    x.saturating_add(step / 2).div_euclid(step)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rounding_is_to_nearest_and_saturates() {
        assert_eq!(round_f32(1.5), Some(2));
        assert_eq!(round_f32(-1.5), Some(-2));
        assert_eq!(round_f32(0.49), Some(0));
        assert_eq!(round_f32(f32::NAN), None);
        assert_eq!(round_f32(f32::INFINITY), Some(i64::MAX));
        assert_eq!(round_f64(f64::NEG_INFINITY), Some(i64::MIN));
        assert_eq!(div_round(37, 25), 1);
        assert_eq!(div_round(38, 25), 2);
        assert_eq!(div_round(-32, 64), 0);
        assert_eq!(div_round(-33, 64), -1);
        assert_eq!(div_round(i64::MAX, 25), i64::MAX / 25);
    }
}
