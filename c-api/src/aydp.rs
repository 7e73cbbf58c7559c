//! AYDP from C: `pl_aydp_*`, both profiles. The decoder is
//! `aydp_proto::Decoder<PL_AYDP_CAPACITY>`.

use aydp_proto::{
    Decoder, DirectOutput, EncodeError, Encoder, Error, FixDetail, FixQuality, Frame, Message,
    Position, Profile, Raw, SystemControl, SystemValueUpdate, Timestamp, UpdateMode, VesselData,
    WindDirection, WindSpeed,
};

use crate::face::{self, Proto, Stream};
use crate::ffi::{self, fields, pl_error, sat32};
use crate::state::{self, PL_STATE_AYDP};
use crate::*;

/// Bytes of the longest message one AYDP decoder holds (header, data and checksum).
pub const PL_AYDP_CAPACITY: usize = 512;
/// Bytes of the longest message the decoder accepts: a buffer this long holds any frame
/// `pl_aydp_encode` writes for it.
pub const PL_AYDP_MAX_FRAME_LEN: usize = PL_AYDP_CAPACITY;

/// Profile `Spec` (the 2016 document, DECISIONS.md Y1): the length counts the whole message,
/// sub-seconds in milliseconds.
pub const PL_AYDP_SPEC: u32 = 0;
/// Profile `Reference` (the released AYDP software, Y2): the length counts data bytes,
/// sub-seconds in microseconds.
pub const PL_AYDP_REFERENCE: u32 = 1;

/// The Rust decoder a `pl_aydp_decoder` holds.
pub(crate) type Inner = Decoder<PL_AYDP_CAPACITY>;

state::c_states! {
    PL_AYDP_DECODER_WORDS = 74, PL_AYDP_DECODER_SIZE = 592, PL_AYDP_DECODER_ALIGN = 8,
    of "a `pl_aydp_decoder`";
    /// An AYDP decoder, owned by the caller. Set it up with `pl_aydp_init` first.
    pl_aydp_decoder: Stream<Inner>, PL_STATE_AYDP;
}

/// `kind`: time sync (Spec, type 0, normal).
pub const PL_AYDP_TIME_SYNC: u8 = 0;
/// `kind`: heartbeat (Spec, type 0, expedited).
pub const PL_AYDP_HEARTBEAT: u8 = 1;
/// `kind`: no-op (Reference, type 0).
pub const PL_AYDP_NO_OP: u8 = 2;
/// `kind`: position (3), `body.position`.
pub const PL_AYDP_POSITION: u8 = 3;
/// `kind`: fix quality (4), `body.fix_quality`.
pub const PL_AYDP_FIX_QUALITY: u8 = 4;
/// `kind`: fix detail (5): `body.count` satellites, read each with `pl_aydp_satellite`;
/// `data` holds the whole data (count byte first).
pub const PL_AYDP_FIX_DETAIL: u8 = 5;
/// `kind`: direct output (7): `body.count` entries, read each with `pl_aydp_output_entry`;
/// `data` holds the whole data (u16 count first).
pub const PL_AYDP_DIRECT_OUTPUT: u8 = 6;
/// `kind`: system value update (8), `body.update`.
pub const PL_AYDP_SYSTEM_VALUE_UPDATE: u8 = 7;
/// `kind`: system control (9), `body.control`.
pub const PL_AYDP_SYSTEM_CONTROL: u8 = 8;
/// `kind`: wind speed (Reference, 1), `body.value` (mph).
pub const PL_AYDP_WIND_SPEED: u8 = 9;
/// `kind`: wind direction (Reference, 2), `body.value` (degrees).
pub const PL_AYDP_WIND_DIRECTION: u8 = 10;
/// `kind`: vessel data (Reference, 17), `body.vessel`.
pub const PL_AYDP_VESSEL_DATA: u8 = 11;
/// `kind`: a type the document leaves "TBD" (Spec 1, 2, 6): raw `data`.
pub const PL_AYDP_TBD: u8 = 12;
/// `kind`: user-defined (100..=126): raw `data`.
pub const PL_AYDP_USER_DEFINED: u8 = 13;
/// `kind`: any other type: raw `data`.
pub const PL_AYDP_UNKNOWN: u8 = 14;

/// Position (3).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct pl_aydp_position {
    /// Latitude, degrees.
    pub latitude: f64,
    /// Longitude, degrees.
    pub longitude: f64,
    /// Altitude, m.
    pub altitude: f32,
}

