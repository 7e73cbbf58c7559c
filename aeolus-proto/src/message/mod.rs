//! Typed AEOLUS messages (sections 6 and 7): one plain struct per message with `parse`,
//! `emit` and `buffer_len`, and the [`Message`] enum that covers every ID. Multi-byte fields
//! are little-endian (DECISIONS.md A1).

mod field;
mod layout;
mod text;

pub use layout::{
    Accel, AeolusInfo, Attitude, CALIBINFO_LEN, Compass, DEBUGINFO_LEN, Gps, Gyro, Magnet,
    Pressure, SetTime, Temp, Wind,
};
pub use text::Text;

use crate::{CrcMode, EncodeError, Error, encode_frame};

/// Message IDs of the table in section 6.
pub mod id {
    /// AEOLUSINFO.
    pub const AEOLUSINFO: u8 = 51;
    /// PRESSURE.
    pub const PRESSURE: u8 = 61;
    /// GYRO.
    pub const GYRO: u8 = 62;
    /// ACCEL.
    pub const ACCEL: u8 = 63;
    /// MAGNET.
    pub const MAGNET: u8 = 64;
    /// TEMP.
    pub const TEMP: u8 = 65;
    /// GPS.
    pub const GPS: u8 = 66;
    /// ATTITUDE.
    pub const ATTITUDE: u8 = 71;
    /// COMPASS.
    pub const COMPASS: u8 = 72;
    /// WIND.
    pub const WIND: u8 = 73;
    /// CALIBINFO.
    pub const CALIBINFO: u8 = 75;
    /// DEBUGINFO.
    pub const DEBUGINFO: u8 = 76;
    /// LOG.
    pub const LOG: u8 = 81;
    /// TOAST.
    pub const TOAST: u8 = 82;
    /// COMMAND (DECISIONS.md A5: 11, not the 82 repeated in section 7.15).
    pub const COMMAND: u8 = 11;
    /// SETTIME.
    pub const SETTIME: u8 = 12;
}

/// COMPASS calibration status (section 7.9): a signed byte (DECISIONS.md A7).
///
/// ```
/// use aeolus_proto::message::{CalibrationStatus, Compass};
/// let compass = Compass { calibration: CalibrationStatus::FieldWeak, ..Compass::default() };
/// let mut data = [0u8; Compass::LEN];
/// compass.emit(&mut data).unwrap();
/// assert_eq!(data[1], 0xFE); // -2
/// assert_eq!(Compass::parse(&data).unwrap().calibration, CalibrationStatus::FieldWeak);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum CalibrationStatus {
    /// 1: no calibration.
    #[default]
    NoCalibration,
    /// 2: calibration just finished.
    JustFinished,
    /// 3: calibration ok.
    Ok,
    /// 4: calibrating.
    Calibrating,
    /// -1: too few data.
    TooFewData,
    /// -2: field weak.
    FieldWeak,
    /// -3: field distorted.
    FieldDistorted,
    /// -4: error very high.
    ErrorVeryHigh,
    /// Any other value, kept as received.
    Other(i8),
}

impl CalibrationStatus {
    /// Decodes the status byte.
    ///
    /// ```
    /// use aeolus_proto::message::CalibrationStatus;
    /// assert_eq!(CalibrationStatus::from_i8(-2), CalibrationStatus::FieldWeak);
    /// assert_eq!(CalibrationStatus::from_i8(9).to_i8(), 9);
    /// ```
    pub const fn from_i8(v: i8) -> Self {
        match v {
            1 => Self::NoCalibration,
            2 => Self::JustFinished,
            3 => Self::Ok,
            4 => Self::Calibrating,
            -1 => Self::TooFewData,
            -2 => Self::FieldWeak,
            -3 => Self::FieldDistorted,
            -4 => Self::ErrorVeryHigh,
            other => Self::Other(other),
        }
    }

    /// The status byte.
    ///
    /// ```
    /// use aeolus_proto::message::CalibrationStatus;
    /// assert_eq!(CalibrationStatus::FieldWeak.to_i8(), -2);
    /// assert_eq!(CalibrationStatus::Other(9).to_i8(), 9);
    /// ```
    pub const fn to_i8(self) -> i8 {
        match self {
            Self::NoCalibration => 1,
            Self::JustFinished => 2,
            Self::Ok => 3,
            Self::Calibrating => 4,
            Self::TooFewData => -1,
            Self::FieldWeak => -2,
            Self::FieldDistorted => -3,
            Self::ErrorVeryHigh => -4,
            Self::Other(v) => v,
        }
    }
}

