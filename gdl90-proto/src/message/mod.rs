//! Typed GDL90 messages: one plain struct per message with `ID`, `LEN`, `parse`, `emit` and
//! `buffer_len`, their byte tables in the private `layout` module, and the [`Message`] enum that covers every
//! ID (raw for the IDs this crate does not type).
//!
//! Physical values carry their unit in their name (`_deg`, `_ft`, `_kt`, `_fpm`, `_m`), and
//! every field with an "invalid" or "not available" code on the wire is an `Option` (or an
//! enum), so a marker is never read as a value. Encoders clamp out-of-range values to the
//! nearest valid code (angles are reduced instead: 370 degrees is 10 degrees); they never
//! wrap and never turn a value into a marker.

mod foreflight;
mod geo_altitude;
mod heartbeat;
mod layout;
mod report;
mod scale;
mod stratux;
mod text;

pub use foreflight::{Ahrs, AltitudeDatum, FOREFLIGHT_ID, ForeFlightId, Heading};
pub use geo_altitude::GeoAltitude;
pub use heartbeat::Heartbeat;
pub use report::{AddressType, Emergency, LatLon, Report, Track};
pub use stratux::{STRATUX_AHRS_HEADER, STRATUX_AHRS_ID, StratuxAhrs};
pub use text::{CallSign, Name};

use crate::{EncodeError, Error, encode_frame};

/// Message IDs (ICD table 2, ForeFlight's 0x65 and Stratux's 0x4C).
pub mod id {
    /// Heartbeat.
    pub const HEARTBEAT: u8 = 0;
    /// Initialization (display to GDL 90; kept raw).
    pub const INITIALIZATION: u8 = 2;
    /// UAT uplink data (kept raw).
    pub const UPLINK: u8 = 7;
    /// Height above terrain (kept raw).
    pub const HEIGHT_ABOVE_TERRAIN: u8 = 9;
    /// Ownship Report.
    pub const OWNSHIP: u8 = 10;
    /// Ownship Geometric Altitude.
    pub const GEO_ALTITUDE: u8 = 11;
    /// Traffic Report.
    pub const TRAFFIC: u8 = 20;
    /// Basic UAT report (kept raw).
    pub const BASIC_REPORT: u8 = 30;
    /// Long UAT report (kept raw).
    pub const LONG_REPORT: u8 = 31;
    /// ForeFlight extensions (sub-ID 0: ID, 1: AHRS).
    pub const FOREFLIGHT: u8 = super::FOREFLIGHT_ID;
    /// Stratux AHRS report (the Levil "LE" format: `0x4C 0x45 0x01 0x01`).
    pub const STRATUX_AHRS: u8 = super::STRATUX_AHRS_ID;
}

/// Any GDL90 message: typed where this crate knows the layout, raw otherwise.
///
/// The [`Decoder`](crate::Decoder) delivers these; [`Message::encode`] puts one on the wire.
///
/// ```
/// use gdl90_proto::{MAX_ENCODED_LEN, message::{GeoAltitude, Message}};
/// let msg = Message::GeoAltitude(GeoAltitude { altitude_ft: 1500, ..Default::default() });
/// let mut wire = [0u8; MAX_ENCODED_LEN];
/// let n = msg.encode(&mut wire).unwrap();
/// assert_eq!(&wire[..4], &[0x7E, 11, 0x01, 0x2C]);
/// assert_eq!(wire[n - 1], 0x7E);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub enum Message<'a> {
    /// Heartbeat (0).
    Heartbeat(Heartbeat),
    /// Ownship Report (10).
    Ownship(Report),
    /// Ownship Geometric Altitude (11).
    GeoAltitude(GeoAltitude),
    /// Traffic Report (20).
    Traffic(Report),
    /// ForeFlight ID (0x65, sub-ID 0).
    ForeFlightId(ForeFlightId),
    /// ForeFlight AHRS (0x65, sub-ID 1).
    Ahrs(Ahrs),
    /// Stratux AHRS report (0x4C with the `45 01 01` header).
    StratuxAhrs(StratuxAhrs),
    /// Any other ID (or a ForeFlight sub-ID other than 0 and 1, or a 0x4C without the `0x45`
    /// byte), kept raw.
    Unknown {
        /// The message ID.
        id: u8,
        /// The data (after the ID, before the CRC; a ForeFlight sub-ID is its first byte).
        data: &'a [u8],
    },
}