/// Fix quality (4).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct pl_aydp_fix_quality {
    /// Fix type.
    pub fix_type: u8,
    /// Mean dilution of precision.
    pub mean_dop: f32,
    /// Horizontal DOP.
    pub hdop: f32,
    /// Vertical DOP.
    pub vdop: f32,
    /// Satellites.
    pub satellites: u8,
}

/// One satellite of a fix detail message.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct pl_aydp_satellite {
    /// Satellite ID.
    pub id: u8,
    /// Azimuth.
    pub azimuth: f32,
    /// Elevation.
    pub elevation: f32,
    /// Signal to noise ratio.
    pub snr: f32,
}

/// One entry of a direct output message.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct pl_aydp_output_entry {
    /// Device.
    pub device: u8,
    /// Channel.
    pub channel: u8,
    /// Value.
    pub value: f32,
}

/// System value update (8).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct pl_aydp_update {
    /// Address.
    pub address: u16,
    /// Update type: 1 single value, 2 whole array, 3 one element.
    pub mode: u8,
    /// 0 (single), the element count (array) or the element index (element).
    pub field: u32,
    /// The value bytes (little-endian), NULL when `value_len` is 0.
    pub value: *const u8,
    /// Bytes at `value`.
    pub value_len: usize,
}

/// System control (9).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct pl_aydp_control {
    /// 1 request data (at `address`), 2 store configuration.
    pub command: u8,
    /// The address of a data request.
    pub address: u16,
}

/// Vessel data (Reference, 17).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct pl_aydp_vessel {
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

/// The typed content of an AYDP message; the member is chosen by `pl_aydp_message.kind`.
#[repr(C)]
#[derive(Clone, Copy)]
pub union pl_aydp_body {
    /// `PL_AYDP_POSITION`.
    pub position: pl_aydp_position,
    /// `PL_AYDP_FIX_QUALITY`.
    pub fix_quality: pl_aydp_fix_quality,
    /// `PL_AYDP_FIX_DETAIL` (satellites) and `PL_AYDP_DIRECT_OUTPUT` (entries); decoded only.
    pub count: u32,
    /// `PL_AYDP_SYSTEM_VALUE_UPDATE`.
    pub update: pl_aydp_update,
    /// `PL_AYDP_SYSTEM_CONTROL`.
    pub control: pl_aydp_control,
    /// `PL_AYDP_WIND_SPEED` (mph), `PL_AYDP_WIND_DIRECTION` (degrees).
    pub value: f32,
    /// `PL_AYDP_VESSEL_DATA`.
    pub vessel: pl_aydp_vessel,
}

/// One AYDP message.
///
/// Decoded, `data` points at the message's data inside the decoder (valid until the next
/// call on it). To encode, `kind` selects the member of `body`; the raw kinds (TBD,
/// user-defined, unknown), fix detail and direct output take their data from `data` (fix
/// detail and direct output: the whole data, count first, validated).
#[repr(C)]
#[derive(Clone, Copy)]
pub struct pl_aydp_message {
    /// `PL_AYDP_*` kind: which member of `body` holds the fields.
    pub kind: u8,
    /// The base type (0..=126). Encode: used by the raw kinds only.
    pub msg_type: u8,
    /// 1 for an expedited message (6-byte header, no time), 0 for a normal one.
    pub expedited: u8,
    /// Bytes of the message on the wire (header, data, checksum); 0 in a message struct
    /// `PL_ERROR` cleared.
    pub wire_len: u32,
    /// Decoded: where the message starts, in bytes fed to this decoder since `pl_aydp_init`.
    /// Encode: ignored.
    pub offset: u64,
    /// Normal messages: seconds of the header's time.
    pub seconds: i64,
    /// Normal messages: sub-seconds (milliseconds in Spec, microseconds in Reference).
    pub subsec: i64,
    /// The data bytes, NULL when `data_len` is 0.
    pub data: *const u8,
    /// Bytes at `data`.
    pub data_len: usize,
    /// The typed fields.
    pub body: pl_aydp_body,
}

/// The counters of an AYDP decoder.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct pl_aydp_stats {
    /// Messages delivered with a good checksum.
    pub frames_ok: u32,
    /// Checksum failures.
    pub checksum_errors: u32,
    /// Length fields out of bounds.
    pub length_errors: u32,
    /// Bytes thrown away.
    pub bytes_discarded: u32,
    /// Bytes held, undecided (a message in progress, or bytes a rescan has still to read).
    pub held_bytes: u32,
}

