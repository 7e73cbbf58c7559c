//! Typed values: motor numbers, stick values, waypoint slots and action words, acks, firmware versions.

use crate::Error;

/// A motor number, 1..=12 (K7).
///
/// ```
/// use aok_proto::Motor;
/// let m = Motor::new(10)?;
/// assert_eq!(m.command_byte(), b'A');
/// assert_eq!(Motor::from_command_byte(b'3').map(Motor::get), Some(3));
/// assert!(Motor::new(13).is_err());
/// # Ok::<(), aok_proto::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(try_from = "u8", into = "u8")
)]
pub struct Motor(u8);

impl Motor {
    /// The lowest motor number.
    pub const MIN: u8 = 1;
    /// The highest motor number.
    pub const MAX: u8 = 12;

    /// A motor number, checked to lie in 1..=12.
    ///
    /// ```
    /// assert!(aok_proto::Motor::new(0).is_err());
    /// ```
    pub const fn new(number: u8) -> Result<Self, Error> {
        if number >= Self::MIN && number <= Self::MAX {
            Ok(Self(number))
        } else {
            Err(Error::InvalidMotor(number))
        }
    }

    /// The motor number, 1..=12.
    ///
    /// ```
    /// assert_eq!(aok_proto::Motor::new(7).map(|m| m.get()), Ok(7));
    /// ```
    pub const fn get(self) -> u8 {
        self.0
    }

    /// The command byte of this motor's test frame: '1'..='9' for motors 1..=9, 'A'..='C' for 10..=12.
    ///
    /// ```
    /// assert_eq!(aok_proto::Motor::new(12).map(|m| m.command_byte()), Ok(0x43));
    /// ```
    pub const fn command_byte(self) -> u8 {
        if self.0 <= 9 {
            0x30 + self.0
        } else {
            0x37 + self.0
        }
    }

    /// The motor a motor-test command byte addresses, if it is one.
    ///
    /// ```
    /// assert_eq!(aok_proto::Motor::from_command_byte(0x40), None);
    /// ```
    pub const fn from_command_byte(byte: u8) -> Option<Self> {
        // Bit `i` set: `0x31 + i` addresses a motor (bits 0 to 8: `31`..`39`, motors 1 to 9;
        // bits 16 to 18: `41`..`43`, motors 10 to 12). One shift of a mask: the decoders ask
        // this of every command's first byte, and two range tests cost about twice the
        // instructions on Cortex-M.
        const MOTOR_BYTES: u32 = 0x0007_01ff;
        let bit = match MOTOR_BYTES.checked_shr(byte.wrapping_sub(0x31) as u32) {
            Some(mask) => mask & 1,
            None => 0,
        };
        if bit == 0 {
            None
        } else if byte < 0x41 {
            Some(Self(byte - 0x30))
        } else {
            Some(Self(byte - 0x37))
        }
    }
}

impl TryFrom<u8> for Motor {
    type Error = Error;
    fn try_from(n: u8) -> Result<Self, Error> {
        Self::new(n)
    }
}

impl From<Motor> for u8 {
    fn from(m: Motor) -> u8 {
        m.0
    }
}

/// An external-control stick value, -200..=200 (K9).
///
/// ```
/// use aok_proto::Stick;
/// assert_eq!(Stick::new(-32)?.get(), -32);
/// assert!(Stick::new(201).is_err());
/// assert_eq!(Stick::saturating(-999).get(), -200);
/// # Ok::<(), aok_proto::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(try_from = "i16", into = "i16")
)]
pub struct Stick(i16);

impl Stick {
    /// The lowest stick value.
    pub const MIN: i16 = -200;
    /// The highest stick value.
    pub const MAX: i16 = 200;
    /// The centre position.
    pub const CENTER: Self = Self(0);

    /// A stick value, checked to lie in -200..=200.
    ///
    /// ```
    /// assert!(aok_proto::Stick::new(200).is_ok());
    /// ```
    pub const fn new(value: i16) -> Result<Self, Error> {
        if value >= Self::MIN && value <= Self::MAX {
            Ok(Self(value))
        } else {
            Err(Error::StickOutOfRange(value))
        }
    }

