//! The fixed-size messages, each declared as the table of section 7 declares it.

use super::{CalibrationStatus, field::Field};
use crate::{EncodeError, Error};

/// Declares a fixed-size message: a plain struct plus `ID`, `LEN`, `parse`, `emit` and
/// `buffer_len`. Offsets are data offsets (after the ID); bytes not listed are reserved,
/// sent as zero and ignored on receipt (DECISIONS.md A4).
macro_rules! fixed_message {
    (
        $(#[$meta:meta])*
        $name:ident = $id:literal, $len:literal bytes {
            $( $(#[$fmeta:meta])* $field:ident : $ty:ty = $off:literal, )*
        }
    ) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Copy, PartialEq, Default)]
        #[cfg_attr(feature = "defmt", derive(defmt::Format))]
        #[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
        pub struct $name {
            $( $(#[$fmeta])* pub $field: $ty, )*
        }

        impl $name {
            /// The message ID.
            pub const ID: u8 = $id;
            /// The data length in bytes (after the ID, before the CRC).
            pub const LEN: usize = $len;
            /// The layout as declared: `(field, type, data offset)` per field, for tools that
            /// describe the wire format (the Wireshark dissector `protolink wireshark` writes).
            pub const FIELDS: &'static [(&'static str, &'static str, usize)] =
                &[ $( (stringify!($field), stringify!($ty), $off), )* ];
            // Every field must fit inside the data: checked at compile time.
            #[allow(clippy::int_plus_one)]
            const _FITS: () = { $( assert!($off + <$ty as Field>::SIZE <= $len); )* };

            /// Parses the data bytes (between the ID and the CRC).
            ///
            /// ```
            #[doc = concat!("use aeolus_proto::{Error, message::", stringify!($name), "};")]
            #[doc = concat!("let data = [0u8; ", stringify!($len), "];")]
            #[doc = concat!("assert!(", stringify!($name), "::parse(&data).is_ok());")]
            #[doc = concat!("let empty = ", stringify!($name), "::parse(&[]);")]
            #[doc = concat!(
                "assert_eq!(empty, Err(Error::WrongLength { id: ", stringify!($id),
                ", expected: ", stringify!($len), ", actual: 0 }));"
            )]
            /// ```
            ///
            /// # Errors
            /// [`Error::WrongLength`] unless `data` is exactly [`Self::LEN`] bytes.
            pub fn parse(data: &[u8]) -> Result<Self, Error> {
                if data.len() != Self::LEN {
                    return Err(Error::WrongLength {
                        id: Self::ID,
                        expected: Self::LEN as u16,
                        actual: data.len().min(u16::MAX as usize) as u16,
                    });
                }
                let () = Self::_FITS;
                Ok(Self { $( $field: <$ty as Field>::read(data, $off), )* })
            }

            /// Writes the data bytes into `out`, reserved bytes zeroed; returns [`Self::LEN`].
            ///
            /// ```
            #[doc = concat!("use aeolus_proto::{EncodeError, message::", stringify!($name), "};")]
            #[doc = concat!("let msg = ", stringify!($name), "::default();")]
            #[doc = concat!("let mut out = [0xAA; ", stringify!($len), "];")]
            #[doc = concat!("assert_eq!(msg.emit(&mut out), Ok(", stringify!($len), "));")]
            #[doc = concat!("assert_eq!(", stringify!($name), "::parse(&out), Ok(msg));")]
            #[doc = concat!(
                "assert_eq!(msg.emit(&mut out[1..]), Err(EncodeError::BufferTooSmall { needed: ",
                stringify!($len), " }));"
            )]
            /// ```
            ///
            /// # Errors
            /// [`EncodeError::BufferTooSmall`] if `out` is shorter than [`Self::LEN`].
            pub fn emit(&self, out: &mut [u8]) -> Result<usize, EncodeError> {
                let Some(out) = out.get_mut(..Self::LEN) else {
                    return Err(EncodeError::BufferTooSmall { needed: Self::LEN });
                };
                out.copy_from_slice(&self.data());
                Ok(Self::LEN)
            }

            /// The data bytes, reserved bytes zeroed: what [`Self::emit`] writes. An array of
            /// exactly the layout's length, so the compiler zeroes only the reserved bytes
            /// (the fields' stores cover the rest) and needs no buffer of the longest layout.
            #[inline]
            pub(crate) fn data(&self) -> [u8; $len] {
                let mut out = [0u8; $len];
                $( <$ty as Field>::write(&self.$field, &mut out, $off); )*
                out
            }

            /// The data length [`Self::emit`] writes.
            ///
            /// ```
            #[doc = concat!("use aeolus_proto::message::", stringify!($name), ";")]
            #[doc = concat!("assert_eq!(", stringify!($name), "::default().buffer_len(), ", stringify!($len), ");")]
            /// ```
            pub const fn buffer_len(&self) -> usize {
                Self::LEN
            }
        }
    };
}