/// The profile `p` names (`PL_AYDP_SPEC`, `PL_AYDP_REFERENCE`).
pub(crate) fn profile(p: u32) -> Option<Profile> {
    match p {
        PL_AYDP_SPEC => Some(Profile::Spec),
        PL_AYDP_REFERENCE => Some(Profile::Reference),
        _ => None,
    }
}

/// `pl_aydp_init`: a fresh decoder for the profile `p` names.
pub(crate) fn decoder(p: u32) -> Option<Inner> {
    profile(p).map(Inner::new)
}

const NO_BODY: pl_aydp_body = pl_aydp_body { count: 0 };

fn body_of(m: &Message<'_>) -> (u8, pl_aydp_body) {
    match m {
        Message::TimeSync => (PL_AYDP_TIME_SYNC, NO_BODY),
        Message::Heartbeat => (PL_AYDP_HEARTBEAT, NO_BODY),
        Message::NoOp => (PL_AYDP_NO_OP, NO_BODY),
        Message::Position(p) => {
            let position = fields! { p => pl_aydp_position { latitude, longitude, altitude } };
            (PL_AYDP_POSITION, pl_aydp_body { position })
        }
        Message::FixQuality(q) => {
            let fix_quality = fields! { q => pl_aydp_fix_quality {
                fix_type, mean_dop, hdop, vdop, satellites,
            } };
            (PL_AYDP_FIX_QUALITY, pl_aydp_body { fix_quality })
        }
        Message::FixDetail(d) => (
            PL_AYDP_FIX_DETAIL,
            pl_aydp_body {
                count: sat32(d.len()),
            },
        ),
        Message::DirectOutput(d) => (
            PL_AYDP_DIRECT_OUTPUT,
            pl_aydp_body {
                count: sat32(d.len()),
            },
        ),
        Message::SystemValueUpdate(u) => (
            PL_AYDP_SYSTEM_VALUE_UPDATE,
            pl_aydp_body {
                update: pl_aydp_update {
                    address: u.address,
                    mode: u.mode.code(),
                    field: u.mode.field(),
                    value: u.data.as_ptr(),
                    value_len: u.data.len(),
                },
            },
        ),
        Message::SystemControl(c) => (
            PL_AYDP_SYSTEM_CONTROL,
            pl_aydp_body {
                control: match *c {
                    SystemControl::RequestData { address } => pl_aydp_control {
                        command: 1,
                        address,
                    },
                    SystemControl::StoreConfiguration => pl_aydp_control {
                        command: 2,
                        address: 0,
                    },
                },
            },
        ),
        Message::WindSpeed(w) => (PL_AYDP_WIND_SPEED, pl_aydp_body { value: w.0 }),
        Message::WindDirection(w) => (PL_AYDP_WIND_DIRECTION, pl_aydp_body { value: w.0 }),
        Message::VesselData(v) => {
            let vessel = fields! { v => pl_aydp_vessel {
                roll, pitch, heading, roll_rate, pitch_rate, heading_rate, latitude, longitude,
                track, speed_over_ground, fix_type, satellites, mean_dop, hdop, vdop,
            } };
            (PL_AYDP_VESSEL_DATA, pl_aydp_body { vessel })
        }
        Message::Tbd(_) => (PL_AYDP_TBD, NO_BODY),
        Message::UserDefined(_) => (PL_AYDP_USER_DEFINED, NO_BODY),
        Message::Unknown(_) => (PL_AYDP_UNKNOWN, NO_BODY),
    }
}

impl Proto for pl_aydp_decoder {
    type Dec = Inner;
    type Msg = pl_aydp_message;
    type Stats = pl_aydp_stats;
    const EMPTY: pl_aydp_message = {
        // SAFETY: integers and a raw pointer: all zeros is a valid value (NULL for `data`).
        let mut m: pl_aydp_message = unsafe { core::mem::zeroed() };
        m.kind = PL_AYDP_UNKNOWN;
        m
    };
    fn fill(frame: Frame<'_>, msg: &mut pl_aydp_message, err: &mut pl_error) -> i32 {
        let t = frame.timestamp().unwrap_or_default();
        let data = frame.data();
        let mut c = pl_aydp_message {
            kind: PL_AYDP_UNKNOWN,
            msg_type: frame.base_type(),
            expedited: frame.is_expedited().into(),
            wire_len: 0,
            offset: 0,
            seconds: t.seconds,
            subsec: t.subsec,
            data: data.as_ptr(),
            data_len: data.len(),
            body: NO_BODY,
        };
        let status = match frame.message() {
            Ok(m) => {
                (c.kind, c.body) = body_of(&m);
                PL_MESSAGE
            }
            Err(e) => {
                // The frame's checksum was good; its typed parse failed. `*msg` keeps the raw
                // data (kind unknown).
                *err = Self::error(e);
                PL_ERROR
            }
        };
        *msg = c;
        status
    }

