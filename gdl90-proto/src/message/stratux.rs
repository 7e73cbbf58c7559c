//! The Stratux AHRS report, ID 0x4C: the Levil "LE" AHRS format, which Stratux sends beside
//! ForeFlight's AHRS and which EFB apps such as WingX, iFly and AvPlan read attitude from.
//!
//! The layout is the one Stratux's `makeAHRSGDL90Report` writes (in `main/gps.go` of
//! `cyoung/stratux`; older trees had it in `main/gen_gdl90.go`): the ID, then `0x45 0x01
//! 0x01`, then nine big-endian 16-bit fields and two reserved bytes, 24 bytes in all before
//! the CRC. Every field but the pressure altitude is signed with `0x7FFF` for invalid; the
//! pressure altitude is unsigned, offset by 5000 ft, with `0xFFFF` for invalid.

use super::layout::stratux_ahrs as f;
use super::scale::round_f32;
use super::{check_len, emit_into};
use crate::{EncodeError, Error};

/// The message ID.
pub const STRATUX_AHRS_ID: u8 = 0x4C;
/// The three bytes after the ID: `0x45` ('E', of Levil's "LE"), then `0x01 0x01`.
pub const STRATUX_AHRS_HEADER: [u8; 3] = [0x45, 0x01, 0x01];

/// The invalid marker of the signed fields.
const INVALID: i64 = 0x7FFF;
/// The largest value a signed field sends (one below the marker).
const SIGNED_MAX: i64 = INVALID - 1;
/// Roll and pitch limit, 0.1 degree.
const ANGLE_LIMIT: i64 = 1800;
/// Heading limit, 0.1 degree.
const HEADING_LIMIT: i64 = 3600;
/// The pressure altitude's offset, feet, and its invalid marker.
const ALTITUDE_OFFSET_FT: i64 = 5000;
const ALTITUDE_INVALID: u64 = 0xFFFF;

/// Stratux AHRS report (ID 0x4C): attitude, heading, slip, turn rate, load factor, airspeed,
/// pressure altitude and vertical speed, each `None` when the device marks it invalid.
///
/// Angles and rates travel in tenths (of a degree, a degree per second, a G); airspeed in
/// knots, pressure altitude in feet and vertical speed in feet per minute travel whole.
/// Encoding rounds to the wire step, clamps to the range each field states (never onto an
/// invalid marker), and sends NaN as invalid.
///
/// ```
/// use gdl90_proto::message::StratuxAhrs;
/// let ahrs = StratuxAhrs {
///     roll_deg: Some(30.0),
///     pitch_deg: Some(-2.5),
///     heading_deg: Some(90.0),
///     g_load: Some(1.2),
///     pressure_altitude_ft: Some(1000),
///     ..StratuxAhrs::default()
/// };
/// let mut data = [0u8; StratuxAhrs::LEN];
/// ahrs.emit(&mut data).unwrap();
/// assert_eq!(&data[..9], &[0x45, 0x01, 0x01, 0x01, 0x2C, 0xFF, 0xE7, 0x03, 0x84]);
/// assert_eq!(&data[9..11], &[0x7F, 0xFF]); // slip/skid invalid
/// assert_eq!(&data[17..19], &[0x17, 0x70]); // 1000 ft + 5000 = 6000
/// assert_eq!(StratuxAhrs::parse(&data), Ok(ahrs));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct StratuxAhrs {
    /// Roll, degrees, right wing down positive, 0.1-degree steps. A received value beyond
    /// ±180 rejects the message; encoding clamps to ±180.
    pub roll_deg: Option<f32>,
    /// Pitch, degrees, nose up positive; as [`StratuxAhrs::roll_deg`].
    pub pitch_deg: Option<f32>,
    /// Heading, degrees, 0.1-degree steps (Stratux sends its gyro heading; the message does
    /// not say true or magnetic). A received value beyond ±360 rejects the message; encoding
    /// reduces an angle beyond ±360 into 0..360 (so it is never clamped to a wrong direction).
    pub heading_deg: Option<f32>,
    /// Slip/skid, degrees, 0.1-degree steps (Stratux sends its slip angle negated).
    pub slip_skid_deg: Option<f32>,
    /// Yaw (turn) rate, degrees per second, 0.1 steps, positive right.
    pub yaw_rate_dps: Option<f32>,
    /// Load factor, G, 0.1 steps (1.0 in level flight).
    pub g_load: Option<f32>,
    /// Indicated airspeed, knots, -32768..=32766.
    pub indicated_airspeed_kt: Option<i16>,
    /// Pressure altitude, feet, -5000..=60534 (sent as feet + 5000 in an unsigned field).
    pub pressure_altitude_ft: Option<i32>,
    /// Vertical speed, feet per minute, positive up, -32768..=32766.
    pub vertical_speed_fpm: Option<i16>,
}

impl StratuxAhrs {
    /// The message ID (0x4C).
    pub const ID: u8 = STRATUX_AHRS_ID;
    /// The data length in bytes (the three header bytes included, the CRC excluded).
    pub const LEN: usize = f::LEN;

