//! What the PC sends: every command as a plain `Repr` with `parse`, `emit` and `buffer_len`.
//! The bytes of every frame are in the crate's private `layout` (published as [`Command::FRAMES`]).

use crate::layout::{
    bulk_read, control, external_control as ext, motor_test, read_parameter, read_waypoint,
    set_parameter as set, waypoint as wp,
};
use crate::layout::{bytes, put};
use crate::values::{ActionWord, Motor, Stick, WaypointSlot};
use crate::{EncodeError, Error, checked_value, xor};

/// `63`: the two- and three-byte control commands (no checksum, K5).
pub const CONTROL: u8 = control::START;
/// `73`: set a parameter.
pub const SET_PARAMETER: u8 = set::START;
/// `67`: read a parameter.
pub const READ_PARAMETER: u8 = read_parameter::START;
/// `47`: bulk read 16 parameters (firmware >= 0.35).
pub const BULK_READ: u8 = bulk_read::START;
/// `77`: set a waypoint (and the header of the waypoint reply).
pub const WAYPOINT: u8 = wp::START;
/// `78`: read a waypoint.
pub const READ_WAYPOINT: u8 = read_waypoint::START;
/// `53`: external control.
pub const EXTERNAL_CONTROL: u8 = ext::START;

/// The longest command (and the longest device message): a waypoint frame, 19 bytes.
pub const MAX_COMMAND_LEN: usize = crate::layout::MAX_FRAME_LEN;

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

/// A parameter number and value (`73` set, and the parameter reply).
///
/// ```
/// use aok_proto::{Command, ParameterValue};
/// let set = Command::SetParameter(ParameterValue { number: 12, value: 1500 });
/// let mut wire = [0u8; 7];
/// let n = set.emit(&mut wire)?;
/// assert_eq!(&wire[..n], &[0x73, 0x0C, 0x00, 0x00, 0x05, 0xDC, 0xD5]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ParameterValue {
    /// The parameter number.
    pub number: u8,
    /// The value (i32, MSB first on the wire, K3).
    pub value: i32,
}

/// A motor-test value (K7): lapses after 500 ms unless repeated.
///
/// ```
/// use aok_proto::{Command, Motor, MotorTest};
/// let test = MotorTest { motor: Motor::new(3)?, value: 40 };
/// let mut wire = [0u8; 3];
/// let n = Command::MotorTest(test).emit(&mut wire)?;
/// assert_eq!(&wire[..n], &[0x33, 0x28, 0x1B]); // motor 3's start byte, the value, the XOR
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct MotorTest {
    /// The motor.
    pub motor: Motor,
    /// The test value.
    pub value: u8,
}

/// A waypoint, POI or FBC target (K8). Set with `77`, and the device's reply to `78`.
///
/// ```
/// use aok_proto::{ActionWord, Command, Waypoint, WaypointSlot};
/// let poi = Waypoint { slot: WaypointSlot::MissionPoi, longitude: 100, latitude: -100,
///                      action1: ActionWord::NONE, action2: ActionWord::NONE };
/// let mut wire = [0u8; 19];
/// assert_eq!(Command::SetWaypoint(poi).emit(&mut wire), Ok(19));
/// // Start, slot 31, then longitude and latitude, MSB first.
/// assert_eq!(&wire[..10], &[0x77, 0x1F, 0, 0, 0, 0x64, 0xFF, 0xFF, 0xFF, 0x9C]);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Waypoint {
    /// The slot.
    pub slot: WaypointSlot,
    /// Longitude, raw (unit unstated, K8).
    pub longitude: i32,
    /// Latitude, raw.
    pub latitude: i32,
    /// The first action word.
    pub action1: ActionWord,
    /// The second action word.
    pub action2: ActionWord,
}

