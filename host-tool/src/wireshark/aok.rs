//! The AOK part of the generated dissector: the frames in both directions as the crate
//! publishes them (`aok_proto::Message::FRAMES`, `Command::FRAMES`, built from its private
//! layout), the `63` control sub-commands and the motor bytes found by asking the crate's own
//! `Command::parse`, and the hand-written scan (each direction's decoder rules, passively).

use std::fmt::Write as _;

use aok_proto::{Command, FrameLayout, Message, MotorTest};

use super::fill;
use crate::decoders::aok_command_fields;

/// A field: name, type (`u8`, `i32be`, `i16le`, `u16le`, `slot`, `action`, `stick`), offset.
pub(crate) type Field = (&'static str, &'static str, usize);

/// A frame: start byte, name, length, the checked bytes and the checksum's offset (`None`: no
/// checksum), fields.
pub(crate) type AokFrame = (
    u8,
    &'static str,
    usize,
    Option<(core::ops::Range<usize>, usize)>,
    &'static [Field],
);

fn frame(f: &FrameLayout) -> AokFrame {
    (f.start, f.name, f.len, f.checksum.clone(), f.fields)
}

/// What the device sends (USER4), read as the PC reads it: `Message::FRAMES`.
pub(crate) fn device_frames() -> Vec<AokFrame> {
    Message::FRAMES.iter().map(frame).collect()
}

/// What the PC sends (USER3), read as the device reads it (control and motor test apart):
/// `Command::FRAMES`.
pub(crate) fn pc_frames() -> Vec<AokFrame> {
    Command::FRAMES.iter().map(frame).collect()
}

/// The offset of the field `name` of `f`.
fn offset(f: &FrameLayout, name: &str) -> usize {
    f.fields
        .iter()
        .find(|(n, _, _)| *n == name)
        .map_or(usize::MAX, |x| x.2)
}

/// The `63` sub-commands (K5), by asking the crate: sub-command, name, length.
pub(crate) fn control_subs() -> Vec<(u8, String, usize)> {
    (0..=255u8)
        .filter_map(|sub| {
            let (cmd, n) = Command::parse(&[Command::CONTROL.start, sub, 0]).ok()?;
            Some((sub, aok_command_fields(&cmd).0, n))
        })
        .collect()
}

/// The motor test command bytes (K7), by asking the crate: byte, motor number.
pub(crate) fn motor_bytes() -> Vec<(u8, u8)> {
    (0..=255u8)
        .filter_map(|b| match Command::parse(&[b, 0, b]) {
            Ok((Command::MotorTest(MotorTest { motor, .. }), _)) => Some((b, motor.get())),
            _ => None,
        })
        .collect()
}

fn size(ty: &str) -> usize {
    match ty {
        "u8" | "slot" => 1,
        "i16le" | "u16le" | "stick" => 2,
        _ => 4,
    }
}

fn declare(w: &mut String, key: &str, ty: &str) {
    let ctor = match ty {
        "u8" => "uint8, base.DEC",
        "i32be" => "int32, base.DEC",
        "i16le" | "stick" => "int16, base.DEC",
        "u16le" => "uint16, base.DEC",
        _ => "string",
    };
    let (ctor, base) = ctor.split_once(", ").unwrap_or((ctor, ""));
    let base = if base.is_empty() {
        String::new()
    } else {
        format!(", {base}")
    };
    let label = key.rsplit('.').next().unwrap_or(key);
    let _ = writeln!(
        w,
        "FK[\"{key}\"] = ProtoField.{ctor}(\"{key}\", \"{label}\"{base})"
    );
}

fn table(w: &mut String, var: &str, frames: &[AokFrame]) {
    let _ = writeln!(w, "local {var} = {{");
    for (start, name, len, ck, fields) in frames {
        let prefix = format!("aok.{}", name.to_lowercase());
        let ck = ck.as_ref().map_or("nil".to_string(), |(r, at)| {
            format!("{{ {}, {}, {at} }}", r.start, r.end)
        });
        let _ = write!(
            w,
            "  [{start}] = {{ name = \"{name}\", len = {len}, check = {ck}, fields = {{"
        );
        for (f, ty, off) in fields.iter() {
            let _ = write!(w, " {{ \"{prefix}.{f}\", \"{ty}\", {off}, {} }},", size(ty));
        }
        let _ = writeln!(w, " }} }},");
    }
    let _ = writeln!(w, "}}");
}

