//! Which rows go into the tables: the message types asked for (`--types`) and the rows whose
//! `time` lies in `[--since, --until)`. Everything by default.
//!
//! A type is named as its table is (`GYRO`, `FIX_QUALITY`, `ERROR` for the error events), in
//! any case, or with its protocol in front when two protocols have it (`aydp.HEARTBEAT`); a
//! name no protocol has is refused. A time is RFC 3339 (`2024-05-01T12:00:00Z`, a fraction of
//! a second and an offset such as `+02:00` allowed) or a day (`2024-05-01`, its midnight UTC).
//! A row is compared by its `time` column: the capture record's time, else an AYDP header's;
//! with `--since` or `--until`, a row without a time is left out, since it cannot be placed.

use crate::proto::{Proto, proto_name};

/// Every message type's table name, by protocol, and `AIR` (an export's derived air data);
/// `ERROR` (the error events) is any protocol's.
pub const TYPES: [(Proto, &str); 60] = [
    (Proto::Aeolus, "AEOLUSINFO"),
    (Proto::Aeolus, "PRESSURE"),
    (Proto::Aeolus, "GYRO"),
    (Proto::Aeolus, "ACCEL"),
    (Proto::Aeolus, "MAGNET"),
    (Proto::Aeolus, "TEMP"),
    (Proto::Aeolus, "GPS"),
    (Proto::Aeolus, "ATTITUDE"),
    (Proto::Aeolus, "COMPASS"),
    (Proto::Aeolus, "WIND"),
    (Proto::Aeolus, "CALIBINFO"),
    (Proto::Aeolus, "DEBUGINFO"),
    (Proto::Aeolus, "LOG"),
    (Proto::Aeolus, "TOAST"),
    (Proto::Aeolus, "COMMAND"),
    (Proto::Aeolus, "SETTIME"),
    (Proto::Aeolus, "UNKNOWN"),
    (Proto::Aeolus, "AIR"),
    (Proto::Aydp, "TIME_SYNC"),
    (Proto::Aydp, "HEARTBEAT"),
    (Proto::Aydp, "NO_OP"),
    (Proto::Aydp, "POSITION"),
    (Proto::Aydp, "FIX_QUALITY"),
    (Proto::Aydp, "FIX_DETAIL"),
    (Proto::Aydp, "DIRECT_OUTPUT"),
    (Proto::Aydp, "SYSTEM_VALUE_UPDATE"),
    (Proto::Aydp, "SYSTEM_CONTROL"),
    (Proto::Aydp, "WIND_SPEED"),
    (Proto::Aydp, "WIND_DIRECTION"),
    (Proto::Aydp, "VESSEL_DATA"),
    (Proto::Aydp, "TBD"),
    (Proto::Aydp, "USER_DEFINED"),
    (Proto::Aydp, "UNKNOWN"),
    (Proto::Aok, "DEBUG"),
    (Proto::Aok, "ACK"),
    (Proto::Aok, "PARAMETER"),
    (Proto::Aok, "WAYPOINT"),
    (Proto::Aok, "DEBUG_OFF"),
    (Proto::Aok, "DEBUG_ON"),
    (Proto::Aok, "RESET"),
    (Proto::Aok, "SAVE_WAYPOINTS"),
    (Proto::Aok, "LOAD_WAYPOINTS"),
    (Proto::Aok, "LOAD_SET"),
    (Proto::Aok, "SAVE_SET"),
    (Proto::Aok, "START_SET"),
    (Proto::Aok, "SET_PARAMETER"),
    (Proto::Aok, "READ_PARAMETER"),
    (Proto::Aok, "BULK_READ"),
    (Proto::Aok, "MOTOR_TEST"),
    (Proto::Aok, "SET_WAYPOINT"),
    (Proto::Aok, "READ_WAYPOINT"),
    (Proto::Aok, "EXTERNAL_CONTROL"),
    (Proto::Gdl90, "HEARTBEAT"),
    (Proto::Gdl90, "OWNSHIP"),
    (Proto::Gdl90, "GEO_ALTITUDE"),
    (Proto::Gdl90, "TRAFFIC"),
    (Proto::Gdl90, "FOREFLIGHT_ID"),
    (Proto::Gdl90, "FOREFLIGHT_AHRS"),
    (Proto::Gdl90, "STRATUX_AHRS"),
    (Proto::Gdl90, "UNKNOWN"),
];

/// The table of the error events.
const ERROR: &str = "ERROR";

/// Whether `name` is a table of `proto` (any protocol when `None`).
fn is_type(proto: Option<Proto>, name: &str) -> bool {
    name == ERROR
        || TYPES
            .iter()
            .any(|&(p, n)| n == name && proto.is_none_or(|q| q == p))
}

