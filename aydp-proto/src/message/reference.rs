//! Types of the `Reference` profile (Y2): wind speed (1), wind direction (2), vessel data (17).

use super::{exact, fixed_payload};
use crate::error::Result;
use crate::header::{array_at, put};
use crate::layout::{vessel_data as at, wind};

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
    pub const LEN: usize = wind::LEN;
    /// The layout: `(field, wire type, data offset)` per field, for tools that describe the
    /// wire format (the Wireshark dissector `protolink wireshark` writes). Little-endian;
    /// `uflt16` is binary16 without a sign.
    ///
    /// ```
    /// use aydp_proto::WindSpeed;
    /// assert_eq!(WindSpeed::FIELDS, [("value", "f32", 0)]);
    /// ```
    pub const FIELDS: &'static [(&'static str, &'static str, usize)] = wind::FIELDS;
    /// Parse exactly 4 bytes.
    ///
    /// ```
    /// use aydp_proto::{Error, WindSpeed};
    /// let short = Error::PayloadTooShort { msg_type: 1, expected: 4, actual: 3 };
    /// assert_eq!(WindSpeed::parse(&[0, 0, 0x60]), Err(short));
    /// ```
    pub fn parse(data: &[u8]) -> Result<Self> {
        Ok(Self(f32::from_le_bytes(*exact::<{ Self::LEN }>(
            data,
            Self::TYPE,
        )?)))
    }
    /// The 4 data bytes.
    ///
    /// ```
    /// use aydp_proto::WindSpeed;
    /// let mut data = [0u8; WindSpeed::LEN];
    /// assert_eq!(WindSpeed(3.5).emit(&mut data), Ok(WindSpeed::LEN));
    /// assert_eq!(data, [0x00, 0x00, 0x60, 0x40]);
    /// ```
    pub(crate) fn data(&self) -> [u8; Self::LEN] {
        self.0.to_le_bytes()
    }
}
fixed_payload!(WindSpeed);

/// Wind direction (type 2 in `Reference`): one f32, degrees.
///
/// ```
/// use aydp_proto::WindDirection;
/// let mut data = [0u8; WindDirection::LEN];
/// WindDirection(270.0).emit(&mut data).unwrap();
/// assert_eq!(WindDirection::parse(&data), Ok(WindDirection(270.0)));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct WindDirection(pub f32);

impl WindDirection {
    /// Base type.
    pub const TYPE: u8 = 2;
    /// Data length.
    pub const LEN: usize = wind::LEN;
    /// The layout: `(field, wire type, data offset)` per field, for tools that describe the
    /// wire format (the Wireshark dissector `protolink wireshark` writes). Little-endian;
    /// `uflt16` is binary16 without a sign.
    ///
    /// ```
    /// use aydp_proto::WindDirection;
    /// assert_eq!(WindDirection::FIELDS, [("value", "f32", 0)]);
    /// ```
    pub const FIELDS: &'static [(&'static str, &'static str, usize)] = wind::FIELDS;
    /// Parse exactly 4 bytes.
    ///
    /// ```
    /// use aydp_proto::{Error, WindDirection};
    /// assert_eq!(WindDirection::parse(&[0x00, 0x00, 0x87, 0x43]), Ok(WindDirection(270.0)));
    /// let long = Error::PayloadTooLong { msg_type: 2, expected: 4, actual: 5 };
    /// assert_eq!(WindDirection::parse(&[0; 5]), Err(long));
    /// ```
    pub fn parse(data: &[u8]) -> Result<Self> {
        Ok(Self(f32::from_le_bytes(*exact::<{ Self::LEN }>(
            data,
            Self::TYPE,
        )?)))
    }
    /// The 4 data bytes.
    ///
    /// ```
    /// use aydp_proto::WindDirection;
    /// let mut data = [0u8; WindDirection::LEN];
    /// assert_eq!(WindDirection(270.0).emit(&mut data), Ok(WindDirection::LEN));
    /// assert_eq!(data, [0x00, 0x00, 0x87, 0x43]);
    /// ```
    pub(crate) fn data(&self) -> [u8; Self::LEN] {
        self.0.to_le_bytes()
    }
}
fixed_payload!(WindDirection);