impl Waypoint {
    /// Whether a mission ends at this waypoint: its coordinates are 0/0 or -1/-1 (K8).
    ///
    /// ```
    /// use aok_proto::{ActionWord, Waypoint, WaypointSlot};
    /// let w = Waypoint { slot: WaypointSlot::MissionPoi, longitude: -1, latitude: -1,
    ///                    action1: ActionWord::NONE, action2: ActionWord::NONE };
    /// assert!(w.ends_mission());
    /// ```
    pub const fn ends_mission(&self) -> bool {
        (self.longitude == 0 && self.latitude == 0) || (self.longitude == -1 && self.latitude == -1)
    }

    /// The 19-byte `77` frame ([`crate::layout::waypoint`]).
    pub(crate) fn frame(&self) -> [u8; wp::LEN] {
        let mut f = [0u8; wp::LEN];
        f[0] = wp::START;
        f[wp::SLOT] = self.slot.wire();
        put!(f, wp::LONGITUDE, self.longitude.to_be_bytes(), 4);
        put!(f, wp::LATITUDE, self.latitude.to_be_bytes(), 4);
        put!(f, wp::ACTION1, self.action1.raw().to_be_bytes(), 4);
        put!(f, wp::ACTION2, self.action2.raw().to_be_bytes(), 4);
        f[wp::CHECKSUM] = xor(&f[wp::CHECKED]);
        f
    }

    /// Parse a complete `77` frame (checksum first, then the slot).
    pub(crate) fn from_frame(f: &[u8; wp::LEN]) -> Result<Self, Error> {
        if xor(&f[wp::CHECKED]) != f[wp::CHECKSUM] {
            return Err(Error::mismatch(f, wp::CHECKED, wp::CHECKSUM));
        }
        Ok(Self {
            slot: WaypointSlot::from_wire(f[wp::SLOT])?,
            longitude: i32::from_be_bytes(bytes!(f, wp::LONGITUDE, 4)),
            latitude: i32::from_be_bytes(bytes!(f, wp::LATITUDE, 4)),
            action1: ActionWord(u32::from_be_bytes(bytes!(f, wp::ACTION1, 4))),
            action2: ActionWord(u32::from_be_bytes(bytes!(f, wp::ACTION2, 4))),
        })
    }
}

/// External control (K9): sticks, the unused pitch, and how long the values hold.
///
/// ```
/// use aok_proto::{Command, ExternalControl, Stick};
/// let sticks = ExternalControl {
///     roll: Stick::new(10)?, nick: Stick::new(-10)?, yaw: Stick::new(0)?, pitch: 0, expiry_ms: 500,
/// };
/// let mut wire = [0u8; 12];
/// let n = Command::ExternalControl(sticks).emit(&mut wire)?;
/// // Two bytes a field, least significant first (K9), then the XOR.
/// assert_eq!(&wire[..n], &[0x53, 0x0A, 0x00, 0xF6, 0xFF, 0, 0, 0, 0, 0xF4, 0x01, 0xF6]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ExternalControl {
    /// Roll stick.
    pub roll: Stick,
    /// Nick (pitch attitude) stick.
    pub nick: Stick,
    /// Yaw stick.
    pub yaw: Stick,
    /// The "pitch" (throttle) field. The device ignores it, so it is raw and unchecked.
    pub pitch: i16,
    /// Expiry in ms: without a new frame in this time the RC takes over again.
    pub expiry_ms: u16,
}

