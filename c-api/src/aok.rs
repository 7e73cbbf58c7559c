//! AOK from C, both sides: `pl_aok_device_*` reads what a PC sends (commands) and
//! `pl_aok_pc_*` reads what the device sends (messages).

use aok_proto::{
    Ack, ActionWord, Command, CommandDecoder, DebugValue, Decode, EncodeError, Error,
    ExternalControl, FirmwareVersion, Message, MessageDecoder, Motor, MotorTest, ParameterValue,
    ReplyForm, Stick, Waypoint, WaypointSlot,
};

use crate::face::{self, Proto, Stream};
use crate::ffi::{self, pl_error};
use crate::state::{self, State};
use crate::*;

/// 64-bit words in a `pl_aok_device_decoder` and in a `pl_aok_pc_decoder`.
pub const PL_AOK_DECODER_WORDS: usize = 13;
/// Size of `pl_aok_device_decoder` and of `pl_aok_pc_decoder` in bytes: the tag and the
/// decoder (an upper bound over the supported targets).
pub const PL_AOK_DECODER_SIZE: usize = 104;
/// Alignment of the AOK decoders in bytes.
pub const PL_AOK_DECODER_ALIGN: usize = 8;
/// Bytes of the longest frame either side sends (a command, or a headed reply).
pub const PL_AOK_MAX_FRAME_LEN: usize = 19;

/// The device side: decodes the commands a PC sends. Set it up with `pl_aok_device_init`.
#[repr(C)]
pub struct pl_aok_device_decoder {
    /// Opaque.
    pub opaque: [u64; PL_AOK_DECODER_WORDS],
}

/// The PC side: decodes what the device sends. Set it up with `pl_aok_pc_init`.
#[repr(C)]
pub struct pl_aok_pc_decoder {
    /// Opaque.
    pub opaque: [u64; PL_AOK_DECODER_WORDS],
}

// SAFETY: plain words; `fits` is asserted below; the kind is this state's alone.
unsafe impl State for pl_aok_device_decoder {
    type Inner = Stream<CommandDecoder>;
    const KIND: u32 = state::PL_STATE_AOK_DEVICE;
}
const _: () = assert!(state::fits::<pl_aok_device_decoder>());
// SAFETY: plain words; `fits` is asserted below; the kind is this state's alone.
unsafe impl State for pl_aok_pc_decoder {
    type Inner = Stream<MessageDecoder>;
    const KIND: u32 = state::PL_STATE_AOK_PC;
}
const _: () = assert!(state::fits::<pl_aok_pc_decoder>());
const _: () = assert!(PL_AOK_DECODER_SIZE == core::mem::size_of::<pl_aok_pc_decoder>());
const _: () = assert!(core::mem::align_of::<MessageDecoder>() <= PL_AOK_DECODER_ALIGN);
const _: () = assert!(core::mem::align_of::<CommandDecoder>() <= PL_AOK_DECODER_ALIGN);
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
    i.kind = match *c {
        Command::DebugOff => PL_AOK_DEBUG_OFF,
        Command::DebugOn => PL_AOK_DEBUG_ON,
        Command::Reset => PL_AOK_RESET,
        Command::SaveWaypoints => PL_AOK_SAVE_WAYPOINTS,
        Command::LoadWaypoints => PL_AOK_LOAD_WAYPOINTS,
        Command::LoadSet(n) => {
            i.number = n;
            PL_AOK_LOAD_SET
        }
        Command::SaveSet(n) => {
            i.number = n;
            PL_AOK_SAVE_SET
        }
        Command::StartSet(n) => {
            i.number = n;
            PL_AOK_START_SET
        }
        Command::SetParameter(p) => {
            (i.number, i.value) = (p.number, p.value);
            PL_AOK_SET_PARAMETER
        }
        Command::ReadParameter(n) => {
            i.number = n;
            PL_AOK_READ_PARAMETER
        }
        Command::BulkRead(n) => {
            i.number = n;
            PL_AOK_BULK_READ
        }
        Command::MotorTest(m) => {
            (i.motor, i.motor_value) = (m.motor.get(), m.value);
            PL_AOK_MOTOR_TEST
        }
        Command::SetWaypoint(w) => {
            i.waypoint = waypoint_c(&w);
            PL_AOK_SET_WAYPOINT
        }
        Command::ReadWaypoint(s) => {
            i.number = s.wire();
            PL_AOK_READ_WAYPOINT
        }
        Command::ExternalControl(e) => {
            i.external = pl_aok_external {
                roll: e.roll.get(),
                nick: e.nick.get(),
                yaw: e.yaw.get(),
                pitch: e.pitch,
                expiry_ms: e.expiry_ms,
            };
            PL_AOK_EXTERNAL_CONTROL
        }
    };
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

