//! The errors, one type per operation: [`Error`] for what received bytes give, [`EncodeError`]
//! for encoding. The system-value registry's operations fail with their own type,
//! [`crate::registry::RegistryError`].

use core::fmt;

/// What can go wrong with received bytes: a decoder's events (framing, checksum, length) and a
/// typed parse. Encoding fails with [`EncodeError`], the registry's operations with
/// [`RegistryError`](crate::registry::RegistryError).
///
/// ```
/// use aydp_proto::{Decode, Decoder, Error, Profile};
/// let mut d = Decoder::<64>::new(Profile::Spec);
/// let mut got = Vec::new();
/// d.feed(&[0xFF, 0x89, 0x08, 0, 0, 0, 0x02, 0x7D], |e| got.push(e.err()));
/// assert!(matches!(got[0], Some(Error::ChecksumMismatch { id: 0x89, .. })));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Error {
    /// The input ends before the header or the message it announces is complete.
    Truncated,
    /// The first byte is not the 0xFF start byte.
    BadStart,
    /// The type byte is 0xFF, which is never a type (Y3, Y5).
    ReservedType,
    /// A base type above 126 was given to [`crate::message::Message::parse`] (base types are
    /// 0..=126).
    BadType(u8),
    /// The length field is below the profile minimum, beyond the decoder capacity, or does not
    /// match the bytes present.
    BadLength(u32),
    /// The XOR checksum does not match (Y4). The same fields as in every protocol crate.
    ChecksumMismatch {
        /// The type byte as received (it may itself be corrupted).
        id: u8,
        /// The XOR of the bytes from the start through the last data byte.
        computed: u16,
        /// The checksum byte carried by the message.
        received: u16,
    },
    /// The data is shorter than the message type needs.
    PayloadTooShort {
        /// Base message type.
        msg_type: u8,
        /// Minimum data length the type needs.
        expected: usize,
        /// Data length received.
        actual: usize,
    },
    /// The data is longer than the message type allows.
    PayloadTooLong {
        /// Base message type.
        msg_type: u8,
        /// Data length the type allows.
        expected: usize,
        /// Data length received.
        actual: usize,
    },
    /// A count field does not agree with the data length (fix detail, direct output).
    CountMismatch {
        /// Base message type.
        msg_type: u8,
        /// Count announced in the message.
        count: usize,
    },
    /// A `uflt16` field has its sign bit set (Y7).
    NegativeUflt16,
    /// A system value update has an update type other than 1, 2 or 3.
    UnknownUpdateMode(u8),
    /// A single-value update carries a non-zero "array size or element" field.
    NonZeroSingleIndex(u32),
    /// A system control message carries an unknown command byte.
    UnknownCommand(u8),
    /// More satellites than the caller's list can hold.
    TooManySatellites(usize),
}

impl Error {
    /// The checksum failure of `frame` (start byte through checksum byte, whose XOR is not 0).
    #[cold]
    #[inline(never)]
    pub(crate) fn mismatch(frame: &[u8]) -> Self {
        let received = frame.last().copied().unwrap_or(0);
        Error::ChecksumMismatch {
            id: frame.get(1).copied().unwrap_or(0),
            computed: u16::from(crate::checksum::xor(frame) ^ received),
            received: u16::from(received),
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Error::Truncated => f.write_str("input truncated"),
            Error::BadStart => f.write_str("missing 0xFF start byte"),
            Error::ReservedType => f.write_str("type byte 0xFF is reserved"),
            Error::BadType(t) => write!(f, "base type {t} is outside 0..=126"),
            Error::BadLength(l) => write!(f, "bad length field {l}"),
            Error::ChecksumMismatch { .. } => f.write_str("checksum mismatch"),
            Error::PayloadTooShort {
                msg_type,
                expected,
                actual,
            } => write!(
                f,
                "type {msg_type}: data too short ({actual} bytes, needs {expected})"
            ),
            Error::PayloadTooLong {
                msg_type,
                expected,
                actual,
            } => write!(
                f,
                "type {msg_type}: data too long ({actual} bytes, allows {expected})"
            ),
            Error::CountMismatch { msg_type, count } => {
                write!(
                    f,
                    "type {msg_type}: count {count} does not match the length"
                )
            }
            Error::NegativeUflt16 => f.write_str("uflt16 field has its sign bit set"),
            Error::UnknownUpdateMode(m) => write!(f, "unknown update type {m}"),
            Error::NonZeroSingleIndex(i) => {
                write!(f, "single-value update with non-zero element field {i}")
            }
            Error::UnknownCommand(c) => write!(f, "unknown system control command {c}"),
            Error::TooManySatellites(n) => write!(f, "{n} satellites do not fit the list"),
        }
    }
}

impl core::error::Error for Error {}

/// Result alias used throughout the crate.
pub type Result<T> = core::result::Result<T, Error>;

/// What encoding a message (or building its data) can fail with.
///
/// ```
/// use aydp_proto::{EncodeError, Encoder, Profile, Raw};
/// let ping = Raw { msg_type: 5, data: &[1, 2] };
/// let mut buf = [0u8; 4];
/// let e = Encoder::new(Profile::Spec).encode(&ping, None, &mut buf);
/// assert_eq!(e, Err(EncodeError::BufferTooSmall { needed: 9 }));
/// let e = Encoder::new(Profile::Reference).encode(&ping, None, &mut buf);
/// assert_eq!(e, Err(EncodeError::ExpeditedInReference));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
// 8-aligned: the encoders return `Result<usize, EncodeError>`, and with the enum's own
// alignment the expedited encode costs 5 % more on Cortex-M3 (scripts/bench-check.py).
#[repr(align(8))]
pub enum EncodeError {
    /// The output buffer is too small; `needed` bytes are required.
    BufferTooSmall {
        /// Bytes the message needs.
        needed: usize,
    },
    /// A base type above 126 was given to an encoder (base types are 0..=126).
    BadType(u8),
    /// The message data is too long for its 32-bit length field, or a list builder's count
    /// field is full.
    TooLong,
    /// An expedited header was asked of an encoder in the `Reference` profile: the AYDP
    /// reference software has no expedited header (its receiver loses the frame after one),
    /// so that profile only encodes normal messages ([`crate::Profile::has_expedited`]).
    ExpeditedInReference,
}

impl fmt::Display for EncodeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            EncodeError::BufferTooSmall { needed } => {
                write!(f, "buffer too small: {needed} bytes needed")
            }
            EncodeError::BadType(t) => write!(f, "base type {t} is outside 0..=126"),
            EncodeError::TooLong => f.write_str("message too long for the length field"),
            EncodeError::ExpeditedInReference => f.write_str(
                "the Reference profile has no expedited header: send a normal message with a timestamp",
            ),
        }
    }
}

impl core::error::Error for EncodeError {}