impl<'a> Message<'a> {
    /// Parses the data of a message with ID `id`.
    ///
    /// ```
    /// use gdl90_proto::message::Message;
    /// let msg = Message::parse(11, &[0x01, 0x2C, 0x7F, 0xFF]).unwrap();
    /// let Message::GeoAltitude(alt) = msg else { panic!() };
    /// assert_eq!((alt.altitude_ft, alt.vfom_m), (1500, None));
    /// assert_eq!(Message::parse(7, &[1, 2, 3]).unwrap(), Message::Unknown { id: 7, data: &[1, 2, 3] });
    /// ```
    ///
    /// # Errors
    /// [`Error::WrongLength`] for a typed ID with the wrong data length, and
    /// [`Error::OutOfRange`] for an AHRS message (ForeFlight or Stratux) with an attitude or
    /// heading out of range, a Stratux AHRS report without the `45 01 01` header, or a report
    /// with a latitude beyond ±90 degrees.
    pub fn parse(id: u8, data: &'a [u8]) -> Result<Self, Error> {
        Ok(match (id, data.first()) {
            (id::HEARTBEAT, _) => Self::Heartbeat(Heartbeat::parse(data)?),
            (id::OWNSHIP, _) => Self::Ownship(Report::parse(id, data)?),
            (id::GEO_ALTITUDE, _) => Self::GeoAltitude(GeoAltitude::parse(data)?),
            (id::TRAFFIC, _) => Self::Traffic(Report::parse(id, data)?),
            (id::FOREFLIGHT, Some(&ForeFlightId::SUB_ID)) => {
                Self::ForeFlightId(ForeFlightId::parse(data)?)
            }
            (id::FOREFLIGHT, Some(&Ahrs::SUB_ID)) => Self::Ahrs(Ahrs::parse(data)?),
            (id::STRATUX_AHRS, Some(&0x45)) => Self::StratuxAhrs(StratuxAhrs::parse(data)?),
            _ => Self::Unknown { id, data },
        })
    }

    /// The message ID.
    ///
    /// ```
    /// use gdl90_proto::message::{Ahrs, Message};
    /// assert_eq!(Message::Ahrs(Ahrs::default()).id(), 0x65);
    /// assert_eq!(Message::Unknown { id: 7, data: &[] }.id(), 7);
    /// ```
    pub const fn id(&self) -> u8 {
        match self {
            Self::Heartbeat(_) => id::HEARTBEAT,
            Self::Ownship(_) => id::OWNSHIP,
            Self::GeoAltitude(_) => id::GEO_ALTITUDE,
            Self::Traffic(_) => id::TRAFFIC,
            Self::ForeFlightId(_) | Self::Ahrs(_) => id::FOREFLIGHT,
            Self::StratuxAhrs(_) => id::STRATUX_AHRS,
            Self::Unknown { id, .. } => *id,
        }
    }