fn error(e: Error) -> pl_error {
    match e {
        Error::Truncated => pl_error::kind(PL_ERR_TRUNCATED),
        Error::ChecksumMismatch {
            id,
            computed,
            received,
        } => pl_error::new(
            PL_ERR_CHECKSUM_MISMATCH,
            id.into(),
            computed.into(),
            received.into(),
        ),
        Error::UnknownCommand(b) => pl_error::new(PL_ERR_UNKNOWN_COMMAND, 0, 0, b.into()),
        Error::InvalidSlot(v) | Error::InvalidWaypoint(v) | Error::InvalidMotor(v) => {
            pl_error::new(PL_ERR_INVALID_VALUE, 0, 0, v.into())
        }
        Error::StickOutOfRange(v) => pl_error::new(PL_ERR_INVALID_VALUE, 0, 0, v as u16 as u32),
        Error::InvalidAction(v) => pl_error::new(PL_ERR_INVALID_VALUE, 0, 0, v.into()),
    }
}

/// The two sides' decoders, each with its item's C conversion.
trait Side: Decode<Error = Error> {
    /// The form of the replies the decoder reads (the device side reads commands: any).
    fn form(&self) -> ReplyForm;
    /// The item as the C struct.
    fn to_c(item: Self::Item<'_>, form: ReplyForm) -> pl_aok_item;
}

impl Side for CommandDecoder {
    fn form(&self) -> ReplyForm {
        ReplyForm::Headed
    }

    fn to_c(c: Command, _: ReplyForm) -> pl_aok_item {
        command_c(&c)
    }
}

impl Side for MessageDecoder {
    fn form(&self) -> ReplyForm {
        self.reply_form()
    }

    fn to_c(m: Message, _: ReplyForm) -> pl_aok_item {
        message_c(&m)
    }
}

/// Both AOK states are one `Proto` over their side's decoder.
macro_rules! aok_proto {
    ($state:ty, $dec:ty) => {
        impl Proto for $state {
            type Dec = $dec;
            type Msg = pl_aok_item;
            type Stats = pl_aok_stats;
            type Ctx = ReplyForm;

            fn empty() -> pl_aok_item {
                pl_aok_item::default()
            }

            fn context(d: &$dec) -> ReplyForm {
                d.form()
            }

            fn fill(
                item: <$dec as Decode>::Item<'_>,
                form: ReplyForm,
                msg: &mut pl_aok_item,
                _: &mut pl_error,
            ) -> i32 {
                *msg = <$dec>::to_c(item, form);
                PL_MESSAGE
            }

            fn error(e: Error) -> pl_error {
                error(e)
            }

            fn place(msg: &mut pl_aok_item, offset: u64, wire_len: u32) {
                (msg.offset, msg.wire_len) = (offset, wire_len);
            }

            fn stats(d: &$dec) -> pl_aok_stats {
                let s = d.stats();
                pl_aok_stats {
                    frames_ok: s.frames_ok,
                    checksum_errors: s.checksum_errors,
                    unknown_bytes: s.unknown_bytes,
                    invalid: s.invalid,
                    abandoned: s.abandoned,
                    bytes_discarded: s.bytes_discarded,
                    held_bytes: ffi::sat32(d.held_bytes()),
                }
            }
        }
    };
}
aok_proto!(pl_aok_device_decoder, CommandDecoder);
aok_proto!(pl_aok_pc_decoder, MessageDecoder);

/// Sets up the device side's decoder. Returns 0, `PL_E_NULL` or `PL_E_INVALID` (`dec` not
/// aligned for its type).
///
/// ```c
/// pl_aok_device_decoder dec;
/// pl_aok_device_init(&dec);
/// ```
///
/// # Safety
/// `dec` is NULL or points to writable memory for a `pl_aok_device_decoder`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_aok_device_init(dec: *mut pl_aok_device_decoder) -> i32 {
    // SAFETY: the caller's promise.
    unsafe { face::init(dec, CommandDecoder::new()) }
}

