//! The AOK part of the generated dissector: the frames of `aok_proto::layout` in both
//! directions, the `63` control sub-commands and the motor bytes found by asking the crate's own
//! `Command::parse`, and the hand-written scan (each direction's decoder rules, passively).

use std::fmt::Write as _;

use aok_proto::layout::{
    bulk_read, control, debug, external_control, motor_test, parameter_reply, read_parameter,
    read_waypoint, set_parameter, waypoint,
};
use aok_proto::{Command, MotorTest};

use crate::decoders::aok_command_fields;

/// A field: name, type (`u8`, `i32be`, `i16le`, `u16le`, `slot`, `action`, `stick`), offset.
pub type Field = (&'static str, &'static str, usize);

/// A frame: start byte, name, length, the checked bytes and the checksum's offset (`None`: no
/// checksum), fields.
pub type AokFrame = (
    u8,
    &'static str,
    usize,
    Option<(core::ops::Range<usize>, usize)>,
    &'static [Field],
);

const WAYPOINT_FIELDS: &[Field] = &[
    ("slot", "slot", waypoint::SLOT),
    ("longitude", "i32be", waypoint::LONGITUDE),
    ("latitude", "i32be", waypoint::LATITUDE),
    ("action1", "action", waypoint::ACTION1),
    ("action2", "action", waypoint::ACTION2),
];

/// What the device sends (USER4), read as the PC reads it.
pub fn device_frames() -> [AokFrame; 3] {
    [
        (
            debug::START,
            "DEBUG",
            debug::LEN,
            Some((debug::CHECKED, debug::CHECKSUM)),
            &[
                ("number", "u8", debug::NUMBER),
                ("value", "i32be", debug::VALUE),
            ],
        ),
        (
            parameter_reply::START,
            "PARAMETER",
            parameter_reply::LEN,
            Some((parameter_reply::CHECKED, parameter_reply::CHECKSUM)),
            &[
                ("number", "u8", parameter_reply::NUMBER),
                ("value", "i32be", parameter_reply::VALUE),
            ],
        ),
        (
            waypoint::START,
            "WAYPOINT",
            waypoint::LEN,
            Some((waypoint::CHECKED, waypoint::CHECKSUM)),
            WAYPOINT_FIELDS,
        ),
    ]
}

/// What the PC sends (USER3), read as the device reads it (control and motor test apart).
pub fn pc_frames() -> [AokFrame; 6] {
    [
        (
            set_parameter::START,
            "SET_PARAMETER",
            set_parameter::LEN,
            Some((set_parameter::CHECKED, set_parameter::CHECKSUM)),
            &[
                ("number", "u8", set_parameter::NUMBER),
                ("value", "i32be", set_parameter::VALUE),
            ],
        ),
        (
            read_parameter::START,
            "READ_PARAMETER",
            read_parameter::LEN,
            None,
            &[("number", "u8", read_parameter::NUMBER)],
        ),
        (
            bulk_read::START,
            "BULK_READ",
            bulk_read::LEN,
            None,
            &[("first", "u8", bulk_read::FIRST)],
        ),
        (
            read_waypoint::START,
            "READ_WAYPOINT",
            read_waypoint::LEN,
            None,
            &[("slot", "slot", read_waypoint::SLOT)],
        ),
        (
            waypoint::START,
            "SET_WAYPOINT",
            waypoint::LEN,
            Some((waypoint::CHECKED, waypoint::CHECKSUM)),
            WAYPOINT_FIELDS,
        ),
        (
            external_control::START,
            "EXTERNAL_CONTROL",
            external_control::LEN,
            Some((external_control::CHECKED, external_control::CHECKSUM)),
            &[
                ("roll", "stick", external_control::ROLL),
                ("nick", "stick", external_control::NICK),
                ("yaw", "stick", external_control::YAW),
                ("pitch", "i16le", external_control::PITCH),
                ("expiry_ms", "u16le", external_control::EXPIRY),
            ],
        ),
    ]
}