/// A type asked for: its table's name, of one protocol or of any.
#[derive(Debug, Clone, PartialEq, Eq)]
struct Wanted {
    proto: Option<Proto>,
    name: String,
}

/// The rows kept: by message type and by time. [`Keep::default`] keeps every row.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Keep {
    /// The types kept; every type when `None`.
    types: Option<Vec<Wanted>>,
    /// The first time kept, µs since the Unix epoch (UTC).
    since: Option<i64>,
    /// The first time no longer kept.
    until: Option<i64>,
}

impl Keep {
    /// The rows of the types `types` (every type when empty) whose time is at or after `since`
    /// and before `until` (each a text as `--since` takes it).
    ///
    /// # Errors
    /// One sentence: a name that is no message type, a text that is no time, or `since` not
    /// before `until`.
    ///
    /// ```
    /// use protolink::columns::Keep;
    /// let keep = Keep::new(&["gyro".into(), "aydp.HEARTBEAT".into()], Some("2024-05-01"), None)?;
    /// assert!(keep.keeps_type("GYRO", Some(protolink::proto::Proto::Aeolus)));
    /// assert!(!keep.keeps_type("HEARTBEAT", Some(protolink::proto::Proto::Gdl90)));
    /// assert!(keep.keeps_time(Some(1_714_521_600_000_000)) && !keep.keeps_time(None));
    /// assert_eq!(
    ///     Keep::new(&["GYROS".into()], None, None).unwrap_err(),
    ///     "'GYROS' is no message type of aeolus, aydp, aok or gdl90 (docs/columns.md lists them, ERROR is the errors)"
    /// );
    /// # Ok::<(), String>(())
    /// ```
    pub fn new(
        types: &[String],
        since: Option<&str>,
        until: Option<&str>,
    ) -> std::result::Result<Keep, String> {
        let mut wanted = Vec::new();
        for text in types {
            let w = wanted_type(text)?;
            if !wanted.contains(&w) {
                wanted.push(w);
            }
        }
        let since = since.map(parse_time).transpose()?;
        let until = until.map(parse_time).transpose()?;
        if let (Some(s), Some(u)) = (since, until)
            && s >= u
        {
            return Err(format!(
                "--since ({}) is not before --until ({}): no row would be kept",
                since.map(format_time).unwrap_or_default(),
                until.map(format_time).unwrap_or_default()
            ));
        }
        Ok(Keep {
            types: (!wanted.is_empty()).then_some(wanted),
            since,
            until,
        })
    }

    /// Whether `--types` names the table `name` (of any protocol).
    ///
    /// ```
    /// use protolink::columns::Keep;
    /// assert!(Keep::new(&["air".into()], None, None)?.names("AIR"));
    /// assert!(!Keep::default().names("AIR"));
    /// # Ok::<(), String>(())
    /// ```
    pub fn names(&self, name: &str) -> bool {
        self.types
            .as_ref()
            .is_some_and(|types| types.iter().any(|w| w.name == name))
    }

    /// Whether every row is kept.
    pub fn keeps_everything(&self) -> bool {
        self.types.is_none() && self.since.is_none() && self.until.is_none()
    }

    /// Whether a row of the table `name` of protocol `proto` is kept by its type.
    pub fn keeps_type(&self, name: &str, proto: Option<Proto>) -> bool {
        self.types.as_ref().is_none_or(|types| {
            types
                .iter()
                .any(|w| w.name == name && (w.proto.is_none() || w.proto == proto))
        })
    }

    /// Whether a row of time `time` (µs since the Unix epoch) is kept by its time.
    pub fn keeps_time(&self, time: Option<i64>) -> bool {
        if self.since.is_none() && self.until.is_none() {
            return true;
        }
        time.is_some_and(|t| self.since.is_none_or(|s| t >= s) && self.until.is_none_or(|u| t < u))
    }
}

/// A `--types` entry: `NAME` or `PROTO.NAME`, in any case.
fn wanted_type(text: &str) -> std::result::Result<Wanted, String> {
    let trimmed = text.trim();
    let (proto, name) = match trimmed.split_once('.') {
        Some((p, n)) => {
            let proto = [Proto::Aeolus, Proto::Aydp, Proto::Aok, Proto::Gdl90]
                .into_iter()
                .find(|&q| proto_name(q).eq_ignore_ascii_case(p))
                .ok_or_else(|| {
                    format!("'{text}' names no protocol: a type is NAME or PROTO.NAME, PROTO one of aeolus, aydp, aok and gdl90")
                })?;
            (Some(proto), n)
        }
        None => (None, trimmed),
    };
    let name = name.to_ascii_uppercase();
    if !is_type(proto, &name) {
        return Err(match proto {
            Some(p) => format!(
                "'{text}' is no message type of {} (docs/columns.md lists them, ERROR is the errors)",
                proto_name(p)
            ),
            None => format!(
                "'{text}' is no message type of aeolus, aydp, aok or gdl90 (docs/columns.md lists them, ERROR is the errors)"
            ),
        });
    }
    Ok(Wanted { proto, name })
}

