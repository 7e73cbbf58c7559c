//! Typed messages and the [`Message`] enum that ties them to type numbers per profile.
//!
//! Each typed message gives its bytes as a table, `FIELDS` (name, wire type, offset) and `LEN`
//! ([`Position::FIELDS`], [`Frame::HEADER_FIELDS`](crate::Frame::HEADER_FIELDS) for the
//! header), for tools that describe the wire format.

mod control;
mod fix;
mod output;
mod position;
mod reference;
mod svu;

pub use control::SystemControl;
pub use fix::{FixDetail, FixDetailBuilder, FixQuality, Satellite, SatelliteList, Satellites};
pub use output::{DirectOutput, DirectOutputBuilder, Entries, OutputEntry};
pub use position::Position;
pub use reference::{VesselData, WindDirection, WindSpeed};
pub use svu::{SystemValueUpdate, UpdateMode};

use crate::encode::{Payload, Raw};
use crate::error::{Error, Result};
use crate::profile::Profile;

pub(crate) const fn too_short(msg_type: u8, expected: usize, actual: usize) -> Error {
    Error::PayloadTooShort {
        msg_type,
        expected,
        actual,
    }
}

pub(crate) const fn too_long(msg_type: u8, expected: usize, actual: usize) -> Error {
    Error::PayloadTooLong {
        msg_type,
        expected,
        actual,
    }
}

/// `data` as exactly `K` bytes, or a typed too-short/too-long error.
pub(crate) fn exact<const K: usize>(data: &[u8], msg_type: u8) -> Result<&[u8; K]> {
    if data.len() < K {
        return Err(too_short(msg_type, K, data.len()));
    }
    <&[u8; K]>::try_from(data).map_err(|_| too_long(msg_type, K, data.len()))
}

/// `emit` and `buffer_len` for a fixed-size type with `LEN`, `Default` and `data()`: the one
/// encode vocabulary of this workspace (`aeolus_proto`'s typed messages read the same).
macro_rules! fixed_emit {
    ($t:ident) => {
        impl $t {
            /// The number of bytes [`Self::emit`] writes: [`Self::LEN`].
            ///
            /// ```
            #[doc = concat!("use aydp_proto::", stringify!($t), ";")]
            #[doc = concat!("assert_eq!(", stringify!($t), "::default().buffer_len(), ", stringify!($t), "::LEN);")]
            /// ```
            pub const fn buffer_len(&self) -> usize {
                Self::LEN
            }

            /// Writes the [`Self::LEN`] data bytes into `out`; returns [`Self::LEN`].
            ///
            /// ```
            #[doc = concat!("use aydp_proto::{EncodeError, ", stringify!($t), "};")]
            #[doc = concat!("let value = ", stringify!($t), "::default();")]
            #[doc = concat!("let mut out = [0u8; ", stringify!($t), "::LEN];")]
            #[doc = concat!("assert_eq!(value.emit(&mut out), Ok(", stringify!($t), "::LEN));")]
            #[doc = concat!("let needed = ", stringify!($t), "::LEN;")]
            /// assert_eq!(value.emit(&mut out[..needed - 1]), Err(EncodeError::BufferTooSmall { needed }));
            /// ```
            ///
            /// # Errors
            /// [`EncodeError::BufferTooSmall`](crate::EncodeError::BufferTooSmall) if `out` is
            /// shorter than [`Self::LEN`]; `out` is then untouched.
            pub fn emit(&self, out: &mut [u8]) -> core::result::Result<usize, $crate::EncodeError> {
                let dst = out
                    .get_mut(..Self::LEN)
                    .ok_or($crate::EncodeError::BufferTooSmall { needed: Self::LEN })?;
                $crate::header::put(dst, 0, &self.data());
                Ok(Self::LEN)
            }
        }
    };
}
pub(crate) use fixed_emit;

/// `Payload` (and `emit`, `buffer_len`) for a fixed-size type with `TYPE`, `LEN` and `data()`.
macro_rules! fixed_payload {
    ($t:ident) => {
        $crate::message::fixed_emit!($t);

        impl $crate::encode::Payload for $t {
            fn base_type(&self) -> u8 {
                Self::TYPE
            }
            fn buffer_len(&self) -> usize {
                Self::LEN
            }
            fn data_byte(&self, index: usize) -> u8 {
                self.data().get(index).copied().unwrap_or(0)
            }
            fn write_data(&self, out: &mut [u8]) {
                $crate::header::put(out, 0, &self.data());
            }
        }
    };
}
pub(crate) use fixed_payload;

