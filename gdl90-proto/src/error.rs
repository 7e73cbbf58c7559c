//! The crate's errors, one type per operation: [`Error`] for decoding, [`EncodeError`] for
//! encoding.

use core::fmt;

/// What decoding can report: deframing a stream, checking a frame, parsing a message.
///
/// Decoders report these as events and carry on: no input makes them panic.
///
/// ```
/// use gdl90_proto::{Decode, Decoder, Error};
/// let mut d = Decoder::<64>::new();
/// let mut got = Vec::new();
/// d.feed(&[0x7E, 0x00, 0x7E], |e| got.push(e.err()));
/// assert_eq!(got, [Some(Error::TooShort)]);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub enum Error {
    /// A frame grew past the decoder's capacity. Its bytes were dropped and the decoder waits
    /// for the next flag.
    Overflow,
    /// The received CRC does not match the CRC of the ID and data. GDL90 has no "no CRC"
    /// value: a received `00 00` is checked like any other CRC.
    ChecksumMismatch {
        /// The message ID as received (it may itself be corrupted).
        id: u8,
        /// The CRC computed over the received ID and data.
        computed: u16,
        /// The CRC carried by the frame.
        received: u16,
    },
    /// A frame too short to hold an ID and a CRC (1 or 2 bytes between the flags).
    TooShort,
    /// The input ended inside a frame ([`crate::Decode::finish`]).
    Truncated,
    /// An escape byte (0x7D) followed by something other than 0x5D or 0x5E.
    InvalidEscape,
    /// An escape byte (0x7D) right before a flag: the frame was aborted.
    EscapedFlag,
    /// A message this crate types arrived with the wrong number of data bytes.
    WrongLength {
        /// The message ID.
        id: u8,
        /// The data length the layout prescribes (after the ID, before the CRC; a ForeFlight
        /// sub-ID counts as data).
        expected: u16,
        /// The data length received.
        actual: u16,
    },
    /// A field holds a value its specification rules out, which rejects the whole message
    /// (ForeFlight AHRS: roll or pitch beyond ±180°, heading beyond ±360°; a report's
    /// latitude beyond ±90°).
    OutOfRange {
        /// The message ID.
        id: u8,
        /// The field, as named in this crate's types.
        field: &'static str,
    },
}

impl Error {
    /// The errors of the AEOLUS framing layer this crate reuses. Its decoder runs in its
    /// lenient mode and never reports `MissingCrc` (this crate turns an unchecked `00 00`
    /// into [`Error::ChecksumMismatch`] itself); `WrongLength` and `TextTooLong` belong to
    /// AEOLUS messages, which this crate does not use. They map to the nearest GDL90 error
    /// only to keep the conversion total.
    pub(crate) fn from_framing(e: aeolus_proto::Error) -> Self {
        use aeolus_proto::Error as A;
        match e {
            A::Overflow => Error::Overflow,
            A::ChecksumMismatch {
                id,
                computed,
                received,
            } => Error::ChecksumMismatch {
                id,
                computed,
                received,
            },
            A::MissingCrc { id } => Error::ChecksumMismatch {
                id,
                computed: 0,
                received: 0,
            },
            A::TooShort => Error::TooShort,
            A::Truncated => Error::Truncated,
            A::InvalidEscape => Error::InvalidEscape,
            A::EscapedFlag => Error::EscapedFlag,
            A::WrongLength {
                id,
                expected,
                actual,
            } => Error::WrongLength {
                id,
                expected,
                actual,
            },
            A::TextTooLong { id, len } => Error::WrongLength {
                id,
                expected: 0,
                actual: len,
            },
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Error::Overflow => f.write_str("frame longer than the decoder capacity"),
            Error::ChecksumMismatch {
                id,
                computed,
                received,
            } => write!(
                f,
                "CRC mismatch on message {id:#04x}: computed {computed:#06x}, received {received:#06x}"
            ),
            Error::TooShort => f.write_str("frame too short to hold an ID and a CRC"),
            Error::Truncated => f.write_str("input ended inside a frame"),
            Error::InvalidEscape => f.write_str("escape byte followed by an invalid byte"),
            Error::EscapedFlag => f.write_str("escape byte right before a flag (frame aborted)"),
            Error::WrongLength {
                id,
                expected,
                actual,
            } => write!(
                f,
                "message {id:#04x} has {actual} data bytes, expected {expected}"
            ),
            Error::OutOfRange { id, field } => {
                write!(f, "message {id:#04x}: {field} out of range")
            }
        }
    }
}

impl core::error::Error for Error {}

/// What encoding can fail with.
///
/// ```
/// use gdl90_proto::{message::{GeoAltitude, Message}, EncodeError};
/// let alt = GeoAltitude { altitude_ft: 1500, vertical_warning: false, vfom_m: Some(10) };
/// let mut out = [0u8; 4];
/// let e = Message::GeoAltitude(alt).encode(&mut out);
/// assert_eq!(e, Err(EncodeError::BufferTooSmall { needed: 16 }));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub enum EncodeError {
    /// The output buffer cannot hold what was asked for; a buffer of `needed` bytes does.
    BufferTooSmall {
        /// Bytes that hold the output: exactly the data's length for `emit`, the worst case
        /// ([`crate::max_encoded_len`]) for an escaped frame.
        needed: usize,
    },
}

impl EncodeError {
    /// The AEOLUS framing layer's encode error: only `BufferTooSmall` comes from framing (a
    /// text's length is checked when a text is built, which this crate never does).
    pub(crate) fn from_framing(e: aeolus_proto::EncodeError) -> Self {
        match e {
            aeolus_proto::EncodeError::BufferTooSmall { needed }
            | aeolus_proto::EncodeError::TextTooLong { len: needed } => {
                EncodeError::BufferTooSmall { needed }
            }
        }
    }
}

impl fmt::Display for EncodeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            EncodeError::BufferTooSmall { needed } => {
                write!(f, "output buffer too small: {needed} bytes needed")
            }
        }
    }
}

impl core::error::Error for EncodeError {}
