//! Types of the `Reference` profile (Y2): wind speed (1), wind direction (2), vessel data (17).

use super::{exact, fixed_payload};
use crate::error::Result;
use crate::header::{array_at, put};

/// Wind speed (type 1 in `Reference`): one f32, mph.
///
/// ```
/// use aydp_proto::WindSpeed;
/// assert_eq!(WindSpeed::parse(&[0, 0, 0x60, 0x40]), Ok(WindSpeed(3.5)));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct WindSpeed(pub f32);

impl WindSpeed {
    /// Base type.
    pub const TYPE: u8 = 1;
    /// Data length.
    pub const LEN: usize = 4;
    /// Parse exactly 4 bytes.
    pub fn parse(data: &[u8]) -> Result<Self> {
        Ok(Self(f32::from_le_bytes(*exact::<4>(data, Self::TYPE)?)))
    }
    /// The 4 data bytes.
    pub fn to_bytes(&self) -> [u8; Self::LEN] {
        self.0.to_le_bytes()
    }
}
fixed_payload!(WindSpeed);

/// Wind direction (type 2 in `Reference`): one f32, degrees.
///
/// ```
/// use aydp_proto::WindDirection;
/// assert_eq!(WindDirection::parse(&WindDirection(270.0).to_bytes()), Ok(WindDirection(270.0)));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct WindDirection(pub f32);

impl WindDirection {
    /// Base type.
    pub const TYPE: u8 = 2;
    /// Data length.
    pub const LEN: usize = 4;
    /// Parse exactly 4 bytes.
    pub fn parse(data: &[u8]) -> Result<Self> {
        Ok(Self(f32::from_le_bytes(*exact::<4>(data, Self::TYPE)?)))
    }
    /// The 4 data bytes.
    pub fn to_bytes(&self) -> [u8; Self::LEN] {
        self.0.to_le_bytes()
    }
}
fixed_payload!(WindDirection);

/// Vessel data (type 17 in `Reference`): 68 bytes, little-endian, in field order.
///
/// ```
/// use aydp_proto::VesselData;
/// let v = VesselData { heading: 90.0, latitude: 50.5, satellites: 8, ..Default::default() };
/// assert_eq!(VesselData::parse(&v.to_bytes()), Ok(v));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct VesselData {
    /// Roll.
    pub roll: f32,
    /// Pitch.
    pub pitch: f32,
    /// Heading.
    pub heading: f32,
    /// Roll rate.
    pub roll_rate: f32,
    /// Pitch rate.
    pub pitch_rate: f32,
    /// Heading rate.
    pub heading_rate: f32,
    /// Latitude.
    pub latitude: f64,
    /// Longitude.
    pub longitude: f64,
    /// Track.
    pub track: f32,
    /// Speed over ground.
    pub speed_over_ground: f32,
    /// Fix type.
    pub fix_type: i32,
    /// Satellites.
    pub satellites: i32,
    /// Mean DOP.
    pub mean_dop: f32,
    /// Horizontal DOP.
    pub hdop: f32,
    /// Vertical DOP.
    pub vdop: f32,
}

impl VesselData {
    /// Base type.
    pub const TYPE: u8 = 17;
    /// Data length.
    pub const LEN: usize = 68;

    /// Parse exactly 68 bytes.
    pub fn parse(data: &[u8]) -> Result<Self> {
        let b = exact::<{ Self::LEN }>(data, Self::TYPE)?;
        let f = |at| f32::from_le_bytes(array_at(b, at));
        Ok(Self {
            roll: f(0),
            pitch: f(4),
            heading: f(8),
            roll_rate: f(12),
            pitch_rate: f(16),
            heading_rate: f(20),
            latitude: f64::from_le_bytes(array_at(b, 24)),
            longitude: f64::from_le_bytes(array_at(b, 32)),
            track: f(40),
            speed_over_ground: f(44),
            fix_type: i32::from_le_bytes(array_at(b, 48)),
            satellites: i32::from_le_bytes(array_at(b, 52)),
            mean_dop: f(56),
            hdop: f(60),
            vdop: f(64),
        })
    }

    /// The 68 data bytes.
    pub fn to_bytes(&self) -> [u8; Self::LEN] {
        let mut o = [0u8; Self::LEN];
        let fs = [
            (0, self.roll),
            (4, self.pitch),
            (8, self.heading),
            (12, self.roll_rate),
            (16, self.pitch_rate),
            (20, self.heading_rate),
            (40, self.track),
            (44, self.speed_over_ground),
            (56, self.mean_dop),
            (60, self.hdop),
            (64, self.vdop),
        ];
        for (at, v) in fs {
            put(&mut o, at, &v.to_le_bytes());
        }
        put(&mut o, 24, &self.latitude.to_le_bytes());
        put(&mut o, 32, &self.longitude.to_le_bytes());
        put(&mut o, 48, &self.fix_type.to_le_bytes());
        put(&mut o, 52, &self.satellites.to_le_bytes());
        o
    }
}
fixed_payload!(VesselData);
