//! ForeFlight's GDL 90 extensions, ID 0x65: the ID message (sub-ID 0) and AHRS (sub-ID 1).

use super::layout::{ahrs as a, foreflight_id as f};
use super::scale::round_f32;
use super::{Name, check_len, emit_into};
use crate::{EncodeError, Error};

/// The ForeFlight message ID.
pub const FOREFLIGHT_ID: u8 = 0x65;

/// The datum of the geometric altitude (ID 11) a device sends: capabilities bit 0.
///
/// ```
/// use gdl90_proto::message::{AltitudeDatum, ForeFlightId};
/// let id = ForeFlightId { altitude_datum: AltitudeDatum::Msl, ..ForeFlightId::default() };
/// let mut data = [0u8; ForeFlightId::LEN];
/// id.emit(&mut data).unwrap();
/// assert_eq!(&data[34..], &[0, 0, 0, 0x01]); // the capabilities, big-endian
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub enum AltitudeDatum {
    /// 0: height above the WGS-84 ellipsoid (the GDL90 default).
    #[default]
    Wgs84Ellipsoid,
    /// 1: mean sea level.
    Msl,
}

/// ForeFlight ID (0x65, sub-ID 0): who the device is and what it can do.
///
/// ```
/// use gdl90_proto::message::{AltitudeDatum, ForeFlightId, Name};
/// let id = ForeFlightId {
///     serial: Some(0x270F_AE2D),
///     name: Name::new("SkyEcho").unwrap(),
///     long_name: Name::new("SkyEcho").unwrap(),
///     ..ForeFlightId::default()
/// };
/// let mut data = [0u8; ForeFlightId::LEN];
/// id.emit(&mut data).unwrap();
/// assert_eq!(&data[..10], &[0, 1, 0, 0, 0, 0, 0x27, 0x0F, 0xAE, 0x2D]);
/// assert_eq!(ForeFlightId::parse(&data), Ok(id));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct ForeFlightId {
    /// Message version; the specification defines 1 ([`ForeFlightId::VERSION`]).
    pub version: u8,
    /// Device serial number; `None` is all ones, "invalid". Encoding `Some(u64::MAX)`
    /// clamps to `u64::MAX - 1`.
    pub serial: Option<u64>,
    /// Device name (8 bytes, UTF-8, NUL padded).
    pub name: Name<8>,
    /// Device long name (16 bytes, UTF-8, NUL padded).
    pub long_name: Name<16>,
    /// Capabilities bit 0: the datum of the geometric altitude.
    pub altitude_datum: AltitudeDatum,
    /// The other capability bits as received (bit 0 always clear here).
    pub other_capabilities: u32,
}

impl Default for ForeFlightId {
    /// Version 1, everything else empty or invalid.
    fn default() -> Self {
        ForeFlightId {
            version: Self::VERSION,
            serial: None,
            name: Name::default(),
            long_name: Name::default(),
            altitude_datum: AltitudeDatum::default(),
            other_capabilities: 0,
        }
    }
}

impl ForeFlightId {
    /// The message ID.
    pub const ID: u8 = FOREFLIGHT_ID;
    /// The sub-ID (data byte 0).
    pub const SUB_ID: u8 = 0;
    /// The version this layout describes.
    pub const VERSION: u8 = 1;
    /// The data length in bytes (sub-ID included, CRC excluded).
    pub const LEN: usize = f::LEN;