    /// A short name for logs and desk tools (`"UNKNOWN"` for a raw message).
    ///
    /// ```
    /// use gdl90_proto::message::{Ahrs, Message};
    /// assert_eq!(Message::Ahrs(Ahrs::default()).name(), "FOREFLIGHT_AHRS");
    /// assert_eq!(Message::Unknown { id: 7, data: &[] }.name(), "UNKNOWN");
    /// ```
    pub const fn name(&self) -> &'static str {
        match self {
            Self::Heartbeat(_) => "HEARTBEAT",
            Self::Ownship(_) => "OWNSHIP",
            Self::GeoAltitude(_) => "GEO_ALTITUDE",
            Self::Traffic(_) => "TRAFFIC",
            Self::ForeFlightId(_) => "FOREFLIGHT_ID",
            Self::Ahrs(_) => "FOREFLIGHT_AHRS",
            Self::StratuxAhrs(_) => "STRATUX_AHRS",
            Self::Unknown { .. } => "UNKNOWN",
        }
    }

    /// The data length [`Message::emit`] writes.
    ///
    /// ```
    /// use gdl90_proto::message::{Heartbeat, Message};
    /// assert_eq!(Message::Heartbeat(Heartbeat::default()).buffer_len(), 6);
    /// assert_eq!(Message::Unknown { id: 7, data: &[1, 2, 3] }.buffer_len(), 3);
    /// ```
    pub const fn buffer_len(&self) -> usize {
        match self {
            Self::Heartbeat(_) => Heartbeat::LEN,
            Self::Ownship(_) | Self::Traffic(_) => Report::LEN,
            Self::GeoAltitude(_) => GeoAltitude::LEN,
            Self::ForeFlightId(_) => ForeFlightId::LEN,
            Self::Ahrs(_) => Ahrs::LEN,
            Self::StratuxAhrs(_) => StratuxAhrs::LEN,
            Self::Unknown { data, .. } => data.len(),
        }
    }

    /// Writes the message data (without ID, CRC or escaping) into `out`; returns its length.
    ///
    /// ```
    /// use gdl90_proto::{EncodeError, message::Message};
    /// // The ICD's example heartbeat, as parsed.
    /// let msg = Message::parse(0, &[0x81, 0x41, 0xDB, 0xD0, 0x08, 0x02]).unwrap();
    /// let mut data = [0u8; 6];
    /// assert_eq!(msg.emit(&mut data), Ok(6));
    /// assert_eq!(data, [0x81, 0x41, 0xDB, 0xD0, 0x08, 0x02]);
    /// assert_eq!(msg.emit(&mut data[..5]), Err(EncodeError::BufferTooSmall { needed: 6 }));
    /// ```
    ///
    /// # Errors
    /// [`EncodeError::BufferTooSmall`].
    pub fn emit(&self, out: &mut [u8]) -> Result<usize, EncodeError> {
        match self {
            Self::Heartbeat(m) => m.emit(out),
            Self::Ownship(m) | Self::Traffic(m) => m.emit(out),
            Self::GeoAltitude(m) => m.emit(out),
            Self::ForeFlightId(m) => m.emit(out),
            Self::Ahrs(m) => m.emit(out),
            Self::StratuxAhrs(m) => m.emit(out),
            Self::Unknown { data, .. } => {
                let needed = data.len();
                let dst = out
                    .get_mut(..needed)
                    .ok_or(EncodeError::BufferTooSmall { needed })?;
                // Zipped: no length check left to a panic when the copy is not inlined.
                dst.iter_mut().zip(*data).for_each(|(d, s)| *d = *s);
                Ok(data.len())
            }
        }
    }

    /// Encodes the whole frame (flags, ID, data, CRC, escaped) into `out`; returns its
    /// length. [`crate::MAX_ENCODED_LEN`] is enough for every typed message;
    /// [`crate::max_encoded_len`] of [`Message::buffer_len`] for any message. The one way a
    /// message goes on the wire: the variant names the ID (an Ownship and a Traffic Report
    /// share the [`Report`] struct).
    ///
    /// ```
    /// use gdl90_proto::{MAX_ENCODED_LEN, max_encoded_len, message::{Heartbeat, Message, Report}};
    /// // An ID this crate keeps raw (UAT uplink), framed as it is.
    /// let uplink = Message::Unknown { id: 7, data: &[1, 2, 3] };
    /// let mut wire = [0u8; max_encoded_len(3)];
    /// let n = uplink.encode(&mut wire).unwrap();
    /// assert_eq!(&wire[..n], &[0x7E, 0x07, 1, 2, 3, 0xB5, 0x8B, 0x7E]);
    /// // Typed messages: a heartbeat, the same report as ownship (ID 10) and as traffic (ID 20).
    /// let mut wire = [0u8; MAX_ENCODED_LEN];
    /// let n = Message::Heartbeat(Heartbeat::default()).encode(&mut wire).unwrap();
    /// assert_eq!(&wire[..n], &[0x7E, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0x7E]);
    /// let n = Message::Ownship(Report::default()).encode(&mut wire).unwrap();
    /// assert_eq!((wire[1], wire[n - 1]), (10, 0x7E));
    /// let n = Message::Traffic(Report::default()).encode(&mut wire).unwrap();
    /// assert_eq!((wire[1], wire[n - 1]), (20, 0x7E));
    /// ```
    ///
    /// # Errors
    /// [`EncodeError::BufferTooSmall`].
    pub fn encode(&self, out: &mut [u8]) -> Result<usize, EncodeError> {
        match self {
            Self::Unknown { id, data } => encode_frame(*id, data, out),
            _ => {
                let mut data = [0u8; MAX_TYPED_DATA];
                let n = self.emit(&mut data)?;
                encode_frame(self.id(), data.get(..n).unwrap_or(&[]), out)
            }
        }
    }
}

/// The longest typed layout (ForeFlight ID, 38 bytes).
pub(crate) const MAX_TYPED_DATA: usize = ForeFlightId::LEN;

/// `Err(WrongLength)` unless `data` is `len` bytes long.
fn check_len(id: u8, len: usize, data: &[u8]) -> Result<(), Error> {
    if data.len() == len {
        Ok(())
    } else {
        Err(Error::WrongLength {
            id,
            expected: len as u16,
            actual: data.len().min(u16::MAX as usize) as u16,
        })
    }
}

/// Zeroes `out[..len]`, lets `fill` write the fields, returns `len`.
fn emit_into(
    out: &mut [u8],
    len: usize,
    fill: impl FnOnce(&mut [u8]),
) -> Result<usize, EncodeError> {
    let d = out
        .get_mut(..len)
        .ok_or(EncodeError::BufferTooSmall { needed: len })?;
    d.fill(0);
    fill(d);
    Ok(len)
}