    fn error(e: Error) -> pl_error {
        match e {
            Error::Truncated => pl_error::kind(PL_ERR_TRUNCATED),
            Error::ChecksumMismatch {
                id,
                computed,
                received,
            } => pl_error::checksum(id, computed, received),
            Error::ReservedType => pl_error::new(PL_ERR_BAD_TYPE, 0, 0, 0xFF),
            Error::BadType(t) => pl_error::new(PL_ERR_BAD_TYPE, 0, 0, t.into()),
            Error::BadLength(l) => pl_error::new(PL_ERR_BAD_LENGTH, 0, 0, l),
            Error::PayloadTooShort {
                msg_type,
                expected,
                actual,
            }
            | Error::PayloadTooLong {
                msg_type,
                expected,
                actual,
            } => pl_error::wrong_length(msg_type, sat32(expected), sat32(actual)),
            Error::CountMismatch { msg_type, count } => {
                pl_error::new(PL_ERR_COUNT_MISMATCH, msg_type.into(), 0, sat32(count))
            }
            Error::NegativeUflt16 => pl_error::kind(PL_ERR_NEGATIVE_UFLT16),
            Error::UnknownUpdateMode(b) | Error::UnknownCommand(b) => {
                pl_error::new(PL_ERR_UNKNOWN_COMMAND, 0, 0, b.into())
            }
            Error::NonZeroSingleIndex(i) => pl_error::new(PL_ERR_NON_ZERO_SINGLE_INDEX, 0, 0, i),
            _ => pl_error::kind(PL_ERR_OTHER),
        }
    }

    fn stats(d: &Inner) -> pl_aydp_stats {
        face::stats! { d => pl_aydp_stats {
            frames_ok, checksum_errors, length_errors, bytes_discarded,
        } }
    }
}

/// `pl_aydp_satellite_at` and `pl_aydp_output_entry_at`: the item `nth` finds in the data of
/// `*msg`, a decoded message of `kind`, into `*out`. Returns 0, `PL_E_NULL`, or `PL_E_BAD_TAG`
/// (another kind, or no such item).
///
/// # Safety
/// `msg` is NULL or a message whose `data` is readable for `data_len` bytes; `out` is NULL or
/// writable.
pub(crate) unsafe fn nth<T>(
    msg: *const pl_aydp_message,
    kind: u8,
    out: *mut T,
    nth: impl FnOnce(&[u8]) -> Option<T>,
) -> i32 {
    // SAFETY: the caller's promises.
    let (Some(msg), Some(out)) = (unsafe { msg.as_ref() }, unsafe { out.as_mut() }) else {
        return PL_E_NULL;
    };
    // SAFETY: the caller's promise for `data[..data_len]`.
    let Some(data) = (unsafe { ffi::bytes(msg.data, msg.data_len) }) else {
        return PL_E_NULL;
    };
    if msg.kind != kind {
        return PL_E_BAD_TAG;
    }
    match nth(data) {
        Some(item) => {
            *out = item;
            0
        }
        None => PL_E_BAD_TAG,
    }
}

/// The `index`-th satellite of a fix detail message's data.
pub(crate) fn satellite(data: &[u8], index: u32) -> Option<pl_aydp_satellite> {
    let s = FixDetail::parse(data)
        .ok()?
        .satellites()
        .nth(index as usize)?;
    Some(fields! { s => pl_aydp_satellite { id, azimuth, elevation, snr } })
}

/// The `index`-th entry of a direct output message's data.
pub(crate) fn entry(data: &[u8], index: u32) -> Option<pl_aydp_output_entry> {
    let e = DirectOutput::parse(data)
        .ok()?
        .entries()
        .nth(index as usize)?;
    Some(fields! { e => pl_aydp_output_entry { device, channel, value } })
}

