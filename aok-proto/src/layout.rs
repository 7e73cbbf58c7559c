//! Every AOK frame's bytes, in one table: the start byte, the length, each field's offset and
//! the checksum, one module per frame (the smoltcp `wire` `mod field` style; AEOLUS has the same
//! in `aeolus_proto`'s private `message::layout`). [`crate::command`] and [`crate::message`]
//! read and write frames only through these offsets.
//!
//! The module is private: [`FrameLayout`] publishes each frame's facts, built from these
//! offsets (`Command::FRAMES`, `Command::CONTROL`, `Command::MOTOR_TEST`, `Message::FRAMES`),
//! so tools that describe the wire format (the Wireshark dissector `protolink wireshark`
//! writes) read the same table as the code.
//!
//! All checksums are the XOR of the bytes in `CHECKED` (K2, K4). Multi-byte values are
//! big-endian (MSB first, K3) except in external control, which is little-endian (K9).
//!
//! | frame | sent by | bytes |
//! | --- | --- | --- |
//! | [`control`] | PC | `63 SUB` or `63 SUB SET` (no checksum, K5) |
//! | [`set_parameter`] | PC | `73 NUM B1..B4 CRC` |
//! | [`read_parameter`] | PC | `67 NUM` |
//! | [`bulk_read`] | PC | `47 NUM` |
//! | [`motor_test`] | PC | `31..39`/`41..43 VALUE CRC` (K7) |
//! | [`waypoint`] | PC and device | `77 SLOT LON1..4 LAT1..4 ACT1 1..4 ACT2 1..4 CRC` (K8) |
//! | [`read_waypoint`] | PC | `78 SLOT` |
//! | [`external_control`] | PC | `53 ROLL NICK YAW PITCH EXPIRY CRC`, two bytes each, LE (K9) |
//! | [`debug`] | device | `1C NUM B1..B4 CRC` (K2) |
//! | [`parameter_reply`] | device | `FF NUM B1..B4 CRC`, firmware >= 0.31 (K4) |
//! | [`headerless_reply`] | device | `B1..B4 CRC`, firmware <= 0.30 (K4) |
//! | [`ack`] | device | `O`, `E` or `I` (K6) |

/// One frame's bytes as a table, for tools that describe the wire format (the Wireshark
/// dissector `protolink wireshark` writes): [`Command::FRAMES`](crate::Command::FRAMES),
/// [`Command::CONTROL`](crate::Command::CONTROL),
/// [`Command::MOTOR_TEST`](crate::Command::MOTOR_TEST) and
/// [`Message::FRAMES`](crate::Message::FRAMES) give every frame, built from the offsets the
/// encoders and decoders use.
///
/// A field's wire type is one of `u8`, `i32be` (K3), `i16le` and `u16le` (K9), `slot` (a
/// waypoint slot byte, [`WaypointSlot`](crate::WaypointSlot)), `action` (a `u32` big-endian
/// [`ActionWord`](crate::ActionWord)) and `stick` (an `i16` little-endian
/// [`Stick`](crate::Stick)).
///
/// ```
/// use aok_proto::{Command, Message};
/// let debug = &Message::FRAMES[0];
/// assert_eq!((debug.name, debug.start, debug.len), ("DEBUG", 0x1c, 7));
/// assert_eq!(debug.fields, [("number", "u8", 1), ("value", "i32be", 2)]);
/// // The checksum at byte 6 is the XOR of bytes 1..6.
/// assert_eq!(debug.checksum, Some((1..6, 6)));
/// assert!(Command::FRAMES.iter().any(|f| f.name == "EXTERNAL_CONTROL"));
/// ```
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FrameLayout {
    /// The frame's name, upper case (`"SET_PARAMETER"`).
    pub name: &'static str,
    /// The start byte (for a motor test, the first motor's: [`Command::MOTOR_TEST`](crate::Command::MOTOR_TEST)).
    pub start: u8,
    /// The frame length, start byte included (for a control command, the longest form).
    pub len: usize,
    /// The bytes the XOR checksum covers and the checksum's offset; `None`: no checksum.
    pub checksum: Option<(core::ops::Range<usize>, usize)>,
    /// `(field, wire type, offset from the start byte)` per field.
    pub fields: &'static [(&'static str, &'static str, usize)],
}

