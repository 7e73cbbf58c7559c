//! NMEA 0183 sentences: the checksum, the frame (`$`, body, `*HH`, CR LF) and the five
//! sentences `protolink nmea` writes, each from plain values in the units its readers expect.
//!
//! A value that is `None` (stale, invalid, not finite or outside its field's range) becomes
//! an empty field, or, where a reader stops at an empty field (`$POV`), its pair is left out.
//! No sentence exceeds 82 (`MAX_LEN`) characters.
//!
//! | sentence | fields | read by |
//! | --- | --- | --- |
//! | `$GPRMC` | UTC time, status A/V, lat, N/S, lon, E/W, ground speed kt, track deg true, date, (variation empty), mode A/N | every moving-map and gliding app |
//! | `$GPGGA` | UTC time, lat, N/S, lon, E/W, fix 1/0, satellites, (HDOP empty), altitude, M, (geoid separation empty), M, (DGPS empty) | every app; the GPS altitude |
//! | `$PGRMZ` | pressure altitude ft, `f`, `2` (not a GPS altitude) | XCSoar, LK8000 (FLARM sends it the same way) |
//! | `$POV` | `P` static pressure hPa, `Q` dynamic pressure Pa, `T` temperature °C | XCSoar's and LK8000's OpenVario drivers |
//! | `$LXWP0` | logger `N`, TAS km/h, pressure altitude m, vario m/s ×6, heading deg, wind from deg, wind km/h | XCSoar's and LK8000's LX drivers |

use std::fmt::Write as _;
use std::time::Duration;

/// The longest sentence NMEA 0183 allows, `$` and CR LF included.
#[cfg(test)]
pub(crate) const MAX_LEN: usize = 82;

/// The checksum: the XOR of every byte between `$` and `*`.
pub(crate) fn checksum(body: &str) -> u8 {
    body.bytes().fold(0, |x, b| x ^ b)
}

/// The whole sentence for `body` (the text between `$` and `*`): `$BODY*HH\r\n`.
pub(crate) fn frame(body: &str) -> String {
    format!("${body}*{:02X}\r\n", checksum(body))
}

/// A UTC time and date, as RMC and GGA carry them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Utc {
    /// Days since 1970-01-01.
    days: u64,
    /// Hundredths of a second since midnight.
    centis: u64,
}

impl Utc {
    /// The time `since_epoch` after 1970-01-01 00:00:00 UTC.
    pub(crate) fn from_unix(since_epoch: Duration) -> Utc {
        let centis = since_epoch.as_millis() / 10;
        Utc {
            days: (centis / 8_640_000) as u64,
            centis: (centis % 8_640_000) as u64,
        }
    }

    /// `hhmmss.ss`.
    pub(crate) fn time(&self) -> String {
        let s = self.centis / 100;
        format!(
            "{:02}{:02}{:02}.{:02}",
            s / 3600,
            s / 60 % 60,
            s % 60,
            self.centis % 100
        )
    }

    /// `ddmmyy`, from the proleptic Gregorian calendar (civil-from-days).
    pub(crate) fn date(&self) -> String {
        let (year, month, day) = crate::civil::date_of(self.days as i64);
        format!("{day:02}{month:02}{:02}", year.rem_euclid(100))
    }
}

/// A GPS fix as RMC and GGA carry it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Fix {
    /// Latitude, degrees north (-90..=90).
    pub(crate) lat_deg: f64,
    /// Longitude, degrees east (-180..=180).
    pub(crate) lon_deg: f64,
    /// Altitude, metres (the box's GPS altitude).
    pub(crate) altitude_m: f64,
    /// Satellites in use.
    pub(crate) satellites: u8,
    /// Ground speed, knots.
    pub(crate) ground_speed_kt: f64,
    /// Track over ground, degrees true, when known.
    pub(crate) track_deg: Option<f64>,
}

