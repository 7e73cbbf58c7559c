//! The AYDP part of the generated dissector: tables from the typed messages' `FIELDS` and
//! `LEN` (`aydp_proto::Position::FIELDS`, ..., `Frame::HEADER_FIELDS`), which the crate builds
//! from its private layout, and the hand-written framing (profiles, XOR checksum, resync).

use std::fmt::Write as _;

use aydp_proto::message::{USER_FIRST, USER_LAST};
use aydp_proto::profile::{EXPEDITED, EXPEDITED_HEADER_LEN, NORMAL_HEADER_LEN, START};
use aydp_proto::{
    DirectOutput, FixDetail, FixQuality, Frame, OutputEntry, Position, Satellite, SystemControl,
    SystemValueUpdate, VesselData, WindDirection, WindSpeed,
};

use super::fill;
use crate::decoders::AYDP_CAPACITY;

/// A field: name, type (`u8`, `u16`, `u32`, `i32`, `f32`, `f64`, `uflt16`), offset.
pub(crate) type Field = (&'static str, &'static str, usize);

/// A fixed-size AYDP message: base type, profile (`None`: both), name, data length, fields.
pub(crate) type AydpFixed = (
    u8,
    Option<&'static str>,
    &'static str,
    usize,
    &'static [Field],
);

/// The fixed-size typed messages, from their `FIELDS`.
pub(crate) const AYDP_FIXED: [AydpFixed; 5] = [
    (
        Position::TYPE,
        None,
        "POSITION",
        Position::LEN,
        Position::FIELDS,
    ),
    (
        FixQuality::TYPE,
        None,
        "FIX_QUALITY",
        FixQuality::LEN,
        FixQuality::FIELDS,
    ),
    (
        WindSpeed::TYPE,
        Some("reference"),
        "WIND_SPEED",
        WindSpeed::LEN,
        WindSpeed::FIELDS,
    ),
    (
        WindDirection::TYPE,
        Some("reference"),
        "WIND_DIRECTION",
        WindDirection::LEN,
        WindDirection::FIELDS,
    ),
    (
        VesselData::TYPE,
        Some("reference"),
        "VESSEL_DATA",
        VesselData::LEN,
        VesselData::FIELDS,
    ),
];

/// A counted list: base type, name, the list's JSON key, count type and offset, first entry,
/// entry length, entry fields.
pub(crate) type AydpList = (
    u8,
    &'static str,
    &'static str,
    &'static str,
    usize,
    usize,
    usize,
    &'static [Field],
);

/// Fix detail and direct output, from their `FIELDS` (the count) and their entries' `FIELDS`.
pub(crate) const AYDP_LISTS: [AydpList; 2] = [
    (
        FixDetail::TYPE,
        "FIX_DETAIL",
        "satellites",
        FixDetail::FIELDS[0].1,
        FixDetail::FIELDS[0].2,
        FixDetail::HEADER_LEN,
        Satellite::LEN,
        Satellite::FIELDS,
    ),
    (
        DirectOutput::TYPE,
        "DIRECT_OUTPUT",
        "entries",
        DirectOutput::FIELDS[0].1,
        DirectOutput::FIELDS[0].2,
        DirectOutput::HEADER_LEN,
        OutputEntry::LEN,
        OutputEntry::FIELDS,
    ),
];

/// System value update (8): its head, from its `FIELDS`.
pub(crate) const AYDP_SVU: &[Field] = SystemValueUpdate::FIELDS;

/// The offset of the field `name` in `fields` (a header or message table of the crate).
fn offset(fields: &[Field], name: &str) -> usize {
    fields
        .iter()
        .find(|(n, _, _)| *n == name)
        .map_or(usize::MAX, |f| f.2)
}

/// A type name and size for a ProtoField constructor.
pub(crate) fn lua_kind(ty: &str) -> Option<(&'static str, usize)> {
    Some(match ty {
        "u8" => ("uint8", 1),
        "u16" => ("uint16", 2),
        "u32" => ("uint32", 4),
        "i32" => ("int32", 4),
        "f32" => ("float", 4),
        "f64" => ("double", 8),
        "uflt16" => ("float", 2),
        _ => return None,
    })
}

fn declare(w: &mut String, key: &str, ty: &str) {
    let (ctor, _) = lua_kind(ty).unwrap_or(("uint8", 1));
    let base = if ctor.starts_with("uint") || ctor.starts_with("int") {
        ", base.DEC"
    } else {
        ""
    };
    let label = key.rsplit('.').next().unwrap_or(key);
    let _ = writeln!(
        w,
        "FY[\"{key}\"] = ProtoField.{ctor}(\"{key}\", \"{label}\"{base})"
    );
}

fn field_list(w: &mut String, prefix: &str, fields: &[Field]) {
    let _ = write!(w, "{{");
    for (name, ty, off) in fields {
        let size = lua_kind(ty).map_or(1, |k| k.1);
        let _ = write!(w, " {{ \"{prefix}.{name}\", \"{ty}\", {off}, {size} }},");
    }
    let _ = write!(w, " }}");
}

