//! Every AOK frame's bytes, in one table: the start byte, the length, each field's offset and
//! the checksum, one module per frame (the smoltcp `wire` `mod field` style; AEOLUS has the same
//! in `aeolus_proto::message::layout`). [`crate::command`] and [`crate::message`] read and write
//! frames only through these offsets.
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

/// `63 SUB [SET]`: the control commands, two bytes, or three for the parameter-set commands.
pub mod control {
    /// The start byte.
    pub const START: u8 = 0x63;
    /// The sub-command byte.
    pub const SUB: usize = 1;
    /// The flash set number (sub-commands 3, 4 and 5 only).
    pub const SET: usize = 2;
    /// Length without a set number.
    pub const LEN: usize = 2;
    /// Length with a set number.
    pub const LEN_WITH_SET: usize = 3;
}

/// `73 NUM B1..B4 CRC`: set a parameter.
pub mod set_parameter {
    /// The start byte.
    pub const START: u8 = 0x73;
    /// The parameter number.
    pub const NUMBER: usize = 1;
    /// The value, i32 big-endian, four bytes from here.
    pub const VALUE: usize = 2;
    /// The checksum byte.
    pub const CHECKSUM: usize = 6;
    /// The bytes the checksum covers: `NUM..B4`.
    pub const CHECKED: core::ops::Range<usize> = NUMBER..CHECKSUM;
    /// The frame length.
    pub const LEN: usize = 7;
}

/// `67 NUM`: read a parameter.
pub mod read_parameter {
    /// The start byte.
    pub const START: u8 = 0x67;
    /// The parameter number.
    pub const NUMBER: usize = 1;
    /// The frame length.
    pub const LEN: usize = 2;
}

/// `47 NUM`: read 16 parameters from NUM (firmware >= 0.35).
pub mod bulk_read {
    /// The start byte.
    pub const START: u8 = 0x47;
    /// The first parameter number.
    pub const FIRST: usize = 1;
    /// The frame length.
    pub const LEN: usize = 2;
}

/// `31..39`/`41..43 VALUE CRC`: motor test; the start byte names the motor (K7).
pub mod motor_test {
    /// The test value.
    pub const VALUE: usize = 1;
    /// The checksum byte.
    pub const CHECKSUM: usize = 2;
    /// The bytes the checksum covers: the start byte and the value.
    pub const CHECKED: core::ops::Range<usize> = 0..CHECKSUM;
    /// The frame length.
    pub const LEN: usize = 3;
}

/// `77 SLOT LON LAT ACT1 ACT2 CRC`: set a waypoint (PC), and the reply to `78` (device).
pub mod waypoint {
    /// The start byte.
    pub const START: u8 = 0x77;
    /// The slot byte.
    pub const SLOT: usize = 1;
    /// Longitude, i32 big-endian.
    pub const LONGITUDE: usize = 2;
    /// Latitude, i32 big-endian.
    pub const LATITUDE: usize = 6;
    /// The first action word, u32 big-endian.
    pub const ACTION1: usize = 10;
    /// The second action word, u32 big-endian.
    pub const ACTION2: usize = 14;
    /// The checksum byte.
    pub const CHECKSUM: usize = 18;
    /// The bytes the checksum covers: `SLOT..ACT2`.
    pub const CHECKED: core::ops::Range<usize> = SLOT..CHECKSUM;
    /// The frame length: the longest AOK frame.
    pub const LEN: usize = 19;
}

/// `78 SLOT`: read a waypoint.
pub mod read_waypoint {
    /// The start byte.
    pub const START: u8 = 0x78;
    /// The slot byte.
    pub const SLOT: usize = 1;
    /// The frame length.
    pub const LEN: usize = 2;
}

/// `53 ROLL NICK YAW PITCH EXPIRY CRC`: external control, each field two bytes little-endian.
pub mod external_control {
    /// The start byte.
    pub const START: u8 = 0x53;
    /// Roll stick, i16.
    pub const ROLL: usize = 1;
    /// Nick stick, i16.
    pub const NICK: usize = 3;
    /// Yaw stick, i16.
    pub const YAW: usize = 5;
    /// The unused pitch field, i16.
    pub const PITCH: usize = 7;
    /// Expiry in ms, u16.
    pub const EXPIRY: usize = 9;
    /// The checksum byte.
    pub const CHECKSUM: usize = 11;
    /// The bytes the checksum covers: `ROLL..EXPIRY`.
    pub const CHECKED: core::ops::Range<usize> = ROLL..CHECKSUM;
    /// The frame length.
    pub const LEN: usize = 12;
}

/// `1C NUM B1..B4 CRC`: a debug value.
pub mod debug {
    /// The start byte.
    pub const START: u8 = 0x1c;
    /// The debug value's number.
    pub const NUMBER: usize = 1;
    /// The value, i32 big-endian.
    pub const VALUE: usize = 2;
    /// The checksum byte.
    pub const CHECKSUM: usize = 6;
    /// The bytes the checksum covers: `NUM..B4`.
    pub const CHECKED: core::ops::Range<usize> = NUMBER..CHECKSUM;
    /// The frame length.
    pub const LEN: usize = 7;
}

/// `FF NUM B1..B4 CRC`: a parameter reply, firmware >= 0.31.
pub mod parameter_reply {
    /// The start byte.
    pub const START: u8 = 0xff;
    /// The parameter number.
    pub const NUMBER: usize = 1;
    /// The value, i32 big-endian.
    pub const VALUE: usize = 2;
    /// The checksum byte.
    pub const CHECKSUM: usize = 6;
    /// The bytes the checksum covers: only `B1..B4` (K4).
    pub const CHECKED: core::ops::Range<usize> = VALUE..CHECKSUM;
    /// The frame length.
    pub const LEN: usize = 7;
}

/// `B1..B4 CRC`: a parameter reply, firmware <= 0.30; the number is the pending request's.
pub mod headerless_reply {
    /// The value, i32 big-endian.
    pub const VALUE: usize = 0;
    /// The checksum byte.
    pub const CHECKSUM: usize = 4;
    /// The bytes the checksum covers: `B1..B4`.
    pub const CHECKED: core::ops::Range<usize> = VALUE..CHECKSUM;
    /// The frame length.
    pub const LEN: usize = 5;
}

/// `O`, `E` or `I`: a one-byte ack ([`crate::Ack`]).
pub mod ack {
    /// The frame length.
    pub const LEN: usize = 1;
}

/// The longest frame in either direction ([`waypoint::LEN`]): the decoders' buffer size.
pub const MAX_FRAME_LEN: usize = waypoint::LEN;

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