    /// Parses the data bytes (sub-ID included).
    ///
    /// ```
    /// use gdl90_proto::{Error, message::ForeFlightId};
    /// let mut data = [0u8; ForeFlightId::LEN];
    /// data[1] = 1; // version 1, serial 0, no names
    /// assert_eq!(ForeFlightId::parse(&data).unwrap().serial, Some(0));
    /// let short = ForeFlightId::parse(&data[..37]);
    /// assert_eq!(short, Err(Error::WrongLength { id: 0x65, expected: 38, actual: 37 }));
    /// ```
    ///
    /// # Errors
    /// [`Error::WrongLength`] unless `data` is exactly [`Self::LEN`] bytes.
    pub fn parse(data: &[u8]) -> Result<Self, Error> {
        check_len(Self::ID, Self::LEN, data)?;
        let serial = f::SERIAL.get(data);
        let mut name = [0u8; 8];
        let mut long_name = [0u8; 16];
        if let (Some(n), Some(l)) = (data.get(f::NAME), data.get(f::LONG_NAME)) {
            // Zipped copies: no length check left to a panic when the copy is not inlined.
            name.iter_mut().zip(n).for_each(|(d, s)| *d = *s);
            long_name.iter_mut().zip(l).for_each(|(d, s)| *d = *s);
        }
        let caps = f::CAPABILITIES.get(data) as u32;
        Ok(ForeFlightId {
            version: f::VERSION.get(data) as u8,
            serial: (serial != u64::MAX).then_some(serial),
            name: Name::from_bytes(name),
            long_name: Name::from_bytes(long_name),
            altitude_datum: if f::ALTITUDE_DATUM.get_flag(data) {
                AltitudeDatum::Msl
            } else {
                AltitudeDatum::Wgs84Ellipsoid
            },
            other_capabilities: caps & !1,
        })
    }

    /// Writes the data bytes into `out`; returns [`Self::LEN`].
    ///
    /// ```
    /// use gdl90_proto::message::ForeFlightId;
    /// let mut data = [0u8; ForeFlightId::LEN];
    /// assert_eq!(ForeFlightId::default().emit(&mut data), Ok(38));
    /// // Sub-ID 0, version 1, then the serial: all ones, "invalid".
    /// assert_eq!(&data[..10], &[0, 1, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF]);
    /// ```
    ///
    /// # Errors
    /// [`EncodeError::BufferTooSmall`] if `out` is shorter than [`Self::LEN`].
    pub fn emit(&self, out: &mut [u8]) -> Result<usize, EncodeError> {
        emit_into(out, Self::LEN, |d| {
            f::SUB_ID.put(d, Self::SUB_ID as u64);
            f::VERSION.put(d, self.version as u64);
            f::SERIAL.put(d, self.serial.map_or(u64::MAX, |s| s.min(u64::MAX - 1)));
            if let Some(dst) = d.get_mut(f::NAME) {
                dst.iter_mut()
                    .zip(self.name.as_bytes())
                    .for_each(|(d, s)| *d = *s);
            }
            if let Some(dst) = d.get_mut(f::LONG_NAME) {
                dst.iter_mut()
                    .zip(self.long_name.as_bytes())
                    .for_each(|(d, s)| *d = *s);
            }
            f::CAPABILITIES.put(d, (self.other_capabilities & !1) as u64);
            f::ALTITUDE_DATUM.put_flag(d, self.altitude_datum == AltitudeDatum::Msl);
        })
    }

    /// The data length [`Self::emit`] writes.
    ///
    /// ```
    /// use gdl90_proto::message::ForeFlightId;
    /// assert_eq!(ForeFlightId::default().buffer_len(), 38);
    /// ```
    pub const fn buffer_len(&self) -> usize {
        Self::LEN
    }
}

/// An AHRS heading and its reference.
///
/// ```
/// use gdl90_proto::message::{Ahrs, Heading};
/// let mut data = [0u8; Ahrs::LEN];
/// Ahrs { heading: Some(Heading::True(90.0)), ..Ahrs::default() }.emit(&mut data).unwrap();
/// assert_eq!(&data[5..7], &[0x03, 0x84]); // 900 tenths of a degree
/// Ahrs { heading: Some(Heading::Magnetic(90.0)), ..Ahrs::default() }.emit(&mut data).unwrap();
/// assert_eq!(&data[5..7], &[0x83, 0x84]); // bit 15: magnetic
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub enum Heading {
    /// True heading, degrees.
    True(f32),
    /// Magnetic heading, degrees.
    Magnetic(f32),
}

impl Heading {
    /// The angle in degrees, whatever its reference.
    ///
    /// ```
    /// use gdl90_proto::message::Heading;
    /// assert_eq!(Heading::Magnetic(271.3).degrees(), 271.3);
    /// ```
    pub const fn degrees(&self) -> f32 {
        match *self {
            Heading::True(d) | Heading::Magnetic(d) => d,
        }
    }
}

