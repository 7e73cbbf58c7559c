//! Every AYDP message's bytes, in one table: one module per header or message, each field's
//! offset as a named constant (the smoltcp `wire` `mod field` style; AEOLUS has the same in
//! `aeolus_proto`'s private `message::layout`, AOK in `aok_proto`'s private `layout`). The
//! header offsets count from the start byte; the message offsets count from the first data
//! byte (after the header). The typed messages in [`crate::message`] and the header in
//! `crate::header` read and write bytes only through these offsets.
//!
//! The module is private: each module's `FIELDS` (name, wire type, offset) is published as
//! the typed message's `FIELDS` (`Position::FIELDS`, ..., `Frame::HEADER_FIELDS` for the
//! header), so tools that describe the wire format (the Wireshark dissector
//! `protolink wireshark` writes) read the same table as the code.
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
pub(crate) mod header {
    /// The start byte, 0xFF.
    pub(crate) const START: usize = 0;
    /// The type byte (bit 7: expedited).
    pub(crate) const TYPE: usize = 1;
    /// The length field, u32.
    pub(crate) const LENGTH: usize = 2;
    /// Normal messages only: the time's seconds, i64.
    pub(crate) const SECONDS: usize = 6;
    /// Normal messages only: the time's sub-seconds, i64 (unit per profile).
    pub(crate) const SUBSEC: usize = 14;
    /// An expedited header's length.
    pub(crate) const EXPEDITED_LEN: usize = 6;
    /// A normal header's length.
    pub(crate) const NORMAL_LEN: usize = 22;
    /// The fields as the public `FIELDS` table gives them: name, wire type, offset.
    pub(crate) const FIELDS: &[(&str, &str, usize)] = &[
        ("start", "u8", START),
        ("type", "u8", TYPE),
        ("length", "u32", LENGTH),
        ("seconds", "i64", SECONDS),
        ("subsec", "i64", SUBSEC),
    ];
}

/// Wind speed (1) and wind direction (2), `Reference` profile: one `f32`.
pub(crate) mod wind {
    /// The value, f32.
    pub(crate) const VALUE: usize = 0;
    /// The data length.
    pub(crate) const LEN: usize = 4;
    /// The fields as the public `FIELDS` table gives them: name, wire type, offset.
    pub(crate) const FIELDS: &[(&str, &str, usize)] = &[("value", "f32", VALUE)];
}

/// Position (3).
pub(crate) mod position {
    /// Latitude, f64 degrees.
    pub(crate) const LATITUDE: usize = 0;
    /// Longitude, f64 degrees.
    pub(crate) const LONGITUDE: usize = 8;
    /// Altitude, f32.
    pub(crate) const ALTITUDE: usize = 16;
    /// The data length.
    pub(crate) const LEN: usize = 20;
    /// The fields as the public `FIELDS` table gives them: name, wire type, offset.
    pub(crate) const FIELDS: &[(&str, &str, usize)] = &[
        ("latitude", "f64", LATITUDE),
        ("longitude", "f64", LONGITUDE),
        ("altitude", "f32", ALTITUDE),
    ];
}

/// Position fix quality (4).
pub(crate) mod fix_quality {
    /// Fix type, u8.
    pub(crate) const FIX_TYPE: usize = 0;
    /// Mean DOP, uflt16.
    pub(crate) const MEAN_DOP: usize = 1;
    /// Horizontal DOP, uflt16.
    pub(crate) const HDOP: usize = 3;
    /// Vertical DOP, uflt16.
    pub(crate) const VDOP: usize = 5;
    /// Satellites, u8.
    pub(crate) const SATELLITES: usize = 7;
    /// The data length.
    pub(crate) const LEN: usize = 8;
    /// The fields as the public `FIELDS` table gives them: name, wire type, offset.
    pub(crate) const FIELDS: &[(&str, &str, usize)] = &[
        ("fix_type", "u8", FIX_TYPE),
        ("mean_dop", "uflt16", MEAN_DOP),
        ("hdop", "uflt16", HDOP),
        ("vdop", "uflt16", VDOP),
        ("satellites", "u8", SATELLITES),
    ];
}

/// Position fix detail (5): a count, then that many [`satellite`] entries.
pub(crate) mod fix_detail {
    /// The number of satellites, u8.
    pub(crate) const COUNT: usize = 0;
    /// The first satellite entry.
    pub(crate) const ENTRIES: usize = 1;
    /// The fields as the public `FIELDS` table gives them: name, wire type, offset.
    pub(crate) const FIELDS: &[(&str, &str, usize)] = &[("count", "u8", COUNT)];
}

/// One satellite of a fix detail, offsets inside the entry.
pub(crate) mod satellite {
    /// Satellite ID, u8.
    pub(crate) const ID: usize = 0;
    /// Azimuth, uflt16.
    pub(crate) const AZIMUTH: usize = 1;
    /// Elevation, uflt16.
    pub(crate) const ELEVATION: usize = 3;
    /// Signal-to-noise ratio, uflt16.
    pub(crate) const SNR: usize = 5;
    /// The entry length.
    pub(crate) const LEN: usize = 7;
    /// The fields as the public `FIELDS` table gives them: name, wire type, offset.
    pub(crate) const FIELDS: &[(&str, &str, usize)] = &[
        ("id", "u8", ID),
        ("azimuth", "uflt16", AZIMUTH),
        ("elevation", "uflt16", ELEVATION),
        ("snr", "uflt16", SNR),
    ];
}

