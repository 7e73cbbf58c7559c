//! The AEOLUS part of the generated dissector: the fixed-size messages' fields from
//! `aeolus_proto::message::*::FIELDS`, the text and raw messages, the CRC-16 table, and the
//! hand-written framing (`lua/aeolus_dissect.lua`).

use std::fmt::Write as _;

use aeolus_proto::message::{
    Accel, AeolusInfo, Attitude, CALIBINFO_LEN, Compass, DEBUGINFO_LEN, Gps, Gyro, Magnet,
    Pressure, SetTime, Temp, Wind, id,
};

use crate::error::{Error, Result};

/// A fixed-size message: ID, name, data length, `(field, type, offset)`.
type Fixed = (
    u8,
    &'static str,
    usize,
    &'static [(&'static str, &'static str, usize)],
);

/// Every fixed-size AEOLUS message, from the layout tables.
pub const FIXED: [Fixed; 11] = [
    (
        AeolusInfo::ID,
        "AEOLUSINFO",
        AeolusInfo::LEN,
        AeolusInfo::FIELDS,
    ),
    (Pressure::ID, "PRESSURE", Pressure::LEN, Pressure::FIELDS),
    (Gyro::ID, "GYRO", Gyro::LEN, Gyro::FIELDS),
    (Accel::ID, "ACCEL", Accel::LEN, Accel::FIELDS),
    (Magnet::ID, "MAGNET", Magnet::LEN, Magnet::FIELDS),
    (Temp::ID, "TEMP", Temp::LEN, Temp::FIELDS),
    (Gps::ID, "GPS", Gps::LEN, Gps::FIELDS),
    (Attitude::ID, "ATTITUDE", Attitude::LEN, Attitude::FIELDS),
    (Compass::ID, "COMPASS", Compass::LEN, Compass::FIELDS),
    (Wind::ID, "WIND", Wind::LEN, Wind::FIELDS),
    (SetTime::ID, "SETTIME", SetTime::LEN, SetTime::FIELDS),
];

/// Messages carried as text (to the first NUL).
pub(crate) const TEXT: [(u8, &str); 2] = [(id::TOAST, "TOAST"), (id::COMMAND, "COMMAND")];
/// Messages carried as raw bytes, with their fixed length (`None`: any length).
pub(crate) const RAW: [(u8, &str, Option<usize>); 3] = [
    (id::CALIBINFO, "CALIBINFO", Some(CALIBINFO_LEN)),
    (id::DEBUGINFO, "DEBUGINFO", Some(DEBUGINFO_LEN)),
    (id::LOG, "LOG", None),
];

/// A field type from the layout: (element Lua ProtoField constructor, element size, count).
fn lua_type(ty: &str) -> Option<(&'static str, usize, usize)> {
    let elem = |t: &str| -> Option<(&'static str, usize)> {
        Some(match t.trim() {
            "u8" => ("uint8", 1),
            "bool" => ("bool", 1),
            "f32" => ("float", 4),
            "f64" => ("double", 8),
            "CalibrationStatus" => ("int8", 1),
            _ => return None,
        })
    };
    if let Some(inner) = ty
        .trim()
        .strip_prefix('[')
        .and_then(|t| t.strip_suffix(']'))
    {
        let (t, n) = inner.split_once(';')?;
        let (name, size) = elem(t)?;
        return Some((name, size, n.trim().parse().ok()?));
    }
    let (name, size) = elem(ty)?;
    Some((name, size, 1))
}

/// The CRC-16 lookup table (the crate's own `checksum` of each single byte's shifted value).
fn crc_table() -> Vec<u16> {
    (0u16..256)
        .map(|i| {
            let mut crc = i << 8;
            for _ in 0..8 {
                crc = (crc << 1)
                    ^ if crc & 0x8000 != 0 {
                        aeolus_proto::crc::POLY
                    } else {
                        0
                    };
            }
            crc
        })
        .collect()
}

/// The AEOLUS part of the Lua source (the dissector's head, which names all three protocols,
/// comes first).
///
/// # Errors
/// [`Error::Unsupported`] if a layout names a field type the generator does not know (a test
/// keeps this from ever shipping).
pub(crate) fn lua(w: &mut String) -> Result<()> {
    w.push_str(include_str!("lua/aeolus_head.lua"));
    // Per-message fields.
    for (_, name, _, fields) in FIXED {
        let lower = name.to_lowercase();
        for (field, ty, _) in fields {
            let (ctor, _, _) = lua_type(ty).ok_or_else(|| {
                Error::Unsupported(format!(
                    "the layout of {name} has a field {field} of type {ty}, which the dissector generator does not know"
                ))
            })?;
            let key = format!("{lower}.{field}");
            let extra = match ctor {
                "uint8" | "int8" if *ty == "CalibrationStatus" => ", base.DEC, calibration",
                "uint8" => ", base.DEC",
                _ => "",
            };
            let _ = writeln!(
                w,
                "F[\"{key}\"] = ProtoField.{ctor}(\"aeolus.{key}\", \"{field}\"{extra})"
            );
        }
    }
    w.push_str(include_str!("lua/aeolus_experts.lua"));
    // The CRC table and an XOR that needs no bit library (Lua 5.1 to 5.4).
    let table = crc_table();
    let _ = write!(w, "local CRC = {{ [0] = ");
    for (i, v) in table.iter().enumerate() {
        let _ = write!(w, "{v}{}", if i + 1 < table.len() { ", " } else { "" });
        if i % 16 == 15 && i + 1 < table.len() {
            let _ = write!(w, "\n  ");
        }
    }
    let _ = writeln!(w, " }}");
    w.push_str(include_str!("lua/aeolus_crc16.lua"));
    // Message layouts.
    let _ = writeln!(w, "local FIXED = {{");
    for (id, name, len, fields) in FIXED {
        let lower = name.to_lowercase();
        let _ = write!(
            w,
            "  [{id}] = {{ name = \"{name}\", len = {len}, fields = {{"
        );
        for (field, ty, off) in fields {
            let (ctor, size, count) = lua_type(ty).unwrap_or(("uint8", 1, 1));
            let _ = write!(
                w,
                " {{ \"{lower}.{field}\", {off}, {size}, {count}, {} }},",
                if ctor == "bool" { "true" } else { "false" }
            );
        }
        let _ = writeln!(w, " }} }},");
    }
    let _ = writeln!(w, "}}");
    let _ = write!(w, "local TEXT = {{");
    for (id, name) in TEXT {
        let _ = write!(w, " [{id}] = \"{name}\",");
    }
    let _ = writeln!(w, " }}");
    let _ = write!(w, "local RAW = {{");
    for (id, name, len) in RAW {
        let len = len.map_or("nil".to_string(), |l| l.to_string());
        let _ = write!(w, " [{id}] = {{ name = \"{name}\", len = {len} }},");
    }
    let _ = writeln!(w, " }}");
    w.push_str(DISSECT);
    Ok(())
}

/// The hand-written part: framing, escapes, CRC, and walking a layout.
const DISSECT: &str = include_str!("lua/aeolus_dissect.lua");
