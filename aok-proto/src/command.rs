//! What the PC sends: every command as a plain `Repr` with `parse`, `emit` and `buffer_len`.

use crate::values::{ActionWord, Motor, Stick, WaypointSlot};
use crate::{Error, xor};

/// `63`: the two- and three-byte control commands (no checksum, K5).
pub const CONTROL: u8 = 0x63;
/// `73`: set a parameter.
pub const SET_PARAMETER: u8 = 0x73;
/// `67`: read a parameter.
pub const READ_PARAMETER: u8 = 0x67;
/// `47`: bulk read 16 parameters (firmware >= 0.35).
pub const BULK_READ: u8 = 0x47;
/// `77`: set a waypoint (and the header of the waypoint reply).
pub const WAYPOINT: u8 = 0x77;
/// `78`: read a waypoint.
pub const READ_WAYPOINT: u8 = 0x78;
/// `53`: external control.
pub const EXTERNAL_CONTROL: u8 = 0x53;

/// The longest command (and the longest device message): a waypoint frame, 19 bytes.
pub const MAX_COMMAND_LEN: usize = 19;

/// A parameter number and value (`73` set, and the parameter reply).
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

    /// The 19-byte `77` frame.
    pub(crate) fn frame(&self) -> [u8; 19] {
        let mut f = [0u8; 19];
        f[0] = WAYPOINT;
        f[1] = self.slot.wire();
        let [a, b, c, d] = self.longitude.to_be_bytes();
        f[2] = a;
        f[3] = b;
        f[4] = c;
        f[5] = d;
        let [a, b, c, d] = self.latitude.to_be_bytes();
        f[6] = a;
        f[7] = b;
        f[8] = c;
        f[9] = d;
        let [a, b, c, d] = self.action1.raw().to_be_bytes();
        f[10] = a;
        f[11] = b;
        f[12] = c;
        f[13] = d;
        let [a, b, c, d] = self.action2.raw().to_be_bytes();
        f[14] = a;
        f[15] = b;
        f[16] = c;
        f[17] = d;
        f[18] = xor(&f[1..18]);
        f
    }

    /// Parse a complete `77` frame (checksum first, then the slot).
    pub(crate) fn from_frame(f: &[u8; 19]) -> Result<Self, Error> {
        if xor(&f[1..18]) != f[18] {
            return Err(Error::ChecksumMismatch);
        }
        Ok(Self {
            slot: WaypointSlot::from_wire(f[1])?,
            longitude: i32::from_be_bytes([f[2], f[3], f[4], f[5]]),
            latitude: i32::from_be_bytes([f[6], f[7], f[8], f[9]]),
            action1: ActionWord(u32::from_be_bytes([f[10], f[11], f[12], f[13]])),
            action2: ActionWord(u32::from_be_bytes([f[14], f[15], f[16], f[17]])),
        })
    }
}

