//! AOK from C, both sides: `pl_aok_device_*` reads what a PC sends (commands) and
//! `pl_aok_pc_*` reads what the device sends (messages).

use aok_proto::{
    Ack, ActionWord, Command, CommandDecoder, DebugValue, Decode, EncodeError, Error,
    ExternalControl, Message, MessageDecoder, Motor, MotorTest, ParameterValue, ReplyForm, Stick,
    Waypoint, WaypointSlot,
};

use crate::face::{self, Proto, Stream};
use crate::pl_error;
use crate::state::{self, PL_STATE_AOK_DEVICE, PL_STATE_AOK_PC};
use crate::*;

/// Bytes of the longest frame either side sends (a command, or a headed reply).
pub const PL_AOK_MAX_FRAME_LEN: usize = 19;

state::c_states! {
    PL_AOK_DECODER_WORDS = 13, PL_AOK_DECODER_SIZE = 104, PL_AOK_DECODER_ALIGN = 8,
    of "each of `pl_aok_device_decoder` and `pl_aok_pc_decoder`";
    /// The device side: decodes the commands a PC sends. Set it up with `pl_aok_device_init`.
    pl_aok_device_decoder: Stream<CommandDecoder>, PL_STATE_AOK_DEVICE;
    /// The PC side: decodes what the device sends. Set it up with `pl_aok_pc_init`.
    pl_aok_pc_decoder: Stream<MessageDecoder>, PL_STATE_AOK_PC;
}
const _: () = assert!(PL_AOK_MAX_FRAME_LEN == aok_proto::command::MAX_COMMAND_LEN);

/// Command kind: `63 01` debug off.
pub const PL_AOK_DEBUG_OFF: u8 = 0;
/// Command kind: `63 02` debug on.
pub const PL_AOK_DEBUG_ON: u8 = 1;
/// Command kind: `63 07` reset.
pub const PL_AOK_RESET: u8 = 2;
/// Command kind: `63 08` save waypoints RAM to flash.
pub const PL_AOK_SAVE_WAYPOINTS: u8 = 3;
/// Command kind: `63 09` load waypoints flash to RAM.
pub const PL_AOK_LOAD_WAYPOINTS: u8 = 4;
/// Command kind: `63 03 NUM` load parameter set `number` from flash.
pub const PL_AOK_LOAD_SET: u8 = 5;
/// Command kind: `63 04 NUM` save parameter set `number` to flash.
pub const PL_AOK_SAVE_SET: u8 = 6;
/// Command kind: `63 05 NUM` choose start set `number`.
pub const PL_AOK_START_SET: u8 = 7;
/// Command kind: `73` set parameter `number` to `value`.
pub const PL_AOK_SET_PARAMETER: u8 = 8;
/// Command kind: `67 NUM` read parameter `number`.
pub const PL_AOK_READ_PARAMETER: u8 = 9;
/// Command kind: `47 NUM` read 16 parameters from `number`.
pub const PL_AOK_BULK_READ: u8 = 10;
/// Command kind: motor test, `motor` 1..=12 at `motor_value`.
pub const PL_AOK_MOTOR_TEST: u8 = 11;
/// Command kind: `77` set a waypoint, `waypoint`.
pub const PL_AOK_SET_WAYPOINT: u8 = 12;
/// Command kind: `78 NUM` read the waypoint in slot `number` (wire byte).
pub const PL_AOK_READ_WAYPOINT: u8 = 13;
/// Command kind: `53` external control, `external`.
pub const PL_AOK_EXTERNAL_CONTROL: u8 = 14;

/// Message kind (device to PC): a debug value, `number` and `value`.
pub const PL_AOK_DEBUG: u8 = 20;
/// Message kind: an ack, `ack` ('O' ok, 'E' error, 'I' refused in flight).
pub const PL_AOK_ACK: u8 = 21;
/// Message kind: a parameter value, `number` and `value`.
pub const PL_AOK_PARAMETER: u8 = 22;
/// Message kind: a waypoint, `waypoint`.
pub const PL_AOK_WAYPOINT: u8 = 23;