/// Roll and pitch "invalid".
const ANGLE_INVALID: i64 = 0x7FFF;
/// Roll and pitch limit, 0.1 degree.
const ANGLE_LIMIT: i64 = 1800;
/// Heading limit, 0.1 degree (bits 14-0 are signed, -3600..=3600).
const HEADING_LIMIT: i64 = 3600;
/// Heading, IAS and TAS "invalid".
const WORD_INVALID: u64 = 0xFFFF;

/// ForeFlight AHRS (0x65, sub-ID 1): attitude, heading and airspeeds, each `None` when the
/// device marks it invalid.
///
/// Send the aircraft's heading only: a GPS ground track must not be sent as a heading
/// (ForeFlight's rule); send `None` instead.
///
/// ```
/// use gdl90_proto::message::{Ahrs, Heading};
/// let ahrs = Ahrs {
///     roll_deg: Some(-12.5),
///     pitch_deg: Some(3.0),
///     heading: Some(Heading::Magnetic(271.3)),
///     indicated_airspeed_kt: Some(98),
///     true_airspeed_kt: None,
/// };
/// let mut data = [0u8; Ahrs::LEN];
/// ahrs.emit(&mut data).unwrap();
/// assert_eq!(data, [1, 0xFF, 0x83, 0x00, 0x1E, 0x8A, 0x99, 0x00, 0x62, 0xFF, 0xFF]);
/// assert_eq!(Ahrs::parse(&data), Ok(ahrs));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Ahrs {
    /// Roll, degrees, right wing down positive, 0.1-degree steps. A received value beyond
    /// ±180 rejects the message; encoding clamps to ±180 and sends NaN as invalid.
    pub roll_deg: Option<f32>,
    /// Pitch, degrees, nose up positive; as [`Ahrs::roll_deg`].
    pub pitch_deg: Option<f32>,
    /// Heading, 0.1-degree steps. A received value beyond ±360 rejects the message;
    /// encoding brings an angle outside ±360 into 0..360, and sends NaN as invalid.
    pub heading: Option<Heading>,
    /// Indicated airspeed, knots, 0..=65534; `None` is `0xFFFF`. Encoding clamps.
    pub indicated_airspeed_kt: Option<u16>,
    /// True airspeed, knots, as [`Ahrs::indicated_airspeed_kt`].
    pub true_airspeed_kt: Option<u16>,
}

impl Ahrs {
    /// The message ID.
    pub const ID: u8 = FOREFLIGHT_ID;
    /// The sub-ID (data byte 0).
    pub const SUB_ID: u8 = 1;
    /// The data length in bytes (sub-ID included, CRC excluded).
    pub const LEN: usize = a::LEN;

    /// Parses the data bytes (sub-ID included).
    ///
    /// # Errors
    /// [`Error::WrongLength`] unless `data` is exactly [`Self::LEN`] bytes;
    /// [`Error::OutOfRange`] for a roll or pitch beyond ±180 degrees or a heading beyond
    /// ±360 degrees.
    ///
    /// ```
    /// use gdl90_proto::{Error, message::Ahrs};
    /// // Every field marked invalid.
    /// let none = [1, 0x7F, 0xFF, 0x7F, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF];
    /// assert_eq!(Ahrs::parse(&none), Ok(Ahrs::default()));
    /// // A roll of 180.1 degrees (1801 tenths).
    /// let roll = [1, 0x07, 0x09, 0x7F, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF];
    /// assert_eq!(Ahrs::parse(&roll), Err(Error::OutOfRange { id: 0x65, field: "roll" }));
    /// ```
    pub fn parse(data: &[u8]) -> Result<Self, Error> {
        check_len(Self::ID, Self::LEN, data)?;
        let angle = |bits: &super::layout::Bits, field| {
            let v = bits.get_signed(data);
            if v == ANGLE_INVALID {
                Ok(None)
            } else if v.abs() > ANGLE_LIMIT {
                Err(Error::OutOfRange {
                    id: Self::ID,
                    field,
                })
            } else {
                Ok(Some(v as f32 / 10.0))
            }
        };
        let heading = if a::HEADING_WORD.get(data) == WORD_INVALID {
            None
        } else {
            let v = a::HEADING.get_signed(data);
            if v.abs() > HEADING_LIMIT {
                return Err(Error::OutOfRange {
                    id: Self::ID,
                    field: "heading",
                });
            }
            let deg = v as f32 / 10.0;
            Some(if a::HEADING_MAGNETIC.get_flag(data) {
                Heading::Magnetic(deg)
            } else {
                Heading::True(deg)
            })
        };
        let speed = |bits: &super::layout::Bits| {
            let v = bits.get(data);
            (v != WORD_INVALID).then_some(v as u16)
        };
        Ok(Ahrs {
            roll_deg: angle(&a::ROLL, "roll")?,
            pitch_deg: angle(&a::PITCH, "pitch")?,
            heading,
            indicated_airspeed_kt: speed(&a::IAS),
            true_airspeed_kt: speed(&a::TAS),
        })
    }