/// The AYDP part of the Lua source.
pub(crate) fn lua(w: &mut String) {
    w.push_str(&fill(
        include_str!("lua/aydp_head.lua"),
        &[("EXPEDITED", &EXPEDITED)],
    ));
    for (_, _, name, _, fields) in AYDP_FIXED {
        let prefix = format!("aydp.{}", name.to_lowercase());
        for (f, ty, _) in fields {
            declare(w, &format!("{prefix}.{f}"), ty);
        }
    }
    for (_, name, _, count_ty, _, _, _, fields) in AYDP_LISTS {
        let prefix = format!("aydp.{}", name.to_lowercase());
        declare(w, &format!("{prefix}.count"), count_ty);
        for (f, ty, _) in fields {
            declare(w, &format!("{prefix}.{f}"), ty);
        }
    }
    for (f, ty, _) in AYDP_SVU {
        declare(w, &format!("aydp.system_value_update.{f}"), ty);
    }
    w.push_str(&fill(
        include_str!("lua/aydp_experts.lua"),
        &[
            ("START", &START),
            ("EXPEDITED", &EXPEDITED),
            ("TYPE", &offset(Frame::HEADER_FIELDS, "type")),
            ("LENGTH", &offset(Frame::HEADER_FIELDS, "length")),
            ("SECONDS", &offset(Frame::HEADER_FIELDS, "seconds")),
            ("SUBSEC", &offset(Frame::HEADER_FIELDS, "subsec")),
            ("EXPEDITED_LEN", &EXPEDITED_HEADER_LEN),
            ("NORMAL_LEN", &NORMAL_HEADER_LEN),
            ("CAPACITY", &AYDP_CAPACITY),
            ("USER_FIRST", &USER_FIRST),
            ("USER_LAST", &USER_LAST),
            ("SVU_VALUE", &SystemValueUpdate::HEADER_LEN),
            ("CONTROL_ADDRESS", &offset(SystemControl::FIELDS, "address")),
            ("REQUEST_DATA_LEN", &SystemControl::REQUEST_DATA_LEN),
            (
                "STORE_CONFIGURATION_LEN",
                &SystemControl::STORE_CONFIGURATION_LEN,
            ),
        ],
    ));
    let _ = writeln!(w, "local AYDP_FIXED = {{");
    for (ty, profile, name, len, fields) in AYDP_FIXED {
        let profile = profile.map_or("nil".to_string(), |p| format!("\"{p}\""));
        let _ = write!(
            w,
            "  {{ type = {ty}, profile = {profile}, name = \"{name}\", len = {len}, fields = "
        );
        field_list(w, &format!("aydp.{}", name.to_lowercase()), fields);
        let _ = writeln!(w, " }},");
    }
    let _ = writeln!(w, "}}\nlocal AYDP_LISTS = {{");
    for (ty, name, _, count_ty, count_off, entries, entry_len, fields) in AYDP_LISTS {
        let prefix = format!("aydp.{}", name.to_lowercase());
        let count_size = lua_kind(count_ty).map_or(1, |k| k.1);
        let _ = write!(
            w,
            "  [{ty}] = {{ name = \"{name}\", count = {{ \"{prefix}.count\", \"{count_ty}\", {count_off}, {count_size} }}, entries = {entries}, entry_len = {entry_len}, fields = "
        );
        field_list(w, &prefix, fields);
        let _ = writeln!(w, " }},");
    }
    let _ = write!(w, "}}\nlocal AYDP_SVU = ");
    field_list(w, "aydp.system_value_update", AYDP_SVU);
    let _ = writeln!(w);
    w.push_str(DISSECT_AYDP);
}

/// The hand-written part: resync, checksum, header, and walking the tables.
const DISSECT_AYDP: &str = include_str!("lua/aydp_dissect.lua");

#[cfg(test)]
mod tests {
    use super::*;
    use aydp_proto::{Message, Profile};
    use serde_json::Value;

    /// A value of `ty` at `off` of `data`, as f64 (uflt16 through the crate's own decoder).
    fn read(data: &[u8], ty: &str, off: usize) -> f64 {
        let b = |n: usize| &data[off..off + n];
        match ty {
            "u8" => f64::from(data[off]),
            "u16" => f64::from(u16::from_le_bytes(b(2).try_into().unwrap())),
            "u32" => f64::from(u32::from_le_bytes(b(4).try_into().unwrap())),
            "i32" => f64::from(i32::from_le_bytes(b(4).try_into().unwrap())),
            "f32" => f64::from(f32::from_le_bytes(b(4).try_into().unwrap())),
            "f64" => f64::from_le_bytes(b(8).try_into().unwrap()),
            "uflt16" => f64::from(
                aydp_proto::uflt16::decode(u16::from_le_bytes(b(2).try_into().unwrap())).unwrap(),
            ),
            other => panic!("type {other}"),
        }
    }

