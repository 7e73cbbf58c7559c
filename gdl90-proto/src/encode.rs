//! Putting messages on the wire: flag, ID, data, CRC (LSB first), escaped, flag.
//!
//! The framing is AEOLUS's ([`aeolus_proto::encode_frame`]), which is GDL90's: the same
//! flags, escapes and CRC. GDL90 frames always carry a computed CRC.

use crate::EncodeError;
use crate::message::{
    Ahrs, ForeFlightId, GeoAltitude, Heartbeat, MAX_TYPED_DATA, Report, StratuxAhrs,
};

/// The worst-case length on the wire of a frame carrying `data_len` data bytes: two flags
/// plus the ID, the data and the CRC, every one of them escaped.
///
/// ```
/// use gdl90_proto::{max_encoded_len, message::Heartbeat};
/// let buf = [0u8; max_encoded_len(Heartbeat::LEN)];
/// assert_eq!(buf.len(), 20);
/// ```
pub const fn max_encoded_len(data_len: usize) -> usize {
    aeolus_proto::max_encoded_len(data_len)
}

/// A buffer of this many bytes holds any typed message this crate encodes (the longest is
/// the ForeFlight ID, 38 data bytes).
pub const MAX_ENCODED_LEN: usize = max_encoded_len(MAX_TYPED_DATA);

/// Encodes one frame with message ID `id` and data `data` into `out`; returns the number of
/// bytes written.
///
/// ```
/// use gdl90_proto::encode_frame;
/// // The ICD's heartbeat example (section 2.2.4).
/// let mut out = [0u8; 20];
/// let n = encode_frame(0, &[0x81, 0x41, 0xDB, 0xD0, 0x08, 0x02], &mut out).unwrap();
/// assert_eq!(&out[..n], &[0x7E, 0x00, 0x81, 0x41, 0xDB, 0xD0, 0x08, 0x02, 0xB3, 0x8B, 0x7E]);
/// ```
///
/// # Errors
/// [`EncodeError::BufferTooSmall`] if `out` cannot hold the escaped frame; `out` then holds a
/// partial frame that must not be sent.
pub fn encode_frame(id: u8, data: &[u8], out: &mut [u8]) -> Result<usize, EncodeError> {
    aeolus_proto::encode_frame(id, data, &[], aeolus_proto::CrcMode::Compute, out)
        .map_err(EncodeError::from_framing)
}

/// Encodes a Heartbeat (ID 0) frame into `out`; returns its length.
///
/// ```
/// use gdl90_proto::{encode_heartbeat, MAX_ENCODED_LEN, message::Heartbeat};
/// let hb = Heartbeat {
///     gps_position_valid: true,
///     uat_initialized: true,
///     csa_requested: true,
///     utc_ok: true,
///     seconds_since_midnight: 53467,
///     uplink_messages: 1,
///     basic_long_messages: 2,
///     ..Heartbeat::default()
/// };
/// let mut wire = [0u8; MAX_ENCODED_LEN];
/// let n = encode_heartbeat(&hb, &mut wire).unwrap();
/// assert_eq!(&wire[..n], &[0x7E, 0x00, 0x81, 0x41, 0xDB, 0xD0, 0x08, 0x02, 0xB3, 0x8B, 0x7E]);
/// ```
///
/// # Errors
/// [`EncodeError::BufferTooSmall`]; [`MAX_ENCODED_LEN`] is always enough.
pub fn encode_heartbeat(msg: &Heartbeat, out: &mut [u8]) -> Result<usize, EncodeError> {
    msg.encode(out)
}

/// Encodes an Ownship Report (ID 10) frame into `out`; returns its length.
///
/// ```
/// use gdl90_proto::{encode_ownship, MAX_ENCODED_LEN, message::Report};
/// let mut wire = [0u8; MAX_ENCODED_LEN];
/// let n = encode_ownship(&Report::default(), &mut wire).unwrap();
/// assert_eq!((wire[1], wire[n - 1]), (10, 0x7E));
/// ```
///
/// # Errors
/// [`EncodeError::BufferTooSmall`]; [`MAX_ENCODED_LEN`] is always enough.
pub fn encode_ownship(msg: &Report, out: &mut [u8]) -> Result<usize, EncodeError> {
    msg.encode_ownship(out)
}

/// Encodes a Traffic Report (ID 20) frame into `out`; returns its length.
///
/// ```
/// use gdl90_proto::{encode_traffic, MAX_ENCODED_LEN, message::Report};
/// let mut wire = [0u8; MAX_ENCODED_LEN];
/// let n = encode_traffic(&Report::default(), &mut wire).unwrap();
/// assert_eq!((wire[1], wire[n - 1]), (20, 0x7E));
/// ```
///
/// # Errors
/// [`EncodeError::BufferTooSmall`]; [`MAX_ENCODED_LEN`] is always enough.
pub fn encode_traffic(msg: &Report, out: &mut [u8]) -> Result<usize, EncodeError> {
    msg.encode_traffic(out)
}

