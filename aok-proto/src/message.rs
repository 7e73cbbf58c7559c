//! What the device sends: debug values, acks, parameter replies and waypoint replies. The bytes
//! of every frame are in the crate's private `layout` (published as [`Message::FRAMES`]).

use crate::command::{ParameterValue, WAYPOINT, Waypoint, copy_out};
use crate::layout::{
    ack, bytes, debug, headerless_reply as headerless, parameter_reply as reply, put, waypoint,
};
use crate::values::{Ack, ReplyForm};
use crate::{EncodeError, Error, checked_value, xor};

/// `1C`: the start of a debug-value frame.
pub const DEBUG: u8 = debug::START;
/// `FF`: the start of a parameter reply (firmware >= 0.31).
pub const PARAMETER_REPLY: u8 = reply::START;
/// Length of a debug frame.
pub const DEBUG_LEN: usize = debug::LEN;
/// Length of a headed parameter reply.
pub const HEADED_REPLY_LEN: usize = reply::LEN;
/// Length of a headerless parameter reply.
pub const HEADERLESS_REPLY_LEN: usize = headerless::LEN;
/// Length of a waypoint reply.
pub const WAYPOINT_LEN: usize = waypoint::LEN;

/// A debug value (K2): `1C NUM B1 B2 B3 B4 CRC`.
///
/// ```
/// use aok_proto::{DebugValue, Message};
/// let (message, used) = Message::parse(&[0x1C, 0x56, 0x00, 0x00, 0x00, 0x03, 0x55])?;
/// assert_eq!(message, Message::Debug(DebugValue { number: DebugValue::FLIGHT_STATUS, value: 3 }));
/// assert_eq!(used, 7);
/// # Ok::<(), aok_proto::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct DebugValue {
    /// The debug value's number (86 is the flight status).
    pub number: u8,
    /// The value.
    pub value: i32,
}

impl DebugValue {
    /// The flight status's number; always sent.
    pub const FLIGHT_STATUS: u8 = 86;

    /// The length of its frame: 7.
    ///
    /// ```
    /// assert_eq!(aok_proto::DebugValue::default().buffer_len(), 7);
    /// ```
    pub const fn buffer_len(&self) -> usize {
        DEBUG_LEN
    }

    /// Writes its debug frame (what [`Message::Debug`] emits) into `buf`; returns its length.
    /// A device streams these: the one message type it sends without being asked.
    ///
    /// ```
    /// use aok_proto::DebugValue;
    /// let mut buf = [0u8; 7];
    /// let n = DebugValue { number: 86, value: -2 }.emit(&mut buf)?;
    /// assert_eq!(&buf[..n], &[0x1c, 0x56, 0xff, 0xff, 0xff, 0xfe, 0x57]);
    /// # Ok::<(), aok_proto::EncodeError>(())
    /// ```
    ///
    /// # Errors
    /// [`EncodeError::BufferTooSmall`] if `buf` is shorter than 7 bytes.
    pub fn emit(&self, buf: &mut [u8]) -> Result<usize, EncodeError> {
        copy_out(&value_frame(DEBUG, self.number, self.value), DEBUG_LEN, buf)
    }
}

/// Everything the device sends to the PC.
///
/// ```
/// use aok_proto::{Message, DebugValue, ReplyForm};
/// let mut buf = [0u8; 19];
/// let m = Message::Debug(DebugValue { number: 86, value: -2 });
/// let n = m.emit(&mut buf, ReplyForm::Headed)?;
/// assert_eq!(&buf[..n], &[0x1c, 0x56, 0xff, 0xff, 0xff, 0xfe, 0x57]);
/// assert_eq!(Message::parse(&buf[..n])?, (m, 7));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Message {
    /// A debug value.
    Debug(DebugValue),
    /// An ack.
    Ack(Ack),
    /// A parameter reply. In the headerless form the number is not on the wire; the PC decoder
    /// fills it in from the pending request.
    Parameter(ParameterValue),
    /// A waypoint reply.
    Waypoint(Waypoint),
}

/// `HEAD NUM B1..B4 CRC` ([`debug`] and [`reply`] share the offsets); the debug CRC covers
/// NUM..B4, the parameter reply's only B1..B4 (K2, K4).
fn value_frame(head: u8, number: u8, value: i32) -> [u8; debug::LEN] {
    let mut f = [0u8; debug::LEN];
    f[0] = head;
    f[debug::NUMBER] = number;
    put!(f, debug::VALUE, value.to_be_bytes(), 4);
    f[debug::CHECKSUM] = if head == DEBUG {
        xor(&f[debug::CHECKED])
    } else {
        xor(&f[reply::CHECKED])
    };
    f
}

impl Message {
    /// The frames the device sends with a fixed layout, as the PC reads them, one
    /// [`FrameLayout`](crate::FrameLayout) each: debug value, parameter reply (firmware >=
    /// 0.31), waypoint.
    ///
    /// ```
    /// use aok_proto::Message;
    /// let names: Vec<_> = Message::FRAMES.iter().map(|f| f.name).collect();
    /// assert_eq!(names, ["DEBUG", "PARAMETER", "WAYPOINT"]);
    /// ```
    pub const FRAMES: &'static [crate::FrameLayout] = &crate::layout::DEVICE_FRAMES;