    /// A stick value, clamped to -200..=200.
    ///
    /// ```
    /// assert_eq!(aok_proto::Stick::saturating(300).get(), 200);
    /// ```
    pub const fn saturating(value: i16) -> Self {
        if value < Self::MIN {
            Self(Self::MIN)
        } else if value > Self::MAX {
            Self(Self::MAX)
        } else {
            Self(value)
        }
    }

    /// The value.
    ///
    /// ```
    /// assert_eq!(aok_proto::Stick::CENTER.get(), 0);
    /// ```
    pub const fn get(self) -> i16 {
        self.0
    }
}

impl TryFrom<i16> for Stick {
    type Error = Error;
    fn try_from(v: i16) -> Result<Self, Error> {
        Self::new(v)
    }
}

impl From<Stick> for i16 {
    fn from(s: Stick) -> i16 {
        s.0
    }
}

/// A waypoint number as the user counts them, 1..=31 (wire slots 0..=30).
///
/// ```
/// use aok_proto::WaypointNumber;
/// assert_eq!(WaypointNumber::new(1)?.wire(), 0);
/// assert!(WaypointNumber::new(32).is_err());
/// # Ok::<(), aok_proto::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(try_from = "u8", into = "u8")
)]
pub struct WaypointNumber(u8);

impl WaypointNumber {
    /// A waypoint number, checked to lie in 1..=31.
    ///
    /// ```
    /// assert!(aok_proto::WaypointNumber::new(31).is_ok());
    /// ```
    pub const fn new(number: u8) -> Result<Self, Error> {
        if number >= 1 && number <= 31 {
            Ok(Self(number))
        } else {
            Err(Error::InvalidWaypoint(number))
        }
    }

    /// The number, 1..=31.
    ///
    /// ```
    /// assert_eq!(aok_proto::WaypointNumber::new(5).map(|n| n.get()), Ok(5));
    /// ```
    pub const fn get(self) -> u8 {
        self.0
    }

    /// The wire slot, 0..=30.
    ///
    /// ```
    /// assert_eq!(aok_proto::WaypointNumber::new(31).map(|n| n.wire()), Ok(30));
    /// ```
    pub const fn wire(self) -> u8 {
        self.0 - 1
    }
}

impl TryFrom<u8> for WaypointNumber {
    type Error = Error;
    fn try_from(n: u8) -> Result<Self, Error> {
        Self::new(n)
    }
}

impl From<WaypointNumber> for u8 {
    fn from(n: WaypointNumber) -> u8 {
        n.0
    }
}

/// Where a `77` frame goes (K8).
///
/// ```
/// use aok_proto::{WaypointSlot, WaypointNumber};
/// assert_eq!(WaypointSlot::from_wire(0)?, WaypointSlot::Waypoint(WaypointNumber::new(1)?));
/// assert_eq!(WaypointSlot::from_wire(255)?, WaypointSlot::FbcTarget);
/// assert!(WaypointSlot::from_wire(32).is_err());
/// # Ok::<(), aok_proto::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum WaypointSlot {
    /// Waypoint 1..=31 (wire 0..=30).
    Waypoint(WaypointNumber),
    /// The mission POI stored in flash (wire 31).
    MissionPoi,
    /// The POI in RAM (wire 254).
    RamPoi,
    /// The fly-by-coordinates target (wire 255).
    FbcTarget,
}

impl WaypointSlot {
    /// The slot a wire byte names.
    ///
    /// ```
    /// assert_eq!(aok_proto::WaypointSlot::from_wire(31), Ok(aok_proto::WaypointSlot::MissionPoi));
    /// ```
    pub const fn from_wire(byte: u8) -> Result<Self, Error> {
        match byte {
            0..=30 => Ok(Self::Waypoint(WaypointNumber(byte + 1))),
            31 => Ok(Self::MissionPoi),
            254 => Ok(Self::RamPoi),
            255 => Ok(Self::FbcTarget),
            _ => Err(Error::InvalidSlot(byte)),
        }
    }

