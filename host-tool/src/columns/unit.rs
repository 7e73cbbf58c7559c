//! Each column's unit, as its Arrow field carries it (metadata key `unit`): the protocol
//! crates' units (SI as the box sends them: m, m/s, mbar, rad, deg, ms), told by a field's
//! suffix where the crates give it one, and listed here for the rest. `docs/columns.md` shows
//! them beside each column.

/// The metadata key of a field's unit.
pub(crate) const KEY: &str = "unit";

/// Units by the end of a column's name: its last part, or for an element of a fixed-size array
/// (`name.0`) the array's name.
const SUFFIXES: [(&str, &str); 18] = [
    ("_ms", "ms"),
    ("_radps", "rad/s"),
    ("_mps2", "m/s²"),
    ("_gauss", "gauss"),
    ("_mps", "m/s"),
    ("_mbar", "mbar"),
    ("_deg", "deg"),
    ("_rad", "rad"),
    ("_m", "m"),
    ("celsius", "°C"),
    ("_percent", "%"),
    ("_ft", "ft"),
    ("_kt", "kt"),
    ("_fpm", "ft/min"),
    ("_dps", "deg/s"),
    ("g_load", "g"),
    ("_hpa", "hPa"),
    ("_pa", "Pa"),
];

/// Units of columns whose names do not say them: (message type, or "" for every table,
/// column, unit). An entry for every table comes before the types' own.
const NAMED: [(&str, &str, &str); 11] = [
    ("", "capture_time", "s since 1970"),
    ("", "box_time", "µs since the box started"),
    ("", "offset", "byte"),
    ("", "meta.len", "byte"),
    ("", "meta.time.seconds", "s"),
    ("", "meta.time.subsec", "ms (spec) or µs (reference)"),
    ("POSITION", "latitude", "deg"),
    ("POSITION", "longitude", "deg"),
    ("POSITION", "altitude", "m"),
    ("OWNSHIP", "track.TrueTrack", "deg"),
    ("TRAFFIC", "track.TrueTrack", "deg"),
];

/// The unit of column `column` in the table of message type `table`; `None` for a count, a
/// flag, a text or an identifier.
pub(crate) fn unit(table: &str, column: &str) -> Option<&'static str> {
    if let Some(&(_, _, u)) = NAMED
        .iter()
        .find(|&&(t, c, _)| (t.is_empty() || t == table) && c == column)
    {
        return Some(u);
    }
    let base = match column.rsplit_once('.') {
        Some((array, index)) if !index.is_empty() && index.bytes().all(|b| b.is_ascii_digit()) => {
            array.rsplit('.').next().unwrap_or(array)
        }
        Some((_, last)) => last,
        None => column,
    };
    SUFFIXES
        .iter()
        .find(|(suffix, _)| base.ends_with(suffix))
        .map(|&(_, u)| u)
}

#[cfg(test)]
mod tests {
    use super::unit;

    #[test]
    fn units_by_name_suffix_and_element() {
        assert_eq!(unit("PRESSURE", "airspeed_mps"), Some("m/s"));
        assert_eq!(unit("GYRO", "x_radps"), Some("rad/s"));
        assert_eq!(unit("ACCEL", "x_mps2"), Some("m/s²"));
        assert_eq!(unit("MAGNET", "z_gauss"), Some("gauss"));
        assert_eq!(unit("GPS", "satellites"), None);
        assert_eq!(unit("FIX_QUALITY", "meta.time.seconds"), Some("s"));
        assert_eq!(unit("X", "position.altitude_m"), Some("m"));
        assert_eq!(unit("X", "angles_deg.2"), Some("deg"));
        assert_eq!(unit("X", "mac.0"), None);
    }
}
