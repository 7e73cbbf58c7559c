//! GDL90 from C: `pl_gdl90_*`. The decoder is `gdl90_proto::Decoder<PL_GDL90_CAPACITY>`.

use gdl90_proto::message::{
    AddressType, Ahrs, AltitudeDatum, CallSign, Emergency, ForeFlightId, GeoAltitude, Heading,
    Heartbeat, LatLon, Message, Name, Report, Track,
};
use gdl90_proto::{Decoder, EncodeError, Error};

use crate::face::{self, Proto, Stream};
use crate::pl_error;
use crate::state::{self, PL_STATE_GDL90};
use crate::*;

/// Unescaped bytes one GDL90 decoder holds: the longest standard message (an uplink).
pub const PL_GDL90_CAPACITY: usize = 438;
/// Bytes on the wire of the longest typed message (ForeFlight ID), every byte escaped.
pub const PL_GDL90_MAX_FRAME_LEN: usize = 84;

/// The Rust decoder a `pl_gdl90_decoder` holds.
pub(crate) type Inner = Decoder<PL_GDL90_CAPACITY>;

state::c_states! {
    PL_GDL90_DECODER_WORDS = 68, PL_GDL90_DECODER_SIZE = 544, PL_GDL90_DECODER_ALIGN = 8,
    of "a `pl_gdl90_decoder`";
    /// A GDL90 decoder, owned by the caller. Set it up with `pl_gdl90_init` first.
    pl_gdl90_decoder: Stream<Inner>, PL_STATE_GDL90;
}
const _: () = assert!(PL_GDL90_CAPACITY == gdl90_proto::MAX_FRAME);
const _: () = assert!(PL_GDL90_MAX_FRAME_LEN == gdl90_proto::MAX_ENCODED_LEN);

/// `kind`: heartbeat (ID 0), `body.heartbeat`.
pub const PL_GDL90_HEARTBEAT: u8 = 0;
/// `kind`: ownship report (ID 10), `body.report`.
pub const PL_GDL90_OWNSHIP: u8 = 1;
/// `kind`: ownship geometric altitude (ID 11), `body.geo_altitude`.
pub const PL_GDL90_GEO_ALTITUDE: u8 = 2;
/// `kind`: traffic report (ID 20), `body.report`.
pub const PL_GDL90_TRAFFIC: u8 = 3;
/// `kind`: ForeFlight ID (0x65, sub-ID 0), `body.foreflight_id`.
pub const PL_GDL90_FOREFLIGHT_ID: u8 = 4;
/// `kind`: ForeFlight AHRS (0x65, sub-ID 1), `body.ahrs`.
pub const PL_GDL90_AHRS: u8 = 5;
/// `kind`: any other ID, raw `data` (a Stratux AHRS report, ID 0x4C, comes as this kind with
/// no data: the C face does not type it yet).
pub const PL_GDL90_UNKNOWN: u8 = 6;

/// Heartbeat (0).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct pl_gdl90_heartbeat {
    /// GPS position valid (0/1).
    pub gps_position_valid: u8,
    /// Maintenance required (0/1).
    pub maintenance_required: u8,
    /// IDENT talkback (0/1).
    pub ident: u8,
    /// Address talkback (0/1).
    pub address_talkback: u8,
    /// GPS battery low (0/1).
    pub gps_battery_low: u8,
    /// ATC services talkback (0/1).
    pub atc_services: u8,
    /// UAT initialized (0/1).
    pub uat_initialized: u8,
    /// CSA requested (0/1).
    pub csa_requested: u8,
    /// CSA not available (0/1).
    pub csa_not_available: u8,
    /// UTC timing valid (0/1).
    pub utc_ok: u8,
    /// Seconds since UTC midnight (17 bits).
    pub seconds_since_midnight: u32,
    /// Uplink messages received in the last second (5 bits).
    pub uplink_messages: u8,
    /// Basic and long messages received (10 bits).
    pub basic_long_messages: u16,
}