/// `63 SUB [SET]`: the control commands, two bytes, or three for the parameter-set commands.
pub(crate) mod control {
    /// The start byte.
    pub(crate) const START: u8 = 0x63;
    /// The sub-command byte.
    pub(crate) const SUB: usize = 1;
    /// The flash set number (sub-commands 3, 4 and 5 only).
    pub(crate) const SET: usize = 2;
    /// Length without a set number.
    pub(crate) const LEN: usize = 2;
    /// Length with a set number.
    pub(crate) const LEN_WITH_SET: usize = 3;
}

/// `73 NUM B1..B4 CRC`: set a parameter.
pub(crate) mod set_parameter {
    /// The start byte.
    pub(crate) const START: u8 = 0x73;
    /// The parameter number.
    pub(crate) const NUMBER: usize = 1;
    /// The value, i32 big-endian, four bytes from here.
    pub(crate) const VALUE: usize = 2;
    /// The checksum byte.
    pub(crate) const CHECKSUM: usize = 6;
    /// The bytes the checksum covers: `NUM..B4`.
    pub(crate) const CHECKED: core::ops::Range<usize> = NUMBER..CHECKSUM;
    /// The frame length.
    pub(crate) const LEN: usize = 7;
}

/// `67 NUM`: read a parameter.
pub(crate) mod read_parameter {
    /// The start byte.
    pub(crate) const START: u8 = 0x67;
    /// The parameter number.
    pub(crate) const NUMBER: usize = 1;
    /// The frame length.
    pub(crate) const LEN: usize = 2;
}

/// `47 NUM`: read 16 parameters from NUM (firmware >= 0.35).
pub(crate) mod bulk_read {
    /// The start byte.
    pub(crate) const START: u8 = 0x47;
    /// The first parameter number.
    pub(crate) const FIRST: usize = 1;
    /// The frame length.
    pub(crate) const LEN: usize = 2;
}

/// `31..39`/`41..43 VALUE CRC`: motor test; the start byte names the motor (K7).
pub(crate) mod motor_test {
    /// The test value.
    pub(crate) const VALUE: usize = 1;
    /// The checksum byte.
    pub(crate) const CHECKSUM: usize = 2;
    /// The bytes the checksum covers: the start byte and the value.
    pub(crate) const CHECKED: core::ops::Range<usize> = 0..CHECKSUM;
    /// The frame length.
    pub(crate) const LEN: usize = 3;
}

/// `77 SLOT LON LAT ACT1 ACT2 CRC`: set a waypoint (PC), and the reply to `78` (device).
pub(crate) mod waypoint {
    /// The start byte.
    pub(crate) const START: u8 = 0x77;
    /// The slot byte.
    pub(crate) const SLOT: usize = 1;
    /// Longitude, i32 big-endian.
    pub(crate) const LONGITUDE: usize = 2;
    /// Latitude, i32 big-endian.
    pub(crate) const LATITUDE: usize = 6;
    /// The first action word, u32 big-endian.
    pub(crate) const ACTION1: usize = 10;
    /// The second action word, u32 big-endian.
    pub(crate) const ACTION2: usize = 14;
    /// The checksum byte.
    pub(crate) const CHECKSUM: usize = 18;
    /// The bytes the checksum covers: `SLOT..ACT2`.
    pub(crate) const CHECKED: core::ops::Range<usize> = SLOT..CHECKSUM;
    /// The frame length: the longest AOK frame.
    pub(crate) const LEN: usize = 19;
}

/// `78 SLOT`: read a waypoint.
pub(crate) mod read_waypoint {
    /// The start byte.
    pub(crate) const START: u8 = 0x78;
    /// The slot byte.
    pub(crate) const SLOT: usize = 1;
    /// The frame length.
    pub(crate) const LEN: usize = 2;
}

