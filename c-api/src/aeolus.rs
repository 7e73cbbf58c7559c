//! AEOLUS from C: `pl_aeolus_*`. The decoder is `aeolus_proto::Decoder<PL_AEOLUS_CAPACITY>`.

use aeolus_proto::message::{self as m, CalibrationStatus, Message, Text};
use aeolus_proto::{CrcMode, Decoder, EncodeError, Error, Frame};

use crate::face::{self, Proto, Stream};
use crate::pl_error;
use crate::state::{self, PL_STATE_AEOLUS};
use crate::*;

/// Unescaped bytes (ID + data + CRC) one AEOLUS decoder holds: every fixed-size message,
/// every TOAST and COMMAND text, LOG messages up to 253 data bytes.
pub const PL_AEOLUS_CAPACITY: usize = 256;
/// The longest TOAST or COMMAND text (without its NUL).
pub const PL_AEOLUS_TEXT_CAPACITY: usize = 120;
/// Bytes on the wire of the longest fixed-size message (DEBUGINFO, 208 data bytes), every byte
/// escaped: a buffer this long holds any frame but LOG or unknown ones with more data.
pub const PL_AEOLUS_MAX_FRAME_LEN: usize = 424;

/// The Rust decoder a `pl_aeolus_decoder` holds.
pub(crate) type Inner = Decoder<PL_AEOLUS_CAPACITY>;

state::c_states! {
    PL_AEOLUS_DECODER_WORDS = 44, PL_AEOLUS_DECODER_SIZE = 352, PL_AEOLUS_DECODER_ALIGN = 8,
    of "a `pl_aeolus_decoder`";
    /// An AEOLUS decoder, owned by the caller. Set it up with `pl_aeolus_init` before any other
    /// call; copy it only as a whole.
    pl_aeolus_decoder: Stream<Inner>, PL_STATE_AEOLUS;
}
const _: () = assert!(PL_AEOLUS_TEXT_CAPACITY == aeolus_proto::TEXT_CAPACITY);
const _: () = assert!(
    PL_AEOLUS_MAX_FRAME_LEN == aeolus_proto::max_encoded_len(aeolus_proto::message::DEBUGINFO_LEN)
);

/// PRESSURE, GYRO, ACCEL and MAGNET (61..=64): one layout.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct pl_aeolus_motion {
    /// Data valid (0 or 1).
    pub valid: u8,
    /// Milliseconds since boot.
    pub timestamp_ms: f64,
    /// PRESSURE: static pressure (mbar); GYRO: rate about X (rad/s); ACCEL: X (m/s²);
    /// MAGNET: X (Gauss).
    pub x: f32,
    /// PRESSURE: pitot (dynamic) pressure (mbar); the others: Y.
    pub y: f32,
    /// PRESSURE: the box's airspeed field (m/s), as sent; the spec leaves open whether it is
    /// indicated or true, so derive IAS and TAS from the pressures (docs/protocol-notes.md
    /// PL39); the others: Z.
    pub z: f32,
}

/// AEOLUSINFO (51).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct pl_aeolus_info {
    /// Model: 83 ('S') AEOLUS-SENSE, 65 ('A') AEOLUS.
    pub model: u8,
    /// Firmware version, large/middle/small.
    pub firmware: [u8; 3],
    /// MAC address, byte 0 first.
    pub mac: [u8; 6],
}

/// TEMP (65).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct pl_aeolus_temp {
    /// Data valid (0 or 1).
    pub valid: u8,
    /// Milliseconds since boot.
    pub timestamp_ms: f64,
    /// Temperature, °C.
    pub celsius: f32,
}

/// GPS (66).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct pl_aeolus_gps {
    /// Data valid (0 or 1).
    pub valid: u8,
    /// The receiver has a fix (0 or 1).
    pub has_fix: u8,
    /// Satellites in use.
    pub satellites: u8,
    /// Milliseconds since boot.
    pub timestamp_ms: f64,
    /// Latitude, degrees.
    pub latitude_deg: f32,
    /// Longitude, degrees.
    pub longitude_deg: f32,
    /// Altitude, m.
    pub altitude_m: f32,
    /// Ground speed, m/s.
    pub ground_speed_mps: f32,
}

