//! Every AYDP message's bytes, in one table: one module per header or message, each field's
//! offset as a named constant (the smoltcp `wire` `mod field` style; AEOLUS has the same in
//! `aeolus_proto::message::layout`, AOK in `aok_proto::layout`). The header offsets count from
//! the start byte; the message offsets count from the first data byte (after the header). The
//! typed messages in [`crate::message`] and the header in [`crate::header`] read and write
//! bytes only through these offsets.
//!
//! Everything is little-endian (Y3, Y8); `uflt16` is binary16 without a sign (Y7). The XOR
//! checksum byte follows the data (Y4).
//!
//! | layout | type | data bytes |
//! | --- | --- | --- |
//! | [`header`] | every message | `FF TYPE LEN32 [SECONDS64 SUBSEC64]`: 22 bytes, 6 expedited |
//! | [`wind`] | 1, 2 (`Reference`) | `f32` |
//! | [`position`] | 3 | `LAT f64, LON f64, ALT f32`: 20 |
//! | [`fix_quality`] | 4 | `TYPE u8, MEAN_DOP HDOP VDOP uflt16, SATS u8`: 8 |
//! | [`fix_detail`] + [`satellite`] | 5 | `COUNT u8`, then `COUNT` x (`ID u8, AZ EL SNR uflt16`): 7 each |
//! | [`direct_output`] + [`output_entry`] | 7 | `COUNT u16`, then `COUNT` x (`DEV u8, CH u8, VALUE f32`): 6 each |
//! | [`system_value_update`] | 8 | `MODE u8, ADDRESS u16, FIELD u32`, then the value bytes |
//! | [`system_control`] | 9 | `COMMAND u8` (1: then `ADDRESS u16`) |
//! | [`vessel_data`] | 17 (`Reference`) | 68 bytes, below |

/// The header (Y3), offsets from the start byte.
pub mod header {
    /// The start byte, 0xFF.
    pub const START: usize = 0;
    /// The type byte (bit 7: expedited).
    pub const TYPE: usize = 1;
    /// The length field, u32.
    pub const LENGTH: usize = 2;
    /// Normal messages only: the time's seconds, i64.
    pub const SECONDS: usize = 6;
    /// Normal messages only: the time's sub-seconds, i64 (unit per profile).
    pub const SUBSEC: usize = 14;
    /// An expedited header's length.
    pub const EXPEDITED_LEN: usize = 6;
    /// A normal header's length.
    pub const NORMAL_LEN: usize = 22;
}

/// Wind speed (1) and wind direction (2), `Reference` profile: one `f32`.
pub mod wind {
    /// The value, f32.
    pub const VALUE: usize = 0;
    /// The data length.
    pub const LEN: usize = 4;
}

/// Position (3).
pub mod position {
    /// Latitude, f64 degrees.
    pub const LATITUDE: usize = 0;
    /// Longitude, f64 degrees.
    pub const LONGITUDE: usize = 8;
    /// Altitude, f32.
    pub const ALTITUDE: usize = 16;
    /// The data length.
    pub const LEN: usize = 20;
}

/// Position fix quality (4).
pub mod fix_quality {
    /// Fix type, u8.
    pub const FIX_TYPE: usize = 0;
    /// Mean DOP, uflt16.
    pub const MEAN_DOP: usize = 1;
    /// Horizontal DOP, uflt16.
    pub const HDOP: usize = 3;
    /// Vertical DOP, uflt16.
    pub const VDOP: usize = 5;
    /// Satellites, u8.
    pub const SATELLITES: usize = 7;
    /// The data length.
    pub const LEN: usize = 8;
}

/// Position fix detail (5): a count, then that many [`satellite`] entries.
pub mod fix_detail {
    /// The number of satellites, u8.
    pub const COUNT: usize = 0;
    /// The first satellite entry.
    pub const ENTRIES: usize = 1;
}

/// One satellite of a fix detail, offsets inside the entry.
pub mod satellite {
    /// Satellite ID, u8.
    pub const ID: usize = 0;
    /// Azimuth, uflt16.
    pub const AZIMUTH: usize = 1;
    /// Elevation, uflt16.
    pub const ELEVATION: usize = 3;
    /// Signal-to-noise ratio, uflt16.
    pub const SNR: usize = 5;
    /// The entry length.
    pub const LEN: usize = 7;
}

/// Direct output control (7): a count, then that many [`output_entry`] entries.
pub mod direct_output {
    /// The number of entries, u16.
    pub const COUNT: usize = 0;
    /// The first entry.
    pub const ENTRIES: usize = 2;
}

/// One entry of a direct output control, offsets inside the entry.
pub mod output_entry {
    /// Device number, u8.
    pub const DEVICE: usize = 0;
    /// Channel number, u8.
    pub const CHANNEL: usize = 1;
    /// Calibrated value, f32.
    pub const VALUE: usize = 2;
    /// The entry length.
    pub const LEN: usize = 6;
}

/// System value update (8): a 7-byte head, then the value bytes.
pub mod system_value_update {
    /// Update mode, u8 (1 single, 2 array, 3 element).
    pub const MODE: usize = 0;
    /// Address, u16.
    pub const ADDRESS: usize = 1;
    /// Array count or element index (0 for a single value), u32.
    pub const FIELD: usize = 3;
    /// The first value byte: the head's length.
    pub const VALUE: usize = 7;
}

/// System control (9): a command byte, then its arguments.
pub mod system_control {
    /// The command byte: 1 request data, 2 store configuration.
    pub const COMMAND: usize = 0;
    /// Request data: the address, u16.
    pub const ADDRESS: usize = 1;
    /// The data length of request data.
    pub const REQUEST_DATA_LEN: usize = 3;
    /// The data length of store configuration.
    pub const STORE_CONFIGURATION_LEN: usize = 1;
}

/// Vessel data (17, `Reference` profile).
pub mod vessel_data {
    /// Roll, f32.
    pub const ROLL: usize = 0;
    /// Pitch, f32.
    pub const PITCH: usize = 4;
    /// Heading, f32.
    pub const HEADING: usize = 8;
    /// Roll rate, f32.
    pub const ROLL_RATE: usize = 12;
    /// Pitch rate, f32.
    pub const PITCH_RATE: usize = 16;
    /// Heading rate, f32.
    pub const HEADING_RATE: usize = 20;
    /// Latitude, f64.
    pub const LATITUDE: usize = 24;
    /// Longitude, f64.
    pub const LONGITUDE: usize = 32;
    /// Track, f32.
    pub const TRACK: usize = 40;
    /// Speed over ground, f32.
    pub const SPEED_OVER_GROUND: usize = 44;
    /// Fix type, i32.
    pub const FIX_TYPE: usize = 48;
    /// Satellites, i32.
    pub const SATELLITES: usize = 52;
    /// Mean DOP, f32.
    pub const MEAN_DOP: usize = 56;
    /// Horizontal DOP, f32.
    pub const HDOP: usize = 60;
    /// Vertical DOP, f32.
    pub const VDOP: usize = 64;
    /// The data length.
    pub const LEN: usize = 68;
}