    fn same(json: &Value, ty: &str, v: f64, what: &str) {
        let j = json.as_f64().unwrap();
        if ty == "f32" || ty == "uflt16" {
            assert_eq!(j as f32, v as f32, "{what}");
        } else {
            assert_eq!(j, v, "{what}");
        }
    }

    /// Bytes with every uflt16 of `fields` (at `base + k * step`) a finite positive value.
    fn pattern(len: usize, seed: u8) -> Vec<u8> {
        (0..len)
            .map(|i| (i as u8).wrapping_mul(37).wrapping_add(seed))
            .collect()
    }

    fn tame(data: &mut [u8], fields: &[Field], base: usize) {
        for (_, ty, off) in fields {
            if *ty == "uflt16" {
                data[base + off + 1] &= 0x3F;
            }
        }
    }

    #[test]
    fn every_field_the_generator_looks_up_is_in_the_crates_tables() {
        for name in ["type", "length", "seconds", "subsec"] {
            assert_ne!(offset(Frame::HEADER_FIELDS, name), usize::MAX, "{name}");
        }
        assert_eq!(offset(SystemControl::FIELDS, "address"), 1);
        assert_eq!(offset(Frame::HEADER_FIELDS, "nothing"), usize::MAX);
    }

    #[test]
    fn every_fixed_table_reads_what_the_crates_parse_reads() {
        for (ty, profile, name, len, fields) in AYDP_FIXED {
            let profile = match profile {
                Some("reference") => Profile::Reference,
                _ => Profile::Spec,
            };
            let mut data = pattern(len, ty);
            tame(&mut data, fields, 0);
            let m = Message::parse(ty, false, &data, profile).unwrap();
            let json = crate::render::to_json(&m);
            let (_, obj) = crate::render::variant(json);
            let obj = match obj {
                Value::Number(_) => serde_json::json!({ "value": obj }),
                o => o,
            };
            assert_eq!(obj.as_object().unwrap().len(), fields.len(), "{name}");
            for (f, fty, off) in fields {
                same(
                    &obj[*f],
                    fty,
                    read(&data, fty, *off),
                    &format!("{name}.{f}"),
                );
            }
            // Every byte is a field's: the table covers the layout.
            let covered: usize = fields.iter().map(|(_, t, _)| lua_kind(t).unwrap().1).sum();
            assert_eq!(covered, len, "{name}");
        }
    }

    #[test]
    fn the_list_tables_read_what_the_crates_parse_reads() {
        for (ty, name, key, count_ty, count_off, entries, entry_len, fields) in AYDP_LISTS {
            let n = 3usize;
            let mut data = pattern(entries + n * entry_len, ty);
            let count_size = lua_kind(count_ty).unwrap().1;
            data[count_off..count_off + count_size].fill(0);
            data[count_off] = n as u8;
            for k in 0..n {
                tame(&mut data, fields, entries + k * entry_len);
            }
            let m = Message::parse(ty, false, &data, Profile::Spec).unwrap();
            let json = crate::render::to_json(&m);
            let (_, obj) = crate::render::variant(json);
            let list: Vec<Value> = match &m {
                Message::FixDetail(d) => {
                    d.satellites().map(|s| crate::render::to_json(&s)).collect()
                }
                Message::DirectOutput(d) => {
                    d.entries().map(|e| crate::render::to_json(&e)).collect()
                }
                _ => panic!("{name}: {obj}"),
            };
            assert_eq!(list.len(), n, "{name} {key}");
            for (k, e) in list.iter().enumerate() {
                assert_eq!(e.as_object().unwrap().len(), fields.len(), "{name}");
                for (f, fty, off) in fields {
                    let v = read(&data, fty, entries + k * entry_len + off);
                    same(&e[*f], fty, v, &format!("{name}[{k}].{f}"));
                }
            }
        }
    }

    #[test]
    fn the_system_value_update_table_reads_what_the_crates_parse_reads() {
        let data = [3, 0x34, 0x12, 7, 0, 0, 0, 0xAA, 0xBB];
        let Message::SystemValueUpdate(u) = Message::parse(8, false, &data, Profile::Spec).unwrap()
        else {
            panic!("not an update")
        };
        assert_eq!(
            read(&data, AYDP_SVU[0].1, AYDP_SVU[0].2),
            f64::from(u.mode.code())
        );
        assert_eq!(
            read(&data, AYDP_SVU[1].1, AYDP_SVU[1].2),
            f64::from(u.address)
        );
        assert_eq!(
            read(&data, AYDP_SVU[2].1, AYDP_SVU[2].2),
            f64::from(u.mode.field())
        );
        assert_eq!(&data[SystemValueUpdate::HEADER_LEN..], u.data);
    }
}