/// ATTITUDE (71).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct pl_aeolus_attitude {
    /// Data valid (0 or 1).
    pub valid: u8,
    /// Milliseconds since boot.
    pub timestamp_ms: f64,
    /// Roll, rad.
    pub roll_rad: f32,
    /// Pitch, rad.
    pub pitch_rad: f32,
    /// Yaw, rad.
    pub yaw_rad: f32,
    /// Slip ball indication.
    pub slip_ball: f32,
    /// Turn coordinator indication.
    pub turn_coordinator: f32,
    /// Quaternion x.
    pub qx: f32,
    /// Quaternion y.
    pub qy: f32,
    /// Quaternion z.
    pub qz: f32,
    /// Quaternion w.
    pub qw: f32,
}

/// COMPASS (72).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct pl_aeolus_compass {
    /// Data valid (0 or 1).
    pub valid: u8,
    /// Calibration status byte: 1, 2, 3, 4, -1, -2, -3, -4 (other values kept as received).
    pub calibration: i8,
    /// The heading field holds a value (0 or 1).
    pub has_value: u8,
    /// Calibration progress, percent.
    pub calibration_percent: u8,
    /// Calibration remaining time (raw).
    pub calibration_remaining: u8,
    /// Milliseconds since boot.
    pub timestamp_ms: f64,
    /// Heading, degrees.
    pub heading_deg: f32,
    /// Soft-iron calibration parameters.
    pub soft_iron: [f32; 3],
    /// Hard-iron calibration parameters.
    pub hard_iron: [f32; 9],
}

/// WIND (73).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct pl_aeolus_wind {
    /// Data valid (0 or 1).
    pub valid: u8,
    /// Milliseconds since boot.
    pub timestamp_ms: f64,
    /// Wind magnitude, m/s.
    pub speed_mps: f32,
    /// Wind direction, degrees.
    pub direction_deg: f32,
}

/// SETTIME (12).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct pl_aeolus_settime {
    /// Year minus 1900.
    pub year_since_1900: u8,
    /// Month, January = 0.
    pub month0: u8,
    /// Day of the month.
    pub day: u8,
    /// Hour.
    pub hour: u8,
    /// Minute.
    pub minute: u8,
    /// Second.
    pub second: u8,
}

/// The typed content of a message; the member is chosen by `pl_aeolus_message.id`.
#[repr(C)]
#[derive(Clone, Copy)]
pub union pl_aeolus_body {
    /// AEOLUSINFO (51).
    pub info: pl_aeolus_info,
    /// PRESSURE, GYRO, ACCEL, MAGNET (61..=64).
    pub motion: pl_aeolus_motion,
    /// TEMP (65).
    pub temp: pl_aeolus_temp,
    /// GPS (66).
    pub gps: pl_aeolus_gps,
    /// ATTITUDE (71).
    pub attitude: pl_aeolus_attitude,
    /// COMPASS (72).
    pub compass: pl_aeolus_compass,
    /// WIND (73).
    pub wind: pl_aeolus_wind,
    /// SETTIME (12).
    pub settime: pl_aeolus_settime,
}

/// One AEOLUS message: the ID selects the member of `body`.
///
/// IDs 51, 61..=66, 71..=73 and 12 are typed (`body`). TOAST (82) and COMMAND (11) carry
/// their text (without the NUL) in `data`/`data_len`; CALIBINFO (75), DEBUGINFO (76), LOG
/// (81) and unknown IDs carry their raw data there. Decoded, `data` points into the decoder
/// and stays valid until the next call on it; to encode, point it at your bytes.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct pl_aeolus_message {
    /// The message ID (`PL_AEOLUS_ID_*` or any other byte).
    pub id: u8,
    /// Decoded: 1 if the frame carried `00 00` instead of a CRC. Encode: 1 sends `00 00`
    /// (the spec's "no CRC"), 0 computes the CRC (the default).
    pub no_crc: u8,
    /// Bytes on the wire of the frame, both flags included (a flag between two frames counts
    /// in both); 0 in a message struct `PL_ERROR` cleared.
    pub wire_len: u32,
    /// Decoded: where the frame starts (its opening flag), in bytes fed to this decoder since
    /// `pl_aeolus_init*`. Encode: ignored.
    pub offset: u64,
    /// Raw data, or the text (see above); may be NULL when `data_len` is 0.
    pub data: *const u8,
    /// Bytes at `data`.
    pub data_len: usize,
    /// The typed fields.
    pub body: pl_aeolus_body,
}

