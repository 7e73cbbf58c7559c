//! The errors, one type per operation: [`Error`] for what the wire gives (decoding, parsing,
//! typed values), [`EncodeError`] for encoding into a buffer, [`ClientError`] for what the
//! PC-side client's operations end with.

use core::fmt;

/// What can go wrong with received bytes and values: decoding a stream (the decoders' events),
/// parsing a frame, building a typed value. Encoding fails with [`EncodeError`], the client
/// with [`ClientError`].
///
/// ```
/// use aok_proto::{Command, CommandDecoder, Decode, Error, Motor};
/// // A typed value out of range.
/// assert_eq!(Motor::new(13), Err(Error::InvalidMotor(13)));
/// assert_eq!(Error::InvalidMotor(13).to_string(), "motor number 13 outside 1..=12");
/// // A frame cut short.
/// assert_eq!(Command::parse(&[0x73, 0x0C]), Err(Error::Truncated));
/// // A decoder's events: motor 3 at 40 with a bad checksum (00, not 1B), then a read of 12.
/// let mut decoder = CommandDecoder::new();
/// let mut events = Vec::new();
/// decoder.feed(&[0x33, 0x28, 0x00, 0x67, 0x0C], |event| events.push(event));
/// let mismatch = Error::ChecksumMismatch { id: 0x33, computed: 0x1B, received: 0x00 };
/// assert_eq!(events, [Err(mismatch), Ok(Command::ReadParameter(12))]);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
// Pointer-aligned, as it was while it had a `usize` variant: the decoders' events
// (`Option<Result<_, Error>>`) keep the layout docs/BENCHMARKS.md was measured with. Without
// it, on the byte path of that time, the one-byte figures rose 28 % on x86-64 and the slice
// path 6 % on Cortex-M3 (scripts/bench-check.py).
#[cfg_attr(target_pointer_width = "64", repr(align(8)))]
#[cfg_attr(not(target_pointer_width = "64"), repr(align(4)))]
pub enum Error {
    /// The input ends before the frame does (also: a partial frame given up at the end of the stream, by a decoder's `finish`).
    Truncated,
    /// The first byte is not the start of any frame this side understands.
    UnknownCommand(u8),
    /// The frame's XOR checksum does not match. The same fields as in every protocol crate.
    ChecksumMismatch {
        /// The frame's first byte as received (its type: `1C`, `FF`, `77`, `73`, ...; for a
        /// headerless reply, which has none, its first value byte).
        id: u8,
        /// The XOR of the bytes the checksum covers.
        computed: u16,
        /// The checksum byte carried by the frame.
        received: u16,
    },
    /// A waypoint slot byte outside 0..=31, 254 and 255.
    InvalidSlot(u8),
    /// A waypoint number outside 1..=31.
    InvalidWaypoint(u8),
    /// A motor number outside 1..=12.
    InvalidMotor(u8),
    /// A stick value outside -200..=200.
    StickOutOfRange(i16),
    /// A waypoint action code outside 0..=6.
    InvalidAction(u16),
}

/// How an operation of the PC-side [`Client`](crate::Client) failed.
///
/// ```
/// use aok_proto::ClientError;
/// assert_eq!(ClientError::Timeout.to_string(), "the device did not answer in time");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum ClientError {
    /// The configured firmware does not support the request (bulk read needs >= 0.35).
    Unsupported,
    /// The client is already running an operation.
    Busy,
    /// The device did not answer in time.
    Timeout,
    /// The device answered 'E'.
    Rejected,
    /// The device answered 'I': the parameter may not be changed in flight.
    RefusedInFlight,
    /// The serial port reported an error.
    Serial(SerialError),
}