/// A waypoint, POI or FBC target (DECISIONS.md K8).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct pl_aok_waypoint {
    /// Slot as on the wire: 0..=30 waypoints 1..=31, 31 mission POI, 254 RAM POI, 255 FBC.
    pub slot: u8,
    /// Longitude, raw.
    pub longitude: i32,
    /// Latitude, raw.
    pub latitude: i32,
    /// First action word (low 16 bits value + 32768, high 16 bits action).
    pub action1: u32,
    /// Second action word.
    pub action2: u32,
}

/// External control (`53`, K9): sticks -200..=200.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct pl_aok_external {
    /// Roll.
    pub roll: i16,
    /// Nick.
    pub nick: i16,
    /// Yaw.
    pub yaw: i16,
    /// Pitch (throttle), raw.
    pub pitch: i16,
    /// Expiry, ms.
    pub expiry_ms: u16,
}

/// One AOK command or message: `kind` says which fields hold it (see each `PL_AOK_*`);
/// the others are 0.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct pl_aok_item {
    /// `PL_AOK_*`.
    pub kind: u8,
    /// Parameter, set, debug value number or waypoint slot byte.
    pub number: u8,
    /// Parameter or debug value.
    pub value: i32,
    /// Motor 1..=12.
    pub motor: u8,
    /// Motor test value.
    pub motor_value: u8,
    /// Ack byte.
    pub ack: u8,
    /// Waypoint.
    pub waypoint: pl_aok_waypoint,
    /// External control.
    pub external: pl_aok_external,
    /// Decoded: bytes of the frame on the wire; 0 in an item `PL_ERROR` cleared.
    pub wire_len: u32,
    /// Decoded: where the frame starts, in bytes fed to this decoder since its init. Encode:
    /// ignored.
    pub offset: u64,
}

/// The counters of an AOK decoder (either side).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct pl_aok_stats {
    /// Frames delivered with a good checksum.
    pub frames_ok: u32,
    /// Checksum failures.
    pub checksum_errors: u32,
    /// Bytes that start no known frame.
    pub unknown_bytes: u32,
    /// Frames with a good checksum but an invalid field.
    pub invalid: u32,
    /// Frames given up (line idle).
    pub abandoned: u32,
    /// Bytes thrown away.
    pub bytes_discarded: u32,
    /// Bytes held, undecided (a frame in progress, or bytes a rescan has still to read).
    pub held_bytes: u32,
}

fn waypoint_c(w: &Waypoint) -> pl_aok_waypoint {
    pl_aok_waypoint {
        slot: w.slot.wire(),
        longitude: w.longitude,
        latitude: w.latitude,
        action1: w.action1.raw(),
        action2: w.action2.raw(),
    }
}

fn waypoint_rust(w: &pl_aok_waypoint) -> Result<Waypoint, i32> {
    Ok(Waypoint {
        slot: WaypointSlot::from_wire(w.slot).map_err(|_| PL_E_OUT_OF_RANGE)?,
        longitude: w.longitude,
        latitude: w.latitude,
        action1: ActionWord(w.action1),
        action2: ActionWord(w.action2),
    })
}

fn command_c(c: &Command) -> pl_aok_item {
    let mut i = pl_aok_item::default();
    // The commands that carry one number (a set, a parameter, a slot) give it here.
    let (kind, number) = match *c {
        Command::DebugOff => (PL_AOK_DEBUG_OFF, 0),
        Command::DebugOn => (PL_AOK_DEBUG_ON, 0),
        Command::Reset => (PL_AOK_RESET, 0),
        Command::SaveWaypoints => (PL_AOK_SAVE_WAYPOINTS, 0),
        Command::LoadWaypoints => (PL_AOK_LOAD_WAYPOINTS, 0),
        Command::LoadSet(n) => (PL_AOK_LOAD_SET, n),
        Command::SaveSet(n) => (PL_AOK_SAVE_SET, n),
        Command::StartSet(n) => (PL_AOK_START_SET, n),
        Command::SetParameter(p) => {
            i.value = p.value;
            (PL_AOK_SET_PARAMETER, p.number)
        }
        Command::ReadParameter(n) => (PL_AOK_READ_PARAMETER, n),
        Command::BulkRead(n) => (PL_AOK_BULK_READ, n),
        Command::MotorTest(m) => {
            (i.motor, i.motor_value) = (m.motor.get(), m.value);
            (PL_AOK_MOTOR_TEST, 0)
        }
        Command::SetWaypoint(w) => {
            i.waypoint = waypoint_c(&w);
            (PL_AOK_SET_WAYPOINT, 0)
        }
        Command::ReadWaypoint(s) => (PL_AOK_READ_WAYPOINT, s.wire()),
        Command::ExternalControl(e) => {
            i.external = pl_aok_external {
                roll: e.roll.get(),
                nick: e.nick.get(),
                yaw: e.yaw.get(),
                pitch: e.pitch,
                expiry_ms: e.expiry_ms,
            };
            (PL_AOK_EXTERNAL_CONTROL, 0)
        }
    };
    (i.kind, i.number) = (kind, number);
    i
}