/// `53 ROLL NICK YAW PITCH EXPIRY CRC`: external control, each field two bytes little-endian.
pub(crate) mod external_control {
    /// The start byte.
    pub(crate) const START: u8 = 0x53;
    /// Roll stick, i16.
    pub(crate) const ROLL: usize = 1;
    /// Nick stick, i16.
    pub(crate) const NICK: usize = 3;
    /// Yaw stick, i16.
    pub(crate) const YAW: usize = 5;
    /// The unused pitch field, i16.
    pub(crate) const PITCH: usize = 7;
    /// Expiry in ms, u16.
    pub(crate) const EXPIRY: usize = 9;
    /// The checksum byte.
    pub(crate) const CHECKSUM: usize = 11;
    /// The bytes the checksum covers: `ROLL..EXPIRY`.
    pub(crate) const CHECKED: core::ops::Range<usize> = ROLL..CHECKSUM;
    /// The frame length.
    pub(crate) const LEN: usize = 12;
}

/// `1C NUM B1..B4 CRC`: a debug value.
pub(crate) mod debug {
    /// The start byte.
    pub(crate) const START: u8 = 0x1c;
    /// The debug value's number.
    pub(crate) const NUMBER: usize = 1;
    /// The value, i32 big-endian.
    pub(crate) const VALUE: usize = 2;
    /// The checksum byte.
    pub(crate) const CHECKSUM: usize = 6;
    /// The bytes the checksum covers: `NUM..B4`.
    pub(crate) const CHECKED: core::ops::Range<usize> = NUMBER..CHECKSUM;
    /// The frame length.
    pub(crate) const LEN: usize = 7;
}

/// `FF NUM B1..B4 CRC`: a parameter reply, firmware >= 0.31.
pub(crate) mod parameter_reply {
    /// The start byte.
    pub(crate) const START: u8 = 0xff;
    /// The parameter number.
    pub(crate) const NUMBER: usize = 1;
    /// The value, i32 big-endian.
    pub(crate) const VALUE: usize = 2;
    /// The checksum byte.
    pub(crate) const CHECKSUM: usize = 6;
    /// The bytes the checksum covers: only `B1..B4` (K4).
    pub(crate) const CHECKED: core::ops::Range<usize> = VALUE..CHECKSUM;
    /// The frame length.
    pub(crate) const LEN: usize = 7;
}

/// `B1..B4 CRC`: a parameter reply, firmware <= 0.30; the number is the pending request's.
pub(crate) mod headerless_reply {
    /// The value, i32 big-endian.
    pub(crate) const VALUE: usize = 0;
    /// The checksum byte.
    pub(crate) const CHECKSUM: usize = 4;
    /// The bytes the checksum covers: `B1..B4`.
    pub(crate) const CHECKED: core::ops::Range<usize> = VALUE..CHECKSUM;
    /// The frame length.
    pub(crate) const LEN: usize = 5;
}

/// `O`, `E` or `I`: a one-byte ack ([`crate::Ack`]).
pub(crate) mod ack {
    /// The frame length.
    pub(crate) const LEN: usize = 1;
}

/// The frames the PC sends with a fixed layout, as [`Command::FRAMES`](crate::Command::FRAMES)
/// gives them (control and motor test apart: [`CONTROL`], [`MOTOR_TEST`]).
pub(crate) const PC_FRAMES: [FrameLayout; 6] = [
    FrameLayout {
        name: "SET_PARAMETER",
        start: set_parameter::START,
        len: set_parameter::LEN,
        checksum: Some((set_parameter::CHECKED, set_parameter::CHECKSUM)),
        fields: &[
            ("number", "u8", set_parameter::NUMBER),
            ("value", "i32be", set_parameter::VALUE),
        ],
    },
    FrameLayout {
        name: "READ_PARAMETER",
        start: read_parameter::START,
        len: read_parameter::LEN,
        checksum: None,
        fields: &[("number", "u8", read_parameter::NUMBER)],
    },
    FrameLayout {
        name: "BULK_READ",
        start: bulk_read::START,
        len: bulk_read::LEN,
        checksum: None,
        fields: &[("first", "u8", bulk_read::FIRST)],
    },
    FrameLayout {
        name: "READ_WAYPOINT",
        start: read_waypoint::START,
        len: read_waypoint::LEN,
        checksum: None,
        fields: &[("slot", "slot", read_waypoint::SLOT)],
    },
    FrameLayout {
        name: "SET_WAYPOINT",
        ..WAYPOINT
    },
    FrameLayout {
        name: "EXTERNAL_CONTROL",
        start: external_control::START,
        len: external_control::LEN,
        checksum: Some((external_control::CHECKED, external_control::CHECKSUM)),
        fields: &[
            ("roll", "stick", external_control::ROLL),
            ("nick", "stick", external_control::NICK),
            ("yaw", "stick", external_control::YAW),
            ("pitch", "i16le", external_control::PITCH),
            ("expiry_ms", "u16le", external_control::EXPIRY),
        ],
    },
];