    /// The slot's wire byte.
    ///
    /// ```
    /// assert_eq!(aok_proto::WaypointSlot::RamPoi.wire(), 254);
    /// ```
    pub const fn wire(self) -> u8 {
        match self {
            Self::Waypoint(n) => n.wire(),
            Self::MissionPoi => 31,
            Self::RamPoi => 254,
            Self::FbcTarget => 255,
        }
    }
}

/// The action of a waypoint action word (K8), with its wire value.
///
/// ```
/// use aok_proto::Action;
/// assert_eq!(Action::SetFlySpeed as u16, 6);
/// assert_eq!(Action::from_code(2), Ok(Action::HoldAndClimb));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[repr(u16)]
pub enum Action {
    /// No action.
    None = 0,
    /// Pause, value in seconds.
    Pause = 1,
    /// Hold and climb, value in metres.
    HoldAndClimb = 2,
    /// Hold and sink, value in metres.
    HoldAndSink = 3,
    /// Fly and climb, value in metres.
    FlyAndClimb = 4,
    /// Fly and sink, value in metres.
    FlyAndSink = 5,
    /// Set the fly speed, value in cm/s.
    SetFlySpeed = 6,
}

impl Action {
    /// All actions in code order.
    pub const ALL: [Self; 7] = [
        Self::None,
        Self::Pause,
        Self::HoldAndClimb,
        Self::HoldAndSink,
        Self::FlyAndClimb,
        Self::FlyAndSink,
        Self::SetFlySpeed,
    ];

    /// The action with this code.
    ///
    /// ```
    /// assert!(aok_proto::Action::from_code(7).is_err());
    /// ```
    pub const fn from_code(code: u16) -> Result<Self, Error> {
        match code {
            0 => Ok(Self::None),
            1 => Ok(Self::Pause),
            2 => Ok(Self::HoldAndClimb),
            3 => Ok(Self::HoldAndSink),
            4 => Ok(Self::FlyAndClimb),
            5 => Ok(Self::FlyAndSink),
            6 => Ok(Self::SetFlySpeed),
            _ => Err(Error::InvalidAction(code)),
        }
    }

    /// The action's code.
    ///
    /// ```
    /// assert_eq!(aok_proto::Action::Pause.code(), 1);
    /// ```
    pub const fn code(self) -> u16 {
        self as u16
    }
}

/// A waypoint action word as it travels (K8): high 16 bits the action, low 16 bits the value + 32768.
///
/// The raw word is kept, so a word with an unknown action survives a round trip; [`ActionWord::action`]
/// reports it.
///
/// ```
/// use aok_proto::{Action, ActionWord};
/// let w = ActionWord::new(Action::HoldAndClimb, 15);
/// assert_eq!(w.raw(), 0x0002_800f);
/// assert_eq!(w.action(), Ok(Action::HoldAndClimb));
/// assert_eq!(w.value(), 15);
/// assert_eq!(ActionWord::new(Action::Pause, -1).raw() & 0xffff, 32767);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ActionWord(pub u32);

impl ActionWord {
    /// The offset added to the value in the low 16 bits.
    pub const OFFSET: i32 = 32768;
    /// "No action, value 0".
    pub const NONE: Self = Self::new(Action::None, 0);

    /// The word for an action and its value.
    ///
    /// ```
    /// assert_eq!(aok_proto::ActionWord::new(aok_proto::Action::Pause, 1).raw(), 0x0001_8001);
    /// ```
    pub const fn new(action: Action, value: i16) -> Self {
        // value + 32768 in 16 bits is the value with its sign bit flipped.
        let low = (value as u16) ^ 0x8000;
        Self(((action as u32) << 16) | low as u32)
    }

    /// The raw 32-bit word.
    ///
    /// ```
    /// assert_eq!(aok_proto::ActionWord(7).raw(), 7);
    /// ```
    pub const fn raw(self) -> u32 {
        self.0
    }

    /// The action, if its code is one of the seven.
    ///
    /// ```
    /// assert!(aok_proto::ActionWord(0x0007_8000).action().is_err());
    /// ```
    pub const fn action(self) -> Result<Action, Error> {
        Action::from_code((self.0 >> 16) as u16)
    }

