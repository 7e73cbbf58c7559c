//! Positions: local north/east offsets in metres to latitude/longitude.
//!
//! A spherical Earth of radius [`EARTH_RADIUS_M`] with a local tangent plane at
//! the start point. Over the few kilometres a turn covers the error is far below
//! a GPS receiver's; the tests measure distances with the haversine formula on
//! the same sphere.
//!
//! ```
//! use flight_sim::geo;
//! let (lat, lon) = geo::offset(48.0, 11.0, 1000.0, 0.0);
//! assert!((geo::distance_m(48.0, 11.0, lat, lon) - 1000.0).abs() < 0.01);
//! ```

use libm::{asin, cos, sin, sqrt};

/// Mean Earth radius (IUGG), m.
pub const EARTH_RADIUS_M: f64 = 6_371_008.8;

const DEG: f64 = core::f64::consts::PI / 180.0;

/// The point `north_m` metres north and `east_m` metres east of
/// (`lat_deg`, `lon_deg`), on the tangent plane at that point. The latitude
/// is clamped to ±90° and the longitude wrapped into `[-180, 180)`.
///
/// ```
/// let (lat, lon) = flight_sim::geo::offset(0.0, 179.999, 0.0, 1000.0);
/// assert!(lon < -179.99); // wrapped across the antimeridian
/// # let _ = lat;
/// ```
pub fn offset(lat_deg: f64, lon_deg: f64, north_m: f64, east_m: f64) -> (f64, f64) {
    let lat = lat_deg + north_m / EARTH_RADIUS_M / DEG;
    let lon = lon_deg + east_m / (EARTH_RADIUS_M * lon_scale(lat_deg)) / DEG;
    (lat.clamp(-90.0, 90.0), wrap_lon(lon))
}

/// Great-circle distance between two points, m (haversine).
///
/// ```
/// let d = flight_sim::geo::distance_m(0.0, 0.0, 0.0, 1.0);
/// assert!((d - 111_195.08).abs() < 0.1);
/// ```
pub fn distance_m(lat1_deg: f64, lon1_deg: f64, lat2_deg: f64, lon2_deg: f64) -> f64 {
    let (p1, p2) = (lat1_deg * DEG, lat2_deg * DEG);
    let dp = p2 - p1;
    let dl = (lon2_deg - lon1_deg) * DEG;
    let h = sin(dp / 2.0) * sin(dp / 2.0) + cos(p1) * cos(p2) * sin(dl / 2.0) * sin(dl / 2.0);
    2.0 * EARTH_RADIUS_M * asin(sqrt(h.clamp(0.0, 1.0)))
}

/// The length of a degree of longitude over that of latitude at `lat_deg`: cos(latitude),
/// at least 10⁻⁶. Fixed-point cosine (`crate::turn`, 4·10⁻⁹): plenty for a scale factor, and
/// it keeps trigonometry out of the firmware.
pub(crate) fn lon_scale(lat_deg: f64) -> f64 {
    let (_, cos) = crate::turn::sin_cos(crate::turn::from_deg(lat_deg));
    (f64::from(cos) / f64::from(crate::turn::ONE)).max(1e-6)
}

/// Wraps a longitude into `[-180, 180)`.
pub(crate) fn wrap_lon(lon: f64) -> f64 {
    if (-180.0..180.0).contains(&lon) {
        return lon;
    }
    let w = remainder(lon + 180.0, 360.0);
    if w < 0.0 { w + 180.0 } else { w - 180.0 }
}

/// `x` minus the whole multiples of `period` it holds, like C's `fmod` (the
/// result has the sign of `x`), for `|x / period| < 2^63`; beyond that it
/// stays finite but meaningless. Much smaller than `libm::fmod` on a
/// Cortex-M, which matters for the firmware's flash budget.
pub(crate) fn remainder(x: f64, period: f64) -> f64 {
    let whole = (x / period) as i64; // truncates toward zero, saturates
    x - whole as f64 * period
}