/// External control (K9): sticks, the unused pitch, and how long the values hold.
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
/// # Ok::<(), aok_proto::Error>(())
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
            Some(1 | 2 | 7 | 8 | 9) => Len::Is(2),
            Some(3..=5) => Len::Is(3),
            Some(_) => Len::Unknown,
        },
        SET_PARAMETER => Len::Is(7),
        READ_PARAMETER | BULK_READ | READ_WAYPOINT => Len::Is(2),
        0x31..=0x39 | 0x41..=0x43 => Len::Is(3),
        WAYPOINT => Len::Is(19),
        EXTERNAL_CONTROL => Len::Is(12),
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
    /// Parse the command at the start of `bytes`; returns it and the number of bytes it took.
    ///
    /// Checksums are verified; field values are range-checked (slots, sticks).
    ///
    /// ```
    /// use aok_proto::{Command, Error};
    /// assert_eq!(Command::parse(&[0x63, 0x04, 2]), Ok((Command::SaveSet(2), 3)));
    /// assert_eq!(Command::parse(&[0x33, 0x28, 0x00]), Err(Error::ChecksumMismatch));
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
                let f = fixed::<2>(bytes)?;
                match f[1] {
                    1 => Ok(Self::DebugOff),
                    2 => Ok(Self::DebugOn),
                    7 => Ok(Self::Reset),
                    8 => Ok(Self::SaveWaypoints),
                    9 => Ok(Self::LoadWaypoints),
                    3 => Ok(Self::LoadSet(fixed::<3>(bytes)?[2])),
                    4 => Ok(Self::SaveSet(fixed::<3>(bytes)?[2])),
                    5 => Ok(Self::StartSet(fixed::<3>(bytes)?[2])),
                    _ => Err(Error::UnknownCommand(first)),
                }
            }
            SET_PARAMETER => {
                let f = fixed::<7>(bytes)?;
                if xor(&f[1..6]) != f[6] {
                    return Err(Error::ChecksumMismatch);
                }
                Ok(Self::SetParameter(ParameterValue {
                    number: f[1],
                    value: i32::from_be_bytes([f[2], f[3], f[4], f[5]]),
                }))
            }
            READ_PARAMETER => Ok(Self::ReadParameter(fixed::<2>(bytes)?[1])),
            BULK_READ => Ok(Self::BulkRead(fixed::<2>(bytes)?[1])),
            READ_WAYPOINT => Ok(Self::ReadWaypoint(WaypointSlot::from_wire(
                fixed::<2>(bytes)?[1],
            )?)),
            WAYPOINT => Ok(Self::SetWaypoint(Waypoint::from_frame(fixed::<19>(
                bytes,
            )?)?)),
            EXTERNAL_CONTROL => {
                let f = fixed::<12>(bytes)?;
                if xor(&f[1..11]) != f[11] {
                    return Err(Error::ChecksumMismatch);
                }
                Ok(Self::ExternalControl(ExternalControl {
                    roll: Stick::new(i16::from_le_bytes([f[1], f[2]]))?,
                    nick: Stick::new(i16::from_le_bytes([f[3], f[4]]))?,
                    yaw: Stick::new(i16::from_le_bytes([f[5], f[6]]))?,
                    pitch: i16::from_le_bytes([f[7], f[8]]),
                    expiry_ms: u16::from_le_bytes([f[9], f[10]]),
                }))
            }
            _ => match Motor::from_command_byte(first) {
                Some(motor) => {
                    let f = fixed::<3>(bytes)?;
                    if f[0] ^ f[1] != f[2] {
                        return Err(Error::ChecksumMismatch);
                    }
                    Ok(Self::MotorTest(MotorTest { motor, value: f[1] }))
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

    /// The encoded frame in a fixed array, and its length.
    pub fn to_bytes(&self) -> ([u8; MAX_COMMAND_LEN], usize) {
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
                let [a, b, c, d] = p.value.to_be_bytes();
                f[0] = SET_PARAMETER;
                f[1] = p.number;
                f[2] = a;
                f[3] = b;
                f[4] = c;
                f[5] = d;
                f[6] = p.number ^ a ^ b ^ c ^ d;
            }
            Self::ReadParameter(n) => {
                f[0] = READ_PARAMETER;
                f[1] = n;
            }
            Self::BulkRead(n) => {
                f[0] = BULK_READ;
                f[1] = n;
            }
            Self::ReadWaypoint(s) => {
                f[0] = READ_WAYPOINT;
                f[1] = s.wire();
            }
            Self::MotorTest(m) => {
                f[0] = m.motor.command_byte();
                f[1] = m.value;
                f[2] = f[0] ^ m.value;
            }
            Self::SetWaypoint(w) => f = w.frame(),
            Self::ExternalControl(e) => {
                let [r0, r1] = e.roll.get().to_le_bytes();
                let [n0, n1] = e.nick.get().to_le_bytes();
                let [y0, y1] = e.yaw.get().to_le_bytes();
                let [p0, p1] = e.pitch.to_le_bytes();
                let [e0, e1] = e.expiry_ms.to_le_bytes();
                let body = [r0, r1, n0, n1, y0, y1, p0, p1, e0, e1];
                f[0] = EXTERNAL_CONTROL;
                f[1..11].copy_from_slice(&body);
                f[11] = xor(&body);
            }
        }
        (f, self.buffer_len())
    }

    /// Write the command into `buf`; returns the number of bytes written.
    ///
    /// ```
    /// use aok_proto::{Command, Motor, MotorTest};
    /// let mut buf = [0u8; 3];
    /// let cmd = Command::MotorTest(MotorTest { motor: Motor::new(3)?, value: 40 });
    /// assert_eq!(cmd.emit(&mut buf)?, 3);
    /// assert_eq!(buf, [0x33, 0x28, 0x1b]);
    /// assert!(cmd.emit(&mut [0u8; 2]).is_err());
    /// # Ok::<(), aok_proto::Error>(())
    /// ```
    pub fn emit(&self, buf: &mut [u8]) -> Result<usize, Error> {
        let (f, n) = self.to_bytes();
        copy_out(&f, n, buf)
    }

    /// The reply the device sends to this command, as far as the spec defines one.
    ///
    /// `73` and `77` are acked, `67`, `47` and `78` are answered with data, the rest get nothing.
    ///
    /// ```
    /// use aok_proto::{Command, pc::Expect};
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
/// decoder ([`crate::PcDecoder`]) how to read headerless parameter replies and whether single
/// bytes 'O'/'E'/'I' are acks. Also reachable as `pc::Expect`.
///
/// ```
/// use aok_proto::pc::Expect;
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
    f[0] = CONTROL;
    f[1] = sub;
}

fn control_n(f: &mut [u8; MAX_COMMAND_LEN], sub: u8, n: u8) {
    f[0] = CONTROL;
    f[1] = sub;
    f[2] = n;
}

/// Copy the first `n` bytes of `src` into `buf`.
pub(crate) fn copy_out(src: &[u8], n: usize, buf: &mut [u8]) -> Result<usize, Error> {
    let src = src.get(..n).ok_or(Error::BufferTooSmall)?;
    let dst = buf.get_mut(..src.len()).ok_or(Error::BufferTooSmall)?;
    dst.copy_from_slice(src);
    Ok(src.len())
}