/// The `63` sub-commands (K5), by asking the crate: sub-command, name, length.
pub fn control_subs() -> Vec<(u8, String, usize)> {
    (0..=255u8)
        .filter_map(|sub| {
            let (cmd, n) = Command::parse(&[control::START, sub, 0]).ok()?;
            Some((sub, aok_command_fields(&cmd).0, n))
        })
        .collect()
}

/// The motor test command bytes (K7), by asking the crate: byte, motor number.
pub fn motor_bytes() -> Vec<(u8, u8)> {
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
pub fn lua(w: &mut String) {
    let device = device_frames();
    let pc = pc_frames();
    let subs = control_subs();
    let motors = motor_bytes();
    let _ = writeln!(
        w,
        "
-- AOK ----------------------------------------------------------------------------------------
-- From aok_proto::layout. USER3 (150): what the PC sends, read as the device reads it; USER4
-- (151): what the device sends, read as the PC reads it (firmware >= 0.31: headed replies).
-- A lone O/E/I ack is not decodable passively (only a PC that sent a command expects one):
-- such bytes are skipped, as `protolink decode` skips them, and shown as not decoded.
local aok = Proto(\"aok\", \"AOK copter serial protocol\")
local FK = {{}}
FK.status = ProtoField.string(\"aok.status\", \"Status\")
FK.error = ProtoField.string(\"aok.error\", \"Error\")
FK.direction = ProtoField.string(\"aok.direction\", \"Sent by\")
FK.name = ProtoField.string(\"aok.name\", \"Message\")
FK.start = ProtoField.uint8(\"aok.start\", \"Start byte\", base.HEX)
FK.len = ProtoField.uint32(\"aok.len\", \"Length on the wire\", base.DEC)
FK.checksum = ProtoField.uint8(\"aok.checksum\", \"Checksum\", base.HEX)
FK.checksum_computed = ProtoField.uint8(\"aok.checksum_computed\", \"Checksum computed\", base.HEX)
FK.checksum_status = ProtoField.string(\"aok.checksum_status\", \"Checksum status\")
FK.skipped = ProtoField.bytes(\"aok.skipped\", \"Bytes not decoded\")
FK[\"aok.motor_test.motor\"] = ProtoField.uint8(\"aok.motor_test.motor\", \"motor\", base.DEC)
FK[\"aok.motor_test.value\"] = ProtoField.uint8(\"aok.motor_test.value\", \"value\", base.DEC)"
    );
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
        if *len == control::LEN_WITH_SET {
            let key = format!("aok.{}.set", name.to_lowercase());
            if declared.insert(key.clone()) {
                declare(w, &key, "u8");
            }
        }
    }
    let _ = writeln!(
        w,
        "aok.fields = {{}}
for _, v in pairs(FK) do table.insert(aok.fields, v) end
local EK = {{
  checksum_bad = ProtoExpert.new(\"aok.checksum_bad\", \"XOR checksum mismatch (one byte dropped, scanning resumes)\", expert.group.CHECKSUM, expert.severity.ERROR),
  invalid = ProtoExpert.new(\"aok.invalid\", \"A frame with a good checksum and a value out of range (one byte dropped)\", expert.group.MALFORMED, expert.severity.ERROR),
  skipped = ProtoExpert.new(\"aok.skipped\", \"Not decodable passively (noise, or a lone O/E/I ack)\", expert.group.UNDECODED, expert.severity.NOTE),
}}
aok.experts = {{ EK.checksum_bad, EK.invalid, EK.skipped }}
local AOK_CONTROL = {}
local AOK_CONTROL_SUB = {{",
        control::START
    );
    for (sub, name, len) in &subs {
        let _ = writeln!(
            w,
            "  [{sub}] = {{ name = \"{name}\", len = {len}, set = {} }},",
            if *len == control::LEN_WITH_SET {
                format!("\"aok.{}.set\"", name.to_lowercase())
            } else {
                "nil".into()
            }
        );
    }
    let _ = writeln!(w, "}}\nlocal AOK_CONTROL_SET = {}", control::SET);
    let _ = write!(w, "local AOK_MOTOR = {{");
    for (b, m) in &motors {
        let _ = write!(w, " [{b}] = {m},");
    }
    let _ = writeln!(
        w,
        " }}\nlocal AOK_MOTOR_VALUE, AOK_MOTOR_LEN, AOK_MOTOR_CHECK = {}, {}, {{ {}, {}, {} }}",
        motor_test::VALUE,
        motor_test::LEN,
        motor_test::CHECKED.start,
        motor_test::CHECKED.end,
        motor_test::CHECKSUM
    );
    table(w, "AOK_DEVICE", &device);
    table(w, "AOK_PC", &pc);
    w.push_str(DISSECT_AOK);
}

/// The hand-written part: the scan of either direction, checksums, fields.
const DISSECT_AOK: &str = r#"
local function aok_slot(b)
  if b <= 30 then return tostring(b + 1) end
  if b == 31 then return "poi" end
  if b == 254 then return "ram-poi" end
  if b == 255 then return "fbc" end
  return nil
end
local AOK_ACTIONS = { [0] = "none", "pause", "hold-and-climb", "hold-and-sink", "fly-and-climb", "fly-and-sink", "set-fly-speed" }
local function aok_action(word)
  local a, low = math.floor(word / 65536), word % 65536
  if AOK_ACTIONS[a] then return AOK_ACTIONS[a] .. ":" .. (low - 32768) end
  return string.format("raw:0x%08x", word)
end

-- The result of a candidate at `p` of `t`: nil (more bytes needed), or a frame description.
local function aok_candidate(t, p, dir)
  local n = t:len() - p
  local b = t(p, 1):uint()
  local f
  if dir == "device" then
    f = AOK_DEVICE[b]
  elseif b == AOK_CONTROL then
    if n < 2 then return "more" end
    local sub = AOK_CONTROL_SUB[t(p + 1, 1):uint()]
    if not sub then return nil end
    return { name = sub.name, len = sub.len, fields = sub.set and { { sub.set, "u8", AOK_CONTROL_SET, 1 } } or {} }
  elseif AOK_MOTOR[b] then
    return { name = "MOTOR_TEST", len = AOK_MOTOR_LEN, check = AOK_MOTOR_CHECK, motor = AOK_MOTOR[b],
      fields = { { "aok.motor_test.value", "u8", AOK_MOTOR_VALUE, 1 } } }
  else
    f = AOK_PC[b]
  end
  return f
end

local function aok_scan(t, pinfo, tree, dir, stream_proto)
  local n = t:len()
  local names = {}
  local p = 0
  local open = nil
  local skip_from = nil
  local function flush_skip(to)
    if skip_from then
      local it = tree:add(stream_proto, t(skip_from, to - skip_from), "AOK: bytes not decoded (noise, or a lone O/E/I ack: not decodable passively)")
      it:add(FK.skipped, t(skip_from, to - skip_from))
      it:add_proto_expert_info(EK.skipped)
      skip_from = nil
    end
  end
  while p < n do
    local f = aok_candidate(t, p, dir)
    if f == "more" then
      flush_skip(p); open = p; break
    elseif f == nil then
      skip_from = skip_from or p
      p = p + 1
    elseif n - p < f.len then
      flush_skip(p); open = p; break
    else
      flush_skip(p)
      local fr = t(p, f.len)
      local ok = true
      local computed, got
      if f.check then
        computed = 0
        for i = f.check[1], f.check[2] - 1 do computed = xor8(computed, fr(i, 1):uint()) end
        got = fr(f.check[3], 1):uint()
        ok = computed == got
      end
      local sub = tree:add(aok, fr)
      sub:add(FK.direction, fr(0, 0), dir)
      sub:add(FK.start, fr(0, 1))
      sub:add(FK.len, fr, f.len)
      if f.check then
        sub:add(FK.checksum, fr(f.check[3], 1))
        sub:add(FK.checksum_computed, fr(f.check[3], 1), computed)
        local cst = sub:add(FK.checksum_status, fr(f.check[3], 1), ok and "ok" or "bad")
        if not ok then cst:add_proto_expert_info(EK.checksum_bad) end
      else
        sub:add(FK.checksum_status, fr(0, 0), "none")
      end
      if not ok then
        sub:add(FK.status, fr(0, 0), "bad_checksum")
        sub:append_text(": " .. f.name .. "?, checksum mismatch, one byte dropped")
        table.insert(names, "[bad checksum]")
        p = p + 1
      else
        local why = nil
        for _, fd in ipairs(f.fields) do
          local key, ty, off, size = fd[1], fd[2], fd[3], fd[4]
          local r = fr(off, size)
          if ty == "slot" then
            local s = aok_slot(r:uint())
            if s then sub:add(FK[key], r, s) else why = "invalid waypoint slot " .. r:uint() end
          elseif ty == "action" then
            sub:add(FK[key], r, aok_action(r:uint()))
          elseif ty == "i32be" then
            sub:add(FK[key], r, r:int())
          elseif ty == "stick" then
            local v = r:le_int()
            if v < -200 or v > 200 then why = "stick value " .. v .. " outside -200..=200" end
            sub:add_le(FK[key], r)
          elseif ty == "i16le" or ty == "u16le" then
            sub:add_le(FK[key], r)
          else
            sub:add(FK[key], r)
          end
          if why then break end
        end
        if f.motor then sub:add(FK["aok.motor_test.motor"], fr(0, 1), f.motor) end
        if why then
          local st = sub:add(FK.status, fr(0, 0), "invalid")
          sub:add(FK.error, fr(0, 0), why)
          st:add_proto_expert_info(EK.invalid)
          sub:append_text(": " .. why .. ", one byte dropped")
          table.insert(names, "[invalid]")
          p = p + 1
        else
          sub:add(FK.status, fr(0, 0), "ok")
          sub:add(FK.name, fr(0, 1), f.name)
          sub:append_text(", " .. f.name)
          table.insert(names, f.name)
          p = p + f.len
        end
      end
    end
  end
  flush_skip(p)
  pinfo.cols.protocol = "AOK"
  pinfo.cols.info = (dir == "pc" and "PC->device: " or "device->PC: ") .. table.concat(names, ", ")
  return open
end

local aok_carry, aok_carry_in = {}, {}
local function aok_stream(name, desc, dir)
  local p = Proto(name, desc)
  function p.dissector(tvb, pinfo, tree)
    local key = dir .. iface_key(pinfo)
    if not pinfo.visited then aok_carry_in[pinfo.number .. key] = aok_carry[key] or "" end
    local prefix = aok_carry_in[pinfo.number .. key] or ""
    local t = tvb
    if #prefix > 0 then
      t = (ByteArray.new(prefix) .. tvb:bytes()):tvb("AOK stream (this packet after the previous one's open frame)")
    end
    local open = aok_scan(t, pinfo, tree, dir, p)
    if not pinfo.visited then
      local tail = ""
      if open then tail = t:bytes():subset(open, t:len() - open):tohex() end
      aok_carry[key] = tail
    end
    return tvb:len()
  end
  return p
end
-- USER3 and USER4 are wtap encapsulations 48 and 49.
encap:add((wtap_encaps and wtap_encaps.USER3) or 48, aok_stream("aok_pc", "AOK byte stream, PC to device", "pc"))
encap:add((wtap_encaps and wtap_encaps.USER4) or 49, aok_stream("aok_device", "AOK byte stream, device to PC", "device"))
"#;

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
        assert_eq!((n, motor_test::LEN), (3, 3));
        let (_, fields) = aok_command_fields(&c);
        assert_eq!(fields["value"], b[motor_test::VALUE]);
    }
}