/// Device side: decodes the PC's bytes `bytes[..len]` up to the next event, as
/// `pl_aeolus_parse` (`*cmd` holds a command; a rescan's further events come first with
/// `*used` 0: call until `PL_NOTHING`). `PL_ERROR` clears `*cmd`.
///
/// ```c
/// size_t off = 0, used;
/// int32_t st;
/// while ((st = pl_aok_device_parse(&dec, buf + off, len - off, &used, &cmd, &err)) > 0) {
///     off += used;
///     if (st == PL_MESSAGE && cmd.kind == PL_AOK_RESET) reboot();
/// }
/// ```
///
/// # Safety
/// `dec` is NULL or points to a `pl_aok_device_decoder` (one `pl_aok_device_init` did not set
/// up gets `PL_E_INVALID`) that nothing else uses during the call; `bytes` is NULL (with `len`
/// 0) or readable for `len` bytes; `used`, `cmd` and `err` are NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_aok_device_parse(
    dec: *mut pl_aok_device_decoder,
    bytes: *const u8,
    len: usize,
    used: *mut usize,
    cmd: *mut pl_aok_item,
    err: *mut pl_error,
) -> i32 {
    // SAFETY: the caller's promises.
    unsafe { face::parse(dec, bytes, len, used, cmd, err) }
}

/// Device side: decodes all of `bytes[..len]` and calls `on_event(ctx, ...)` for every event,
/// in order (exactly those of `pl_aok_device_parse`). Returns `PL_NOTHING`, `PL_E_NULL` or
/// `PL_E_INVALID`.
///
/// ```c
/// pl_aok_device_feed(&dec, rx_buf, n, on_command, &app);
/// ```
///
/// # Safety
/// `dec` is NULL or points to a `pl_aok_device_decoder` (one `pl_aok_device_init` did not set up
/// gets `PL_E_INVALID`); `bytes` is NULL (with `len` 0) or readable for `len` bytes; `on_event` may
/// be called with `ctx` and does not use `dec`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_aok_device_feed(
    dec: *mut pl_aok_device_decoder,
    bytes: *const u8,
    len: usize,
    on_event: pl_aok_callback,
    ctx: *mut core::ffi::c_void,
) -> i32 {
    // SAFETY: the caller's promises.
    unsafe { face::feed(dec, bytes, len, on_event, ctx) }
}

/// Device side: the PC's stream ended or its line went quiet: a partial command is given up
/// (`PL_ERR_TRUNCATED`) and what followed it rescanned. One event per call; call until
/// `PL_NOTHING`.
///
/// ```c
/// while ((st = pl_aok_device_finish(&dec, &cmd, &err)) > 0) if (st == PL_MESSAGE) run(&cmd);
/// ```
///
/// # Safety
/// As `pl_aok_device_parse`, for `dec`, `cmd` and `err`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_aok_device_finish(
    dec: *mut pl_aok_device_decoder,
    cmd: *mut pl_aok_item,
    err: *mut pl_error,
) -> i32 {
    // SAFETY: the caller's promises.
    unsafe { face::finish(dec, cmd, err) }
}

/// Device side: the decoder's counters. Returns 0, `PL_E_NULL` or `PL_E_INVALID`.
///
/// ```c
/// pl_aok_stats st;
/// pl_aok_device_get_stats(&dec, &st);
/// ```
///
/// # Safety
/// `dec` is NULL or points to a `pl_aok_device_decoder` (one `pl_aok_device_init` did not set up
/// gets `PL_E_INVALID`); `stats` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_aok_device_get_stats(
    dec: *const pl_aok_device_decoder,
    stats: *mut pl_aok_stats,
) -> i32 {
    // SAFETY: the caller's promises.
    unsafe { face::get_stats(dec, stats) }
}

/// Sets up the PC side's decoder for a device running firmware `major.minor` (<= 0.30 sends
/// headerless parameter replies, >= 0.31 headed ones; DECISIONS.md K4). Returns 0, `PL_E_NULL`
/// or `PL_E_INVALID` (`dec` not aligned for its type).
///
/// ```c
/// pl_aok_pc_decoder dec;
/// pl_aok_pc_init(&dec, 0, 35);
/// ```
///
/// # Safety
/// `dec` is NULL or points to writable memory for a `pl_aok_pc_decoder`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_aok_pc_init(dec: *mut pl_aok_pc_decoder, major: u8, minor: u8) -> i32 {
    // SAFETY: the caller's promise.
    unsafe { face::init(dec, MessageDecoder::new(FirmwareVersion::new(major, minor))) }
}