/// AEOLUSINFO.
pub const PL_AEOLUS_ID_AEOLUSINFO: u8 = 51;
/// PRESSURE (`body.motion`: x static, y pitot in mbar, z airspeed in m/s).
pub const PL_AEOLUS_ID_PRESSURE: u8 = 61;
/// GYRO (`body.motion`, rad/s).
pub const PL_AEOLUS_ID_GYRO: u8 = 62;
/// ACCEL (`body.motion`, m/s²).
pub const PL_AEOLUS_ID_ACCEL: u8 = 63;
/// MAGNET (`body.motion`, Gauss).
pub const PL_AEOLUS_ID_MAGNET: u8 = 64;
/// TEMP.
pub const PL_AEOLUS_ID_TEMP: u8 = 65;
/// GPS.
pub const PL_AEOLUS_ID_GPS: u8 = 66;
/// ATTITUDE.
pub const PL_AEOLUS_ID_ATTITUDE: u8 = 71;
/// COMPASS.
pub const PL_AEOLUS_ID_COMPASS: u8 = 72;
/// WIND.
pub const PL_AEOLUS_ID_WIND: u8 = 73;
/// CALIBINFO (raw, 32 bytes).
pub const PL_AEOLUS_ID_CALIBINFO: u8 = 75;
/// DEBUGINFO (raw, 208 bytes).
pub const PL_AEOLUS_ID_DEBUGINFO: u8 = 76;
/// LOG (raw, any length).
pub const PL_AEOLUS_ID_LOG: u8 = 81;
/// TOAST (text).
pub const PL_AEOLUS_ID_TOAST: u8 = 82;
/// COMMAND (text).
pub const PL_AEOLUS_ID_COMMAND: u8 = 11;
/// SETTIME.
pub const PL_AEOLUS_ID_SETTIME: u8 = 12;

/// The counters of an AEOLUS decoder (wrapping `uint32_t`, the Rust `Stats`).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct pl_aeolus_stats {
    /// Frames delivered with a good CRC.
    pub frames_ok: u32,
    /// Frames delivered without a CRC (`00 00`).
    pub frames_no_crc: u32,
    /// Frames whose CRC did not match.
    pub checksum_errors: u32,
    /// Strict mode: frames rejected for carrying no CRC.
    pub missing_crc: u32,
    /// Frames longer than the capacity.
    pub overflows: u32,
    /// Frames too short to hold an ID and a CRC.
    pub too_short: u32,
    /// Invalid escapes and escaped flags.
    pub bad_escapes: u32,
    /// Bytes thrown away.
    pub bytes_discarded: u32,
    /// Bytes of delivered frames.
    pub frame_bytes: u32,
    /// Flag bytes seen.
    pub flags: u32,
    /// Bytes of a frame in progress, held (not yet in any other counter).
    pub held_bytes: u32,
}

fn motion(valid: bool, timestamp_ms: f64, x: f32, y: f32, z: f32) -> pl_aeolus_motion {
    pl_aeolus_motion {
        valid: valid.into(),
        timestamp_ms,
        x,
        y,
        z,
    }
}

