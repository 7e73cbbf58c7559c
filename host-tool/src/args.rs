//! Checking numbers on the command line: durations with a unit, windows of time, and floats in
//! a stated range.
//!
//! Every parser here refuses NaN, infinities, values out of range and empty text with one
//! sentence that names the range and the unit, so clap reports it and exits with status 2.
//! Nothing is silently clamped or taken as zero.

use std::ops::Range;
use std::time::Duration;

/// The longest duration any option accepts: one year.
pub(crate) const MAX_DURATION: Duration = Duration::from_secs(365 * 24 * 3600);

/// The latest end of a window of time ([`time_window`]): one day.
pub(crate) const MAX_WINDOW_END: Duration = Duration::from_secs(24 * 3600);

/// The units a duration may carry.
const UNITS: [(&str, f64); 4] = [("ms", 1e-3), ("s", 1.0), ("min", 60.0), ("h", 3600.0)];

/// Parses a duration: a number with a unit (`500ms`, `2s`, `1.5min`, `1h`), or a plain number in
/// `plain_unit` seconds (1.0 for `--seconds`, 0.001 for `--timeout-ms`). It must lie in
/// `min..=max`.
///
/// # Errors
/// A sentence naming the accepted range.
pub(crate) fn duration(
    text: &str,
    plain_unit: f64,
    min: Duration,
    max: Duration,
) -> Result<Duration, String> {
    let t = text.trim();
    let plain = if plain_unit >= 1.0 { "s" } else { "ms" };
    let range = format!(
        "a duration from {} to {} (a plain number is in {plain}; units ms, s, min, h)",
        show(min),
        show(max)
    );
    let (number, scale) = UNITS
        .iter()
        .filter_map(|(unit, scale)| t.strip_suffix(unit).map(|n| (n, *scale)))
        .find(|(n, _)| n.trim_end().parse::<f64>().is_ok())
        .unwrap_or((t, plain_unit));
    let value: f64 = number
        .trim_end()
        .parse()
        .map_err(|_| format!("'{text}' is not {range}"))?;
    let secs = value * scale;
    if !secs.is_finite() || secs < min.as_secs_f64() || secs > max.as_secs_f64() {
        return Err(format!("'{text}' is out of range: expected {range}"));
    }
    Ok(Duration::from_secs_f64(secs))
}

/// A duration for humans: `500 ms`, `2 s`, `1.5 s`.
pub(crate) fn show(d: Duration) -> String {
    if d < Duration::from_secs(1) && !d.is_zero() {
        format!("{} ms", d.as_millis())
    } else {
        format!("{} s", d.as_secs_f64())
    }
}

/// `--seconds`: how long a command runs, 0 s to one year; a plain number is in seconds.
///
/// # Errors
/// A sentence naming the range.
pub(crate) fn run_time(text: &str) -> Result<Duration, String> {
    duration(text, 1.0, Duration::ZERO, MAX_DURATION)
}

/// A reply timeout: 1 ms to one hour; a plain number is in milliseconds.
///
/// # Errors
/// A sentence naming the range.
pub(crate) fn timeout_ms(text: &str) -> Result<Duration, String> {
    duration(
        text,
        1e-3,
        Duration::from_millis(1),
        Duration::from_secs(3600),
    )
}

/// A hold or quiet time: 0 ms to one hour; a plain number is in milliseconds.
///
/// # Errors
/// A sentence naming the range.
pub(crate) fn period_ms(text: &str) -> Result<Duration, String> {
    duration(text, 1e-3, Duration::ZERO, Duration::from_secs(3600))
}

/// A window of time after a start, `FROM..TO` (`--gps-outage`): each end is a duration as
/// [`run_time`] reads it (a plain number is in seconds), from 0 to [`MAX_WINDOW_END`] (one
/// day), and FROM comes before TO. The window holds FROM and not TO.
///
/// # Errors
/// A sentence naming the syntax and the range, or saying that the window is empty.
pub(crate) fn time_window(text: &str) -> Result<Range<Duration>, String> {
    let not_a_window = || {
        format!(
            "'{text}' is not a window FROM..TO (each a time after the start from 0 to {}, \
             a plain number in seconds, FROM before TO)",
            show(MAX_WINDOW_END)
        )
    };
    let (from, to) = text.trim().split_once("..").ok_or_else(not_a_window)?;
    let end = |t: &str| duration(t, 1.0, Duration::ZERO, MAX_WINDOW_END).ok();
    let (Some(from), Some(to)) = (end(from), end(to)) else {
        return Err(not_a_window());
    };
    if from >= to {
        return Err(format!(
            "'{text}' is an empty window: FROM must come before TO"
        ));
    }
    Ok(from..to)
}