/// Encodes an Ownship Geometric Altitude (ID 11) frame into `out`; returns its length.
///
/// ```
/// use gdl90_proto::{encode_geo_altitude, MAX_ENCODED_LEN, message::GeoAltitude};
/// let alt = GeoAltitude { altitude_ft: -1000, vertical_warning: true, vfom_m: None };
/// let mut wire = [0u8; MAX_ENCODED_LEN];
/// let n = encode_geo_altitude(&alt, &mut wire).unwrap();
/// assert_eq!(&wire[1..6], &[11, 0xFF, 0x38, 0xFF, 0xFF]);
/// assert_eq!(n, 9);
/// ```
///
/// # Errors
/// [`EncodeError::BufferTooSmall`]; [`MAX_ENCODED_LEN`] is always enough.
pub fn encode_geo_altitude(msg: &GeoAltitude, out: &mut [u8]) -> Result<usize, EncodeError> {
    msg.encode(out)
}

/// Encodes a ForeFlight ID (0x65, sub-ID 0) frame into `out`; returns its length.
///
/// ```
/// use gdl90_proto::{encode_foreflight_id, MAX_ENCODED_LEN, message::{ForeFlightId, Name}};
/// let id = ForeFlightId { name: Name::new("Box").unwrap(), ..ForeFlightId::default() };
/// let mut wire = [0u8; MAX_ENCODED_LEN];
/// let n = encode_foreflight_id(&id, &mut wire).unwrap();
/// assert_eq!(&wire[1..4], &[0x65, 0x00, 0x01]);
/// assert_eq!(wire[n - 1], 0x7E);
/// ```
///
/// # Errors
/// [`EncodeError::BufferTooSmall`]; [`MAX_ENCODED_LEN`] is always enough.
pub fn encode_foreflight_id(msg: &ForeFlightId, out: &mut [u8]) -> Result<usize, EncodeError> {
    msg.encode(out)
}

/// Encodes a ForeFlight AHRS (0x65, sub-ID 1) frame into `out`; returns its length.
///
/// ```
/// use gdl90_proto::{encode_ahrs, MAX_ENCODED_LEN, message::{Ahrs, Heading}};
/// let ahrs = Ahrs { roll_deg: Some(250.0), heading: Some(Heading::True(f32::NAN)), ..Ahrs::default() };
/// let mut wire = [0u8; MAX_ENCODED_LEN];
/// let n = encode_ahrs(&ahrs, &mut wire).unwrap();
/// // Roll clamped to +180.0 (1800 = 0x0708); the NaN heading sent as invalid.
/// assert_eq!(&wire[1..10], &[0x65, 0x01, 0x07, 0x08, 0x7F, 0xFF, 0xFF, 0xFF, 0xFF]);
/// assert_eq!(wire[n - 1], 0x7E);
/// ```
///
/// # Errors
/// [`EncodeError::BufferTooSmall`]; [`MAX_ENCODED_LEN`] is always enough.
pub fn encode_ahrs(msg: &Ahrs, out: &mut [u8]) -> Result<usize, EncodeError> {
    msg.encode(out)
}

/// Encodes a Stratux AHRS report (ID 0x4C, header `45 01 01`) frame into `out`; returns its
/// length.
///
/// ```
/// use gdl90_proto::{encode_stratux_ahrs, MAX_ENCODED_LEN, message::StratuxAhrs};
/// let ahrs = StratuxAhrs { roll_deg: Some(30.0), pressure_altitude_ft: Some(0), ..StratuxAhrs::default() };
/// let mut wire = [0u8; MAX_ENCODED_LEN];
/// let n = encode_stratux_ahrs(&ahrs, &mut wire).unwrap();
/// assert_eq!(&wire[1..7], &[0x4C, 0x45, 0x01, 0x01, 0x01, 0x2C]); // roll 300 tenths
/// assert_eq!(&wire[19..21], &[0x13, 0x88]); // 0 ft + 5000 (flag and ID before data byte 17)
/// assert_eq!(wire[n - 1], 0x7E);
/// ```
///
/// # Errors
/// [`EncodeError::BufferTooSmall`]; [`MAX_ENCODED_LEN`] is always enough.
pub fn encode_stratux_ahrs(msg: &StratuxAhrs, out: &mut [u8]) -> Result<usize, EncodeError> {
    msg.encode(out)
}