/// Writes the Rust message into the caller's C struct, field by field in place (no whole
/// struct built and copied: a message costs a few hundred instructions less on Cortex-M3).
/// Raw data points into `msg`'s bytes; writing a union member is safe, reading one is not.
fn fill(out: &mut pl_aeolus_message, msg: &Message<'_>, no_crc: bool) {
    out.id = msg.id();
    out.no_crc = no_crc.into();
    let mut data: &[u8] = &[];
    let b = &mut out.body;
    match msg {
        Message::AeolusInfo(v) => {
            b.info = pl_aeolus_info {
                model: v.model,
                firmware: v.firmware,
                mac: v.mac,
            }
        }
        Message::Pressure(v) => {
            b.motion = motion(
                v.valid,
                v.timestamp_ms,
                v.static_mbar,
                v.pitot_mbar,
                v.airspeed_mps,
            )
        }
        Message::Gyro(v) => b.motion = motion(v.valid, v.timestamp_ms, v.x, v.y, v.z),
        Message::Accel(v) => b.motion = motion(v.valid, v.timestamp_ms, v.x, v.y, v.z),
        Message::Magnet(v) => b.motion = motion(v.valid, v.timestamp_ms, v.x, v.y, v.z),
        Message::Temp(v) => {
            b.temp = pl_aeolus_temp {
                valid: v.valid.into(),
                timestamp_ms: v.timestamp_ms,
                celsius: v.celsius,
            }
        }
        Message::Gps(v) => {
            b.gps = pl_aeolus_gps {
                valid: v.valid.into(),
                has_fix: v.has_fix.into(),
                satellites: v.satellites,
                timestamp_ms: v.timestamp_ms,
                latitude_deg: v.latitude_deg,
                longitude_deg: v.longitude_deg,
                altitude_m: v.altitude_m,
                ground_speed_mps: v.ground_speed_mps,
            }
        }
        Message::Attitude(v) => {
            b.attitude = pl_aeolus_attitude {
                valid: v.valid.into(),
                timestamp_ms: v.timestamp_ms,
                roll_rad: v.roll_rad,
                pitch_rad: v.pitch_rad,
                yaw_rad: v.yaw_rad,
                slip_ball: v.slip_ball,
                turn_coordinator: v.turn_coordinator,
                qx: v.qx,
                qy: v.qy,
                qz: v.qz,
                qw: v.qw,
            }
        }
        Message::Compass(v) => {
            b.compass = pl_aeolus_compass {
                valid: v.valid.into(),
                calibration: v.calibration.to_i8(),
                has_value: v.has_value.into(),
                calibration_percent: v.calibration_percent,
                calibration_remaining: v.calibration_remaining,
                timestamp_ms: v.timestamp_ms,
                heading_deg: v.heading_deg,
                soft_iron: v.soft_iron,
                hard_iron: v.hard_iron,
            }
        }
        Message::Wind(v) => {
            b.wind = pl_aeolus_wind {
                valid: v.valid.into(),
                timestamp_ms: v.timestamp_ms,
                speed_mps: v.speed_mps,
                direction_deg: v.direction_deg,
            }
        }
        Message::SetTime(v) => {
            b.settime = pl_aeolus_settime {
                year_since_1900: v.year_since_1900,
                month0: v.month0,
                day: v.day,
                hour: v.hour,
                minute: v.minute,
                second: v.second,
            }
        }
        // The caller points `data` at the text inside the frame.
        Message::Toast(_) | Message::Command(_) => {}
        Message::CalibInfo(d)
        | Message::DebugInfo(d)
        | Message::Log(d)
        | Message::Unknown { data: d, .. } => data = d,
    }
    out.data = data.as_ptr();
    out.data_len = data.len();
}

impl Proto for pl_aeolus_decoder {
    type Dec = Inner;
    type Msg = pl_aeolus_message;
    type Stats = pl_aeolus_stats;
    // SAFETY: integers, floats and a raw pointer: all zeros is a valid value (NULL for `data`).
    const EMPTY: pl_aeolus_message = unsafe { core::mem::zeroed() };

    fn fill(frame: Frame<'_>, msg: &mut pl_aeolus_message, err: &mut pl_error) -> i32 {
        match frame.message() {
            Ok(m) => {
                fill(msg, &m, !frame.has_crc());
                if let Message::Toast(t) | Message::Command(t) = &m {
                    // The text is the start of the frame's data (up to the NUL): point there.
                    let text = frame.data().get(..t.as_bytes().len()).unwrap_or(&[]);
                    msg.data = text.as_ptr();
                    msg.data_len = text.len();
                }
                PL_MESSAGE
            }
            Err(e) => {
                // The raw frame stays available (DECISIONS.md A4).
                *msg = Self::EMPTY;
                let raw = Message::Unknown {
                    id: frame.id(),
                    data: frame.data(),
                };
                fill(msg, &raw, !frame.has_crc());
                *err = Self::error(e);
                PL_ERROR
            }
        }
    }