    /// The value: the low 16 bits minus 32768.
    ///
    /// ```
    /// assert_eq!(aok_proto::ActionWord(0x0006_80fa).value(), 250);
    /// ```
    pub const fn value(self) -> i16 {
        ((self.0 as u16) ^ 0x8000) as i16
    }
}

/// A single-byte acknowledgement from the device (K6).
///
/// ```
/// use aok_proto::Ack;
/// assert_eq!(Ack::from_byte(b'O'), Some(Ack::Ok));
/// assert_eq!(Ack::InFlight.byte(), 0x49);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[repr(u8)]
pub enum Ack {
    /// 'O': received and applied.
    Ok = b'O',
    /// 'E': error.
    Error = b'E',
    /// 'I': refused, the copter is flying and the parameter is not in-flight changeable.
    InFlight = b'I',
}

impl Ack {
    /// The ack a byte stands for.
    ///
    /// ```
    /// assert_eq!(aok_proto::Ack::from_byte(b'X'), None);
    /// ```
    pub const fn from_byte(byte: u8) -> Option<Self> {
        match byte {
            b'O' => Some(Self::Ok),
            b'E' => Some(Self::Error),
            b'I' => Some(Self::InFlight),
            _ => None,
        }
    }

    /// The ack's byte.
    ///
    /// ```
    /// assert_eq!(aok_proto::Ack::Ok.byte(), b'O');
    /// ```
    pub const fn byte(self) -> u8 {
        self as u8
    }
}

/// Which of the two parameter-reply forms the device sends (K4).
///
/// ```
/// use aok_proto::{Message, ParameterValue, ReplyForm};
/// let reply = Message::Parameter(ParameterValue { number: 12, value: 1500 });
/// let mut wire = [0u8; 7];
/// let n = reply.emit(&mut wire, ReplyForm::Headerless)?;
/// assert_eq!(&wire[..n], &[0x00, 0x00, 0x05, 0xDC, 0xD9]);
/// let n = reply.emit(&mut wire, ReplyForm::Headed)?;
/// assert_eq!(&wire[..n], &[0xFF, 0x0C, 0x00, 0x00, 0x05, 0xDC, 0xD9]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum ReplyForm {
    /// Firmware <= 0.30: `B1 B2 B3 B4 CRC`, no header and no number.
    Headerless,
    /// Firmware >= 0.31: `FF NUM B1 B2 B3 B4 CRC`.
    Headed,
}

/// The device's firmware version, which decides the reply form and whether bulk read exists.
///
/// ```
/// use aok_proto::{FirmwareVersion, ReplyForm};
/// assert_eq!(FirmwareVersion::new(0, 30).reply_form(), ReplyForm::Headerless);
/// assert_eq!(FirmwareVersion::new(0, 31).reply_form(), ReplyForm::Headed);
/// assert!(!FirmwareVersion::new(0, 34).has_bulk_read());
/// assert!(FirmwareVersion::new(0, 35).has_bulk_read());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct FirmwareVersion {
    /// Major version.
    pub major: u8,
    /// Minor version (0.31 has minor 31).
    pub minor: u8,
}

impl FirmwareVersion {
    /// The newest form: headed replies and bulk read (0.35).
    pub const LATEST: Self = Self::new(0, 35);

    /// A version `major.minor`.
    ///
    /// ```
    /// assert_eq!(aok_proto::FirmwareVersion::new(0, 31).minor, 31);
    /// ```
    pub const fn new(major: u8, minor: u8) -> Self {
        Self { major, minor }
    }

    /// The parameter-reply form this firmware sends.
    ///
    /// ```
    /// assert_eq!(aok_proto::FirmwareVersion::new(1, 0).reply_form(), aok_proto::ReplyForm::Headed);
    /// ```
    pub const fn reply_form(self) -> ReplyForm {
        if self.major == 0 && self.minor <= 30 {
            ReplyForm::Headerless
        } else {
            ReplyForm::Headed
        }
    }

    /// Whether the firmware knows bulk read `47` (>= 0.35).
    ///
    /// ```
    /// assert!(aok_proto::FirmwareVersion::LATEST.has_bulk_read());
    /// ```
    pub const fn has_bulk_read(self) -> bool {
        self.major > 0 || self.minor >= 35
    }
}