/// Parses a finite number in `lo..=hi`, for the error naming `unit`.
///
/// # Errors
/// A sentence naming the range.
pub(crate) fn number_in(text: &str, lo: f32, hi: f32, unit: &str) -> Result<f32, String> {
    let range = format!("a number from {lo} to {hi} {unit}");
    let v: f32 = text
        .trim()
        .parse()
        .map_err(|_| format!("'{text}' is not {range}"))?;
    if v.is_finite() && (lo..=hi).contains(&v) {
        Ok(v)
    } else {
        Err(format!("'{text}' is out of range: expected {range}"))
    }
}

/// A finite `f32` (any magnitude), such as an output value.
///
/// # Errors
/// A sentence when the text is not a finite number.
pub(crate) fn finite(text: &str) -> Result<f32, String> {
    number_in(text, f32::MIN, f32::MAX, "").map_err(|_| format!("'{text}' is not a finite number"))
}

/// The examples of this module's items, as tests (the items are crate-private, so rustdoc
/// does not run them).
#[cfg(test)]
#[allow(unused_imports, clippy::unnecessary_wraps)]
mod examples {
    use super::*;

    #[test]
    fn duration_example() -> Result<(), Box<dyn std::error::Error>> {
        use std::time::Duration;
        let (min, max) = (Duration::ZERO, Duration::from_secs(60));
        assert_eq!(duration("2", 1.0, min, max), Ok(Duration::from_secs(2)));
        assert_eq!(
            duration("250ms", 1.0, min, max),
            Ok(Duration::from_millis(250))
        );
        assert_eq!(
            duration("250", 1e-3, min, max),
            Ok(Duration::from_millis(250))
        );
        assert!(duration("inf", 1.0, min, max).is_err());
        assert!(duration("-5", 1.0, min, max).is_err());
        assert!(
            duration("2min", 1.0, min, max)
                .unwrap_err()
                .contains("0 s to 60 s")
        );
        Ok(())
    }

    #[test]
    fn show_example() -> Result<(), Box<dyn std::error::Error>> {
        use std::time::Duration;
        assert_eq!(show(Duration::from_millis(1500)), "1.5 s");
        assert_eq!(show(Duration::from_millis(20)), "20 ms");
        Ok(())
    }

    #[test]
    fn run_time_example() -> Result<(), Box<dyn std::error::Error>> {
        assert_eq!(run_time("1.5").unwrap().as_millis(), 1500);
        assert!(run_time("1e20").is_err());
        assert!(run_time("nan").is_err());
        Ok(())
    }

    #[test]
    fn timeout_ms_example() -> Result<(), Box<dyn std::error::Error>> {
        assert_eq!(timeout_ms("2s").unwrap().as_millis(), 2000);
        assert_eq!(timeout_ms("150").unwrap().as_millis(), 150);
        assert!(timeout_ms("0").is_err());
        Ok(())
    }

    #[test]
    fn period_ms_example() -> Result<(), Box<dyn std::error::Error>> {
        assert_eq!(period_ms("0").unwrap().as_millis(), 0);
        assert!(period_ms("-1").is_err());
        Ok(())
    }

    #[test]
    fn time_window_example() -> Result<(), Box<dyn std::error::Error>> {
        use std::time::Duration;
        let w = time_window("4..8").unwrap();
        assert_eq!(
            (w.start, w.end),
            (Duration::from_secs(4), Duration::from_secs(8))
        );
        assert_eq!(
            time_window("0.5..2min").unwrap().end,
            Duration::from_secs(120)
        );
        assert!(
            time_window("8..4")
                .unwrap_err()
                .contains("FROM must come before TO")
        );
        for bad in [
            "4", "4..", "..8", "-1..8", "4..nan", "4..inf", "0..86401", "4..8..9",
        ] {
            assert!(
                time_window(bad)
                    .unwrap_err()
                    .contains("is not a window FROM..TO"),
                "{bad}"
            );
        }
        Ok(())
    }

    #[test]
    fn number_in_example() -> Result<(), Box<dyn std::error::Error>> {
        assert_eq!(number_in("20", -60.0, 60.0, "degrees"), Ok(20.0));
        assert!(
            number_in("nan", -60.0, 60.0, "degrees")
                .unwrap_err()
                .contains("-60 to 60 degrees")
        );
        Ok(())
    }

    #[test]
    fn finite_example() -> Result<(), Box<dyn std::error::Error>> {
        assert_eq!(finite("-5"), Ok(-5.0));
        assert!(finite("inf").is_err());
        Ok(())
    }
}
