//! Ownship Geometric Altitude, ID 11 (ICD 3.8).

use super::layout::geo_altitude as f;
use super::scale::div_round;
use super::{check_len, emit_into};
use crate::{EncodeError, Error};

const STEP_FT: i64 = 5;
const VFOM_NOT_AVAILABLE: u64 = 0x7FFF;

/// Ownship Geometric Altitude (ID 11): altitude above the datum the ForeFlight ID message
/// names (WGS-84 ellipsoid unless it says MSL), and its vertical figure of merit.
///
/// ```
/// use gdl90_proto::message::GeoAltitude;
/// let alt = GeoAltitude { altitude_ft: 1500, vertical_warning: false, vfom_m: Some(10) };
/// let mut data = [0u8; GeoAltitude::LEN];
/// alt.emit(&mut data).unwrap();
/// assert_eq!(data, [0x01, 0x2C, 0x00, 0x0A]); // 300 x 5 ft, 10 m
/// assert_eq!(GeoAltitude::parse(&data), Ok(alt));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct GeoAltitude {
    /// Geometric altitude, feet, 5 ft steps, -163 840..=163 835. Encoding rounds to the
    /// nearest step and clamps.
    pub altitude_ft: i32,
    /// The vertical warning bit.
    pub vertical_warning: bool,
    /// Vertical figure of merit, metres, 0..=32766 (32766 also stands for "more than
    /// that"); `None` is `0x7FFF`, not available. Encoding clamps.
    pub vfom_m: Option<u16>,
}

impl GeoAltitude {
    /// The message ID.
    pub const ID: u8 = 11;
    /// The data length in bytes (after the ID, before the CRC).
    pub const LEN: usize = f::LEN;

    /// Parses the data bytes.
    ///
    /// ```
    /// use gdl90_proto::{Error, message::GeoAltitude};
    /// let alt = GeoAltitude::parse(&[0xFF, 0xFF, 0x80, 0x0A]).unwrap();
    /// assert_eq!(alt, GeoAltitude { altitude_ft: -5, vertical_warning: true, vfom_m: Some(10) });
    /// let e = GeoAltitude::parse(&[0xFF, 0xFF]);
    /// assert_eq!(e, Err(Error::WrongLength { id: 11, expected: 4, actual: 2 }));
    /// ```
    ///
    /// # Errors
    /// [`Error::WrongLength`] unless `data` is exactly [`Self::LEN`] bytes.
    pub fn parse(data: &[u8]) -> Result<Self, Error> {
        check_len(Self::ID, Self::LEN, data)?;
        let vfom = f::VFOM.get(data);
        Ok(GeoAltitude {
            altitude_ft: (f::ALTITUDE.get_signed(data) * STEP_FT) as i32,
            vertical_warning: f::VERTICAL_WARNING.get_flag(data),
            vfom_m: (vfom != VFOM_NOT_AVAILABLE).then_some(vfom as u16),
        })
    }

    /// Writes the data bytes into `out` (values clamped); returns [`Self::LEN`].
    ///
    /// ```
    /// use gdl90_proto::message::GeoAltitude;
    /// let alt = GeoAltitude { altitude_ft: 1502, vertical_warning: false, vfom_m: None };
    /// let mut data = [0u8; GeoAltitude::LEN];
    /// alt.emit(&mut data).unwrap();
    /// assert_eq!(data, [0x01, 0x2C, 0x7F, 0xFF]); // 1500 ft, VFOM not available
    /// ```
    ///
    /// # Errors
    /// [`EncodeError::BufferTooSmall`] if `out` is shorter than [`Self::LEN`].
    pub fn emit(&self, out: &mut [u8]) -> Result<usize, EncodeError> {
        emit_into(out, Self::LEN, |d| {
            let steps =
                div_round(self.altitude_ft as i64, STEP_FT).clamp(i16::MIN as i64, i16::MAX as i64);
            f::ALTITUDE.put(d, steps as u64);
            f::VERTICAL_WARNING.put_flag(d, self.vertical_warning);
            let vfom = match self.vfom_m {
                Some(m) => (m as u64).min(VFOM_NOT_AVAILABLE - 1),
                None => VFOM_NOT_AVAILABLE,
            };
            f::VFOM.put(d, vfom);
        })
    }

    /// The data length [`Self::emit`] writes.
    ///
    /// ```
    /// use gdl90_proto::message::GeoAltitude;
    /// assert_eq!(GeoAltitude::default().buffer_len(), 4);
    /// ```
    pub const fn buffer_len(&self) -> usize {
        Self::LEN
    }
}