/// `ddmm.mmmmm,N` (or `dddmm.mmmmm,E` with `degree_digits` 3): 1e-5 minute steps, about
/// 2 cm. `None` beyond `limit` degrees or not finite.
fn angle(value: f64, limit: f64, degree_digits: usize, hemispheres: [char; 2]) -> Option<String> {
    if !value.is_finite() || value.abs() > limit {
        return None;
    }
    let steps = (value.abs() * 60.0 * 1e5).round() as u64;
    let (degrees, rest) = (steps / 6_000_000, steps % 6_000_000);
    let hemisphere = if value < 0.0 {
        hemispheres[1]
    } else {
        hemispheres[0]
    };
    Some(format!(
        "{degrees:0degree_digits$}{:02}.{:05},{hemisphere}",
        rest / 100_000,
        rest % 100_000
    ))
}

/// A number with `decimals` digits after the point, or nothing when it is unknown, not
/// finite, or outside `range` (its field's plausible values, which also keep every sentence
/// within `MAX_LEN`).
fn number(value: Option<f64>, range: (f64, f64), decimals: usize) -> String {
    value
        .filter(|v| v.is_finite() && (range.0..=range.1).contains(v))
        .map_or_else(String::new, |v| format!("{v:.decimals$}"))
}

/// Altitudes, metres: -9999.9..=99999.9.
const ALTITUDE_M: (f64, f64) = (-9_999.9, 99_999.9);
/// Speeds, knots or km/h: 0..=999.9 (RMC's ground speed: 0..=9999.9).
const SPEED: (f64, f64) = (0.0, 999.9);

/// An angle in 0..360 with one decimal (359.96 is 0.0, not 360.0), or nothing.
fn bearing(value: Option<f64>) -> String {
    let tenths = value
        .filter(|v| v.is_finite())
        .map(|v| (v * 10.0).round().rem_euclid(3600.0) / 10.0);
    number(tenths, (0.0, 359.9), 1)
}

/// The position fields `lat,N,lon,E`, or `None` without a usable fix.
fn position(fix: Option<&Fix>) -> Option<String> {
    let f = fix?;
    let lat = angle(f.lat_deg, 90.0, 2, ['N', 'S'])?;
    let lon = angle(f.lon_deg, 180.0, 3, ['E', 'W'])?;
    Some(format!("{lat},{lon}"))
}

/// `$GPRMC`: with a fix, status `A` and mode `A`; without, status `V`, mode `N`, and empty
/// position, speed and track (the time and date are the host's and stay).
pub(crate) fn rmc(utc: &Utc, fix: Option<&Fix>) -> String {
    let body = match (position(fix), fix) {
        (Some(pos), Some(f)) => format!(
            "GPRMC,{},A,{pos},{},{},{},,,A",
            utc.time(),
            number(Some(f.ground_speed_kt.max(0.0)), (0.0, 9_999.9), 1),
            bearing(f.track_deg),
            utc.date()
        ),
        _ => format!("GPRMC,{},V,,,,,,,{},,,N", utc.time(), utc.date()),
    };
    frame(&body)
}

/// `$GPGGA`: with a fix, quality 1, the satellites and the altitude in metres; without,
/// quality 0, empty position and altitude, and `satellites` as the receiver reports them (or
/// empty).
pub(crate) fn gga(utc: &Utc, fix: Option<&Fix>, satellites: Option<u8>) -> String {
    let body = match (position(fix), fix) {
        (Some(pos), Some(f)) => format!(
            "GPGGA,{},{pos},1,{:02},,{},M,,M,,",
            utc.time(),
            f.satellites.min(99),
            number(Some(f.altitude_m), ALTITUDE_M, 1)
        ),
        _ => format!(
            "GPGGA,{},,,,,0,{},,,M,,M,,",
            utc.time(),
            satellites.map_or_else(String::new, |n| format!("{:02}", n.min(99)))
        ),
    };
    frame(&body)
}

/// `$PGRMZ`: the pressure altitude in whole feet, `f`, and `2` (a barometric, not a GPS
/// altitude, as FLARM sends it); empty when unknown.
pub(crate) fn pgrmz(pressure_altitude_ft: Option<f64>) -> String {
    frame(&format!(
        "PGRMZ,{},f,2",
        number(pressure_altitude_ft, (-32_000.0, 320_000.0), 0)
    ))
}

/// What `$POV` carries (OpenVario: each value a one-letter type and a number).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Pov {
    /// `P`: static pressure, hPa.
    pub(crate) static_hpa: Option<f64>,
    /// `Q`: dynamic (pitot minus static) pressure, Pa.
    pub(crate) dynamic_pa: Option<f64>,
    /// `T`: outside air temperature, °C.
    pub(crate) celsius: Option<f64>,
}