/// Ownship and traffic reports (10, 20). `has_*` say whether the optional field holds a
/// value (0/1).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct pl_gdl90_report {
    /// Traffic alert (0/1).
    pub traffic_alert: u8,
    /// Address type nibble.
    pub address_type: u8,
    /// Participant address (24 bits).
    pub address: u32,
    /// The position is valid (0/1).
    pub has_position: u8,
    /// Latitude, degrees.
    pub lat_deg: f64,
    /// Longitude, degrees.
    pub lon_deg: f64,
    /// The pressure altitude is valid (0/1).
    pub has_pressure_altitude: u8,
    /// Pressure altitude, feet.
    pub pressure_altitude_ft: i32,
    /// Airborne (0/1).
    pub airborne: u8,
    /// Report extrapolated (0/1).
    pub extrapolated: u8,
    /// Track kind: 0 none, 1 true track, 2 magnetic heading, 3 true heading.
    pub track_kind: u8,
    /// Track or heading, degrees.
    pub track_deg: f32,
    /// Navigation integrity category.
    pub nic: u8,
    /// Navigation accuracy category for position.
    pub nacp: u8,
    /// The ground speed is valid (0/1).
    pub has_ground_speed: u8,
    /// Ground speed, knots.
    pub ground_speed_kt: u16,
    /// The vertical rate is valid (0/1).
    pub has_vertical_rate: u8,
    /// Vertical rate, feet per minute.
    pub vertical_rate_fpm: i32,
    /// Emitter category.
    pub emitter: u8,
    /// Call sign, 8 bytes, space padded (not NUL-terminated).
    pub call_sign: [u8; 8],
    /// Emergency / priority code nibble.
    pub emergency: u8,
}

/// Ownship geometric altitude (11).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct pl_gdl90_geo_altitude {
    /// Geometric altitude, feet.
    pub altitude_ft: i32,
    /// Vertical warning (0/1).
    pub vertical_warning: u8,
    /// The vertical figure of merit is valid (0/1).
    pub has_vfom: u8,
    /// Vertical figure of merit, m.
    pub vfom_m: u16,
}

/// ForeFlight ID (0x65 sub-ID 0).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct pl_gdl90_foreflight_id {
    /// Version.
    pub version: u8,
    /// The serial number is valid (0/1).
    pub has_serial: u8,
    /// Serial number.
    pub serial: u64,
    /// Device name, 8 bytes, NUL padded (not always NUL-terminated).
    pub name: [u8; 8],
    /// Long device name, 16 bytes, NUL padded.
    pub long_name: [u8; 16],
    /// Geometric altitude datum: 0 WGS-84 ellipsoid, 1 MSL.
    pub altitude_datum: u8,
    /// The capabilities word without the datum bit.
    pub other_capabilities: u32,
}

/// ForeFlight AHRS (0x65 sub-ID 1).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct pl_gdl90_ahrs {
    /// Roll is valid (0/1).
    pub has_roll: u8,
    /// Roll, degrees.
    pub roll_deg: f32,
    /// Pitch is valid (0/1).
    pub has_pitch: u8,
    /// Pitch, degrees.
    pub pitch_deg: f32,
    /// Heading kind: 0 none, 1 true, 2 magnetic.
    pub heading_kind: u8,
    /// Heading, degrees.
    pub heading_deg: f32,
    /// Indicated airspeed is valid (0/1).
    pub has_indicated_airspeed: u8,
    /// Indicated airspeed, knots.
    pub indicated_airspeed_kt: u16,
    /// True airspeed is valid (0/1).
    pub has_true_airspeed: u8,
    /// True airspeed, knots.
    pub true_airspeed_kt: u16,
}

/// The typed content of a GDL90 message; the member is chosen by `pl_gdl90_message.kind`.
#[repr(C)]
#[derive(Clone, Copy)]
pub union pl_gdl90_body {
    /// `PL_GDL90_HEARTBEAT`.
    pub heartbeat: pl_gdl90_heartbeat,
    /// `PL_GDL90_OWNSHIP`, `PL_GDL90_TRAFFIC`.
    pub report: pl_gdl90_report,
    /// `PL_GDL90_GEO_ALTITUDE`.
    pub geo_altitude: pl_gdl90_geo_altitude,
    /// `PL_GDL90_FOREFLIGHT_ID`.
    pub foreflight_id: pl_gdl90_foreflight_id,
    /// `PL_GDL90_AHRS`.
    pub ahrs: pl_gdl90_ahrs,
}

/// One GDL90 message. Decoded, `id` is the message ID and `data` points at its data in the
/// decoder (valid until the next call on it); to encode an unknown kind, set `id`, `data`
/// and `data_len`.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct pl_gdl90_message {
    /// `PL_GDL90_*` kind.
    pub kind: u8,
    /// The message ID.
    pub id: u8,
    /// Bytes of the frame on the wire, both flags included (a flag between two frames counts
    /// in both); 0 in a message struct `PL_ERROR` cleared.
    pub wire_len: u32,
    /// Decoded: where the frame starts (its opening flag), in bytes fed to this decoder since
    /// `pl_gdl90_init`. Encode: ignored.
    pub offset: u64,
    /// Raw data of an unknown message (a ForeFlight sub-ID is its first byte).
    pub data: *const u8,
    /// Bytes at `data`.
    pub data_len: usize,
    /// The typed fields.
    pub body: pl_gdl90_body,
}