/// Vessel data (type 17 in `Reference`): 68 bytes, little-endian, in field order.
///
/// ```
/// use aydp_proto::VesselData;
/// let v = VesselData { heading: 90.0, latitude: 50.5, satellites: 8, ..Default::default() };
/// let mut data = [0u8; VesselData::LEN];
/// v.emit(&mut data).unwrap();
/// assert_eq!(VesselData::parse(&data), Ok(v));
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
    pub const LEN: usize = at::LEN;
    /// The layout: `(field, wire type, data offset)` per field, for tools that describe the
    /// wire format (the Wireshark dissector `protolink wireshark` writes). Little-endian;
    /// `uflt16` is binary16 without a sign.
    ///
    /// ```
    /// use aydp_proto::VesselData;
    /// assert_eq!(VesselData::FIELDS[6], ("latitude", "f64", 24));
    /// ```
    pub const FIELDS: &'static [(&'static str, &'static str, usize)] = at::FIELDS;

    /// Parse exactly 68 bytes.
    ///
    /// ```
    /// use aydp_proto::{Error, VesselData};
    /// let mut data = [0u8; 68];
    /// data[8..12].copy_from_slice(&[0x00, 0x00, 0xB4, 0x42]); // heading 90.0
    /// assert_eq!(VesselData::parse(&data).unwrap().heading, 90.0);
    /// let short = Error::PayloadTooShort { msg_type: 17, expected: 68, actual: 67 };
    /// assert_eq!(VesselData::parse(&data[..67]), Err(short));
    /// ```
    pub fn parse(data: &[u8]) -> Result<Self> {
        let b = exact::<{ Self::LEN }>(data, Self::TYPE)?;
        let f = |at| f32::from_le_bytes(array_at(b, at));
        Ok(Self {
            roll: f(at::ROLL),
            pitch: f(at::PITCH),
            heading: f(at::HEADING),
            roll_rate: f(at::ROLL_RATE),
            pitch_rate: f(at::PITCH_RATE),
            heading_rate: f(at::HEADING_RATE),
            latitude: f64::from_le_bytes(array_at(b, at::LATITUDE)),
            longitude: f64::from_le_bytes(array_at(b, at::LONGITUDE)),
            track: f(at::TRACK),
            speed_over_ground: f(at::SPEED_OVER_GROUND),
            fix_type: i32::from_le_bytes(array_at(b, at::FIX_TYPE)),
            satellites: i32::from_le_bytes(array_at(b, at::SATELLITES)),
            mean_dop: f(at::MEAN_DOP),
            hdop: f(at::HDOP),
            vdop: f(at::VDOP),
        })
    }

    /// The 68 data bytes.
    ///
    /// ```
    /// use aydp_proto::VesselData;
    /// let v = VesselData { heading: 90.0, latitude: 50.5, satellites: 8, ..Default::default() };
    /// let mut b = [0u8; VesselData::LEN];
    /// v.emit(&mut b).unwrap();
    /// assert_eq!(&b[8..12], &[0x00, 0x00, 0xB4, 0x42]);
    /// assert_eq!(&b[24..32], &[0, 0, 0, 0, 0, 0x40, 0x49, 0x40]);
    /// assert_eq!(&b[52..56], &[8, 0, 0, 0]);
    /// ```
    pub(crate) fn data(&self) -> [u8; Self::LEN] {
        let mut o = [0u8; Self::LEN];
        let fs = [
            (at::ROLL, self.roll),
            (at::PITCH, self.pitch),
            (at::HEADING, self.heading),
            (at::ROLL_RATE, self.roll_rate),
            (at::PITCH_RATE, self.pitch_rate),
            (at::HEADING_RATE, self.heading_rate),
            (at::TRACK, self.track),
            (at::SPEED_OVER_GROUND, self.speed_over_ground),
            (at::MEAN_DOP, self.mean_dop),
            (at::HDOP, self.hdop),
            (at::VDOP, self.vdop),
        ];
        for (at, v) in fs {
            put(&mut o, at, &v.to_le_bytes());
        }
        put(&mut o, at::LATITUDE, &self.latitude.to_le_bytes());
        put(&mut o, at::LONGITUDE, &self.longitude.to_le_bytes());
        put(&mut o, at::FIX_TYPE, &self.fix_type.to_le_bytes());
        put(&mut o, at::SATELLITES, &self.satellites.to_le_bytes());
        o
    }
}
fixed_payload!(VesselData);
