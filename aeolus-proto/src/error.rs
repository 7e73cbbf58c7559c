//! The crate's errors, one type per operation: [`Error`] for decoding, [`EncodeError`] for
//! building and encoding what is sent.

use core::fmt;

/// What decoding can report: deframing a stream or a datagram, checking a frame, parsing a
/// message.
///
/// Decoders report these and carry on: no input makes them panic.
///
/// ```
/// use aeolus_proto::{Decode, Decoder, Error};
/// let mut d = Decoder::<64>::new();
/// let mut got = Vec::new();
/// d.feed(&[0x7E, 0x52, b'h', b'i', 0, 0x00, 0x01, 0x7E], |e| got.push(e.err()));
/// assert!(matches!(got[0], Some(Error::ChecksumMismatch { id: 82, .. })));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Error {
    /// A frame grew past the decoder's capacity. Its bytes were dropped and the decoder
    /// waits for the next flag.
    Overflow,
    /// The received CRC does not match the CRC of the ID and data.
    ChecksumMismatch {
        /// The message ID as received (it may itself be corrupted).
        id: u8,
        /// The CRC computed over the received ID and data.
        computed: u16,
        /// The CRC carried by the frame.
        received: u16,
    },
    /// Strict mode: the frame carries `00 00` instead of a CRC.
    MissingCrc {
        /// The message ID as received.
        id: u8,
    },
    /// A frame too short to hold an ID and a CRC (1 or 2 bytes between the flags).
    TooShort,
    /// An escape byte (0x7D) followed by something other than 0x5D or 0x5E.
    InvalidEscape,
    /// An escape byte (0x7D) right before a flag: the frame was aborted.
    EscapedFlag,
    /// A datagram or a stream ([`crate::Decode::finish`]) ended inside a frame (no closing
    /// flag).
    Truncated,
    /// A known fixed-size message ID arrived with the wrong number of data bytes.
    WrongLength {
        /// The message ID.
        id: u8,
        /// The data length the spec prescribes for this ID.
        expected: u16,
        /// The data length received.
        actual: u16,
    },
    /// A TOAST or COMMAND text is longer than [`crate::TEXT_CAPACITY`].
    TextTooLong {
        /// The message ID.
        id: u8,
        /// The length of the received text.
        len: u16,
    },
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
                "CRC mismatch on message {id}: computed {computed:#06x}, received {received:#06x}"
            ),
            Error::MissingCrc { id } => write!(f, "message {id} carries no CRC (strict mode)"),
            Error::TooShort => f.write_str("frame too short to hold an ID and a CRC"),
            Error::InvalidEscape => f.write_str("escape byte followed by an invalid byte"),
            Error::EscapedFlag => f.write_str("escape byte right before a flag (frame aborted)"),
            Error::Truncated => f.write_str("datagram ends inside a frame"),
            Error::WrongLength {
                id,
                expected,
                actual,
            } => write!(
                f,
                "message {id} has {actual} data bytes, expected {expected}"
            ),
            Error::TextTooLong { id, len } => write!(
                f,
                "message {id} carries a {len}-byte text, more than {} allowed",
                crate::TEXT_CAPACITY
            ),
        }
    }
}

impl core::error::Error for Error {}

/// What building or encoding a message to send can fail with.
///
/// ```
/// use aeolus_proto::{message::Text, EncodeError};
/// let e = Text::new(&"x".repeat(300)).unwrap_err();
/// assert_eq!(e, EncodeError::TextTooLong { len: 300 });
/// let mut out = [0u8; 2];
/// assert_eq!(Text::new("hi").unwrap().emit(&mut out), Err(EncodeError::BufferTooSmall { needed: 3 }));
/// assert_eq!(e.to_string(), "a 300-byte text, more than 120 allowed");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum EncodeError {
    /// The output buffer cannot hold what was asked for; a buffer of `needed` bytes does.
    BufferTooSmall {
        /// Bytes that hold the output: exactly the data's length for `emit`, the worst case
        /// ([`crate::max_encoded_len`]) for an escaped frame.
        needed: usize,
    },
    /// A TOAST or COMMAND text given to [`crate::message::Text::new`] is longer than
    /// [`crate::TEXT_CAPACITY`].
    TextTooLong {
        /// The text's length in bytes.
        len: usize,
    },
}

impl fmt::Display for EncodeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            EncodeError::BufferTooSmall { needed } => {
                write!(f, "output buffer too small: {needed} bytes needed")
            }
            EncodeError::TextTooLong { len } => write!(
                f,
                "a {len}-byte text, more than {} allowed",
                crate::TEXT_CAPACITY
            ),
        }
    }
}

impl core::error::Error for EncodeError {}