fixed_message! {
    /// AEOLUSINFO (51): model, firmware version and MAC address (section 7.1).
    ///
    /// ```
    /// use aeolus_proto::message::AeolusInfo;
    /// let info = AeolusInfo { model: b'S', firmware: [3, 8, 0], mac: [2, 0, 0, 0xAB, 0xCD, 0xEF] };
    /// let mut data = [0u8; AeolusInfo::LEN];
    /// info.emit(&mut data).unwrap();
    /// assert_eq!(&data[..4], &[0x53, 3, 8, 0]);
    /// assert_eq!(&data[8..14], &[2, 0, 0, 0xAB, 0xCD, 0xEF]);
    /// ```
    AeolusInfo = 51, 32 bytes {
        /// Model: 83 (`'S'`) AEOLUS-SENSE, 65 (`'A'`) AEOLUS (DECISIONS.md A10).
        model: u8 = 0,
        /// Firmware version, large/middle/small (`[3, 8, 0]` is v3.8.0).
        firmware: [u8; 3] = 1,
        /// MAC address of the WiFi adapter, byte 0 first.
        mac: [u8; 6] = 8,
    }
}

fixed_message! {
    /// PRESSURE (61): static and pitot pressure and airspeed (section 7.2).
    ///
    /// ```
    /// use aeolus_proto::message::Pressure;
    /// let mut data = [0u8; Pressure::LEN];
    /// data[0] = 1;
    /// data[24..28].copy_from_slice(&[0x00, 0x00, 0xC8, 0x41]); // 25.0 m/s
    /// let p = Pressure::parse(&data).unwrap();
    /// assert!(p.valid);
    /// assert_eq!(p.airspeed_mps, 25.0);
    /// ```
    Pressure = 61, 32 bytes {
        /// Data valid.
        valid: bool = 0,
        /// Milliseconds since boot.
        timestamp_ms: f64 = 8,
        /// Static pressure, mbar.
        static_mbar: f32 = 16,
        /// Pitot pressure, mbar.
        pitot_mbar: f32 = 20,
        /// Airspeed, m/s.
        airspeed_mps: f32 = 24,
    }
}

fixed_message! {
    /// GYRO (62): angular rates about the body axes, rad/s (section 7.3).
    ///
    /// Encoding one into a buffer (the data first, then the frame around it):
    ///
    /// ```
    /// use aeolus_proto::{encode_frame, max_encoded_len, CrcMode, message::Gyro};
    ///
    /// let gyro = Gyro { valid: true, timestamp_ms: 7.0, x: 0.01, y: 0.0, z: -0.02 };
    /// let mut data = [0u8; Gyro::LEN];
    /// gyro.emit(&mut data).unwrap();
    /// let mut frame = [0u8; max_encoded_len(Gyro::LEN)];
    /// let n = encode_frame(Gyro::ID, &data, &[], CrcMode::Compute, &mut frame).unwrap();
    /// assert_eq!((frame[0], frame[1], frame[n - 1]), (0x7E, 62, 0x7E));
    /// ```
    Gyro = 62, 32 bytes {
        /// Data valid.
        valid: bool = 0,
        /// Milliseconds since boot.
        timestamp_ms: f64 = 8,
        /// Rate about X (forward), rad/s.
        x: f32 = 16,
        /// Rate about Y (right), rad/s.
        y: f32 = 20,
        /// Rate about Z (down), rad/s.
        z: f32 = 24,
    }
}