/// `$POV` with a pair for each known value, or `None` when none is known. A reader stops at
/// the first pair without a number, so an unknown value is left out, not sent empty.
pub fn pov(air: &Pov) -> Option<String> {
    let mut body = String::from("POV");
    for (kind, value, range) in [
        ('P', air.static_hpa, (0.0, 2_000.0)),
        ('Q', air.dynamic_pa, (-99_999.0, 99_999.0)),
        ('T', air.celsius, (-999.0, 999.0)),
    ] {
        let v = number(value, range, 2);
        if !v.is_empty() {
            let _ = write!(body, ",{kind},{v}");
        }
    }
    (body.len() > 3).then(|| frame(&body))
}

/// What `$LXWP0` carries (LXNAV's vario sentence).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Lxwp0 {
    /// True airspeed, km/h (XCSoar and LK8000 read this field as TAS).
    pub(crate) tas_kmh: Option<f64>,
    /// Pressure altitude, metres (1013.25 hPa datum).
    pub(crate) pressure_altitude_m: Option<f64>,
    /// Vertical speed, m/s, positive up (sent in all six vario fields).
    pub(crate) vario_mps: Option<f64>,
    /// Heading, degrees (magnetic: the compass).
    pub(crate) heading_deg: Option<f64>,
    /// Direction the wind blows from, degrees.
    pub(crate) wind_from_deg: Option<f64>,
    /// Wind speed, km/h.
    pub(crate) wind_kmh: Option<f64>,
}

/// `$LXWP0,N,tas,alt,v1..v6,hdg,wind_dir,wind_speed`: logger not recording (`N`); each
/// unknown value an empty field. The six vario fields are the last second's samples on an LX
/// device; here each holds the current vertical speed, so a reader that filters the six
/// (XCSoar) or takes the last (LK8000) reads the same value. Wind direction and speed go out
/// together or not at all.
pub fn lxwp0(v: &Lxwp0) -> String {
    // Two decimals below 10 m/s, one above: six fields of at most six characters.
    let vario = match v.vario_mps {
        Some(x) if x.abs() < 9.995 => number(Some(x), (-10.0, 10.0), 2),
        x => number(x, (-99.9, 99.9), 1),
    };
    let (wind_dir, wind_speed) = match (bearing(v.wind_from_deg), number(v.wind_kmh, SPEED, 1)) {
        (d, s) if !d.is_empty() && !s.is_empty() => (d, s),
        _ => (String::new(), String::new()),
    };
    frame(&format!(
        "LXWP0,N,{},{},{vario},{vario},{vario},{vario},{vario},{vario},{},{wind_dir},{wind_speed}",
        number(v.tas_kmh, SPEED, 1),
        number(v.pressure_altitude_m, ALTITUDE_M, 1),
        bearing(v.heading_deg),
    ))
}

#[cfg(test)]
mod tests {
    //! Literal sentences. Every checksum below was computed outside this code (with pynmea2's
    //! `NMEASentence.checksum`), not by [`checksum`].

    use super::*;

    fn utc() -> Utc {
        // 2024-02-29 12:35:19.50 UTC.
        Utc::from_unix(Duration::from_millis(1_709_210_119_500))
    }

    fn fix() -> Fix {
        Fix {
            lat_deg: 48.353_8,
            lon_deg: -11.786_1,
            altitude_m: 1000.04,
            satellites: 10,
            ground_speed_kt: 97.19,
            track_deg: Some(359.96),
        }
    }

    #[test]
    fn the_standards_examples_check() {
        // The classic examples of NMEA 0183, with their published checksums.
        let rmc = "GPRMC,123519,A,4807.038,N,01131.000,E,022.4,084.4,230394,003.1,W";
        assert_eq!(frame(rmc), format!("${rmc}*6A\r\n"));
        let gga = "GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,";
        assert_eq!(frame(gga), format!("${gga}*47\r\n"));
    }