    /// Parses the data bytes (after the ID, header included).
    ///
    /// ```
    /// use gdl90_proto::{Error, message::StratuxAhrs};
    /// let mut data = vec![0x45, 0x01, 0x01];
    /// data.extend([0x7F, 0xFF].repeat(10));
    /// data[17..19].copy_from_slice(&[0xFF, 0xFF]);
    /// assert_eq!(StratuxAhrs::parse(&data), Ok(StratuxAhrs::default())); // all invalid
    /// data[3..5].copy_from_slice(&1801i16.to_be_bytes());
    /// assert_eq!(StratuxAhrs::parse(&data), Err(Error::OutOfRange { id: 0x4C, field: "roll" }));
    /// ```
    ///
    /// # Errors
    /// [`Error::WrongLength`] unless `data` is exactly [`Self::LEN`] bytes;
    /// [`Error::OutOfRange`] for a header other than `45 01 01` (field `"header"`), a roll or
    /// pitch beyond ±180 degrees or a heading beyond ±360 degrees.
    pub fn parse(data: &[u8]) -> Result<Self, Error> {
        check_len(Self::ID, Self::LEN, data)?;
        let out_of_range = |field| Error::OutOfRange {
            id: Self::ID,
            field,
        };
        if data.get(f::HEADER) != Some(&STRATUX_AHRS_HEADER[..]) {
            return Err(out_of_range("header"));
        }
        let signed = |bits: &super::layout::Bits| {
            let v = bits.get_signed(data);
            (v != INVALID).then_some(v)
        };
        let limited = |bits, limit, field| match signed(bits) {
            Some(v) if v.abs() > limit => Err(out_of_range(field)),
            v => Ok(v.map(|v| v as f32 / 10.0)),
        };
        let tenths = |bits| signed(bits).map(|v| v as f32 / 10.0);
        let altitude = f::PRESSURE_ALTITUDE.get(data);
        Ok(StratuxAhrs {
            roll_deg: limited(&f::ROLL, ANGLE_LIMIT, "roll")?,
            pitch_deg: limited(&f::PITCH, ANGLE_LIMIT, "pitch")?,
            heading_deg: limited(&f::HEADING, HEADING_LIMIT, "heading")?,
            slip_skid_deg: tenths(&f::SLIP_SKID),
            yaw_rate_dps: tenths(&f::YAW_RATE),
            g_load: tenths(&f::G),
            indicated_airspeed_kt: signed(&f::IAS).map(|v| v as i16),
            pressure_altitude_ft: (altitude != ALTITUDE_INVALID)
                .then(|| (altitude as i64 - ALTITUDE_OFFSET_FT) as i32),
            vertical_speed_fpm: signed(&f::VERTICAL_SPEED).map(|v| v as i16),
        })
    }

    /// Writes the data bytes into `out` (header, fields clamped or marked invalid as each
    /// says, reserved bytes `7F FF` as Stratux sends them); returns [`Self::LEN`].
    ///
    /// ```
    /// use gdl90_proto::message::StratuxAhrs;
    /// let mut data = [0u8; StratuxAhrs::LEN];
    /// StratuxAhrs { heading_deg: Some(450.0), pressure_altitude_ft: Some(-9000), ..Default::default() }
    ///     .emit(&mut data)
    ///     .unwrap();
    /// assert_eq!(&data[7..9], &900i16.to_be_bytes()); // 450 is 90
    /// assert_eq!(&data[17..19], &[0, 0]); // clamped to -5000 ft
    /// assert_eq!(&data[21..], &[0x7F, 0xFF]);
    /// ```
    ///
    /// # Errors
    /// [`EncodeError::BufferTooSmall`] if `out` is shorter than [`Self::LEN`].
    pub fn emit(&self, out: &mut [u8]) -> Result<usize, EncodeError> {
        emit_into(out, Self::LEN, |d| {
            if let Some(h) = d.get_mut(f::HEADER) {
                h.copy_from_slice(&STRATUX_AHRS_HEADER);
            }
            let tenths = |x: Option<f32>, lo: i64, hi: i64| {
                x.and_then(|x| round_f32(x * 10.0))
                    .map_or(INVALID, |v| v.clamp(lo, hi))
            };
            let wide = (i64::from(i16::MIN), SIGNED_MAX);
            f::ROLL.put(d, tenths(self.roll_deg, -ANGLE_LIMIT, ANGLE_LIMIT) as u64);
            f::PITCH.put(d, tenths(self.pitch_deg, -ANGLE_LIMIT, ANGLE_LIMIT) as u64);
            let heading = self
                .heading_deg
                .and_then(|x| round_f32(x * 10.0))
                .map_or(INVALID, |v| {
                    // An angle: one beyond ±360 is reduced rather than clamped.
                    if (-HEADING_LIMIT..=HEADING_LIMIT).contains(&v) {
                        v
                    } else {
                        v.rem_euclid(HEADING_LIMIT)
                    }
                });
            f::HEADING.put(d, heading as u64);
            f::SLIP_SKID.put(d, tenths(self.slip_skid_deg, wide.0, wide.1) as u64);
            f::YAW_RATE.put(d, tenths(self.yaw_rate_dps, wide.0, wide.1) as u64);
            f::G.put(d, tenths(self.g_load, wide.0, wide.1) as u64);
            let whole = |v: Option<i16>| v.map_or(INVALID, |v| i64::from(v).min(SIGNED_MAX));
            f::IAS.put(d, whole(self.indicated_airspeed_kt) as u64);
            let altitude = self.pressure_altitude_ft.map_or(ALTITUDE_INVALID, |ft| {
                (i64::from(ft) + ALTITUDE_OFFSET_FT).clamp(0, ALTITUDE_INVALID as i64 - 1) as u64
            });
            f::PRESSURE_ALTITUDE.put(d, altitude);
            f::VERTICAL_SPEED.put(d, whole(self.vertical_speed_fpm) as u64);
            f::RESERVED.put(d, INVALID as u64);
        })
    }

    /// The data length [`Self::emit`] writes.
    ///
    /// ```
    /// use gdl90_proto::message::StratuxAhrs;
    /// assert_eq!(StratuxAhrs::default().buffer_len(), 23);
    /// ```
    pub const fn buffer_len(&self) -> usize {
        Self::LEN
    }
}