/// Everything the PC sends to the device.
///
/// ```
/// use aok_proto::Command;
/// let mut buf = [0u8; 19];
/// let n = Command::ReadParameter(12).emit(&mut buf)?;
/// assert_eq!(&buf[..n], &[0x67, 0x0c]);
/// assert_eq!(Command::parse(&buf[..n])?, (Command::ReadParameter(12), 2));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Command {
    /// `63 01`: stop sending debug values.
    DebugOff,
    /// `63 02`: send debug values.
    DebugOn,
    /// `63 07`: reset the device.
    Reset,
    /// `63 08`: save the waypoints from RAM to flash.
    SaveWaypoints,
    /// `63 09`: load the waypoints from flash to RAM.
    LoadWaypoints,
    /// `63 03 NUM`: load parameter set NUM from flash.
    LoadSet(u8),
    /// `63 04 NUM`: save the parameters to flash set NUM.
    SaveSet(u8),
    /// `63 05 NUM`: choose flash set NUM as the start set.
    StartSet(u8),
    /// `73 NUM B1..B4 CRC`: set a parameter in RAM.
    SetParameter(ParameterValue),
    /// `67 NUM`: read a parameter.
    ReadParameter(u8),
    /// `47 NUM`: read parameters NUM..NUM+15 (firmware >= 0.35).
    BulkRead(u8),
    /// `31..39`/`41..43 VALUE CRC`: motor test.
    MotorTest(MotorTest),
    /// `77 NUM ... CRC`: set a waypoint.
    SetWaypoint(Waypoint),
    /// `78 NUM`: read a waypoint.
    ReadWaypoint(WaypointSlot),
    /// `53 ... CRC`: external control.
    ExternalControl(ExternalControl),
}

/// How long a command starting with `first` (and `second`, when known) is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Len {
    /// Not a command start.
    Unknown,
    /// A `63` whose sub-command byte has not arrived.
    More,
    /// A command of this many bytes.
    Is(usize),
}

/// The length of the command that starts with these bytes.
#[inline]
pub(crate) const fn command_len(first: u8, second: Option<u8>) -> Len {
    match first {
        CONTROL => match second {
            None => Len::More,
            Some(1 | 2 | 7 | 8 | 9) => Len::Is(control::LEN),
            Some(3..=5) => Len::Is(control::LEN_WITH_SET),
            Some(_) => Len::Unknown,
        },
        SET_PARAMETER => Len::Is(set::LEN),
        READ_PARAMETER => Len::Is(read_parameter::LEN),
        BULK_READ => Len::Is(bulk_read::LEN),
        READ_WAYPOINT => Len::Is(read_waypoint::LEN),
        0x31..=0x39 | 0x41..=0x43 => Len::Is(motor_test::LEN),
        WAYPOINT => Len::Is(wp::LEN),
        EXTERNAL_CONTROL => Len::Is(ext::LEN),
        _ => Len::Unknown,
    }
}

fn fixed<const N: usize>(bytes: &[u8]) -> Result<&[u8; N], Error> {
    bytes
        .get(..N)
        .and_then(|s| <&[u8; N]>::try_from(s).ok())
        .ok_or(Error::Truncated)
}

impl Command {
    /// The frames the PC sends with a fixed layout, one [`FrameLayout`](crate::FrameLayout)
    /// each: set parameter, read parameter, bulk read, read waypoint, set waypoint, external
    /// control (control and motor test: [`Command::CONTROL`], [`Command::MOTOR_TEST`]).
    ///
    /// ```
    /// use aok_proto::Command;
    /// let names: Vec<_> = Command::FRAMES.iter().map(|f| f.name).collect();
    /// assert_eq!(names[0], "SET_PARAMETER");
    /// assert_eq!(Command::FRAMES[0].fields[1], ("value", "i32be", 2));
    /// ```
    pub const FRAMES: &'static [crate::FrameLayout] = &crate::layout::PC_FRAMES;
    /// The control commands' frame (`63 SUB [SET]`, K5): its longest form, with the set
    /// number; a sub-command without one is two bytes.
    ///
    /// ```
    /// use aok_proto::Command;
    /// assert_eq!((Command::CONTROL.start, Command::CONTROL.len), (0x63, 3));
    /// assert_eq!(Command::CONTROL.fields[1], ("set", "u8", 2));
    /// ```
    pub const CONTROL: crate::FrameLayout = crate::layout::CONTROL;
    /// The motor test frame (K7): the start byte names the motor (motor 1's, `0x31`, here).
    ///
    /// ```
    /// use aok_proto::Command;
    /// assert_eq!(Command::MOTOR_TEST.len, 3);
    /// assert_eq!(Command::MOTOR_TEST.checksum, Some((0..2, 2)));
    /// ```
    pub const MOTOR_TEST: crate::FrameLayout = crate::layout::MOTOR_TEST;