    /// Writes the data bytes into `out` (values clamped or marked invalid as each field
    /// says); returns [`Self::LEN`].
    ///
    /// ```
    /// use gdl90_proto::message::Ahrs;
    /// let mut data = [0u8; Ahrs::LEN];
    /// Ahrs { roll_deg: Some(200.0), pitch_deg: Some(f32::NAN), ..Ahrs::default() }.emit(&mut data).unwrap();
    /// // Roll clamped to 180 degrees (0x0708 tenths), NaN pitch sent as invalid (0x7FFF).
    /// assert_eq!(&data[..5], &[1, 0x07, 0x08, 0x7F, 0xFF]);
    /// ```
    ///
    /// # Errors
    /// [`EncodeError::BufferTooSmall`] if `out` is shorter than [`Self::LEN`].
    pub fn emit(&self, out: &mut [u8]) -> Result<usize, EncodeError> {
        emit_into(out, Self::LEN, |d| {
            a::SUB_ID.put(d, Self::SUB_ID as u64);
            let angle = |deg: Option<f32>| {
                deg.and_then(|x| round_f32(x * 10.0))
                    .map_or(ANGLE_INVALID, |v| v.clamp(-ANGLE_LIMIT, ANGLE_LIMIT))
            };
            a::ROLL.put(d, angle(self.roll_deg) as u64);
            a::PITCH.put(d, angle(self.pitch_deg) as u64);
            a::HEADING_WORD.put(d, heading_word(self.heading));
            let speed =
                |kt: Option<u16>| kt.map_or(WORD_INVALID, |v| (v as u64).min(WORD_INVALID - 1));
            a::IAS.put(d, speed(self.indicated_airspeed_kt));
            a::TAS.put(d, speed(self.true_airspeed_kt));
        })
    }

    /// The data length [`Self::emit`] writes.
    ///
    /// ```
    /// use gdl90_proto::message::Ahrs;
    /// assert_eq!(Ahrs::default().buffer_len(), 11);
    /// ```
    pub const fn buffer_len(&self) -> usize {
        Self::LEN
    }
}

/// The heading word: bit 15 magnetic, bits 14-0 signed tenths of a degree; `0xFFFF` when
/// invalid or NaN.
fn heading_word(heading: Option<Heading>) -> u64 {
    let Some(h) = heading else {
        return WORD_INVALID;
    };
    let Some(mut tenths) = round_f32(h.degrees() * 10.0) else {
        return WORD_INVALID;
    };
    if !(-HEADING_LIMIT..=HEADING_LIMIT).contains(&tenths) {
        // An angle: reduce it rather than clamp, it is the same direction.
        tenths = tenths.rem_euclid(HEADING_LIMIT);
    }
    let magnetic = matches!(h, Heading::Magnetic(_));
    if magnetic && tenths == -1 {
        // Magnetic -0.1 degree would be 0xFFFF, the invalid marker: send 359.9 instead.
        tenths = HEADING_LIMIT - 1;
    }
    let bits = (tenths as u64) & a::HEADING.max();
    bits | (magnetic as u64) << 15
}