    fn error(e: Error) -> pl_error {
        match e {
            Error::Overflow => pl_error::kind(PL_ERR_OVERFLOW),
            Error::ChecksumMismatch {
                id,
                computed,
                received,
            } => pl_error::checksum(id, computed, received),
            Error::MissingCrc { id } => pl_error::new(PL_ERR_MISSING_CRC, id.into(), 0, 0),
            Error::TooShort => pl_error::kind(PL_ERR_TOO_SHORT),
            Error::InvalidEscape => pl_error::kind(PL_ERR_INVALID_ESCAPE),
            Error::EscapedFlag => pl_error::kind(PL_ERR_ESCAPED_FLAG),
            Error::Truncated => pl_error::kind(PL_ERR_TRUNCATED),
            Error::WrongLength {
                id,
                expected,
                actual,
            } => pl_error::wrong_length(id, expected, actual),
            Error::TextTooLong { id, len } => {
                pl_error::new(PL_ERR_TEXT_TOO_LONG, id.into(), 0, len.into())
            }
        }
    }

    fn stats(d: &Inner) -> pl_aeolus_stats {
        face::stats! { d => pl_aeolus_stats {
            frames_ok, frames_no_crc, checksum_errors, missing_crc, overflows, too_short,
            bad_escapes, bytes_discarded, frame_bytes, flags,
        } }
    }
}

fn text(data: &[u8]) -> Result<Text, i32> {
    Text::from_bytes(data).map_err(|_| PL_E_INVALID)
}

/// `pl_aeolus_encode`: `msg`, with its raw data `data`, as one whole frame into `out`.
pub(crate) fn encode(msg: &pl_aeolus_message, data: &[u8], out: &mut [u8]) -> Result<usize, i32> {
    let mode = if msg.no_crc != 0 {
        CrcMode::Omit
    } else {
        CrcMode::Compute
    };
    from_c(msg, data)?.encode(out, mode).map_err(|e| match e {
        EncodeError::BufferTooSmall { .. } => PL_E_BUFFER_TOO_SMALL,
        EncodeError::TextTooLong { .. } => PL_E_INVALID,
    })
}

/// `pl_aeolus_max_encoded_len`: `usize::MAX` where the length would not fit.
pub(crate) fn max_encoded_len(data_len: usize) -> usize {
    if data_len > (usize::MAX - 8) / 2 {
        return usize::MAX;
    }
    aeolus_proto::max_encoded_len(data_len)
}

/// The C struct as a Rust message; `data` is the struct's raw data. The body is read as the
/// member `msg.id` selects: every member is plain numbers, so any bytes are a valid value and
/// a wrong member gives wrong numbers, never undefined behaviour.
fn from_c<'a>(msg: &pl_aeolus_message, data: &'a [u8]) -> Result<Message<'a>, i32> {
    // SAFETY (every union read below): the union's members are all made of integers and
    // floats, for which every bit pattern is valid, and `body` is as large as its largest
    // member, so any read is defined.
    let b = &msg.body;
    Ok(match msg.id {
        // SAFETY: see above.
        PL_AEOLUS_ID_AEOLUSINFO => info_message(unsafe { b.info }),
        id @ (PL_AEOLUS_ID_PRESSURE
        | PL_AEOLUS_ID_GYRO
        | PL_AEOLUS_ID_ACCEL
        | PL_AEOLUS_ID_MAGNET) => {
            // SAFETY: see above.
            motion_message(id, unsafe { b.motion })
        }
        // SAFETY: see above.
        PL_AEOLUS_ID_TEMP => temp_message(unsafe { b.temp }),
        // SAFETY: see above.
        PL_AEOLUS_ID_GPS => gps_message(unsafe { b.gps }),
        // SAFETY: see above.
        PL_AEOLUS_ID_ATTITUDE => attitude_message(unsafe { b.attitude }),
        // SAFETY: see above.
        PL_AEOLUS_ID_COMPASS => compass_message(unsafe { b.compass }),
        // SAFETY: see above.
        PL_AEOLUS_ID_WIND => wind_message(unsafe { b.wind }),
        // SAFETY: see above.
        PL_AEOLUS_ID_SETTIME => settime_message(unsafe { b.settime }),
        PL_AEOLUS_ID_TOAST => Message::Toast(text(data)?),
        PL_AEOLUS_ID_COMMAND => Message::Command(text(data)?),
        PL_AEOLUS_ID_CALIBINFO => Message::CalibInfo(data),
        PL_AEOLUS_ID_DEBUGINFO => Message::DebugInfo(data),
        PL_AEOLUS_ID_LOG => Message::Log(data),
        id => Message::Unknown { id, data },
    })
}

