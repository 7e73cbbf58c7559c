//! The encoders of both sides: [`encode_command`] (the PC's commands, and the ready-made
//! [`DEBUG_OFF`] and [`DEBUG_ON`]) and the device's replies ([`encode_debug`],
//! [`encode_ack`], [`encode_parameter`], [`encode_bulk`], [`encode_waypoint`]). Each writes
//! into `buf` and returns the bytes written, or [`EncodeError::BufferTooSmall`].

use crate::EncodeError;
use crate::command::{Command, ParameterValue, Waypoint};
use crate::message::{DebugValue, HEADED_REPLY_LEN, Message};
use crate::values::{Ack, ReplyForm};

/// `63 01`, debug off, ready to send.
///
/// ```
/// use aok_proto::{Command, DEBUG_OFF};
/// assert_eq!(Command::parse(&DEBUG_OFF), Ok((Command::DebugOff, 2)));
/// ```
pub const DEBUG_OFF: [u8; 2] = [0x63, 0x01];
/// `63 02`, debug on, ready to send.
///
/// ```
/// use aok_proto::{Command, DEBUG_ON};
/// assert_eq!(Command::parse(&DEBUG_ON), Ok((Command::DebugOn, 2)));
/// ```
pub const DEBUG_ON: [u8; 2] = [0x63, 0x02];

/// Encode any command (the same as [`Command::emit`]): the PC side.
///
/// ```
/// use aok_proto::{encode_command, Command, ParameterValue};
/// let mut buf = [0u8; 19];
/// let n = encode_command(&Command::SetParameter(ParameterValue { number: 12, value: 1500 }), &mut buf)?;
/// assert_eq!(&buf[..n], &[0x73, 0x0c, 0x00, 0x00, 0x05, 0xdc, 0xd5]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn encode_command(command: &Command, buf: &mut [u8]) -> Result<usize, EncodeError> {
    command.emit(buf)
}

/// Encode a debug value frame `1C NUM B1..B4 CRC`.
///
/// ```
/// use aok_proto::{encode_debug, DebugValue};
/// let mut buf = [0u8; 7];
/// encode_debug(DebugValue { number: 3, value: 305419896 }, &mut buf)?;
/// assert_eq!(buf, [0x1c, 0x03, 0x12, 0x34, 0x56, 0x78, 0x0b]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn encode_debug(value: DebugValue, buf: &mut [u8]) -> Result<usize, EncodeError> {
    Message::Debug(value).emit(ReplyForm::Headed, buf)
}

/// Encode a single-byte ack.
///
/// ```
/// let mut buf = [0u8; 1];
/// aok_proto::encode_ack(aok_proto::Ack::Ok, &mut buf)?;
/// assert_eq!(buf, [b'O']);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn encode_ack(ack: Ack, buf: &mut [u8]) -> Result<usize, EncodeError> {
    Message::Ack(ack).emit(ReplyForm::Headed, buf)
}

/// Encode a parameter reply in the given firmware form (K4).
///
/// ```
/// use aok_proto::{encode_parameter, ParameterValue, ReplyForm};
/// let mut buf = [0u8; 7];
/// let p = ParameterValue { number: 12, value: 1500 };
/// assert_eq!(encode_parameter(p, ReplyForm::Headed, &mut buf)?, 7);
/// assert_eq!(buf, [0xff, 0x0c, 0x00, 0x00, 0x05, 0xdc, 0xd9]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn encode_parameter(
    value: ParameterValue,
    form: ReplyForm,
    buf: &mut [u8],
) -> Result<usize, EncodeError> {
    Message::Parameter(value).emit(form, buf)
}

/// Encode the 16 replies to a bulk read `47 NUM`: parameters NUM..NUM+15 (numbers wrap at 255), in the
/// headed form (bulk read exists only from 0.35). Needs 112 bytes.
///
/// ```
/// let mut buf = [0u8; 112];
/// let n = aok_proto::encode_bulk(10, &[7; 16], &mut buf)?;
/// assert_eq!(n, 112);
/// assert_eq!(&buf[..7], &[0xff, 10, 0, 0, 0, 7, 7]);
/// assert_eq!(buf[105], 0xff);
/// assert_eq!(buf[106], 25);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn encode_bulk(first: u8, values: &[i32; 16], buf: &mut [u8]) -> Result<usize, EncodeError> {
    let out = buf
        .get_mut(..HEADED_REPLY_LEN * 16)
        .ok_or(EncodeError::BufferTooSmall {
            needed: HEADED_REPLY_LEN * 16,
        })?;
    let mut number = first;
    for (chunk, &value) in out.chunks_exact_mut(HEADED_REPLY_LEN).zip(values) {
        Message::Parameter(ParameterValue { number, value }).emit(ReplyForm::Headed, chunk)?;
        number = number.wrapping_add(1);
    }
    Ok(HEADED_REPLY_LEN * 16)
}

/// Encode the waypoint reply (the same `77` frame the PC sends to set one).
///
/// ```
/// use aok_proto::{encode_waypoint, ActionWord, Waypoint, WaypointSlot};
/// let w = Waypoint { slot: WaypointSlot::FbcTarget, longitude: 1, latitude: 2,
///                    action1: ActionWord::NONE, action2: ActionWord::NONE };
/// let mut buf = [0u8; 19];
/// assert_eq!(encode_waypoint(&w, &mut buf)?, 19);
/// assert_eq!(&buf[..2], &[0x77, 0xff]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn encode_waypoint(waypoint: &Waypoint, buf: &mut [u8]) -> Result<usize, EncodeError> {
    Message::Waypoint(*waypoint).emit(ReplyForm::Headed, buf)
}