fixed_message! {
    /// ACCEL (63): specific force along the body axes, m/s² (section 7.4). Its data is 40
    /// bytes long (table 6); the last 12 are reserved.
    ///
    /// ```
    /// use aeolus_proto::message::Accel;
    /// let accel = Accel { valid: true, z: -9.5, ..Accel::default() };
    /// let mut data = [0xAA; Accel::LEN];
    /// accel.emit(&mut data).unwrap();
    /// assert_eq!(&data[24..28], &[0x00, 0x00, 0x18, 0xC1]); // -9.5
    /// assert_eq!(&data[28..], &[0; 12]);
    /// ```
    Accel = 63, 40 bytes {
        /// Data valid.
        valid: bool = 0,
        /// Milliseconds since boot.
        timestamp_ms: f64 = 8,
        /// X (forward), m/s².
        x: f32 = 16,
        /// Y (right), m/s².
        y: f32 = 20,
        /// Z (down), m/s². Gravity alone reads -g.
        z: f32 = 24,
    }
}

fixed_message! {
    /// MAGNET (64): magnetic field along the body axes, Gauss (section 7.5).
    ///
    /// ```
    /// use aeolus_proto::message::Magnet;
    /// let mut data = [0u8; Magnet::LEN];
    /// data[16..20].copy_from_slice(&[0x00, 0x00, 0x00, 0x3F]); // 0.5
    /// assert_eq!(Magnet::parse(&data).unwrap().x, 0.5);
    /// ```
    Magnet = 64, 32 bytes {
        /// Data valid.
        valid: bool = 0,
        /// Milliseconds since boot.
        timestamp_ms: f64 = 8,
        /// X (forward), Gauss.
        x: f32 = 16,
        /// Y (right), Gauss.
        y: f32 = 20,
        /// Z (down), Gauss.
        z: f32 = 24,
    }
}

fixed_message! {
    /// TEMP (65): outside air temperature (section 7.6).
    ///
    /// ```
    /// use aeolus_proto::message::Temp;
    /// let temp = Temp { valid: true, timestamp_ms: 1500.0, celsius: 21.5 };
    /// let mut data = [0u8; Temp::LEN];
    /// temp.emit(&mut data).unwrap();
    /// assert_eq!(&data[8..20], &[0, 0, 0, 0, 0, 0x70, 0x97, 0x40, 0, 0, 0xAC, 0x41]);
    /// ```
    Temp = 65, 32 bytes {
        /// Data valid.
        valid: bool = 0,
        /// Milliseconds since boot.
        timestamp_ms: f64 = 8,
        /// Temperature, °C.
        celsius: f32 = 16,
    }
}

fixed_message! {
    /// GPS (66): position fix (section 7.7).
    ///
    /// ```
    /// use aeolus_proto::message::Gps;
    /// let fix = Gps { valid: true, has_fix: true, satellites: 9, latitude_deg: 47.5, ..Gps::default() };
    /// let mut data = [0u8; Gps::LEN];
    /// fix.emit(&mut data).unwrap();
    /// assert_eq!(&data[..3], &[1, 1, 9]);
    /// assert_eq!(&data[16..20], &[0x00, 0x00, 0x3E, 0x42]); // 47.5
    /// ```
    Gps = 66, 32 bytes {
        /// Data valid.
        valid: bool = 0,
        /// The receiver has a fix.
        has_fix: bool = 1,
        /// Satellites in use.
        satellites: u8 = 2,
        /// Milliseconds since boot.
        timestamp_ms: f64 = 8,
        /// Latitude, degrees.
        latitude_deg: f32 = 16,
        /// Longitude, degrees.
        longitude_deg: f32 = 20,
        /// Altitude, m.
        altitude_m: f32 = 24,
        /// Ground speed, m/s.
        ground_speed_mps: f32 = 28,
    }
}