/// The AOK part of the Lua source.
pub(crate) fn lua(w: &mut String) {
    let device = device_frames();
    let pc = pc_frames();
    let subs = control_subs();
    let motors = motor_bytes();
    w.push_str(include_str!("lua/aok_head.lua"));
    let mut declared = std::collections::BTreeSet::new();
    for (_, name, _, _, fields) in device.iter().chain(pc.iter()) {
        for (f, ty, _) in fields.iter() {
            let key = format!("aok.{}.{f}", name.to_lowercase());
            if declared.insert(key.clone()) {
                declare(w, &key, ty);
            }
        }
    }
    for (_, name, len) in &subs {
        if *len == Command::CONTROL.len {
            let key = format!("aok.{}.set", name.to_lowercase());
            if declared.insert(key.clone()) {
                declare(w, &key, "u8");
            }
        }
    }
    w.push_str(&fill(
        include_str!("lua/aok_experts.lua"),
        &[("CONTROL", &Command::CONTROL.start)],
    ));
    for (sub, name, len) in &subs {
        let _ = writeln!(
            w,
            "  [{sub}] = {{ name = \"{name}\", len = {len}, set = {} }},",
            if *len == Command::CONTROL.len {
                format!("\"aok.{}.set\"", name.to_lowercase())
            } else {
                "nil".into()
            }
        );
    }
    let _ = writeln!(
        w,
        "}}\nlocal AOK_CONTROL_SET = {}",
        offset(&Command::CONTROL, "set")
    );
    let motor = Command::MOTOR_TEST;
    let (check, check_at) = motor.checksum.clone().unwrap_or((0..0, 0));
    let _ = write!(w, "local AOK_MOTOR = {{");
    for (b, m) in &motors {
        let _ = write!(w, " [{b}] = {m},");
    }
    let _ = writeln!(
        w,
        " }}\nlocal AOK_MOTOR_VALUE, AOK_MOTOR_LEN, AOK_MOTOR_CHECK = {}, {}, {{ {}, {}, {} }}",
        offset(&motor, "value"),
        motor.len,
        check.start,
        check.end,
        check_at
    );
    table(w, "AOK_DEVICE", &device);
    table(w, "AOK_PC", &pc);
    w.push_str(DISSECT_AOK);
}

/// The hand-written part: the scan of either direction, checksums, fields.
const DISSECT_AOK: &str = include_str!("lua/aok_dissect.lua");

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::Value;

    /// A frame of `f` with pattern fields (slots and sticks in range) and a good checksum.
    fn build(f: &AokFrame, seed: u8) -> Vec<u8> {
        let (start, _, len, check, fields) = f;
        let mut b: Vec<u8> = (0..*len)
            .map(|i| (i as u8).wrapping_mul(29).wrapping_add(seed))
            .collect();
        b[0] = *start;
        for (_, ty, off) in fields.iter() {
            match *ty {
                "slot" => b[*off] = 7,
                "stick" => b[*off..*off + 2].copy_from_slice(&(-150i16).to_le_bytes()),
                _ => {}
            }
        }
        if let Some((r, at)) = check {
            b[*at] = b[r.clone()].iter().fold(0, |a, x| a ^ x);
        }
        b
    }

    fn expected(b: &[u8], ty: &str, off: usize) -> Value {
        let arr = |n: usize| &b[off..off + n];
        match ty {
            "u8" => Value::from(b[off]),
            "i32be" => Value::from(i32::from_be_bytes(arr(4).try_into().unwrap())),
            "i16le" | "stick" => Value::from(i16::from_le_bytes(arr(2).try_into().unwrap())),
            "u16le" => Value::from(u16::from_le_bytes(arr(2).try_into().unwrap())),
            "slot" => Value::from(crate::decoders::slot_name(
                aok_proto::WaypointSlot::from_wire(b[off]).unwrap(),
            )),
            "action" => Value::from(crate::decoders::action_name(aok_proto::ActionWord(
                u32::from_be_bytes(arr(4).try_into().unwrap()),
            ))),
            other => panic!("type {other}"),
        }
    }

    fn check(name: &str, fields: &[Field], b: &[u8], got: &Value) {
        assert_eq!(
            got.as_object().unwrap().len(),
            fields.len(),
            "{name}: {got}"
        );
        for (f, ty, off) in fields {
            assert_eq!(got[*f], expected(b, ty, *off), "{name}.{f}");
        }
    }

    #[test]
    fn every_field_the_generator_looks_up_is_in_the_crates_tables() {
        assert_eq!(offset(&Command::CONTROL, "set"), 2);
        assert_eq!(offset(&Command::MOTOR_TEST, "value"), 1);
        assert!(Command::MOTOR_TEST.checksum.is_some());
    }

    #[test]
    fn the_device_tables_read_what_the_pcs_parse_reads() {
        for f in device_frames() {
            let b = build(&f, 3);
            let (m, n) = aok_proto::Message::parse(&b).unwrap();
            assert_eq!(n, f.2);
            let (name, fields) = crate::decoders::aok_message_fields(&m);
            assert_eq!(name, f.1);
            check(f.1, f.4, &b, &fields);
            // A flipped checksum is refused by the crate too.
            if let Some((_, at)) = &f.3 {
                let mut bad = b.clone();
                bad[*at] ^= 1;
                assert!(aok_proto::Message::parse(&bad).is_err(), "{}", f.1);
            }
        }
    }

    #[test]
    fn the_pc_tables_read_what_the_devices_parse_reads() {
        for f in pc_frames() {
            let b = build(&f, 5);
            let (c, n) = Command::parse(&b).unwrap();
            assert_eq!(n, f.2);
            let (name, fields) = aok_command_fields(&c);
            assert_eq!(name, f.1);
            check(f.1, f.4, &b, &fields);
        }
        // The control sub-commands and motor bytes the generator found (K5, K7).
        assert_eq!(control_subs().len(), 8);
        assert_eq!(motor_bytes().len(), 12);
        let b = [0x33, 9, 0x33 ^ 9];
        let (c, n) = Command::parse(&b).unwrap();
        assert_eq!((n, Command::MOTOR_TEST.len), (3, 3));
        let (_, fields) = aok_command_fields(&c);
        assert_eq!(fields["value"], b[offset(&Command::MOTOR_TEST, "value")]);
    }
}