fn command_rust(i: &pl_aok_item) -> Result<Command, i32> {
    let stick = |v: i16| Stick::new(v).map_err(|_| PL_E_OUT_OF_RANGE);
    Ok(match i.kind {
        PL_AOK_DEBUG_OFF => Command::DebugOff,
        PL_AOK_DEBUG_ON => Command::DebugOn,
        PL_AOK_RESET => Command::Reset,
        PL_AOK_SAVE_WAYPOINTS => Command::SaveWaypoints,
        PL_AOK_LOAD_WAYPOINTS => Command::LoadWaypoints,
        PL_AOK_LOAD_SET => Command::LoadSet(i.number),
        PL_AOK_SAVE_SET => Command::SaveSet(i.number),
        PL_AOK_START_SET => Command::StartSet(i.number),
        PL_AOK_SET_PARAMETER => Command::SetParameter(ParameterValue {
            number: i.number,
            value: i.value,
        }),
        PL_AOK_READ_PARAMETER => Command::ReadParameter(i.number),
        PL_AOK_BULK_READ => Command::BulkRead(i.number),
        PL_AOK_MOTOR_TEST => Command::MotorTest(MotorTest {
            motor: Motor::new(i.motor).map_err(|_| PL_E_OUT_OF_RANGE)?,
            value: i.motor_value,
        }),
        PL_AOK_SET_WAYPOINT => Command::SetWaypoint(waypoint_rust(&i.waypoint)?),
        PL_AOK_READ_WAYPOINT => {
            Command::ReadWaypoint(WaypointSlot::from_wire(i.number).map_err(|_| PL_E_OUT_OF_RANGE)?)
        }
        PL_AOK_EXTERNAL_CONTROL => Command::ExternalControl(ExternalControl {
            roll: stick(i.external.roll)?,
            nick: stick(i.external.nick)?,
            yaw: stick(i.external.yaw)?,
            pitch: i.external.pitch,
            expiry_ms: i.external.expiry_ms,
        }),
        _ => return Err(PL_E_BAD_TAG),
    })
}

fn message_c(m: &Message) -> pl_aok_item {
    let mut i = pl_aok_item::default();
    i.kind = match *m {
        Message::Debug(d) => {
            (i.number, i.value) = (d.number, d.value);
            PL_AOK_DEBUG
        }
        Message::Ack(a) => {
            i.ack = a.byte();
            PL_AOK_ACK
        }
        Message::Parameter(p) => {
            (i.number, i.value) = (p.number, p.value);
            PL_AOK_PARAMETER
        }
        Message::Waypoint(w) => {
            i.waypoint = waypoint_c(&w);
            PL_AOK_WAYPOINT
        }
    };
    i
}

/// An error as the C struct (both sides).
fn error(e: Error) -> pl_error {
    match e {
        Error::Truncated => pl_error::kind(PL_ERR_TRUNCATED),
        Error::ChecksumMismatch {
            id,
            computed,
            received,
        } => pl_error::checksum(id, computed, received),
        Error::UnknownCommand(b) => pl_error::new(PL_ERR_UNKNOWN_COMMAND, 0, 0, b.into()),
        Error::InvalidSlot(v) | Error::InvalidWaypoint(v) | Error::InvalidMotor(v) => {
            pl_error::new(PL_ERR_INVALID_VALUE, 0, 0, v.into())
        }
        Error::StickOutOfRange(v) => pl_error::new(PL_ERR_INVALID_VALUE, 0, 0, v as u16 as u32),
        Error::InvalidAction(v) => pl_error::new(PL_ERR_INVALID_VALUE, 0, 0, v.into()),
    }
}