    /// Parse the command at the start of `bytes`; returns it and the number of bytes it took.
    ///
    /// Checksums are verified; field values are range-checked (slots, sticks).
    ///
    /// ```
    /// use aok_proto::{Command, Error};
    /// assert_eq!(Command::parse(&[0x63, 0x04, 2]), Ok((Command::SaveSet(2), 3)));
    /// let mismatch = Error::ChecksumMismatch { id: 0x33, computed: 0x33 ^ 0x28, received: 0 };
    /// assert_eq!(Command::parse(&[0x33, 0x28, 0x00]), Err(mismatch));
    /// assert_eq!(Command::parse(&[0x73, 0x0c]), Err(Error::Truncated));
    /// ```
    pub fn parse(bytes: &[u8]) -> Result<(Self, usize), Error> {
        let (&first, rest) = bytes.split_first().ok_or(Error::Truncated)?;
        match command_len(first, rest.first().copied()) {
            Len::Unknown => Err(Error::UnknownCommand(first)),
            Len::More => Err(Error::Truncated),
            Len::Is(n) => Ok((Self::parse_known(first, bytes)?, n)),
        }
    }

    /// Parse a frame whose first byte is a known command start; `bytes` may be longer than the frame.
    #[inline]
    pub(crate) fn parse_known(first: u8, bytes: &[u8]) -> Result<Self, Error> {
        match first {
            CONTROL => {
                let f = fixed::<{ control::LEN }>(bytes)?;
                let set = || -> Result<u8, Error> {
                    Ok(fixed::<{ control::LEN_WITH_SET }>(bytes)?[control::SET])
                };
                match f[control::SUB] {
                    1 => Ok(Self::DebugOff),
                    2 => Ok(Self::DebugOn),
                    7 => Ok(Self::Reset),
                    8 => Ok(Self::SaveWaypoints),
                    9 => Ok(Self::LoadWaypoints),
                    3 => Ok(Self::LoadSet(set()?)),
                    4 => Ok(Self::SaveSet(set()?)),
                    5 => Ok(Self::StartSet(set()?)),
                    _ => Err(Error::UnknownCommand(first)),
                }
            }
            SET_PARAMETER => {
                let f = fixed::<{ set::LEN }>(bytes)?;
                let (number, value) = checked_value(f)
                    .ok_or_else(|| Error::mismatch(f, set::CHECKED, set::CHECKSUM))?;
                Ok(Self::SetParameter(ParameterValue { number, value }))
            }
            READ_PARAMETER => Ok(Self::ReadParameter(
                fixed::<{ read_parameter::LEN }>(bytes)?[read_parameter::NUMBER],
            )),
            BULK_READ => Ok(Self::BulkRead(
                fixed::<{ bulk_read::LEN }>(bytes)?[bulk_read::FIRST],
            )),
            READ_WAYPOINT => Ok(Self::ReadWaypoint(WaypointSlot::from_wire(
                fixed::<{ read_waypoint::LEN }>(bytes)?[read_waypoint::SLOT],
            )?)),
            WAYPOINT => Ok(Self::SetWaypoint(Waypoint::from_frame(fixed::<
                { wp::LEN },
            >(
                bytes
            )?)?)),
            EXTERNAL_CONTROL => {
                let f = fixed::<{ ext::LEN }>(bytes)?;
                if xor(&f[ext::CHECKED]) != f[ext::CHECKSUM] {
                    return Err(Error::mismatch(f, ext::CHECKED, ext::CHECKSUM));
                }
                Ok(Self::ExternalControl(ExternalControl {
                    roll: Stick::new(i16::from_le_bytes(bytes!(f, ext::ROLL, 2)))?,
                    nick: Stick::new(i16::from_le_bytes(bytes!(f, ext::NICK, 2)))?,
                    yaw: Stick::new(i16::from_le_bytes(bytes!(f, ext::YAW, 2)))?,
                    pitch: i16::from_le_bytes(bytes!(f, ext::PITCH, 2)),
                    expiry_ms: u16::from_le_bytes(bytes!(f, ext::EXPIRY, 2)),
                }))
            }
            _ => match Motor::from_command_byte(first) {
                Some(motor) => {
                    let f = fixed::<{ motor_test::LEN }>(bytes)?;
                    if xor(&f[motor_test::CHECKED]) != f[motor_test::CHECKSUM] {
                        return Err(Error::mismatch(
                            f,
                            motor_test::CHECKED,
                            motor_test::CHECKSUM,
                        ));
                    }
                    Ok(Self::MotorTest(MotorTest {
                        motor,
                        value: f[motor_test::VALUE],
                    }))
                }
                None => Err(Error::UnknownCommand(first)),
            },
        }
    }