/// The frames the device sends, as [`Message::FRAMES`](crate::Message::FRAMES) gives them.
pub(crate) const DEVICE_FRAMES: [FrameLayout; 3] = [
    FrameLayout {
        name: "DEBUG",
        start: debug::START,
        len: debug::LEN,
        checksum: Some((debug::CHECKED, debug::CHECKSUM)),
        fields: &[
            ("number", "u8", debug::NUMBER),
            ("value", "i32be", debug::VALUE),
        ],
    },
    FrameLayout {
        name: "PARAMETER",
        start: parameter_reply::START,
        len: parameter_reply::LEN,
        checksum: Some((parameter_reply::CHECKED, parameter_reply::CHECKSUM)),
        fields: &[
            ("number", "u8", parameter_reply::NUMBER),
            ("value", "i32be", parameter_reply::VALUE),
        ],
    },
    WAYPOINT,
];

/// The waypoint frame, sent both ways.
const WAYPOINT: FrameLayout = FrameLayout {
    name: "WAYPOINT",
    start: waypoint::START,
    len: waypoint::LEN,
    checksum: Some((waypoint::CHECKED, waypoint::CHECKSUM)),
    fields: &[
        ("slot", "slot", waypoint::SLOT),
        ("longitude", "i32be", waypoint::LONGITUDE),
        ("latitude", "i32be", waypoint::LATITUDE),
        ("action1", "action", waypoint::ACTION1),
        ("action2", "action", waypoint::ACTION2),
    ],
};

/// The control commands (K5): the longest form, with the set number.
pub(crate) const CONTROL: FrameLayout = FrameLayout {
    name: "CONTROL",
    start: control::START,
    len: control::LEN_WITH_SET,
    checksum: None,
    fields: &[("sub", "u8", control::SUB), ("set", "u8", control::SET)],
};

/// The motor test (K7); the start byte names the motor (`31..39`, `41..43`), motor 1's here.
pub(crate) const MOTOR_TEST: FrameLayout = FrameLayout {
    name: "MOTOR_TEST",
    start: 0x31,
    len: motor_test::LEN,
    checksum: Some((motor_test::CHECKED, motor_test::CHECKSUM)),
    fields: &[("value", "u8", motor_test::VALUE)],
};

/// The longest frame in either direction ([`waypoint::LEN`]): the decoders' buffer size.
pub(crate) const MAX_FRAME_LEN: usize = waypoint::LEN;

/// The `N` bytes of `frame` from the constant offset `at`, as an array: `bytes!(f, VALUE, 4)`.
/// Constant indices into a fixed-size frame: checked at compile time, no panic path.
macro_rules! bytes {
    ($frame:expr, $at:expr, 4) => {
        [
            $frame[$at],
            $frame[$at + 1],
            $frame[$at + 2],
            $frame[$at + 3],
        ]
    };
    ($frame:expr, $at:expr, 2) => {
        [$frame[$at], $frame[$at + 1]]
    };
}
pub(crate) use bytes;

/// Writes the array `value` (`N` bytes) into `frame` at the constant offset `at`:
/// `put!(f, VALUE, v.to_be_bytes(), 4)`. Constant indices: checked at compile time.
macro_rules! put {
    ($frame:expr, $at:expr, $value:expr, 4) => {{
        let v: [u8; 4] = $value;
        $frame[$at] = v[0];
        $frame[$at + 1] = v[1];
        $frame[$at + 2] = v[2];
        $frame[$at + 3] = v[3];
    }};
    ($frame:expr, $at:expr, $value:expr, 2) => {{
        let v: [u8; 2] = $value;
        $frame[$at] = v[0];
        $frame[$at + 1] = v[1];
    }};
}
pub(crate) use put;