/// The counters of a GDL90 decoder.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct pl_gdl90_stats {
    /// Messages delivered.
    pub frames_ok: u32,
    /// Good frames whose typed parse failed.
    pub invalid: u32,
    /// CRC failures.
    pub checksum_errors: u32,
    /// Frames longer than the capacity.
    pub overflows: u32,
    /// Frames too short.
    pub too_short: u32,
    /// Bad escapes.
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

fn report_c(r: &Report) -> pl_gdl90_report {
    let p = r.position.unwrap_or(LatLon {
        lat_deg: 0.0,
        lon_deg: 0.0,
    });
    let (track_kind, track_deg) = match r.track {
        None => (0, 0.0),
        Some(Track::TrueTrack(d)) => (1, d),
        Some(Track::MagneticHeading(d)) => (2, d),
        Some(Track::TrueHeading(d)) => (3, d),
    };
    pl_gdl90_report {
        traffic_alert: r.traffic_alert.into(),
        address_type: r.address_type.to_nibble(),
        address: r.address,
        has_position: r.position.is_some().into(),
        lat_deg: p.lat_deg,
        lon_deg: p.lon_deg,
        has_pressure_altitude: r.pressure_altitude_ft.is_some().into(),
        pressure_altitude_ft: r.pressure_altitude_ft.unwrap_or(0),
        airborne: r.airborne.into(),
        extrapolated: r.extrapolated.into(),
        track_kind,
        track_deg,
        nic: r.nic,
        nacp: r.nacp,
        has_ground_speed: r.ground_speed_kt.is_some().into(),
        ground_speed_kt: r.ground_speed_kt.unwrap_or(0),
        has_vertical_rate: r.vertical_rate_fpm.is_some().into(),
        vertical_rate_fpm: r.vertical_rate_fpm.unwrap_or(0),
        emitter: r.emitter,
        call_sign: *r.call_sign.as_bytes(),
        emergency: r.emergency.to_nibble(),
    }
}

fn report_rust(r: &pl_gdl90_report) -> Result<Report, i32> {
    Ok(Report {
        traffic_alert: r.traffic_alert != 0,
        address_type: AddressType::from_nibble(r.address_type),
        address: r.address,
        position: (r.has_position != 0).then_some(LatLon {
            lat_deg: r.lat_deg,
            lon_deg: r.lon_deg,
        }),
        pressure_altitude_ft: (r.has_pressure_altitude != 0).then_some(r.pressure_altitude_ft),
        airborne: r.airborne != 0,
        extrapolated: r.extrapolated != 0,
        track: match r.track_kind {
            0 => None,
            1 => Some(Track::TrueTrack(r.track_deg)),
            2 => Some(Track::MagneticHeading(r.track_deg)),
            3 => Some(Track::TrueHeading(r.track_deg)),
            _ => return Err(PL_E_INVALID),
        },
        nic: r.nic,
        nacp: r.nacp,
        ground_speed_kt: (r.has_ground_speed != 0).then_some(r.ground_speed_kt),
        vertical_rate_fpm: (r.has_vertical_rate != 0).then_some(r.vertical_rate_fpm),
        emitter: r.emitter,
        call_sign: CallSign::from_bytes(r.call_sign),
        emergency: Emergency::from_nibble(r.emergency),
    })
}