    #[test]
    fn rmc_and_gga_with_a_fix() {
        // 48.3538 deg = 48 deg 21.22800 min; 11.7861 deg = 11 deg 47.16600 min, west.
        assert_eq!(
            rmc(&utc(), Some(&fix())),
            "$GPRMC,123519.50,A,4821.22800,N,01147.16600,W,97.2,0.0,290224,,,A*72\r\n"
        );
        assert_eq!(
            gga(&utc(), Some(&fix()), Some(10)),
            "$GPGGA,123519.50,4821.22800,N,01147.16600,W,1,10,,1000.0,M,,M,,*73\r\n"
        );
    }

    #[test]
    fn an_unusable_fix_is_void() {
        let beyond = Fix {
            lat_deg: 91.0,
            ..fix()
        };
        let nan = Fix {
            lon_deg: f64::NAN,
            ..fix()
        };
        for f in [beyond, nan] {
            assert_eq!(rmc(&utc(), Some(&f)), rmc(&utc(), None));
            assert!(gga(&utc(), Some(&f), None).contains(",,,,,0,,"));
        }
        assert_eq!(
            gga(&utc(), None, None),
            "$GPGGA,123519.50,,,,,0,,,,M,,M,,*40\r\n"
        );
    }

    #[test]
    fn minutes_never_round_up_to_sixty() {
        // 9.99999999 deg rounds to 10 deg 00.00000 min, not 9 deg 60.00000.
        assert_eq!(
            angle(9.999_999_99, 90.0, 2, ['N', 'S']).unwrap(),
            "1000.00000,N"
        );
        assert_eq!(
            angle(-180.0, 180.0, 3, ['E', 'W']).unwrap(),
            "18000.00000,W"
        );
        assert_eq!(angle(180.01, 180.0, 3, ['E', 'W']), None);
    }

    #[test]
    fn air_data_sentences() {
        let a = Pov {
            static_hpa: Some(898.746),
            dynamic_pa: Some(1377.5),
            celsius: Some(8.5),
        };
        assert_eq!(pov(&a).unwrap(), "$POV,P,898.75,Q,1377.50,T,8.50*33\r\n");
        let only_q = Pov {
            dynamic_pa: Some(-3.0),
            ..Pov::default()
        };
        assert_eq!(pov(&only_q).unwrap(), "$POV,Q,-3.00*28\r\n");
        let full = Lxwp0 {
            tas_kmh: Some(180.0),
            pressure_altitude_m: Some(1000.0),
            vario_mps: Some(-0.5),
            heading_deg: Some(-90.0),
            wind_from_deg: Some(270.0),
            wind_kmh: Some(18.0),
        };
        assert_eq!(
            lxwp0(&full),
            "$LXWP0,N,180.0,1000.0,-0.50,-0.50,-0.50,-0.50,-0.50,-0.50,270.0,270.0,18.0*42\r\n"
        );
        // A wind direction without a speed is no wind.
        let half_wind = Lxwp0 {
            wind_from_deg: Some(270.0),
            ..Lxwp0::default()
        };
        assert_eq!(lxwp0(&half_wind), "$LXWP0,N,,,,,,,,,,,*6D\r\n");
        assert_eq!(pgrmz(Some(-350.6)), "$PGRMZ,-351,f,2*30\r\n");
    }

    #[test]
    fn every_sentence_fits_the_standards_length() {
        let wide = Fix {
            lat_deg: -89.999_99,
            lon_deg: -179.999_99,
            altitude_m: -9_999.9,
            satellites: 255,
            ground_speed_kt: 9_999.9,
            track_deg: Some(359.9),
        };
        let all = Lxwp0 {
            tas_kmh: Some(999.9),
            pressure_altitude_m: Some(-9_999.9),
            vario_mps: Some(-99.9),
            heading_deg: Some(359.9),
            wind_from_deg: Some(359.9),
            wind_kmh: Some(999.9),
        };
        let air = Pov {
            static_hpa: Some(1999.99),
            dynamic_pa: Some(-99_999.0),
            celsius: Some(-999.0),
        };
        for s in [
            rmc(&utc(), Some(&wide)),
            gga(&utc(), Some(&wide), None),
            lxwp0(&all),
            pov(&air).unwrap_or_default(),
            pgrmz(Some(-32_000.0)),
        ] {
            assert!(s.len() <= MAX_LEN, "{} characters: {s}", s.len());
        }
        // Beyond a field's range, or not finite: an empty field, never a huge number.
        let wild = Lxwp0 {
            tas_kmh: Some(1e300),
            pressure_altitude_m: Some(f64::INFINITY),
            vario_mps: Some(-1e9),
            ..Lxwp0::default()
        };
        assert_eq!(lxwp0(&wild), lxwp0(&Lxwp0::default()));
        assert_eq!(pgrmz(Some(1e12)), pgrmz(None));
        assert_eq!(
            pov(&Pov {
                static_hpa: Some(-5.0),
                ..Pov::default()
            }),
            None
        );
    }