/// Base type of time sync (`Spec`) and no-op (`Reference`); expedited it is the heartbeat.
pub const TIME_SYNC: u8 = 0;
/// First user-defined type.
pub const USER_FIRST: u8 = 100;
/// Last user-defined type.
pub const USER_LAST: u8 = 126;

/// Any AYDP message, typed where the profile defines the type.
///
/// | type | `Spec` | `Reference` |
/// |---|---|---|
/// | 0 | `TimeSync` (normal) / `Heartbeat` (expedited) | `NoOp` |
/// | 1, 2 | `Tbd` (raw) | `WindSpeed`, `WindDirection` |
/// | 3, 4, 5, 7, 8, 9 | typed | typed (the document's layouts) |
/// | 6 | `Tbd` (raw) | `Unknown` (raw) |
/// | 17 | `Unknown` (raw) | `VesselData` |
/// | 100..=126 | `UserDefined` (raw) | `UserDefined` (raw) |
/// | other | `Unknown` (raw) | `Unknown` (raw) |
///
/// ```
/// use aydp_proto::{Message, Profile, Position};
/// let mut data = [0u8; Position::LEN];
/// Position { latitude: 1.0, longitude: 2.0, altitude: 3.0 }.emit(&mut data).unwrap();
/// let m = Message::parse(3, false, &data, Profile::Spec).unwrap();
/// assert!(matches!(m, Message::Position(p) if p.altitude == 3.0));
/// assert!(matches!(Message::parse(2, false, &[9], Profile::Spec), Ok(Message::Tbd(_))));
/// assert!(Message::parse(3, false, &data[..19], Profile::Spec).is_err());
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Message<'a> {
    /// Type 0, normal, `Spec`: the header time is the time to set.
    TimeSync,
    /// Type 0, expedited (128), `Spec`.
    Heartbeat,
    /// Type 0 in `Reference` (no-op), normal or expedited.
    NoOp,
    /// Type 3.
    Position(Position),
    /// Type 4.
    FixQuality(FixQuality),
    /// Type 5.
    #[cfg_attr(feature = "serde", serde(borrow))]
    FixDetail(FixDetail<'a>),
    /// Type 7.
    #[cfg_attr(feature = "serde", serde(borrow))]
    DirectOutput(DirectOutput<'a>),
    /// Type 8.
    #[cfg_attr(feature = "serde", serde(borrow))]
    SystemValueUpdate(SystemValueUpdate<'a>),
    /// Type 9.
    SystemControl(SystemControl),
    /// Type 1 in `Reference`.
    WindSpeed(WindSpeed),
    /// Type 2 in `Reference`.
    WindDirection(WindDirection),
    /// Type 17 in `Reference`.
    VesselData(VesselData),
    /// Types 1, 2 and 6 in `Spec` ("TBD" in the document, Y8): raw data.
    #[cfg_attr(feature = "serde", serde(borrow))]
    Tbd(Raw<'a>),
    /// Types 100..=126: raw data.
    #[cfg_attr(feature = "serde", serde(borrow))]
    UserDefined(Raw<'a>),
    /// Any type the profile does not define: raw data.
    #[cfg_attr(feature = "serde", serde(borrow))]
    Unknown(Raw<'a>),
}

fn empty(msg_type: u8, data: &[u8]) -> Result<()> {
    if data.is_empty() {
        Ok(())
    } else {
        Err(too_long(msg_type, 0, data.len()))
    }
}

impl<'a> Message<'a> {
    /// Parse the data of a message of `base_type` (without the expedited bit).
    ///
    /// ```
    /// use aydp_proto::{Error, Message, Profile, SystemControl};
    /// let store = Message::SystemControl(SystemControl::StoreConfiguration);
    /// assert_eq!(Message::parse(9, false, &[2], Profile::Spec), Ok(store));
    /// assert_eq!(Message::parse(0, true, &[], Profile::Spec), Ok(Message::Heartbeat));
    /// assert_eq!(Message::parse(0, true, &[], Profile::Reference), Ok(Message::NoOp));
    /// assert_eq!(Message::parse(127, false, &[], Profile::Spec), Err(Error::BadType(127)));
    /// ```
    // Out of line: a caller that parses in several places keeps one copy (inlined into the
    // firmware's main loop, it cost 416 B of flash more once VESSEL DATA moved out of it).
    #[inline(never)]
    pub fn parse(base_type: u8, expedited: bool, data: &'a [u8], profile: Profile) -> Result<Self> {
        if base_type > USER_LAST {
            // Y3: base types are 0..=126 (the encoder refuses anything else too).
            return Err(Error::BadType(base_type));
        }
        let raw = Raw {
            msg_type: base_type,
            data,
        };
        let m = match (profile, base_type) {
            (Profile::Spec, TIME_SYNC) => {
                empty(base_type, data)?;
                if expedited {
                    Message::Heartbeat
                } else {
                    Message::TimeSync
                }
            }
            (Profile::Reference, TIME_SYNC) => {
                empty(base_type, data)?;
                Message::NoOp
            }
            (Profile::Spec, 1 | 2 | 6) => Message::Tbd(raw),
            (Profile::Reference, WindSpeed::TYPE) => Message::WindSpeed(WindSpeed::parse(data)?),
            (Profile::Reference, WindDirection::TYPE) => {
                Message::WindDirection(WindDirection::parse(data)?)
            }
            (Profile::Reference, VesselData::TYPE) => return Self::parse_vessel(data),
            (_, Position::TYPE) => Message::Position(Position::parse(data)?),
            (_, FixQuality::TYPE) => Message::FixQuality(FixQuality::parse(data)?),
            (_, FixDetail::TYPE) => Message::FixDetail(FixDetail::parse(data)?),
            (_, DirectOutput::TYPE) => Message::DirectOutput(DirectOutput::parse(data)?),
            (_, SystemValueUpdate::TYPE) => {
                Message::SystemValueUpdate(SystemValueUpdate::parse(data)?)
            }
            (_, SystemControl::TYPE) => Message::SystemControl(SystemControl::parse(data)?),
            (_, USER_FIRST..=USER_LAST) => Message::UserDefined(raw),
            _ => Message::Unknown(raw),
        };
        Ok(m)
    }

    /// The Reference profile's VESSEL DATA, out of line: it is the largest variant (eleven
    /// fields), and `parse`'s arms share one exit that stores every field of the largest
    /// variant it builds, whatever the message (on Cortex-M3 a 76-byte result written for each
    /// frame, 32 bytes without it).
    #[inline(never)]
    fn parse_vessel(data: &'a [u8]) -> Result<Self> {
        VesselData::parse(data).map(Message::VesselData)
    }

    fn as_payload(&self) -> &dyn Payload {
        match self {
            Message::TimeSync | Message::Heartbeat | Message::NoOp => &EMPTY,
            Message::Position(p) => p,
            Message::FixQuality(p) => p,
            Message::FixDetail(p) => p,
            Message::DirectOutput(p) => p,
            Message::SystemValueUpdate(p) => p,
            Message::SystemControl(p) => p,
            Message::WindSpeed(p) => p,
            Message::WindDirection(p) => p,
            Message::VesselData(p) => p,
            Message::Tbd(r) | Message::UserDefined(r) | Message::Unknown(r) => r,
        }
    }
}

const EMPTY: Raw<'static> = Raw {
    msg_type: TIME_SYNC,
    data: &[],
};

/// Encoding a `Message` writes its base type; `Heartbeat` and `TimeSync` differ only in
/// whether the encoder is asked for an expedited or a normal message.
impl Payload for Message<'_> {
    fn base_type(&self) -> u8 {
        self.as_payload().base_type()
    }
    fn buffer_len(&self) -> usize {
        self.as_payload().buffer_len()
    }
    fn data_byte(&self, index: usize) -> u8 {
        self.as_payload().data_byte(index)
    }
    fn write_data(&self, out: &mut [u8]) {
        self.as_payload().write_data(out)
    }
}