/// Any AEOLUS message, typed where the spec defines the layout and raw otherwise.
///
/// Parse one from a frame with [`crate::Frame::message`] or [`Message::parse`]; build one and
/// put it on the wire with [`Message::encode`].
///
/// Encoding a GYRO message into a buffer:
///
/// ```
/// use aeolus_proto::{max_encoded_len, CrcMode, message::{Gyro, Message}};
///
/// let gyro = Message::Gyro(Gyro {
///     valid: true,
///     timestamp_ms: 123456.5,
///     x: 0.5,
///     y: -1.25,
///     z: 0.0078125,
/// });
/// let mut buf = [0u8; max_encoded_len(Gyro::LEN)];
/// let n = gyro.encode(&mut buf, CrcMode::Compute).unwrap();
/// // The "gyro" vector of testdata/aeolus-frames.json.
/// assert_eq!(n, 37);
/// assert_eq!(&buf[..4], &[0x7E, 0x3E, 0x01, 0x00]);
/// assert_eq!(&buf[n - 3..n], &[0xBF, 0x26, 0x7E]);
/// ```
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Message<'a> {
    /// AEOLUSINFO (51).
    AeolusInfo(AeolusInfo),
    /// PRESSURE (61).
    Pressure(Pressure),
    /// GYRO (62).
    Gyro(Gyro),
    /// ACCEL (63).
    Accel(Accel),
    /// MAGNET (64).
    Magnet(Magnet),
    /// TEMP (65).
    Temp(Temp),
    /// GPS (66).
    Gps(Gps),
    /// ATTITUDE (71).
    Attitude(Attitude),
    /// COMPASS (72).
    Compass(Compass),
    /// WIND (73).
    Wind(Wind),
    /// CALIBINFO (75), internal use: 32 raw bytes.
    CalibInfo(&'a [u8]),
    /// DEBUGINFO (76), internal use: 208 raw bytes.
    DebugInfo(&'a [u8]),
    /// LOG (81), internal use: raw bytes of any length.
    Log(&'a [u8]),
    /// TOAST (82): a message for the user.
    Toast(Text),
    /// COMMAND (11): a service command such as `"a reboot"`.
    Command(Text),
    /// SETTIME (12).
    SetTime(SetTime),
    /// An ID the spec does not define, kept raw.
    Unknown {
        /// The message ID.
        id: u8,
        /// The data.
        data: &'a [u8],
    },
}

fn raw_fixed(id: u8, len: usize, data: &[u8]) -> Result<&[u8], Error> {
    if data.len() == len {
        Ok(data)
    } else {
        Err(Error::WrongLength {
            id,
            expected: len as u16,
            actual: data.len().min(u16::MAX as usize) as u16,
        })
    }
}

impl<'a> Message<'a> {
    /// Parses the data of a message with ID `id`.
    ///
    /// ```
    /// use aeolus_proto::message::{Message, SetTime};
    /// let mut data = [0u8; 32];
    /// data[..6].copy_from_slice(&[126, 10, 21, 9, 30, 0]);
    /// let msg = Message::parse(12, &data).unwrap();
    /// assert_eq!(msg, Message::SetTime(SetTime {
    ///     year_since_1900: 126, month0: 10, day: 21, hour: 9, minute: 30, second: 0,
    /// }));
    /// ```
    ///
    /// # Errors
    /// [`Error::WrongLength`] for a known fixed-size ID with the wrong data length, and
    /// [`Error::TextTooLong`].
    pub fn parse(id: u8, data: &'a [u8]) -> Result<Self, Error> {
        match id {
            Pressure::ID | Gyro::ID | Accel::ID | Magnet::ID => Self::parse_motion(id, data),
            Gps::ID => Gps::parse(data).map(Self::Gps),
            Attitude::ID => Attitude::parse(data).map(Self::Attitude),
            Compass::ID => Compass::parse(data).map(Self::Compass),
            AeolusInfo::ID => AeolusInfo::parse(data).map(Self::AeolusInfo),
            Temp::ID => Temp::parse(data).map(Self::Temp),
            Wind::ID => Wind::parse(data).map(Self::Wind),
            SetTime::ID => SetTime::parse(data).map(Self::SetTime),
            id::CALIBINFO => raw_fixed(id, CALIBINFO_LEN, data).map(Self::CalibInfo),
            id::DEBUGINFO => raw_fixed(id, DEBUGINFO_LEN, data).map(Self::DebugInfo),
            id::LOG => Ok(Self::Log(data)),
            id::TOAST => Text::parse(id, data).map(Self::Toast),
            id::COMMAND => Text::parse(id, data).map(Self::Command),
            _ => Ok(Self::Unknown { id, data }),
        }
    }

    /// PRESSURE, GYRO, ACCEL and MAGNET, half the telemetry: one layout (valid, timestamp,
    /// three `f32`), parsed out of line. Inlined, their arms would share `parse`'s one exit,
    /// which stores every field of the largest variant whatever the message (about 65
    /// instructions on Cortex-M3); here the four variants store the same five fields.
    #[inline(never)]
    fn parse_motion(id: u8, data: &'a [u8]) -> Result<Self, Error> {
        match id {
            Pressure::ID => Pressure::parse(data).map(Self::Pressure),
            Gyro::ID => Gyro::parse(data).map(Self::Gyro),
            Accel::ID => Accel::parse(data).map(Self::Accel),
            _ => Magnet::parse(data).map(Self::Magnet),
        }
    }

    /// The message ID.
    ///
    /// ```
    /// use aeolus_proto::message::Message;
    /// assert_eq!(Message::parse(82, b"hi\0").unwrap().id(), 82);
    /// assert_eq!(Message::Unknown { id: 200, data: &[] }.id(), 200);
    /// ```
    pub const fn id(&self) -> u8 {
        match self {
            Self::AeolusInfo(_) => id::AEOLUSINFO,
            Self::Pressure(_) => id::PRESSURE,
            Self::Gyro(_) => id::GYRO,
            Self::Accel(_) => id::ACCEL,
            Self::Magnet(_) => id::MAGNET,
            Self::Temp(_) => id::TEMP,
            Self::Gps(_) => id::GPS,
            Self::Attitude(_) => id::ATTITUDE,
            Self::Compass(_) => id::COMPASS,
            Self::Wind(_) => id::WIND,
            Self::CalibInfo(_) => id::CALIBINFO,
            Self::DebugInfo(_) => id::DEBUGINFO,
            Self::Log(_) => id::LOG,
            Self::Toast(_) => id::TOAST,
            Self::Command(_) => id::COMMAND,
            Self::SetTime(_) => id::SETTIME,
            Self::Unknown { id, .. } => *id,
        }
    }

    /// The spec's name of the message (`"UNKNOWN"` for an undefined ID).
    ///
    /// ```
    /// use aeolus_proto::message::{Message, SetTime};
    /// assert_eq!(Message::SetTime(SetTime::default()).name(), "SETTIME");
    /// assert_eq!(Message::Unknown { id: 200, data: &[] }.name(), "UNKNOWN");
    /// ```
    pub const fn name(&self) -> &'static str {
        match self {
            Self::AeolusInfo(_) => "AEOLUSINFO",
            Self::Pressure(_) => "PRESSURE",
            Self::Gyro(_) => "GYRO",
            Self::Accel(_) => "ACCEL",
            Self::Magnet(_) => "MAGNET",
            Self::Temp(_) => "TEMP",
            Self::Gps(_) => "GPS",
            Self::Attitude(_) => "ATTITUDE",
            Self::Compass(_) => "COMPASS",
            Self::Wind(_) => "WIND",
            Self::CalibInfo(_) => "CALIBINFO",
            Self::DebugInfo(_) => "DEBUGINFO",
            Self::Log(_) => "LOG",
            Self::Toast(_) => "TOAST",
            Self::Command(_) => "COMMAND",
            Self::SetTime(_) => "SETTIME",
            Self::Unknown { .. } => "UNKNOWN",
        }
    }

    /// The data length [`Message::emit`] writes.
    ///
    /// ```
    /// use aeolus_proto::message::{Gyro, Message, Text};
    /// assert_eq!(Message::Toast(Text::new("hi").unwrap()).buffer_len(), 3); // with its NUL
    /// assert_eq!(Message::Gyro(Gyro::default()).buffer_len(), Gyro::LEN);
    /// ```
    pub fn buffer_len(&self) -> usize {
        match self {
            Self::Toast(t) | Self::Command(t) => t.buffer_len(),
            Self::CalibInfo(d)
            | Self::DebugInfo(d)
            | Self::Log(d)
            | Self::Unknown { data: d, .. } => d.len(),
            Self::AeolusInfo(_) => AeolusInfo::LEN,
            Self::Pressure(_) => Pressure::LEN,
            Self::Gyro(_) => Gyro::LEN,
            Self::Accel(_) => Accel::LEN,
            Self::Magnet(_) => Magnet::LEN,
            Self::Temp(_) => Temp::LEN,
            Self::Gps(_) => Gps::LEN,
            Self::Attitude(_) => Attitude::LEN,
            Self::Compass(_) => Compass::LEN,
            Self::Wind(_) => Wind::LEN,
            Self::SetTime(_) => SetTime::LEN,
        }
    }

    /// Writes the message data (without ID, CRC or escaping) into `out`; returns its length.
    ///
    /// ```
    /// use aeolus_proto::{EncodeError, message::{Message, Text}};
    /// let toast = Message::Toast(Text::new("hi").unwrap());
    /// let mut out = [0u8; 8];
    /// assert_eq!(toast.emit(&mut out), Ok(3));
    /// assert_eq!(&out[..3], b"hi\0");
    /// assert_eq!(toast.emit(&mut out[..2]), Err(EncodeError::BufferTooSmall { needed: 3 }));
    /// ```
    ///
    /// # Errors
    /// [`EncodeError::BufferTooSmall`].
    pub fn emit(&self, out: &mut [u8]) -> Result<usize, EncodeError> {
        match self {
            Self::AeolusInfo(m) => m.emit(out),
            Self::Pressure(m) => m.emit(out),
            Self::Gyro(m) => m.emit(out),
            Self::Accel(m) => m.emit(out),
            Self::Magnet(m) => m.emit(out),
            Self::Temp(m) => m.emit(out),
            Self::Gps(m) => m.emit(out),
            Self::Attitude(m) => m.emit(out),
            Self::Compass(m) => m.emit(out),
            Self::Wind(m) => m.emit(out),
            Self::SetTime(m) => m.emit(out),
            Self::Toast(t) | Self::Command(t) => t.emit(out),
            Self::CalibInfo(d)
            | Self::DebugInfo(d)
            | Self::Log(d)
            | Self::Unknown { data: d, .. } => {
                let needed = d.len();
                let dst = out
                    .get_mut(..needed)
                    .ok_or(EncodeError::BufferTooSmall { needed })?;
                dst.copy_from_slice(d);
                Ok(d.len())
            }
        }
    }

    /// Encodes the whole frame (flags, ID, data, CRC, escaped) into `out`; returns its length.
    /// [`crate::max_encoded_len`] of [`Message::buffer_len`] is always enough.
    ///
    /// ```
    /// use aeolus_proto::{CrcMode, max_encoded_len, message::{Message, Text}};
    /// let toast = Message::Toast(Text::new("hi").unwrap());
    /// let mut wire = [0u8; max_encoded_len(3)];
    /// let n = toast.encode(&mut wire, CrcMode::Omit).unwrap();
    /// assert_eq!(&wire[..n], &[0x7E, 0x52, b'h', b'i', 0x00, 0x00, 0x00, 0x7E]);
    /// ```
    ///
    /// # Errors
    /// [`EncodeError::BufferTooSmall`].
    pub fn encode(&self, out: &mut [u8], crc: CrcMode) -> Result<usize, EncodeError> {
        let id = self.id();
        match self {
            Self::Toast(t) | Self::Command(t) => encode_frame(id, t.as_bytes(), &[0], crc, out),
            Self::CalibInfo(d)
            | Self::DebugInfo(d)
            | Self::Log(d)
            | Self::Unknown { data: d, .. } => encode_frame(id, d, &[], crc, out),
            Self::AeolusInfo(m) => encode_frame(id, &m.data(), &[], crc, out),
            Self::Pressure(m) => encode_frame(id, &m.data(), &[], crc, out),
            Self::Gyro(m) => encode_frame(id, &m.data(), &[], crc, out),
            Self::Accel(m) => encode_frame(id, &m.data(), &[], crc, out),
            Self::Magnet(m) => encode_frame(id, &m.data(), &[], crc, out),
            Self::Temp(m) => encode_frame(id, &m.data(), &[], crc, out),
            Self::Gps(m) => encode_frame(id, &m.data(), &[], crc, out),
            Self::Attitude(m) => encode_frame(id, &m.data(), &[], crc, out),
            Self::Compass(m) => encode_frame(id, &m.data(), &[], crc, out),
            Self::Wind(m) => encode_frame(id, &m.data(), &[], crc, out),
            Self::SetTime(m) => encode_frame(id, &m.data(), &[], crc, out),
        }
    }
}

impl Message<'_> {
    /// The timestamp (ms since the box booted) of a timestamped telemetry message: GYRO,
    /// ACCEL, MAGNET, PRESSURE, TEMP, GPS, ATTITUDE, COMPASS and WIND; `None` for the others.
    ///
    /// ```
    /// use aeolus_proto::message::{Message, Wind, Text};
    /// let wind = Message::Wind(Wind { timestamp_ms: 1500.0, ..Wind::default() });
    /// assert_eq!(wind.timestamp_ms(), Some(1500.0));
    /// assert_eq!(Message::Toast(Text::new("hi").unwrap()).timestamp_ms(), None);
    /// ```
    pub fn timestamp_ms(&self) -> Option<f64> {
        Some(match self {
            Self::Gyro(m) => m.timestamp_ms,
            Self::Accel(m) => m.timestamp_ms,
            Self::Magnet(m) => m.timestamp_ms,
            Self::Pressure(m) => m.timestamp_ms,
            Self::Temp(m) => m.timestamp_ms,
            Self::Gps(m) => m.timestamp_ms,
            Self::Attitude(m) => m.timestamp_ms,
            Self::Compass(m) => m.timestamp_ms,
            Self::Wind(m) => m.timestamp_ms,
            _ => return None,
        })
    }
}