/// PC side: tell the decoder which reply the command just sent asks for (an ack, a parameter,
/// 16 parameters, a waypoint), so that it reads the device's answer. Returns 0, `PL_E_NULL`,
/// `PL_E_INVALID` (`dec`), `PL_E_BAD_TAG` or `PL_E_OUT_OF_RANGE` (as `pl_aok_encode_command`).
///
/// ```c
/// pl_aok_item get = { .kind = PL_AOK_READ_PARAMETER, .number = 12 };
/// n = pl_aok_encode_command(&get, buf, sizeof buf);
/// uart_write(buf, n);
/// pl_aok_pc_expect_reply(&dec, &get);
/// ```
///
/// # Safety
/// `dec` is NULL or points to a `pl_aok_pc_decoder` (one `pl_aok_pc_init` did not set up gets
/// `PL_E_INVALID`); `cmd` is NULL or readable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_aok_pc_expect_reply(
    dec: *mut pl_aok_pc_decoder,
    cmd: *const pl_aok_item,
) -> i32 {
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

/// PC side: decodes the device's bytes `bytes[..len]` up to the next event, as
/// `pl_aok_device_parse` (`*msg` holds a debug value, an ack, a parameter or a waypoint).
///
/// ```c
/// size_t off = 0, used;
/// int32_t st;
/// while ((st = pl_aok_pc_parse(&dec, buf + off, len - off, &used, &msg, &err)) > 0) {
///     off += used;
///     if (st == PL_MESSAGE && msg.kind == PL_AOK_DEBUG) plot(msg.number, msg.value);
/// }
/// ```
///
/// # Safety
/// As `pl_aok_device_parse`, with a `pl_aok_pc_decoder`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_aok_pc_parse(
    dec: *mut pl_aok_pc_decoder,
    bytes: *const u8,
    len: usize,
    used: *mut usize,
    msg: *mut pl_aok_item,
    err: *mut pl_error,
) -> i32 {
    // SAFETY: the caller's promises.
    unsafe { face::parse(dec, bytes, len, used, msg, err) }
}

/// PC side: decodes all of `bytes[..len]`, `on_event(ctx, ...)` for every event in order
/// (exactly those of `pl_aok_pc_parse`). Returns `PL_NOTHING`, `PL_E_NULL` or `PL_E_INVALID`.
///
/// ```c
/// pl_aok_pc_feed(&dec, rx_buf, n, on_message, &app);
/// ```
///
/// # Safety
/// As `pl_aok_device_feed`, with a `pl_aok_pc_decoder`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_aok_pc_feed(
    dec: *mut pl_aok_pc_decoder,
    bytes: *const u8,
    len: usize,
    on_event: pl_aok_callback,
    ctx: *mut core::ffi::c_void,
) -> i32 {
    // SAFETY: the caller's promises.
    unsafe { face::feed(dec, bytes, len, on_event, ctx) }
}

/// PC side: the device's stream ended or its line went quiet; one event per call, call until
/// `PL_NOTHING` (as `pl_aok_device_finish`).
///
/// ```c
/// while ((st = pl_aok_pc_finish(&dec, &msg, &err)) > 0) if (st == PL_MESSAGE) handle(&msg);
/// ```
///
/// # Safety
/// As `pl_aok_device_parse`, with a `pl_aok_pc_decoder`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_aok_pc_finish(
    dec: *mut pl_aok_pc_decoder,
    msg: *mut pl_aok_item,
    err: *mut pl_error,
) -> i32 {
    // SAFETY: the caller's promises.
    unsafe { face::finish(dec, msg, err) }
}

/// PC side: the decoder's counters. Returns 0, `PL_E_NULL` or `PL_E_INVALID`.
///
/// ```c
/// pl_aok_stats st;
/// pl_aok_pc_get_stats(&dec, &st);
/// ```
///
/// # Safety
/// As `pl_aok_device_get_stats`, with a `pl_aok_pc_decoder`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_aok_pc_get_stats(
    dec: *const pl_aok_pc_decoder,
    stats: *mut pl_aok_stats,
) -> i32 {
    // SAFETY: the caller's promises.
    unsafe { face::get_stats(dec, stats) }
}

/// An event callback of `pl_aok_device_feed` and `pl_aok_pc_feed`: `status` is `PL_MESSAGE`
/// (`*item` holds the command or message) or `PL_ERROR` (`*err`; `*item` cleared). Both
/// pointers are valid only during the call.
pub type pl_aok_callback = Option<
    unsafe extern "C" fn(
        ctx: *mut core::ffi::c_void,
        status: i32,
        item: *const pl_aok_item,
        err: *const pl_error,
    ),