    /// The number of bytes [`Command::emit`] writes.
    ///
    /// ```
    /// assert_eq!(aok_proto::Command::DebugOff.buffer_len(), 2);
    /// assert_eq!(aok_proto::Command::LoadSet(1).buffer_len(), 3);
    /// ```
    pub const fn buffer_len(&self) -> usize {
        match self {
            Self::DebugOff
            | Self::DebugOn
            | Self::Reset
            | Self::SaveWaypoints
            | Self::LoadWaypoints
            | Self::ReadParameter(_)
            | Self::BulkRead(_)
            | Self::ReadWaypoint(_) => 2,
            Self::LoadSet(_) | Self::StartSet(_) | Self::SaveSet(_) | Self::MotorTest(_) => 3,
            Self::SetParameter(_) => 7,
            Self::ExternalControl(_) => 12,
            Self::SetWaypoint(_) => 19,
        }
    }

    /// The frame in a fixed array, and its length: what [`Command::emit`] copies out.
    pub(crate) fn wire(&self) -> ([u8; MAX_COMMAND_LEN], usize) {
        let mut f = [0u8; MAX_COMMAND_LEN];
        match *self {
            Self::DebugOff => control(&mut f, 1),
            Self::DebugOn => control(&mut f, 2),
            Self::Reset => control(&mut f, 7),
            Self::SaveWaypoints => control(&mut f, 8),
            Self::LoadWaypoints => control(&mut f, 9),
            Self::LoadSet(n) => control_n(&mut f, 3, n),
            Self::SaveSet(n) => control_n(&mut f, 4, n),
            Self::StartSet(n) => control_n(&mut f, 5, n),
            Self::SetParameter(p) => {
                f[0] = set::START;
                f[set::NUMBER] = p.number;
                put!(f, set::VALUE, p.value.to_be_bytes(), 4);
                f[set::CHECKSUM] = xor(&f[set::CHECKED]);
            }
            Self::ReadParameter(n) => {
                f[0] = read_parameter::START;
                f[read_parameter::NUMBER] = n;
            }
            Self::BulkRead(n) => {
                f[0] = bulk_read::START;
                f[bulk_read::FIRST] = n;
            }
            Self::ReadWaypoint(s) => {
                f[0] = read_waypoint::START;
                f[read_waypoint::SLOT] = s.wire();
            }
            Self::MotorTest(m) => {
                f[0] = m.motor.command_byte();
                f[motor_test::VALUE] = m.value;
                f[motor_test::CHECKSUM] = xor(&f[motor_test::CHECKED]);
            }
            Self::SetWaypoint(w) => f = w.frame(),
            Self::ExternalControl(e) => {
                f[0] = ext::START;
                put!(f, ext::ROLL, e.roll.get().to_le_bytes(), 2);
                put!(f, ext::NICK, e.nick.get().to_le_bytes(), 2);
                put!(f, ext::YAW, e.yaw.get().to_le_bytes(), 2);
                put!(f, ext::PITCH, e.pitch.to_le_bytes(), 2);
                put!(f, ext::EXPIRY, e.expiry_ms.to_le_bytes(), 2);
                f[ext::CHECKSUM] = xor(&f[ext::CHECKED]);
            }
        }
        (f, self.buffer_len())
    }