    /// The number of bytes [`Message::emit`] writes in the given reply form.
    ///
    /// ```
    /// use aok_proto::{Message, ParameterValue, ReplyForm};
    /// let m = Message::Parameter(ParameterValue { number: 12, value: 1500 });
    /// assert_eq!(m.buffer_len(ReplyForm::Headerless), 5);
    /// assert_eq!(m.buffer_len(ReplyForm::Headed), 7);
    /// ```
    pub const fn buffer_len(&self, form: ReplyForm) -> usize {
        match (self, form) {
            (Self::Debug(_), _) => DEBUG_LEN,
            (Self::Ack(_), _) => ack::LEN,
            (Self::Parameter(_), ReplyForm::Headed) => HEADED_REPLY_LEN,
            (Self::Parameter(_), ReplyForm::Headerless) => HEADERLESS_REPLY_LEN,
            (Self::Waypoint(_), _) => WAYPOINT_LEN,
        }
    }

    /// Write the message's whole frame into `buf` ([`Message::buffer_len`] bytes); returns the
    /// number of bytes written. Parameter replies take the given form (K4); the other messages
    /// have one form and ignore it. The buffer comes first and the form after it, as every
    /// `emit` and `encode` of this workspace takes its choices.
    ///
    /// ```
    /// use aok_proto::{Ack, DebugValue, EncodeError, Message, ParameterValue, ReplyForm};
    /// let m = Message::Parameter(ParameterValue { number: 12, value: 1500 });
    /// let mut buf = [0u8; 7];
    /// assert_eq!(m.emit(&mut buf, ReplyForm::Headerless)?, 5);
    /// assert_eq!(&buf[..5], &[0x00, 0x00, 0x05, 0xdc, 0xd9]);
    /// assert_eq!(m.emit(&mut buf, ReplyForm::Headed)?, 7);
    /// assert_eq!(buf, [0xff, 0x0c, 0x00, 0x00, 0x05, 0xdc, 0xd9]);
    /// // A debug value, an ack: the form changes nothing.
    /// let debug = Message::Debug(DebugValue { number: 3, value: 305419896 });
    /// assert_eq!(debug.emit(&mut buf, ReplyForm::Headed)?, 7);
    /// assert_eq!(buf, [0x1c, 0x03, 0x12, 0x34, 0x56, 0x78, 0x0b]);
    /// assert_eq!(Message::Ack(Ack::Ok).emit(&mut buf, ReplyForm::Headed)?, 1);
    /// assert_eq!(buf[0], b'O');
    /// assert_eq!(
    ///     Message::Ack(Ack::Ok).emit(&mut [], ReplyForm::Headed),
    ///     Err(EncodeError::BufferTooSmall { needed: 1 })
    /// );
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    ///
    /// # Errors
    /// [`EncodeError::BufferTooSmall`] if `buf` is shorter than [`Message::buffer_len`].
    pub fn emit(&self, buf: &mut [u8], form: ReplyForm) -> Result<usize, EncodeError> {
        match *self {
            Self::Debug(d) => d.emit(buf),
            Self::Ack(a) => copy_out(&[a.byte()], ack::LEN, buf),
            Self::Parameter(p) => {
                let f = value_frame(PARAMETER_REPLY, p.number, p.value);
                match form {
                    ReplyForm::Headed => copy_out(&f, HEADED_REPLY_LEN, buf),
                    // The headerless reply is the headed one without `FF NUM`.
                    ReplyForm::Headerless => {
                        copy_out(&f[reply::VALUE..], HEADERLESS_REPLY_LEN, buf)
                    }
                }
            }
            Self::Waypoint(w) => copy_out(&w.frame(), WAYPOINT_LEN, buf),
        }
    }

    /// Parse the self-describing message at the start of `bytes`: a debug frame, an ack byte, a
    /// headed parameter reply or a waypoint reply. Returns it and the bytes it took.
    ///
    /// The headerless (<= 0.30) reply has no header; read it with [`ParameterValue::parse_headerless`].
    ///
    /// ```
    /// use aok_proto::{Message, ParameterValue};
    /// let bytes = [0xff, 0x0c, 0x00, 0x00, 0x05, 0xdc, 0xd9];
    /// assert_eq!(Message::parse(&bytes)?,
    ///            (Message::Parameter(ParameterValue { number: 12, value: 1500 }), 7));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn parse(bytes: &[u8]) -> Result<(Self, usize), Error> {
        let first = *bytes.first().ok_or(Error::Truncated)?;
        match first {
            DEBUG => {
                let f = fixed7(bytes)?;
                let (number, value) = checked_value(f).ok_or_else(|| {
                    use crate::layout::debug::{CHECKED, CHECKSUM};
                    Error::mismatch(f, CHECKED, CHECKSUM)
                })?;
                Ok((Self::Debug(DebugValue { number, value }), DEBUG_LEN))
            }
            PARAMETER_REPLY => {
                let f = fixed7(bytes)?;
                if xor(&f[reply::CHECKED]) != f[reply::CHECKSUM] {
                    return Err(Error::mismatch(f, reply::CHECKED, reply::CHECKSUM));
                }
                Ok((
                    Self::Parameter(ParameterValue {
                        number: f[reply::NUMBER],
                        value: i32::from_be_bytes(bytes!(f, reply::VALUE, 4)),
                    }),
                    HEADED_REPLY_LEN,
                ))
            }
            WAYPOINT => {
                let f = bytes
                    .get(..WAYPOINT_LEN)
                    .and_then(|s| <&[u8; WAYPOINT_LEN]>::try_from(s).ok())
                    .ok_or(Error::Truncated)?;
                Ok((Self::Waypoint(Waypoint::from_frame(f)?), WAYPOINT_LEN))
            }
            _ => match Ack::from_byte(first) {
                Some(a) => Ok((Self::Ack(a), ack::LEN)),
                None => Err(Error::UnknownCommand(first)),
            },
        }
    }
}