/// The sentence for a text that is no time.
fn not_a_time(text: &str) -> String {
    format!(
        "'{text}' is not a time: give one as 2024-05-01T12:00:00Z or 2024-05-01T14:00:00.5+02:00 (RFC 3339), or a day as 2024-05-01"
    )
}

/// `n` digits of `text` at `at` as a number.
fn digits(text: &[u8], at: usize, n: usize) -> Option<i64> {
    let part = text.get(at..at + n)?;
    part.iter().try_fold(0i64, |acc, &b| {
        b.is_ascii_digit().then(|| acc * 10 + i64::from(b - b'0'))
    })
}

/// Days in a month of a year.
fn month_days(year: i64, month: i64) -> i64 {
    let leap = (year % 4 == 0 && year % 100 != 0) || year % 400 == 0;
    match month {
        2 if leap => 29,
        2 => 28,
        4 | 6 | 9 | 11 => 30,
        _ => 31,
    }
}

/// An RFC 3339 time, or a day, as µs since the Unix epoch.
///
/// ```
/// use protolink::columns::parse_time;
/// assert_eq!(parse_time("1970-01-01T00:00:01Z"), Ok(1_000_000));
/// assert_eq!(parse_time("2024-05-01"), parse_time("2024-05-01T02:00:00+02:00"));
/// assert_eq!(parse_time("2024-02-29T00:00:00.25Z"), Ok(1_709_164_800_250_000));
/// assert!(parse_time("2023-02-29").is_err() && parse_time("yesterday").is_err());
/// ```
///
/// # Errors
/// One sentence naming the text, when it is no such time.
pub fn parse_time(text: &str) -> std::result::Result<i64, String> {
    let b = text.trim().as_bytes();
    let fail = || not_a_time(text);
    let year = digits(b, 0, 4).ok_or_else(fail)?;
    let month = digits(b, 5, 2).ok_or_else(fail)?;
    let day = digits(b, 8, 2).ok_or_else(fail)?;
    if b.get(4) != Some(&b'-') || b.get(7) != Some(&b'-') {
        return Err(fail());
    }
    if !(1..=12).contains(&month) || !(1..=month_days(year, month)).contains(&day) {
        return Err(fail());
    }
    let date = crate::civil::days_since_epoch(year, month, day) * 86_400_000_000;
    if b.len() == 10 {
        return Ok(date);
    }
    if !matches!(b.get(10), Some(b'T' | b't' | b' ')) || b.get(13) != Some(&b':') {
        return Err(fail());
    }
    let hour = digits(b, 11, 2).ok_or_else(fail)?;
    let minute = digits(b, 14, 2).ok_or_else(fail)?;
    let second = digits(b, 17, 2).ok_or_else(fail)?;
    if b.get(16) != Some(&b':') || hour > 23 || minute > 59 || second > 59 {
        return Err(fail());
    }
    let mut at = 19;
    let mut micros = 0i64;
    if b.get(at) == Some(&b'.') {
        at += 1;
        let start = at;
        while b.get(at).is_some_and(u8::is_ascii_digit) {
            if at - start < 6 {
                micros = micros * 10 + i64::from(b[at] - b'0');
            }
            at += 1;
        }
        if at == start {
            return Err(fail());
        }
        for _ in (at - start)..6 {
            micros *= 10;
        }
    }
    let offset = match b.get(at) {
        Some(b'Z' | b'z') if b.len() == at + 1 => 0,
        Some(&sign @ (b'+' | b'-')) if b.len() == at + 6 && b.get(at + 3) == Some(&b':') => {
            let h = digits(b, at + 1, 2).ok_or_else(fail)?;
            let m = digits(b, at + 4, 2).ok_or_else(fail)?;
            if h > 23 || m > 59 {
                return Err(fail());
            }
            let minutes = h * 60 + m;
            if sign == b'+' { minutes } else { -minutes }
        }
        _ => return Err(fail()),
    };
    let seconds = hour * 3600 + minute * 60 + second - offset * 60;
    Ok(date + seconds * 1_000_000 + micros)
}