fn body_of(m: &Message<'_>) -> (u8, pl_gdl90_body) {
    match m {
        Message::Heartbeat(h) => (
            PL_GDL90_HEARTBEAT,
            pl_gdl90_body {
                heartbeat: pl_gdl90_heartbeat {
                    gps_position_valid: h.gps_position_valid.into(),
                    maintenance_required: h.maintenance_required.into(),
                    ident: h.ident.into(),
                    address_talkback: h.address_talkback.into(),
                    gps_battery_low: h.gps_battery_low.into(),
                    atc_services: h.atc_services.into(),
                    uat_initialized: h.uat_initialized.into(),
                    csa_requested: h.csa_requested.into(),
                    csa_not_available: h.csa_not_available.into(),
                    utc_ok: h.utc_ok.into(),
                    seconds_since_midnight: h.seconds_since_midnight,
                    uplink_messages: h.uplink_messages,
                    basic_long_messages: h.basic_long_messages,
                },
            },
        ),
        Message::Ownship(r) => (
            PL_GDL90_OWNSHIP,
            pl_gdl90_body {
                report: report_c(r),
            },
        ),
        Message::Traffic(r) => (
            PL_GDL90_TRAFFIC,
            pl_gdl90_body {
                report: report_c(r),
            },
        ),
        Message::GeoAltitude(g) => (
            PL_GDL90_GEO_ALTITUDE,
            pl_gdl90_body {
                geo_altitude: pl_gdl90_geo_altitude {
                    altitude_ft: g.altitude_ft,
                    vertical_warning: g.vertical_warning.into(),
                    has_vfom: g.vfom_m.is_some().into(),
                    vfom_m: g.vfom_m.unwrap_or(0),
                },
            },
        ),
        Message::ForeFlightId(f) => (
            PL_GDL90_FOREFLIGHT_ID,
            pl_gdl90_body {
                foreflight_id: pl_gdl90_foreflight_id {
                    version: f.version,
                    has_serial: f.serial.is_some().into(),
                    serial: f.serial.unwrap_or(0),
                    name: *f.name.as_bytes(),
                    long_name: *f.long_name.as_bytes(),
                    altitude_datum: match f.altitude_datum {
                        AltitudeDatum::Wgs84Ellipsoid => 0,
                        AltitudeDatum::Msl => 1,
                    },
                    other_capabilities: f.other_capabilities,
                },
            },
        ),
        Message::Ahrs(a) => {
            let (heading_kind, heading_deg) = match a.heading {
                None => (0, 0.0),
                Some(Heading::True(d)) => (1, d),
                Some(Heading::Magnetic(d)) => (2, d),
            };
            (
                PL_GDL90_AHRS,
                pl_gdl90_body {
                    ahrs: pl_gdl90_ahrs {
                        has_roll: a.roll_deg.is_some().into(),
                        roll_deg: a.roll_deg.unwrap_or(0.0),
                        has_pitch: a.pitch_deg.is_some().into(),
                        pitch_deg: a.pitch_deg.unwrap_or(0.0),
                        heading_kind,
                        heading_deg,
                        has_indicated_airspeed: a.indicated_airspeed_kt.is_some().into(),
                        indicated_airspeed_kt: a.indicated_airspeed_kt.unwrap_or(0),
                        has_true_airspeed: a.true_airspeed_kt.is_some().into(),
                        true_airspeed_kt: a.true_airspeed_kt.unwrap_or(0),
                    },
                },
            )
        }
        // The C face has no struct for the Stratux AHRS report (yet): it arrives as an
        // unknown message with its ID, 0x4C, and no data.
        Message::StratuxAhrs(_) | Message::Unknown { .. } => (
            PL_GDL90_UNKNOWN,
            pl_gdl90_body {
                geo_altitude: pl_gdl90_geo_altitude::default(),
            },
        ),
    }
}

impl Proto for pl_gdl90_decoder {
    type Dec = Inner;
    type Msg = pl_gdl90_message;
    type Stats = pl_gdl90_stats;
    const EMPTY: pl_gdl90_message = {
        // SAFETY: integers, floats and a raw pointer: all zeros is a valid value.
        let mut m: pl_gdl90_message = unsafe { core::mem::zeroed() };
        m.kind = PL_GDL90_UNKNOWN;
        m
    };

    fn fill(m: Message<'_>, msg: &mut pl_gdl90_message, _: &mut pl_error) -> i32 {
        let data: &[u8] = match m {
            Message::Unknown { data, .. } => data,
            _ => &[],
        };
        let (kind, body) = body_of(&m);
        *msg = pl_gdl90_message {
            kind,
            id: m.id(),
            wire_len: 0,
            offset: 0,
            data: data.as_ptr(),
            data_len: data.len(),
            body,
        };
        PL_MESSAGE
    }

    fn error(e: Error) -> pl_error {
        match e {
            Error::Overflow => pl_error::kind(PL_ERR_OVERFLOW),
            Error::Truncated => pl_error::kind(PL_ERR_TRUNCATED),
            Error::ChecksumMismatch {
                id,
                computed,
                received,
            } => pl_error::checksum(id, computed, received),
            Error::TooShort => pl_error::kind(PL_ERR_TOO_SHORT),
            Error::InvalidEscape => pl_error::kind(PL_ERR_INVALID_ESCAPE),
            Error::EscapedFlag => pl_error::kind(PL_ERR_ESCAPED_FLAG),
            Error::WrongLength {
                id,
                expected,
                actual,
            } => pl_error::wrong_length(id, expected, actual),
            Error::OutOfRange { id, .. } => pl_error::new(PL_ERR_OUT_OF_RANGE, id.into(), 0, 0),
        }
    }

