//! The export's own names for some fields of the typed messages, one entry per message type:
//! the protocol crates keep their Rust names (`Gyro::x`, `timestamp_ms`), while a table's column
//! says its unit in its name, as the other AEOLUS fields do (`airspeed_mps`, `roll_rad`), and
//! holds a time as a time.
//!
//! | field | column | why |
//! |---|---|---|
//! | AEOLUS `timestamp_ms` (f64, ms) | `box_time`, Duration(µs) | the time since the box started, a duration that engines add and compare; not named `_ms`, which its type no longer is |
//! | GYRO `x`, `y`, `z` (rad/s) | `x_radps`, ... | |
//! | ACCEL `x`, `y`, `z` (m/s²) | `x_mps2`, ... | |
//! | MAGNET `x`, `y`, `z` (gauss) | `x_gauss`, ... | |

use super::column::Scalar;
use crate::proto::Proto;

/// How a field's value is written into its column.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Convert {
    /// As it is.
    Same,
    /// Milliseconds (a real) as a Duration of microseconds, rounded; a value that is not finite
    /// or out of the range of one is a null.
    MillisToDuration,
}

/// A field of another name (or type) in the export.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Named {
    /// The field's name in the message type.
    pub(crate) field: &'static str,
    /// Its column's name.
    pub(crate) column: &'static str,
    /// How its value is written.
    pub(crate) convert: Convert,
}

/// An entry of [`NAMES`].
const fn named(field: &'static str, column: &'static str) -> Named {
    Named {
        field,
        column,
        convert: Convert::Same,
    }
}

/// AEOLUS's time of a message: since the box started.
const BOX_TIME: Named = Named {
    field: "timestamp_ms",
    column: "box_time",
    convert: Convert::MillisToDuration,
};

/// The fields of each message type that the export names (or writes) its own way; the other
/// fields' columns have the fields' names.
const NAMES: [(Proto, &str, &[Named]); 9] = [
    (Proto::Aeolus, "PRESSURE", &[BOX_TIME]),
    (
        Proto::Aeolus,
        "GYRO",
        &[
            BOX_TIME,
            named("x", "x_radps"),
            named("y", "y_radps"),
            named("z", "z_radps"),
        ],
    ),
    (
        Proto::Aeolus,
        "ACCEL",
        &[
            BOX_TIME,
            named("x", "x_mps2"),
            named("y", "y_mps2"),
            named("z", "z_mps2"),
        ],
    ),
    (
        Proto::Aeolus,
        "MAGNET",
        &[
            BOX_TIME,
            named("x", "x_gauss"),
            named("y", "y_gauss"),
            named("z", "z_gauss"),
        ],
    ),
    (Proto::Aeolus, "TEMP", &[BOX_TIME]),
    (Proto::Aeolus, "GPS", &[BOX_TIME]),
    (Proto::Aeolus, "ATTITUDE", &[BOX_TIME]),
    (Proto::Aeolus, "COMPASS", &[BOX_TIME]),
    (Proto::Aeolus, "WIND", &[BOX_TIME]),
];

/// The fields of message type `kind` of `proto` that the export names its own way.
pub(crate) fn of(proto: Option<Proto>, kind: &str) -> &'static [Named] {
    NAMES
        .iter()
        .find(|(p, k, _)| Some(*p) == proto && *k == kind)
        .map_or(&[], |(_, _, named)| named)
}

impl Convert {
    /// `v` as its column holds it.
    #[inline]
    pub(crate) fn apply(self, v: Scalar<'_>) -> Scalar<'_> {
        match (self, v) {
            (Convert::MillisToDuration, Scalar::F64(ms)) => {
                millis_to_micros(ms).map_or(Scalar::Null, Scalar::Duration)
            }
            (_, v) => v,
        }
    }

    /// A value of the type its column has, to make the column with when the first value is
    /// none (`None`: a column of the value's own type, made by a value only).
    pub(crate) fn like(self) -> Option<Scalar<'static>> {
        match self {
            Convert::Same => None,
            Convert::MillisToDuration => Some(Scalar::Duration(0)),
        }
    }
}

/// The column of field `field` among `named`, and how its value is written.
pub(crate) fn column(named: &[Named], field: &'static str) -> (&'static str, Convert) {
    named
        .iter()
        .find(|n| n.field == field)
        .map_or((field, Convert::Same), |n| (n.column, n.convert))
}

/// A time in milliseconds as microseconds (none when it is not finite or out of range).
#[allow(clippy::cast_possible_truncation)]
pub(crate) fn millis_to_micros(ms: f64) -> Option<i64> {
    let us = (ms * 1000.0).round();
    // i64::MAX is no f64: the bound is the next power of two, excluded.
    (-9.223_372_036_854_776e18..9.223_372_036_854_776e18)
        .contains(&us)
        .then_some(us as i64)
}

#[cfg(test)]
mod tests {
    use super::{Convert, column, millis_to_micros, of};
    use crate::proto::Proto;

    #[test]
    fn gyro_names_its_unit_and_box_time_is_a_duration() {
        let gyro = of(Some(Proto::Aeolus), "GYRO");
        assert_eq!(column(gyro, "x"), ("x_radps", Convert::Same));
        assert_eq!(
            column(gyro, "timestamp_ms"),
            ("box_time", Convert::MillisToDuration)
        );
        assert_eq!(column(gyro, "valid"), ("valid", Convert::Same));
        // Another protocol's type of the same name keeps its fields' names.
        assert!(of(Some(Proto::Gdl90), "GYRO").is_empty());
        assert_eq!(millis_to_micros(1.5), Some(1500));
        assert_eq!(millis_to_micros(2f64.powi(-24)), Some(0));
        assert_eq!(millis_to_micros(f64::NAN), None);
        assert_eq!(millis_to_micros(1e300), None);
    }
}
