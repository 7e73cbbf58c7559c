//! Position (type 3, Y8): f64 latitude, f64 longitude, f32 altitude, 20 bytes.

use super::{exact, fixed_payload};
use crate::error::Result;
use crate::header::{array_at, put};
use crate::layout::position as at;

/// Position (type 3).
///
/// ```
/// use aydp_proto::Position;
/// let p = Position { latitude: 50.5, longitude: -1.25, altitude: 12.5 };
/// let mut data = [0u8; Position::LEN];
/// p.emit(&mut data).unwrap();
/// assert_eq!(Position::parse(&data), Ok(p));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Position {
    /// Latitude (degrees).
    pub latitude: f64,
    /// Longitude (degrees).
    pub longitude: f64,
    /// Altitude.
    pub altitude: f32,
}

impl Position {
    /// Base type.
    pub const TYPE: u8 = 3;
    /// Data length.
    pub const LEN: usize = at::LEN;
    /// The layout: `(field, wire type, data offset)` per field, for tools that describe the
    /// wire format (the Wireshark dissector `protolink wireshark` writes). Little-endian;
    /// `uflt16` is binary16 without a sign.
    ///
    /// ```
    /// use aydp_proto::Position;
    /// assert_eq!(Position::FIELDS[2], ("altitude", "f32", 16));
    /// ```
    pub const FIELDS: &'static [(&'static str, &'static str, usize)] = at::FIELDS;

    /// Parse exactly 20 data bytes.
    ///
    /// ```
    /// use aydp_proto::{Error, Position};
    /// let data = [0, 0, 0, 0, 0, 0x40, 0x49, 0x40, 0, 0, 0, 0, 0, 0, 0xF4, 0xBF, 0, 0, 0x48, 0x41];
    /// let p = Position::parse(&data).unwrap();
    /// assert_eq!((p.latitude, p.longitude, p.altitude), (50.5, -1.25, 12.5));
    /// let short = Error::PayloadTooShort { msg_type: 3, expected: 20, actual: 19 };
    /// assert_eq!(Position::parse(&data[..19]), Err(short));
    /// ```
    pub fn parse(data: &[u8]) -> Result<Self> {
        let b = exact::<{ Self::LEN }>(data, Self::TYPE)?;
        Ok(Self {
            latitude: f64::from_le_bytes(array_at(b, at::LATITUDE)),
            longitude: f64::from_le_bytes(array_at(b, at::LONGITUDE)),
            altitude: f32::from_le_bytes(array_at(b, at::ALTITUDE)),
        })
    }

    /// The 20 data bytes.
    ///
    /// ```
    /// use aydp_proto::Position;
    /// let p = Position { latitude: 50.5, longitude: -1.25, altitude: 12.5 };
    /// // latitude f64, longitude f64, altitude f32, little-endian
    /// let mut data = [0u8; Position::LEN];
    /// assert_eq!(p.emit(&mut data), Ok(Position::LEN));
    /// assert_eq!(data, [0, 0, 0, 0, 0, 0x40, 0x49, 0x40, 0, 0, 0, 0, 0, 0, 0xF4, 0xBF, 0, 0, 0x48, 0x41]);
    /// ```
    pub(crate) fn data(&self) -> [u8; Self::LEN] {
        let mut out = [0u8; Self::LEN];
        put(&mut out, at::LATITUDE, &self.latitude.to_le_bytes());
        put(&mut out, at::LONGITUDE, &self.longitude.to_le_bytes());
        put(&mut out, at::ALTITUDE, &self.altitude.to_le_bytes());
        out
    }
}

fixed_payload!(Position);