    #[test]
    fn dates_follow_the_calendar() {
        for (unix_s, date) in [
            (0u64, "010170"),
            (951_782_400, "290200"), // 2000-02-29, a leap day of a century year
            (1_709_164_800, "290224"), // 2024-02-29
            (4_107_542_400, "010300"), // 2100-03-01 (2100 is no leap year: 28 Feb before)
        ] {
            assert_eq!(Utc::from_unix(Duration::from_secs(unix_s)).date(), date);
        }
    }
}

/// The examples of this module's items, as tests (the items are crate-private, so rustdoc
/// does not run them).
#[cfg(test)]
#[allow(unused_imports, clippy::unnecessary_wraps)]
mod examples {
    use super::*;

    #[test]
    fn checksum_example() -> Result<(), Box<dyn std::error::Error>> {
        // The NMEA 0183 standard's RMC example ends in *6A.
        assert_eq!(
            checksum("GPRMC,123519,A,4807.038,N,01131.000,E,022.4,084.4,230394,003.1,W"),
            0x6A
        );
        Ok(())
    }

    #[test]
    fn frame_example() -> Result<(), Box<dyn std::error::Error>> {
        assert_eq!(frame("PGRMZ,2282,f,2"), "$PGRMZ,2282,f,2*20\r\n");
        Ok(())
    }

    #[test]
    fn from_unix_example() -> Result<(), Box<dyn std::error::Error>> {
        use std::time::Duration;
        // 2024-02-29 12:35:19.5
        let t = Utc::from_unix(Duration::from_millis(1_709_210_119_500));
        assert_eq!(
            (t.time(), t.date()),
            ("123519.50".to_owned(), "290224".to_owned())
        );
        Ok(())
    }

    #[test]
    fn rmc_example() -> Result<(), Box<dyn std::error::Error>> {
        use std::time::Duration;
        let t = Utc::from_unix(Duration::from_millis(1_709_210_119_500));
        assert_eq!(rmc(&t, None), "$GPRMC,123519.50,V,,,,,,,290224,,,N*7A\r\n");
        Ok(())
    }

    #[test]
    fn gga_example() -> Result<(), Box<dyn std::error::Error>> {
        use std::time::Duration;
        let t = Utc::from_unix(Duration::from_millis(1_709_210_119_500));
        assert_eq!(
            gga(&t, None, Some(3)),
            "$GPGGA,123519.50,,,,,0,03,,,M,,M,,*43\r\n"
        );
        Ok(())
    }

    #[test]
    fn pgrmz_example() -> Result<(), Box<dyn std::error::Error>> {
        assert_eq!(pgrmz(Some(2282.4)), "$PGRMZ,2282,f,2*20\r\n");
        assert_eq!(pgrmz(None), "$PGRMZ,,f,2*2A\r\n");
        Ok(())
    }

    #[test]
    fn pov_example() -> Result<(), Box<dyn std::error::Error>> {
        let a = Pov {
            static_hpa: Some(898.746),
            dynamic_pa: None,
            celsius: Some(8.5),
        };
        assert_eq!(pov(&a).unwrap(), "$POV,P,898.75,T,8.50*4B\r\n");
        assert_eq!(pov(&Pov::default()), None);
        Ok(())
    }

    #[test]
    fn lxwp0_example() -> Result<(), Box<dyn std::error::Error>> {
        let v = Lxwp0 {
            tas_kmh: Some(180.04),
            pressure_altitude_m: Some(1000.0),
            ..Lxwp0::default()
        };
        assert_eq!(lxwp0(&v), "$LXWP0,N,180.0,1000.0,,,,,,,,,*55\r\n");
        Ok(())
    }
}