    /// Write the command's whole frame into `buf` ([`Command::buffer_len`] bytes); returns the
    /// number of bytes written. AOK frames have no framing beyond this.
    ///
    /// ```
    /// use aok_proto::{Command, Motor, MotorTest};
    /// let mut buf = [0u8; 3];
    /// let cmd = Command::MotorTest(MotorTest { motor: Motor::new(3)?, value: 40 });
    /// assert_eq!(cmd.emit(&mut buf)?, 3);
    /// assert_eq!(buf, [0x33, 0x28, 0x1b]);
    /// assert!(cmd.emit(&mut [0u8; 2]).is_err());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn emit(&self, buf: &mut [u8]) -> Result<usize, EncodeError> {
        let (f, n) = self.wire();
        copy_out(&f, n, buf)
    }

    /// The reply the device sends to this command, as far as the spec defines one.
    ///
    /// `73` and `77` are acked, `67`, `47` and `78` are answered with data, the rest get nothing.
    ///
    /// ```
    /// use aok_proto::{Command, Expect};
    /// assert_eq!(Command::ReadParameter(12).expected_reply(), Expect::Parameter(12));
    /// assert_eq!(Command::SaveSet(1).expected_reply(), Expect::Nothing);
    /// ```
    pub const fn expected_reply(&self) -> Expect {
        match self {
            Self::SetParameter(_) | Self::SetWaypoint(_) => Expect::Ack,
            Self::ReadParameter(n) => Expect::Parameter(*n),
            Self::BulkRead(n) => Expect::Bulk(*n),
            Self::ReadWaypoint(s) => Expect::Waypoint(*s),
            _ => Expect::Nothing,
        }
    }
}

/// What the PC is waiting for after a command ([`Command::expected_reply`]). It tells the PC
/// decoder ([`crate::MessageDecoder`]) how to read headerless parameter replies and whether
/// single bytes 'O'/'E'/'I' are acks. Also reachable as `aok_proto::Expect`.
///
/// ```
/// use aok_proto::Expect;
/// assert_eq!(Expect::default(), Expect::Nothing);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Expect {
    /// No request pending: only debug frames and self-describing replies are decoded.
    #[default]
    Nothing,
    /// An ack ('O', 'E' or 'I') after `73` or `77`.
    Ack,
    /// The reply to `67 NUM`.
    Parameter(u8),
    /// The 16 replies to `47 NUM`; pending until the reply for NUM+15 arrives.
    Bulk(u8),
    /// The reply to `78 NUM`.
    Waypoint(WaypointSlot),
}

fn control(f: &mut [u8; MAX_COMMAND_LEN], sub: u8) {
    f[0] = control::START;
    f[control::SUB] = sub;
}

fn control_n(f: &mut [u8; MAX_COMMAND_LEN], sub: u8, n: u8) {
    control(f, sub);
    f[control::SET] = n;
}

/// Copy the first `n` bytes of `src` into `buf`.
pub(crate) fn copy_out(src: &[u8], n: usize, buf: &mut [u8]) -> Result<usize, EncodeError> {
    let src = src
        .get(..n)
        .ok_or(EncodeError::BufferTooSmall { needed: n })?;
    let dst = buf
        .get_mut(..src.len())
        .ok_or(EncodeError::BufferTooSmall { needed: n })?;
    // Zipped: no length check left to a panic when the copy is not inlined (libprotolink.a
    // roots every entry point, and at opt-level "z" this copy stays out of line).
    dst.iter_mut().zip(src).for_each(|(d, s)| *d = *s);
    Ok(src.len())
}