/// `pl_aydp_encode` in profile `p`: `msg`, with its raw data `data`, as one whole message
/// (header, data, checksum) into `out`: expedited if `msg.expedited`, else normal with its
/// time.
///
/// # Safety
/// For a system value update, `body.update.value` is readable for `body.update.value_len`
/// bytes.
pub(crate) unsafe fn encode(
    p: Profile,
    msg: &pl_aydp_message,
    data: &[u8],
    out: &mut [u8],
) -> Result<usize, i32> {
    // SAFETY: the caller's promise, passed on.
    let m = unsafe { from_c(msg, data) }?;
    let time = (msg.expedited == 0).then_some(Timestamp::new(msg.seconds, msg.subsec));
    Encoder::new(p).encode(&m, time, out).map_err(|e| match e {
        EncodeError::BufferTooSmall { .. } => PL_E_BUFFER_TOO_SMALL,
        EncodeError::BadType(_) => PL_E_OUT_OF_RANGE,
        EncodeError::TooLong | EncodeError::ExpeditedInReference => PL_E_INVALID,
    })
}

/// The C struct as a Rust message.
///
/// # Safety
/// `msg.body` is read as the member `msg.kind` selects: every member but `update` is plain
/// numbers (any bytes are valid); `update.value` must be readable for `update.value_len`
/// bytes when `kind` is a system value update.
unsafe fn from_c<'a>(msg: &'a pl_aydp_message, data: &'a [u8]) -> Result<Message<'a>, i32> {
    let raw = Raw {
        msg_type: msg.msg_type,
        data,
    };
    let b = &msg.body;
    Ok(match msg.kind {
        PL_AYDP_TIME_SYNC => Message::TimeSync,
        PL_AYDP_HEARTBEAT => Message::Heartbeat,
        PL_AYDP_NO_OP => Message::NoOp,
        // SAFETY: plain numbers, any bytes valid.
        PL_AYDP_POSITION => Message::Position(fields! { unsafe { b.position } => Position {
            latitude, longitude, altitude,
        } }),
        PL_AYDP_FIX_QUALITY => {
            // SAFETY: plain numbers, any bytes valid.
            Message::FixQuality(fields! { unsafe { b.fix_quality } => FixQuality {
                fix_type, mean_dop, hdop, vdop, satellites,
            } })
        }
        PL_AYDP_FIX_DETAIL => Message::FixDetail(FixDetail::parse(data).map_err(|_| PL_E_INVALID)?),
        PL_AYDP_DIRECT_OUTPUT => {
            Message::DirectOutput(DirectOutput::parse(data).map_err(|_| PL_E_INVALID)?)
        }
        PL_AYDP_SYSTEM_VALUE_UPDATE => {
            // SAFETY: integers and a pointer, any bytes valid as values.
            let u = unsafe { b.update };
            // SAFETY: the caller's promise for `value[..value_len]`.
            let value = unsafe { ffi::bytes(u.value, u.value_len) }.ok_or(PL_E_NULL)?;
            let mode = match u.mode {
                1 => UpdateMode::Single,
                2 => UpdateMode::Array { count: u.field },
                3 => UpdateMode::Element { index: u.field },
                _ => return Err(PL_E_INVALID),
            };
            Message::SystemValueUpdate(SystemValueUpdate {
                address: u.address,
                mode,
                data: value,
            })
        }
        PL_AYDP_SYSTEM_CONTROL => {
            // SAFETY: plain numbers, any bytes valid.
            let c = unsafe { b.control };
            Message::SystemControl(match c.command {
                1 => SystemControl::RequestData { address: c.address },
                2 => SystemControl::StoreConfiguration,
                _ => return Err(PL_E_INVALID),
            })
        }
        // SAFETY: plain numbers, any bytes valid.
        PL_AYDP_WIND_SPEED => Message::WindSpeed(WindSpeed(unsafe { b.value })),
        // SAFETY: plain numbers, any bytes valid.
        PL_AYDP_WIND_DIRECTION => Message::WindDirection(WindDirection(unsafe { b.value })),
        PL_AYDP_VESSEL_DATA => {
            // SAFETY: plain numbers, any bytes valid.
            let v = unsafe { b.vessel };
            Message::VesselData(fields! { v => VesselData {
                roll, pitch, heading, roll_rate, pitch_rate, heading_rate, latitude, longitude,
                track, speed_over_ground, fix_type, satellites, mean_dop, hdop, vdop,
            } })
        }
        PL_AYDP_TBD => Message::Tbd(raw),
        PL_AYDP_USER_DEFINED => Message::UserDefined(raw),
        PL_AYDP_UNKNOWN => Message::Unknown(raw),
        _ => return Err(PL_E_BAD_TAG),
    })
}