/// The device's answer to a bulk read `47 NUM` (firmware >= 0.35): the 16 headed parameter
/// replies for parameters `first`..`first + 15` (numbers wrap past 255), one after the other.
///
/// ```
/// use aok_proto::message::BulkReply;
/// let reply = BulkReply { first: 10, values: [7; 16] };
/// let mut buf = [0u8; BulkReply::LEN];
/// assert_eq!(reply.emit(&mut buf)?, 112);
/// assert_eq!(&buf[..7], &[0xff, 10, 0, 0, 0, 7, 7]);
/// assert_eq!(&buf[105..107], &[0xff, 25]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct BulkReply {
    /// The number of the first parameter, NUM of the request.
    pub first: u8,
    /// The values of parameters `first`..`first + 15`.
    pub values: [i32; 16],
}

impl BulkReply {
    /// The length of the 16 replies: 112 bytes.
    ///
    /// ```
    /// use aok_proto::{BulkReply, message::HEADED_REPLY_LEN};
    /// assert_eq!(BulkReply::LEN, 16 * HEADED_REPLY_LEN);
    /// ```
    pub const LEN: usize = HEADED_REPLY_LEN * 16;

    /// The number of bytes [`BulkReply::emit`] writes: [`BulkReply::LEN`].
    ///
    /// ```
    /// use aok_proto::message::BulkReply;
    /// assert_eq!(BulkReply { first: 0, values: [0; 16] }.buffer_len(), 112);
    /// ```
    pub const fn buffer_len(&self) -> usize {
        Self::LEN
    }

    /// Write the 16 replies into `buf`; returns [`BulkReply::LEN`].
    ///
    /// ```
    /// use aok_proto::{EncodeError, message::BulkReply};
    /// let reply = BulkReply { first: 0, values: [1; 16] };
    /// let mut buf = [0xAA; 111];
    /// assert_eq!(reply.emit(&mut buf), Err(EncodeError::BufferTooSmall { needed: 112 }));
    /// assert_eq!(buf, [0xAA; 111]); // nothing written
    /// ```
    ///
    /// # Errors
    /// [`EncodeError::BufferTooSmall`] if `buf` is shorter than [`BulkReply::LEN`]; `buf` is
    /// then untouched.
    pub fn emit(&self, buf: &mut [u8]) -> Result<usize, EncodeError> {
        let out = buf
            .get_mut(..Self::LEN)
            .ok_or(EncodeError::BufferTooSmall { needed: Self::LEN })?;
        let mut number = self.first;
        for (chunk, &value) in out.chunks_exact_mut(HEADED_REPLY_LEN).zip(&self.values) {
            Message::Parameter(ParameterValue { number, value }).emit(chunk, ReplyForm::Headed)?;
            number = number.wrapping_add(1);
        }
        Ok(Self::LEN)
    }
}

fn fixed7(bytes: &[u8]) -> Result<&[u8; debug::LEN], Error> {
    bytes
        .get(..debug::LEN)
        .and_then(|s| <&[u8; debug::LEN]>::try_from(s).ok())
        .ok_or(Error::Truncated)
}

impl ParameterValue {
    /// Parse a headerless (firmware <= 0.30) reply `B1 B2 B3 B4 CRC`; the number comes from the request.
    ///
    /// ```
    /// use aok_proto::ParameterValue;
    /// let p = ParameterValue::parse_headerless(&[0x00, 0x00, 0x05, 0xdc, 0xd9], 12)?;
    /// assert_eq!(p, ParameterValue { number: 12, value: 1500 });
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn parse_headerless(bytes: &[u8], number: u8) -> Result<Self, Error> {
        let f = bytes
            .get(..HEADERLESS_REPLY_LEN)
            .and_then(|s| <&[u8; HEADERLESS_REPLY_LEN]>::try_from(s).ok())
            .ok_or(Error::Truncated)?;
        if xor(&f[headerless::CHECKED]) != f[headerless::CHECKSUM] {
            return Err(Error::mismatch(
                f,
                headerless::CHECKED,
                headerless::CHECKSUM,
            ));
        }
        Ok(Self {
            number,
            value: i32::from_be_bytes(bytes!(f, headerless::VALUE, 4)),
        })
    }
}