/// µs since the Unix epoch as an RFC 3339 UTC time (to the microsecond when it has any).
fn format_time(t: i64) -> String {
    use crate::civil::date_of;
    let days = t.div_euclid(86_400_000_000);
    let rest = t.rem_euclid(86_400_000_000);
    let (year, month, day) = date_of(days);
    let (s, us) = (rest / 1_000_000, rest % 1_000_000);
    let fraction = if us == 0 {
        String::new()
    } else {
        format!(".{us:06}")
    };
    format!(
        "{year:04}-{month:02}-{day:02}T{:02}:{:02}:{:02}{fraction}Z",
        s / 3600,
        s / 60 % 60,
        s % 60
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn times_round_trip_through_the_calendar() {
        // Every day from 1900 to 2100, at a time with a fraction: parsed, then formatted back.
        let mut t = parse_time("1900-01-01T13:14:15.000123Z").unwrap();
        let end = parse_time("2100-12-31").unwrap();
        while t < end {
            let text = format_time(t);
            assert_eq!(parse_time(&text), Ok(t), "{text}");
            t += 86_400_000_000;
        }
        assert_eq!(parse_time("2000-03-01"), Ok(951_868_800_000_000));
        assert_eq!(parse_time("1969-12-31T23:59:59Z"), Ok(-1_000_000));
    }

    #[test]
    fn bad_times_are_refused_in_one_sentence() {
        for bad in [
            "",
            "2024-13-01",
            "2024-04-31",
            "2024-05-01T24:00:00Z",
            "2024-05-01T12:00:00",
            "2024-05-01T12:00Z",
            "2024-05-01T12:00:00.Z",
            "2024-05-01T12:00:00+0200",
            "1714521600",
        ] {
            let e = parse_time(bad).unwrap_err();
            assert!(e.starts_with(&format!("'{bad}' is not a time")), "{e}");
        }
    }

    #[test]
    fn types_by_name_and_protocol() {
        let keep = Keep::new(&["heartbeat".into(), "error".into()], None, None).unwrap();
        assert!(keep.keeps_type("HEARTBEAT", Some(Proto::Aydp)));
        assert!(keep.keeps_type("HEARTBEAT", Some(Proto::Gdl90)));
        assert!(keep.keeps_type("ERROR", None) && !keep.keeps_type("GYRO", Some(Proto::Aeolus)));
        let e = Keep::new(&["aok.GYRO".into()], None, None).unwrap_err();
        assert_eq!(
            e,
            "'aok.GYRO' is no message type of aok (docs/columns.md lists them, ERROR is the errors)"
        );
        let e = Keep::new(&["mavlink.GYRO".into()], None, None).unwrap_err();
        assert!(e.starts_with("'mavlink.GYRO' names no protocol"), "{e}");
        assert!(Keep::new(&["gdl90.STRATUX_AHRS".into()], None, None).is_ok());
        assert!(Keep::default().keeps_everything());
        assert!(Keep::new(&[], None, None).unwrap().keeps_everything());
    }

    #[test]
    fn every_table_of_the_columns_document_can_be_asked_for() {
        let doc = include_str!("../../../docs/columns.md");
        let mut proto = None;
        let mut seen = 0;
        for line in doc.lines() {
            if let Some(p) = line.strip_prefix("### ") {
                proto = Some(p.to_ascii_lowercase());
            } else if let (Some(p), Some(name)) = (&proto, line.strip_prefix("**")) {
                let name = name.trim_end_matches("**");
                let asked = format!("{p}.{name}");
                assert!(
                    Keep::new(std::slice::from_ref(&asked), None, None).is_ok(),
                    "{asked}"
                );
                seen += 1;
            }
        }
        assert!(seen > 50, "{seen}");
    }

    #[test]
    fn since_is_kept_and_until_is_not() {
        let keep = Keep::new(
            &[],
            Some("1970-01-01T00:00:01Z"),
            Some("1970-01-01T00:00:02Z"),
        )
        .unwrap();
        assert!(keep.keeps_time(Some(1_000_000)) && keep.keeps_time(Some(1_999_999)));
        assert!(!keep.keeps_time(Some(999_999)) && !keep.keeps_time(Some(2_000_000)));
        assert!(!keep.keeps_time(None));
        let e = Keep::new(&[], Some("2024-05-02"), Some("2024-05-01T23:00:00Z")).unwrap_err();
        assert_eq!(
            e,
            "--since (2024-05-02T00:00:00Z) is not before --until (2024-05-01T23:00:00Z): no row would be kept"
        );
    }
}