/// A serial port error, reduced to its kind (mirrors `embedded_hal_nb::serial::ErrorKind`).
///
/// ```
/// # include!(concat!(env!("CARGO_MANIFEST_DIR"), "/src/client/doc_device.rs"));
/// # fn main() {
/// use aok_proto::{Client, ClientError, Command, Config, FirmwareVersion, SerialError};
/// use embedded_hal_nb::serial::ErrorKind;
/// // A fake device (hidden here) whose port fails every write with a framing error.
/// let mut device = FakeDevice::new();
/// device.write_error = Some(ErrorKind::FrameFormat);
/// let mut client = Client::new(device, Config::new(FirmwareVersion::LATEST));
/// let failed = client.run(Command::SaveSet(1), fake_clock());
/// assert_eq!(failed, Err(ClientError::Serial(SerialError::FrameFormat)));
/// assert_eq!(failed.unwrap_err().to_string(), "serial error: FrameFormat");
/// # }
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum SerialError {
    /// The receive buffer was overrun.
    Overrun,
    /// A framing error.
    FrameFormat,
    /// A parity error.
    Parity,
    /// Line noise.
    Noise,
    /// Any other error.
    Other,
}

impl SerialError {
    /// Reduce any `embedded-hal-nb` serial error to its kind.
    ///
    /// ```
    /// use aok_proto::SerialError;
    /// use embedded_hal_nb::serial::ErrorKind;
    /// assert_eq!(SerialError::from_hal(&ErrorKind::Parity), SerialError::Parity);
    /// ```
    pub fn from_hal<E: embedded_hal_nb::serial::Error>(e: &E) -> Self {
        use embedded_hal_nb::serial::ErrorKind as K;
        match e.kind() {
            K::Overrun => Self::Overrun,
            K::FrameFormat => Self::FrameFormat,
            K::Parity => Self::Parity,
            K::Noise => Self::Noise,
            _ => Self::Other,
        }
    }
}

impl Error {
    /// The checksum failure of `frame`, whose bytes `checked` do not XOR to its byte at
    /// `checksum` (the frame's first byte is its `id`). Cold and out of line: the decoders'
    /// hot paths only pass the frame along.
    #[cold]
    #[inline(never)]
    pub(crate) fn mismatch(
        frame: &[u8],
        checked: core::ops::Range<usize>,
        checksum: usize,
    ) -> Self {
        Error::ChecksumMismatch {
            id: frame.first().copied().unwrap_or(0),
            computed: u16::from(crate::xor(frame.get(checked).unwrap_or(&[]))),
            received: u16::from(frame.get(checksum).copied().unwrap_or(0)),
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Truncated => f.write_str("frame truncated"),
            Self::UnknownCommand(b) => write!(f, "unknown command byte 0x{b:02x}"),
            Self::ChecksumMismatch { .. } => f.write_str("checksum mismatch"),
            Self::InvalidSlot(s) => write!(f, "invalid waypoint slot {s}"),
            Self::InvalidWaypoint(n) => write!(f, "waypoint number {n} outside 1..=31"),
            Self::InvalidMotor(m) => write!(f, "motor number {m} outside 1..=12"),
            Self::StickOutOfRange(v) => write!(f, "stick value {v} outside -200..=200"),
            Self::InvalidAction(a) => write!(f, "waypoint action {a} outside 0..=6"),
        }
    }
}

impl core::error::Error for Error {}

impl fmt::Display for ClientError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Unsupported => f.write_str("not supported by the configured firmware"),
            Self::Busy => f.write_str("an operation is already running"),
            Self::Timeout => f.write_str("the device did not answer in time"),
            Self::Rejected => f.write_str("the device answered 'E'"),
            Self::RefusedInFlight => f.write_str("the device refused in flight ('I')"),
            Self::Serial(k) => write!(f, "serial error: {k:?}"),
        }
    }
}

impl core::error::Error for ClientError {}

/// What encoding into a buffer can fail with.
///
/// ```
/// use aok_proto::{Ack, EncodeError, Message, ReplyForm};
/// let mut out = [0u8; 0];
/// assert_eq!(Message::Ack(Ack::Ok).emit(&mut out, ReplyForm::Headed), Err(EncodeError::BufferTooSmall { needed: 1 }));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum EncodeError {
    /// The output buffer is too small for the frame.
    BufferTooSmall {
        /// Bytes the output needs.
        needed: usize,
    },
}

impl fmt::Display for EncodeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::BufferTooSmall { needed } => {
                write!(f, "output buffer too small: {needed} bytes needed")
            }
        }
    }
}

impl core::error::Error for EncodeError {}