>;
/// Encodes a command (PC to device) into `out[..cap]`. Returns its length, or `PL_E_NULL`,
/// `PL_E_BAD_TAG` (not a command kind), `PL_E_OUT_OF_RANGE` (motor, slot or stick out of
/// range) or `PL_E_BUFFER_TOO_SMALL` (`PL_AOK_MAX_FRAME_LEN` is always enough).
///
/// ```c
/// pl_aok_item set = { .kind = PL_AOK_SET_PARAMETER, .number = 12, .value = 1500 };
/// uint8_t buf[PL_AOK_MAX_FRAME_LEN];
/// int32_t n = pl_aok_encode_command(&set, buf, sizeof buf);   /* 73 0C 00 00 05 DC D5 */
/// ```
///
/// # Safety
/// `cmd` is NULL or readable; `out` is NULL or writable for `cap` bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_aok_encode_command(
    cmd: *const pl_aok_item,
    out: *mut u8,
    cap: usize,
) -> i32 {
    // SAFETY: the caller's promise.
    let Some(cmd) = (unsafe { cmd.as_ref() }) else {
        return PL_E_NULL;
    };
    // SAFETY: the caller's promise for `out[..cap]`.
    let out = match unsafe { ffi::buffer(out, cap) } {
        Ok(out) => out,
        Err(code) => return code,
    };
    let c = match command_rust(cmd) {
        Ok(c) => c,
        Err(code) => return code,
    };
    match c.emit(out) {
        Ok(n) => ffi::length(n),
        Err(EncodeError::BufferTooSmall { .. }) => PL_E_BUFFER_TOO_SMALL,
    }
}

/// Encodes a device message (device to PC) into `out[..cap]`: a debug value, an ack ('O',
/// 'E', 'I'), a parameter reply (headed `FF NUM ...` if `headed`, else the firmware <= 0.30
/// form) or a waypoint. Returns its length, or `PL_E_NULL`, `PL_E_BAD_TAG` (not a message
/// kind), `PL_E_OUT_OF_RANGE` (an ack byte or slot outside the protocol) or
/// `PL_E_BUFFER_TOO_SMALL`.
///
/// ```c
/// pl_aok_item dbg = { .kind = PL_AOK_DEBUG, .number = 86, .value = 3 };
/// uint8_t buf[PL_AOK_MAX_FRAME_LEN];
/// int32_t n = pl_aok_encode_message(&dbg, 1, buf, sizeof buf);   /* 7 bytes */
/// ```
///
/// # Safety
/// `msg` is NULL or readable; `out` is NULL or writable for `cap` bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_aok_encode_message(
    msg: *const pl_aok_item,
    headed: u8,
    out: *mut u8,
    cap: usize,
) -> i32 {
    // SAFETY: the caller's promise.
    let Some(msg) = (unsafe { msg.as_ref() }) else {
        return PL_E_NULL;
    };
    // SAFETY: the caller's promise for `out[..cap]`.
    let out = match unsafe { ffi::buffer(out, cap) } {
        Ok(out) => out,
        Err(code) => return code,
    };
    let form = if headed != 0 {
        ReplyForm::Headed
    } else {
        ReplyForm::Headerless
    };
    let result = match msg.kind {
        PL_AOK_DEBUG => Message::Debug(DebugValue {
            number: msg.number,
            value: msg.value,
        })
        .emit(out, ReplyForm::Headed),
        PL_AOK_ACK => match Ack::from_byte(msg.ack) {
            Some(a) => Message::Ack(a).emit(out, ReplyForm::Headed),
            None => return PL_E_OUT_OF_RANGE,
        },
        PL_AOK_PARAMETER => Message::Parameter(ParameterValue {
            number: msg.number,
            value: msg.value,
        })
        .emit(out, form),
        PL_AOK_WAYPOINT => match waypoint_rust(&msg.waypoint) {
            Ok(w) => Message::Waypoint(w).emit(out, ReplyForm::Headed),
            Err(code) => return code,
        },
        _ => return PL_E_BAD_TAG,
    };
    match result {
        Ok(n) => ffi::length(n),
        Err(EncodeError::BufferTooSmall { .. }) => PL_E_BUFFER_TOO_SMALL,
    }
}