/// Direct output control (7): a count, then that many [`output_entry`] entries.
pub(crate) mod direct_output {
    /// The number of entries, u16.
    pub(crate) const COUNT: usize = 0;
    /// The first entry.
    pub(crate) const ENTRIES: usize = 2;
    /// The fields as the public `FIELDS` table gives them: name, wire type, offset.
    pub(crate) const FIELDS: &[(&str, &str, usize)] = &[("count", "u16", COUNT)];
}

/// One entry of a direct output control, offsets inside the entry.
pub(crate) mod output_entry {
    /// Device number, u8.
    pub(crate) const DEVICE: usize = 0;
    /// Channel number, u8.
    pub(crate) const CHANNEL: usize = 1;
    /// Calibrated value, f32.
    pub(crate) const VALUE: usize = 2;
    /// The entry length.
    pub(crate) const LEN: usize = 6;
    /// The fields as the public `FIELDS` table gives them: name, wire type, offset.
    pub(crate) const FIELDS: &[(&str, &str, usize)] = &[
        ("device", "u8", DEVICE),
        ("channel", "u8", CHANNEL),
        ("value", "f32", VALUE),
    ];
}

/// System value update (8): a 7-byte head, then the value bytes.
pub(crate) mod system_value_update {
    /// Update mode, u8 (1 single, 2 array, 3 element).
    pub(crate) const MODE: usize = 0;
    /// Address, u16.
    pub(crate) const ADDRESS: usize = 1;
    /// Array count or element index (0 for a single value), u32.
    pub(crate) const FIELD: usize = 3;
    /// The first value byte: the head's length.
    pub(crate) const VALUE: usize = 7;
    /// The fields as the public `FIELDS` table gives them: name, wire type, offset.
    pub(crate) const FIELDS: &[(&str, &str, usize)] = &[
        ("mode", "u8", MODE),
        ("address", "u16", ADDRESS),
        ("field", "u32", FIELD),
    ];
}

/// System control (9): a command byte, then its arguments.
pub(crate) mod system_control {
    /// The command byte: 1 request data, 2 store configuration.
    pub(crate) const COMMAND: usize = 0;
    /// Request data: the address, u16.
    pub(crate) const ADDRESS: usize = 1;
    /// The data length of request data.
    pub(crate) const REQUEST_DATA_LEN: usize = 3;
    /// The data length of store configuration.
    pub(crate) const STORE_CONFIGURATION_LEN: usize = 1;
    /// The fields as the public `FIELDS` table gives them: name, wire type, offset.
    pub(crate) const FIELDS: &[(&str, &str, usize)] =
        &[("command", "u8", COMMAND), ("address", "u16", ADDRESS)];
}

/// Vessel data (17, `Reference` profile).
pub(crate) mod vessel_data {
    /// Roll, f32.
    pub(crate) const ROLL: usize = 0;
    /// Pitch, f32.
    pub(crate) const PITCH: usize = 4;
    /// Heading, f32.
    pub(crate) const HEADING: usize = 8;
    /// Roll rate, f32.
    pub(crate) const ROLL_RATE: usize = 12;
    /// Pitch rate, f32.
    pub(crate) const PITCH_RATE: usize = 16;
    /// Heading rate, f32.
    pub(crate) const HEADING_RATE: usize = 20;
    /// Latitude, f64.
    pub(crate) const LATITUDE: usize = 24;
    /// Longitude, f64.
    pub(crate) const LONGITUDE: usize = 32;
    /// Track, f32.
    pub(crate) const TRACK: usize = 40;
    /// Speed over ground, f32.
    pub(crate) const SPEED_OVER_GROUND: usize = 44;
    /// Fix type, i32.
    pub(crate) const FIX_TYPE: usize = 48;
    /// Satellites, i32.
    pub(crate) const SATELLITES: usize = 52;
    /// Mean DOP, f32.
    pub(crate) const MEAN_DOP: usize = 56;
    /// Horizontal DOP, f32.
    pub(crate) const HDOP: usize = 60;
    /// Vertical DOP, f32.
    pub(crate) const VDOP: usize = 64;
    /// The data length.
    pub(crate) const LEN: usize = 68;
    /// The fields as the public `FIELDS` table gives them: name, wire type, offset.
    pub(crate) const FIELDS: &[(&str, &str, usize)] = &[
        ("roll", "f32", ROLL),
        ("pitch", "f32", PITCH),
        ("heading", "f32", HEADING),
        ("roll_rate", "f32", ROLL_RATE),
        ("pitch_rate", "f32", PITCH_RATE),
        ("heading_rate", "f32", HEADING_RATE),
        ("latitude", "f64", LATITUDE),
        ("longitude", "f64", LONGITUDE),
        ("track", "f32", TRACK),
        ("speed_over_ground", "f32", SPEED_OVER_GROUND),
        ("fix_type", "i32", FIX_TYPE),
        ("satellites", "i32", SATELLITES),
        ("mean_dop", "f32", MEAN_DOP),
        ("hdop", "f32", HDOP),
        ("vdop", "f32", VDOP),
    ];
}