    /// A frame with a good CRC whose typed parse failed counts in `frame_bytes`, as a message
    /// does: it has its place.
    fn parse_failed(e: &Error) -> bool {
        matches!(e, Error::WrongLength { .. } | Error::OutOfRange { .. })
    }

    fn stats(d: &Inner) -> pl_gdl90_stats {
        face::stats! { d => pl_gdl90_stats {
            frames_ok, invalid, checksum_errors, overflows, too_short, bad_escapes,
            bytes_discarded, frame_bytes, flags,
        } }
    }
}

/// `pl_gdl90_encode`: `msg`, with its raw data `data`, as one whole frame into `out`.
pub(crate) fn encode(msg: &pl_gdl90_message, data: &[u8], out: &mut [u8]) -> Result<usize, i32> {
    from_c(msg, data)?.encode(out).map_err(|e| match e {
        EncodeError::BufferTooSmall { .. } => PL_E_BUFFER_TOO_SMALL,
    })
}

/// The C struct as a Rust message. The body is read as the member `msg.kind` selects; every
/// member is plain numbers, so any bytes are valid.
fn from_c<'a>(msg: &pl_gdl90_message, data: &'a [u8]) -> Result<Message<'a>, i32> {
    let b = &msg.body;
    Ok(match msg.kind {
        PL_GDL90_HEARTBEAT => {
            // SAFETY: plain numbers, any bytes valid.
            let h = unsafe { b.heartbeat };
            Message::Heartbeat(Heartbeat {
                gps_position_valid: h.gps_position_valid != 0,
                maintenance_required: h.maintenance_required != 0,
                ident: h.ident != 0,
                address_talkback: h.address_talkback != 0,
                gps_battery_low: h.gps_battery_low != 0,
                atc_services: h.atc_services != 0,
                uat_initialized: h.uat_initialized != 0,
                csa_requested: h.csa_requested != 0,
                csa_not_available: h.csa_not_available != 0,
                utc_ok: h.utc_ok != 0,
                seconds_since_midnight: h.seconds_since_midnight,
                uplink_messages: h.uplink_messages,
                basic_long_messages: h.basic_long_messages,
            })
        }
        // SAFETY: plain numbers, any bytes valid.
        PL_GDL90_OWNSHIP => Message::Ownship(report_rust(unsafe { &b.report })?),
        // SAFETY: plain numbers, any bytes valid.
        PL_GDL90_TRAFFIC => Message::Traffic(report_rust(unsafe { &b.report })?),
        PL_GDL90_GEO_ALTITUDE => {
            // SAFETY: plain numbers, any bytes valid.
            let g = unsafe { b.geo_altitude };
            Message::GeoAltitude(GeoAltitude {
                altitude_ft: g.altitude_ft,
                vertical_warning: g.vertical_warning != 0,
                vfom_m: (g.has_vfom != 0).then_some(g.vfom_m),
            })
        }
        PL_GDL90_FOREFLIGHT_ID => {
            // SAFETY: plain numbers, any bytes valid.
            let f = unsafe { b.foreflight_id };
            Message::ForeFlightId(ForeFlightId {
                version: f.version,
                serial: (f.has_serial != 0).then_some(f.serial),
                name: Name::from_bytes(f.name),
                long_name: Name::from_bytes(f.long_name),
                altitude_datum: match f.altitude_datum {
                    0 => AltitudeDatum::Wgs84Ellipsoid,
                    1 => AltitudeDatum::Msl,
                    _ => return Err(PL_E_INVALID),
                },
                other_capabilities: f.other_capabilities,
            })
        }
        PL_GDL90_AHRS => {
            // SAFETY: plain numbers, any bytes valid.
            let a = unsafe { b.ahrs };
            Message::Ahrs(Ahrs {
                roll_deg: (a.has_roll != 0).then_some(a.roll_deg),
                pitch_deg: (a.has_pitch != 0).then_some(a.pitch_deg),
                heading: match a.heading_kind {
                    0 => None,
                    1 => Some(Heading::True(a.heading_deg)),
                    2 => Some(Heading::Magnetic(a.heading_deg)),
                    _ => return Err(PL_E_INVALID),
                },
                indicated_airspeed_kt: (a.has_indicated_airspeed != 0)
                    .then_some(a.indicated_airspeed_kt),
                true_airspeed_kt: (a.has_true_airspeed != 0).then_some(a.true_airspeed_kt),
            })
        }
        PL_GDL90_UNKNOWN => Message::Unknown { id: msg.id, data },
        _ => return Err(PL_E_BAD_TAG),
    })
}