fn info_message(v: pl_aeolus_info) -> Message<'static> {
    Message::AeolusInfo(m::AeolusInfo {
        model: v.model,
        firmware: v.firmware,
        mac: v.mac,
    })
}

/// The four messages of three floats (`id` is one of their IDs).
fn motion_message(id: u8, v: pl_aeolus_motion) -> Message<'static> {
    let (valid, timestamp_ms, x, y, z) = (v.valid != 0, v.timestamp_ms, v.x, v.y, v.z);
    match id {
        PL_AEOLUS_ID_PRESSURE => Message::Pressure(m::Pressure {
            valid,
            timestamp_ms,
            static_mbar: x,
            pitot_mbar: y,
            airspeed_mps: z,
        }),
        PL_AEOLUS_ID_GYRO => Message::Gyro(m::Gyro {
            valid,
            timestamp_ms,
            x,
            y,
            z,
        }),
        PL_AEOLUS_ID_ACCEL => Message::Accel(m::Accel {
            valid,
            timestamp_ms,
            x,
            y,
            z,
        }),
        _ => Message::Magnet(m::Magnet {
            valid,
            timestamp_ms,
            x,
            y,
            z,
        }),
    }
}

fn temp_message(v: pl_aeolus_temp) -> Message<'static> {
    Message::Temp(m::Temp {
        valid: v.valid != 0,
        timestamp_ms: v.timestamp_ms,
        celsius: v.celsius,
    })
}

fn gps_message(v: pl_aeolus_gps) -> Message<'static> {
    Message::Gps(m::Gps {
        valid: v.valid != 0,
        has_fix: v.has_fix != 0,
        satellites: v.satellites,
        timestamp_ms: v.timestamp_ms,
        latitude_deg: v.latitude_deg,
        longitude_deg: v.longitude_deg,
        altitude_m: v.altitude_m,
        ground_speed_mps: v.ground_speed_mps,
    })
}

fn attitude_message(v: pl_aeolus_attitude) -> Message<'static> {
    Message::Attitude(m::Attitude {
        valid: v.valid != 0,
        timestamp_ms: v.timestamp_ms,
        roll_rad: v.roll_rad,
        pitch_rad: v.pitch_rad,
        yaw_rad: v.yaw_rad,
        slip_ball: v.slip_ball,
        turn_coordinator: v.turn_coordinator,
        qx: v.qx,
        qy: v.qy,
        qz: v.qz,
        qw: v.qw,
    })
}

fn compass_message(v: pl_aeolus_compass) -> Message<'static> {
    Message::Compass(m::Compass {
        valid: v.valid != 0,
        calibration: CalibrationStatus::from_i8(v.calibration),
        has_value: v.has_value != 0,
        calibration_percent: v.calibration_percent,
        calibration_remaining: v.calibration_remaining,
        timestamp_ms: v.timestamp_ms,
        heading_deg: v.heading_deg,
        soft_iron: v.soft_iron,
        hard_iron: v.hard_iron,
    })
}

fn wind_message(v: pl_aeolus_wind) -> Message<'static> {
    Message::Wind(m::Wind {
        valid: v.valid != 0,
        timestamp_ms: v.timestamp_ms,
        speed_mps: v.speed_mps,
        direction_deg: v.direction_deg,
    })
}

fn settime_message(v: pl_aeolus_settime) -> Message<'static> {
    Message::SetTime(m::SetTime {
        year_since_1900: v.year_since_1900,
        month0: v.month0,
        day: v.day,
        hour: v.hour,
        minute: v.minute,
        second: v.second,
    })
}