/// Both AOK states are one `Proto` over their side's decoder; `$to_c` is the item as the C
/// struct.
macro_rules! aok_proto {
    ($state:ty, $dec:ty, $to_c:ident) => {
        impl Proto for $state {
            type Dec = $dec;
            type Msg = pl_aok_item;
            type Stats = pl_aok_stats;
            // SAFETY: integers only: all zeros is a valid value (`pl_aok_item::default()`).
            const EMPTY: pl_aok_item = unsafe { core::mem::zeroed() };

            fn fill(
                item: <$dec as Decode>::Item<'_>,
                msg: &mut pl_aok_item,
                _: &mut pl_error,
            ) -> i32 {
                *msg = $to_c(&item);
                PL_MESSAGE
            }

            fn error(e: Error) -> pl_error {
                error(e)
            }

            fn stats(d: &$dec) -> pl_aok_stats {
                face::stats! { d => pl_aok_stats {
                    frames_ok, checksum_errors, unknown_bytes, invalid, abandoned, bytes_discarded,
                } }
            }
        }
    };
}
aok_proto!(pl_aok_device_decoder, CommandDecoder, command_c);
aok_proto!(pl_aok_pc_decoder, MessageDecoder, message_c);

/// `pl_aok_pc_expect_reply`: the reply `*cmd` asks for is the one the decoder reads next.
///
/// # Safety
/// As `pl_aok_pc_expect_reply`.
pub(crate) unsafe fn expect_reply(dec: *mut pl_aok_pc_decoder, cmd: *const pl_aok_item) -> i32 {
    // SAFETY: `dec` is NULL or a state (the caller's promise), checked before it is read.
    let d = match unsafe { state::checked(dec) } {
        Ok(d) => d,
        Err(code) => return code,
    };
    // SAFETY: the caller's promises.
    let Some(cmd) = (unsafe { cmd.as_ref() }) else {
        return PL_E_NULL;
    };
    match command_rust(cmd) {
        Ok(c) => {
            d.decoder_mut().expect(c.expected_reply());
            0
        }
        Err(code) => code,
    }
}

/// `pl_aok_encode_command`: the command `*cmd` as its frame into `out`.
pub(crate) fn command_frame(cmd: &pl_aok_item, out: &mut [u8]) -> Result<usize, i32> {
    command_rust(cmd)?.emit(out).map_err(too_small)
}

/// `pl_aok_encode_message`: the device message `*msg` as its frame into `out`, a parameter
/// reply headed or not as `headed` says.
pub(crate) fn message_frame(msg: &pl_aok_item, headed: u8, out: &mut [u8]) -> Result<usize, i32> {
    let form = if headed != 0 {
        ReplyForm::Headed
    } else {
        ReplyForm::Headerless
    };
    let (number, value) = (msg.number, msg.value);
    match msg.kind {
        PL_AOK_DEBUG => Message::Debug(DebugValue { number, value }).emit(out, ReplyForm::Headed),
        PL_AOK_ACK => Message::Ack(Ack::from_byte(msg.ack).ok_or(PL_E_OUT_OF_RANGE)?)
            .emit(out, ReplyForm::Headed),
        PL_AOK_PARAMETER => Message::Parameter(ParameterValue { number, value }).emit(out, form),
        PL_AOK_WAYPOINT => {
            Message::Waypoint(waypoint_rust(&msg.waypoint)?).emit(out, ReplyForm::Headed)
        }
        _ => return Err(PL_E_BAD_TAG),
    }
    .map_err(too_small)
}

/// AOK's one encode error as its code.
fn too_small(e: EncodeError) -> i32 {
    match e {
        EncodeError::BufferTooSmall { .. } => PL_E_BUFFER_TOO_SMALL,
    }
}