fixed_message! {
    /// ATTITUDE (71): Euler angles, slip ball, turn coordinator and quaternion (section 7.8).
    ///
    /// ```
    /// use aeolus_proto::message::Attitude;
    /// let mut data = [0u8; Attitude::LEN];
    /// data[48..52].copy_from_slice(&[0x00, 0x00, 0x80, 0x3F]); // qw = 1.0
    /// let att = Attitude::parse(&data).unwrap();
    /// assert_eq!((att.qx, att.qy, att.qz, att.qw), (0.0, 0.0, 0.0, 1.0));
    /// ```
    Attitude = 71, 52 bytes {
        /// Data valid.
        valid: bool = 0,
        /// Milliseconds since boot.
        timestamp_ms: f64 = 8,
        /// Roll, rad.
        roll_rad: f32 = 16,
        /// Pitch, rad.
        pitch_rad: f32 = 20,
        /// Yaw, rad.
        yaw_rad: f32 = 24,
        /// Slip ball indication.
        slip_ball: f32 = 28,
        /// Turn coordinator indication.
        turn_coordinator: f32 = 32,
        /// Quaternion x.
        qx: f32 = 36,
        /// Quaternion y.
        qy: f32 = 40,
        /// Quaternion z.
        qz: f32 = 44,
        /// Quaternion w.
        qw: f32 = 48,
    }
}

fixed_message! {
    /// COMPASS (72): heading, and the calibration state and parameters (section 7.9).
    ///
    /// ```
    /// use aeolus_proto::message::Compass;
    /// let compass = Compass { valid: true, has_value: true, heading_deg: 90.0, ..Compass::default() };
    /// let mut data = [0u8; Compass::LEN];
    /// compass.emit(&mut data).unwrap();
    /// assert_eq!(&data[16..20], &[0x00, 0x00, 0xB4, 0x42]); // 90.0
    /// ```
    Compass = 72, 80 bytes {
        /// Data valid.
        valid: bool = 0,
        /// Calibration status (DECISIONS.md A7: a signed byte; unknown values kept).
        calibration: CalibrationStatus = 1,
        /// The heading field holds a value.
        has_value: bool = 2,
        /// Calibration progress, percent (0..=100).
        calibration_percent: u8 = 3,
        /// Calibration remaining time (unit unstated by the spec; raw).
        calibration_remaining: u8 = 4,
        /// Milliseconds since boot.
        timestamp_ms: f64 = 8,
        /// Compass heading, degrees.
        heading_deg: f32 = 16,
        /// Soft-iron calibration parameters (bytes 32..44).
        soft_iron: [f32; 3] = 32,
        /// Hard-iron calibration parameters (bytes 44..80).
        hard_iron: [f32; 9] = 44,
    }
}

fixed_message! {
    /// WIND (73): wind vector (section 7.10).
    ///
    /// ```
    /// use aeolus_proto::message::Wind;
    /// let wind = Wind { valid: true, speed_mps: 5.0, direction_deg: 270.0, ..Wind::default() };
    /// let mut data = [0u8; Wind::LEN];
    /// wind.emit(&mut data).unwrap();
    /// assert_eq!(&data[16..24], &[0x00, 0x00, 0xA0, 0x40, 0x00, 0x00, 0x87, 0x43]);
    /// ```
    Wind = 73, 32 bytes {
        /// Data valid.
        valid: bool = 0,
        /// Milliseconds since boot.
        timestamp_ms: f64 = 8,
        /// Wind magnitude, m/s.
        speed_mps: f32 = 16,
        /// Wind direction, degrees.
        direction_deg: f32 = 20,
    }
}

fixed_message! {
    /// SETTIME (12): wall-clock time from the app (section 7.16, DECISIONS.md A8).
    ///
    /// ```
    /// use aeolus_proto::message::SetTime;
    /// // 2026-05-21 09:30:00
    /// let t = SetTime { year_since_1900: 126, month0: 4, day: 21, hour: 9, minute: 30, second: 0 };
    /// let mut data = [0xAA; SetTime::LEN];
    /// t.emit(&mut data).unwrap();
    /// assert_eq!(&data[..6], &[126, 4, 21, 9, 30, 0]);
    /// assert_eq!(&data[6..], &[0; 26]);
    /// ```
    SetTime = 12, 32 bytes {
        /// Year minus 1900.
        year_since_1900: u8 = 0,
        /// Month, January = 0.
        month0: u8 = 1,
        /// Day of the month, 1..=31.
        day: u8 = 2,
        /// Hour, 0..=23.
        hour: u8 = 3,
        /// Minute, 0..=59.
        minute: u8 = 4,
        /// Second, 0..=59.
        second: u8 = 5,
    }
}

/// Data length of CALIBINFO (75), kept raw.
pub const CALIBINFO_LEN: usize = 32;
/// Data length of DEBUGINFO (76), kept raw.
pub const DEBUGINFO_LEN: usize = 208;
