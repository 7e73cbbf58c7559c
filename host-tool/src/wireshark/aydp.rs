//! The AYDP part of the generated dissector: tables from `aydp_proto::layout` and the
//! hand-written framing (profiles, XOR checksum, resync).

use std::fmt::Write as _;

use aydp_proto::layout::{
    direct_output, fix_detail, fix_quality, header, output_entry, position, satellite,
    system_control, system_value_update, vessel_data, wind,
};
use aydp_proto::messages::{USER_FIRST, USER_LAST};
use aydp_proto::profile::{EXPEDITED, START};

use crate::decoders::AYDP_CAPACITY;

/// A field: name, type (`u8`, `u16`, `u32`, `i32`, `f32`, `f64`, `uflt16`), offset.
pub type Field = (&'static str, &'static str, usize);

/// A fixed-size AYDP message: base type, profile (`None`: both), name, data length, fields.
pub type AydpFixed = (
    u8,
    Option<&'static str>,
    &'static str,
    usize,
    &'static [Field],
);

/// The fixed-size typed messages, from the layout.
pub const AYDP_FIXED: [AydpFixed; 5] = [
    (
        3,
        None,
        "POSITION",
        position::LEN,
        &[
            ("latitude", "f64", position::LATITUDE),
            ("longitude", "f64", position::LONGITUDE),
            ("altitude", "f32", position::ALTITUDE),
        ],
    ),
    (
        4,
        None,
        "FIX_QUALITY",
        fix_quality::LEN,
        &[
            ("fix_type", "u8", fix_quality::FIX_TYPE),
            ("mean_dop", "uflt16", fix_quality::MEAN_DOP),
            ("hdop", "uflt16", fix_quality::HDOP),
            ("vdop", "uflt16", fix_quality::VDOP),
            ("satellites", "u8", fix_quality::SATELLITES),
        ],
    ),
    (
        1,
        Some("reference"),
        "WIND_SPEED",
        wind::LEN,
        &[("value", "f32", wind::VALUE)],
    ),
    (
        2,
        Some("reference"),
        "WIND_DIRECTION",
        wind::LEN,
        &[("value", "f32", wind::VALUE)],
    ),
    (
        17,
        Some("reference"),
        "VESSEL_DATA",
        vessel_data::LEN,
        &[
            ("roll", "f32", vessel_data::ROLL),
            ("pitch", "f32", vessel_data::PITCH),
            ("heading", "f32", vessel_data::HEADING),
            ("roll_rate", "f32", vessel_data::ROLL_RATE),
            ("pitch_rate", "f32", vessel_data::PITCH_RATE),
            ("heading_rate", "f32", vessel_data::HEADING_RATE),
            ("latitude", "f64", vessel_data::LATITUDE),
            ("longitude", "f64", vessel_data::LONGITUDE),
            ("track", "f32", vessel_data::TRACK),
            ("speed_over_ground", "f32", vessel_data::SPEED_OVER_GROUND),
            ("fix_type", "i32", vessel_data::FIX_TYPE),
            ("satellites", "i32", vessel_data::SATELLITES),
            ("mean_dop", "f32", vessel_data::MEAN_DOP),
            ("hdop", "f32", vessel_data::HDOP),
            ("vdop", "f32", vessel_data::VDOP),
        ],
    ),
];

/// A counted list: base type, name, the list's JSON key, count type and offset, first entry,
/// entry length, entry fields.
pub type AydpList = (
    u8,
    &'static str,
    &'static str,
    &'static str,
    usize,
    usize,
    usize,
    &'static [Field],
);

/// Fix detail and direct output, from the layout.
pub const AYDP_LISTS: [AydpList; 2] = [
    (
        5,
        "FIX_DETAIL",
        "satellites",
        "u8",
        fix_detail::COUNT,
        fix_detail::ENTRIES,
        satellite::LEN,
        &[
            ("id", "u8", satellite::ID),
            ("azimuth", "uflt16", satellite::AZIMUTH),
            ("elevation", "uflt16", satellite::ELEVATION),
            ("snr", "uflt16", satellite::SNR),
        ],
    ),
    (
        7,
        "DIRECT_OUTPUT",
        "entries",
        "u16",
        direct_output::COUNT,
        direct_output::ENTRIES,
        output_entry::LEN,
        &[
            ("device", "u8", output_entry::DEVICE),
            ("channel", "u8", output_entry::CHANNEL),
            ("value", "f32", output_entry::VALUE),
        ],
    ),
];

/// System value update (8): its head, from the layout.
pub const AYDP_SVU: [Field; 3] = [
    ("mode", "u8", system_value_update::MODE),
    ("address", "u16", system_value_update::ADDRESS),
    ("field", "u32", system_value_update::FIELD),
];

/// A type name and size for a ProtoField constructor.
pub fn lua_kind(ty: &str) -> Option<(&'static str, usize)> {
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
pub fn lua(w: &mut String) {
    let _ = writeln!(
        w,
        "
-- AYDP ---------------------------------------------------------------------------------------
-- From aydp_proto::layout. Profiles (DECISIONS Y1, Y2): spec (USER1, 148): the length counts
-- the whole message, sub-seconds in ms; reference (USER2, 149, and TCP/UDP 6321 as in the AYDP
-- reference software): the length counts data only, sub-seconds in µs.
local aydp = Proto(\"aydp\", \"AYDP yacht protocol\")
local FY = {{}}
FY.status = ProtoField.string(\"aydp.status\", \"Status\")
FY.error = ProtoField.string(\"aydp.error\", \"Error\")
FY.profile = ProtoField.string(\"aydp.profile\", \"Profile\")
FY.name = ProtoField.string(\"aydp.name\", \"Message\")
FY.start = ProtoField.uint8(\"aydp.start\", \"Start\", base.HEX)
FY.type_byte = ProtoField.uint8(\"aydp.type_byte\", \"Type byte\", base.HEX)
FY.type = ProtoField.uint8(\"aydp.type\", \"Type\", base.DEC, nil, 0x7F)
FY.expedited = ProtoField.bool(\"aydp.expedited\", \"Expedited\", 8, nil, {exp})
FY.length = ProtoField.uint32(\"aydp.length\", \"Length field\", base.DEC)
FY.len = ProtoField.uint32(\"aydp.len\", \"Length on the wire\", base.DEC)
FY.seconds = ProtoField.int64(\"aydp.seconds\", \"Seconds\", base.DEC)
FY.subsec = ProtoField.int64(\"aydp.subsec\", \"Sub-seconds\", base.DEC)
FY.checksum = ProtoField.uint8(\"aydp.checksum\", \"Checksum\", base.HEX)
FY.checksum_computed = ProtoField.uint8(\"aydp.checksum_computed\", \"Checksum computed\", base.HEX)
FY.checksum_status = ProtoField.string(\"aydp.checksum_status\", \"Checksum status\")
FY.msg_type = ProtoField.uint8(\"aydp.msg_type\", \"Type (raw message)\", base.DEC)
FY.data = ProtoField.bytes(\"aydp.data\", \"Data\")
FY.data_len = ProtoField.uint32(\"aydp.data_len\", \"Data length\", base.DEC)
FY[\"aydp.system_value_update.data\"] = ProtoField.bytes(\"aydp.system_value_update.data\", \"data\")
FY[\"aydp.system_control.command\"] = ProtoField.uint8(\"aydp.system_control.command\", \"command\", base.DEC, {{ [1] = \"RequestData\", [2] = \"StoreConfiguration\" }})
FY[\"aydp.system_control.address\"] = ProtoField.uint16(\"aydp.system_control.address\", \"address\", base.DEC)",
        exp = EXPEDITED
    );
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
    let _ = writeln!(
        w,
        "aydp.fields = {{}}
for _, v in pairs(FY) do table.insert(aydp.fields, v) end
local EY = {{
  checksum_bad = ProtoExpert.new(\"aydp.checksum_bad\", \"XOR checksum mismatch\", expert.group.CHECKSUM, expert.severity.ERROR),
  bad_length = ProtoExpert.new(\"aydp.bad_length\", \"Bad length field (a false start: one byte dropped, scanning resumes)\", expert.group.MALFORMED, expert.severity.ERROR),
  malformed = ProtoExpert.new(\"aydp.malformed\", \"The message's data does not parse\", expert.group.MALFORMED, expert.severity.ERROR),
  truncated = ProtoExpert.new(\"aydp.truncated\", \"A message is still open at the end of this packet\", expert.group.SEQUENCE, expert.severity.NOTE),
}}
aydp.experts = {{ EY.checksum_bad, EY.bad_length, EY.malformed, EY.truncated }}
local AYDP = {{ START = {START}, EXPEDITED = {EXPEDITED}, TYPE = {ht}, LENGTH = {hl}, SECONDS = {hs}, SUBSEC = {hsub},
  EXPEDITED_LEN = {el}, NORMAL_LEN = {nl}, CAPACITY = {cap}, USER_FIRST = {uf}, USER_LAST = {ul},
  SVU_VALUE = {svv}, CONTROL_ADDRESS = {ca}, REQUEST_DATA_LEN = {rdl}, STORE_CONFIGURATION_LEN = {scl} }}",
        ht = header::TYPE,
        hl = header::LENGTH,
        hs = header::SECONDS,
        hsub = header::SUBSEC,
        el = header::EXPEDITED_LEN,
        nl = header::NORMAL_LEN,
        cap = AYDP_CAPACITY,
        uf = USER_FIRST,
        ul = USER_LAST,
        svv = system_value_update::VALUE,
        ca = system_control::ADDRESS,
        rdl = system_control::REQUEST_DATA_LEN,
        scl = system_control::STORE_CONFIGURATION_LEN,
    );
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
    field_list(w, "aydp.system_value_update", &AYDP_SVU);
    let _ = writeln!(w);
    w.push_str(DISSECT_AYDP);
}

/// The hand-written part: resync, checksum, header, and walking the tables.
const DISSECT_AYDP: &str = r#"
local function xor8(a, b)
  local r, p = 0, 1
  for _ = 1, 8 do
    local x, y = a % 2, b % 2
    if x ~= y then r = r + p end
    a = (a - x) / 2; b = (b - y) / 2; p = p * 2
  end
  return math.floor(r)
end
-- uflt16 (Y7): binary16 without a sign; nil for a set sign bit.
local function uflt16(v)
  if v >= 0x8000 then return nil end
  local e, m = math.floor(v / 1024), v % 1024
  if e == 0 then return m * 2 ^ -24 end
  if e == 31 then if m == 0 then return math.huge end return 0 / 0 end
  return (1 + m / 1024) * 2 ^ (e - 15)
end
-- Adds one table field at `base` in `d`; false for a malformed value.
local function add_field(sub, d, base, f)
  local key, ty, off, size = f[1], f[2], f[3], f[4]
  local r = d(base + off, size)
  if ty == "uflt16" then
    local v = uflt16(r:le_uint())
    if v == nil then return false end
    sub:add(FY[key], r, v)
  else
    sub:add_le(FY[key], r)
  end
  return true
end
local function fixed_for(t, profile)
  for _, m in ipairs(AYDP_FIXED) do
    if m.type == t and (m.profile == nil or m.profile == profile) then return m end
  end
  return nil
end

-- The typed data of one good frame (crate: Message::parse). Returns the name, or nil and why.
local function typed(sub, d, dlen, t, expedited, profile)
  local function raw(name)
    sub:add(FY.msg_type, d(0, 0), t)
    sub:add(FY.data_len, d(0, 0), dlen)
    if dlen > 0 then sub:add(FY.data, d(0, dlen)) end
    return name
  end
  if t > AYDP.USER_LAST then return nil, "bad type " .. t end
  if t == 0 then
    if dlen ~= 0 then return nil, "type 0 carries no data" end
    if profile == "reference" then return "NO_OP" end
    return expedited and "HEARTBEAT" or "TIME_SYNC"
  end
  if profile == "spec" and (t == 1 or t == 2 or t == 6) then return raw("TBD") end
  local m = fixed_for(t, profile)
  if m then
    if dlen ~= m.len then return nil, "wrong data length " .. dlen .. " (" .. m.len .. ")" end
    for _, f in ipairs(m.fields) do
      if not add_field(sub, d, 0, f) then return nil, "uflt16 field has its sign bit set" end
    end
    return m.name
  end
  local l = AYDP_LISTS[t]
  if l then
    local c = l.count
    if dlen < c[3] + c[4] then return nil, "too short" end
    local n = d(c[3], c[4]):le_uint()
    if dlen ~= l.entries + n * l.entry_len then return nil, "count " .. n .. " does not match the length" end
    sub:add_le(FY[c[1]], d(c[3], c[4]))
    for k = 0, n - 1 do
      for _, f in ipairs(l.fields) do
        if not add_field(sub, d, l.entries + k * l.entry_len, f) then return nil, "uflt16 field has its sign bit set" end
      end
    end
    return l.name
  end
  if t == 8 then
    if dlen < AYDP.SVU_VALUE then return nil, "too short" end
    local mode = d(AYDP_SVU[1][3], 1):uint()
    local field = d(AYDP_SVU[3][3], 4):le_uint()
    if mode < 1 or mode > 3 then return nil, "unknown update mode " .. mode end
    if mode == 1 and field ~= 0 then return nil, "single update with a non-zero index" end
    for _, f in ipairs(AYDP_SVU) do add_field(sub, d, 0, f) end
    local key = "aydp.system_value_update.data"
    if dlen > AYDP.SVU_VALUE then sub:add(FY[key], d(AYDP.SVU_VALUE, dlen - AYDP.SVU_VALUE))
    else sub:add(FY[key], d(0, 0), ByteArray.new()) end
    return "SYSTEM_VALUE_UPDATE"
  end
  if t == 9 then
    if dlen == 0 then return nil, "too short" end
    local c = d(0, 1):uint()
    if c == 1 and dlen == AYDP.REQUEST_DATA_LEN then
      sub:add(FY["aydp.system_control.command"], d(0, 1))
      sub:add_le(FY["aydp.system_control.address"], d(AYDP.CONTROL_ADDRESS, 2))
      return "SYSTEM_CONTROL"
    end
    if c == 2 and dlen == AYDP.STORE_CONFIGURATION_LEN then
      sub:add(FY["aydp.system_control.command"], d(0, 1))
      return "SYSTEM_CONTROL"
    end
    return nil, "bad system control"
  end
  if t >= AYDP.USER_FIRST then return raw("USER_DEFINED") end
  return raw("UNKNOWN")
end

local function frame_len(field, expedited, profile)
  local over = (expedited and AYDP.EXPEDITED_LEN or AYDP.NORMAL_LEN) + 1
  if profile == "spec" then
    if field < over then return nil end
    return field
  end
  return field + over
end

-- One good-checksum frame `fr` (start through checksum).
local function aydp_frame(fr, tree, profile)
  local n = fr:len()
  local sub = tree:add(aydp, fr)
  local tb = fr(AYDP.TYPE, 1)
  local expedited = tb:uint() >= AYDP.EXPEDITED
  local t = tb:uint() % AYDP.EXPEDITED
  local hl = expedited and AYDP.EXPEDITED_LEN or AYDP.NORMAL_LEN
  sub:add(FY.profile, fr(0, 0), profile)
  sub:add(FY.start, fr(0, 1))
  sub:add(FY.type, tb)
  sub:add(FY.expedited, tb)
  sub:add_le(FY.length, fr(AYDP.LENGTH, 4))
  sub:add(FY.len, fr, n)
  if not expedited then
    sub:add_le(FY.seconds, fr(AYDP.SECONDS, 8))
    sub:add_le(FY.subsec, fr(AYDP.SUBSEC, 8))
  end
  local cs = fr(n - 1, 1)
  sub:add(FY.checksum, cs)
  sub:add(FY.checksum_computed, cs, cs:uint())
  sub:add(FY.checksum_status, cs, "ok")
  local dlen = n - 1 - hl
  local function d(o, l) return fr(hl + o, l) end
  local name, why = typed(sub, d, dlen, t, expedited, profile)
  if name then
    sub:add(FY.status, fr(0, 0), "ok")
    sub:add(FY.name, tb, name)
    sub:append_text(", " .. name .. " (" .. t .. (expedited and ", expedited" or "") .. ")")
    return name
  end
  local st = sub:add(FY.status, fr(0, 0), "malformed")
  sub:add(FY.error, fr(0, 0), why)
  st:add_proto_expert_info(EY.malformed)
  sub:append_text(", type " .. t .. " malformed: " .. why)
  return "[malformed " .. t .. "]"
end

-- Scans `t` as the crate's decoder does (Y5): noise before a start is dropped, in a run of 0xFF
-- only the last is the start, a failed candidate (bad length, bad checksum) drops its start byte
-- and scanning resumes at the next byte. Returns the offset of an incomplete candidate (nil: none).
local function aydp_scan(t, pinfo, tree, profile)
  local n = t:len()
  local names = {}
  local p = 0
  local open = nil
  while p < n do
    if t(p, 1):uint() ~= AYDP.START then
      p = p + 1
    elseif p + 1 < n and t(p + 1, 1):uint() == AYDP.START then
      p = p + 1
    elseif n - p < AYDP.EXPEDITED_LEN then
      open = p; break
    else
      local field = t(p + AYDP.LENGTH, 4):le_uint()
      local expedited = t(p + AYDP.TYPE, 1):uint() >= AYDP.EXPEDITED
      local total = frame_len(field, expedited, profile)
      if total == nil or total > AYDP.CAPACITY then
        local sub = tree:add(aydp, t(p, AYDP.EXPEDITED_LEN))
        sub:add(FY.profile, t(p, 0), profile)
        sub:add_le(FY.length, t(p + AYDP.LENGTH, 4))
        local st = sub:add(FY.status, t(p, 0), "bad_length")
        st:add_proto_expert_info(EY.bad_length)
        sub:append_text(": bad length field " .. field .. ", one byte dropped")
        table.insert(names, "[bad length]")
        p = p + 1
      elseif n - p < total then
        open = p; break
      else
        local x = 0
        for i = p, p + total - 2 do x = xor8(x, t(i, 1):uint()) end
        local got = t(p + total - 1, 1):uint()
        if x == got then
          table.insert(names, aydp_frame(t(p, total), tree, profile))
          p = p + total
        else
          local sub = tree:add(aydp, t(p, total))
          sub:add(FY.profile, t(p, 0), profile)
          sub:add(FY.type, t(p + AYDP.TYPE, 1))
          sub:add_le(FY.length, t(p + AYDP.LENGTH, 4))
          sub:add(FY.checksum, t(p + total - 1, 1))
          sub:add(FY.checksum_computed, t(p + total - 1, 1), x)
          local cst = sub:add(FY.checksum_status, t(p + total - 1, 1), "bad")
          cst:add_proto_expert_info(EY.checksum_bad)
          sub:add(FY.status, t(p, 0), "bad_checksum")
          sub:append_text(": checksum mismatch, one byte dropped")
          table.insert(names, "[bad checksum]")
          p = p + 1
        end
      end
    end
  end
  pinfo.cols.protocol = "AYDP"
  pinfo.cols.info = table.concat(names, ", ")
  return open
end

function aydp.dissector(tvb, pinfo, tree)
  aydp_scan(tvb, pinfo, tree, "reference")
  return tvb:len()
end

-- A byte stream: the bytes of an open candidate are carried into the next packet of the same
-- stream, so a message is dissected in the packet that completes it (as `protolink decode`
-- reports it).
local aydp_carry, aydp_carry_in = {}, {}
local function aydp_stream(name, desc, profile, key_of)
  local p = Proto(name, desc)
  function p.dissector(tvb, pinfo, tree)
    local key = key_of(pinfo)
    if not pinfo.visited then aydp_carry_in[pinfo.number .. key] = aydp_carry[key] or "" end
    local prefix = aydp_carry_in[pinfo.number .. key] or ""
    local t = tvb
    if #prefix > 0 then
      t = (ByteArray.new(prefix) .. tvb:bytes()):tvb("AYDP stream (this packet after the previous one's open message)")
    end
    local open = aydp_scan(t, pinfo, tree, profile)
    if not pinfo.visited then
      local tail = ""
      if open then tail = t:bytes():subset(open, t:len() - open):tohex() end
      if #tail > 2 * AYDP.CAPACITY then tail = "" end
      aydp_carry[key] = tail
    end
    return tvb:len()
  end
  return p
end
local aydp_interface_id = Field.new("frame.interface_id")
local function iface_key(pinfo)
  local f = aydp_interface_id()
  return "if" .. (f and f.value or 0)
end
local function tcp_key(pinfo)
  return tostring(pinfo.src) .. ":" .. pinfo.src_port .. ">" .. tostring(pinfo.dst) .. ":" .. pinfo.dst_port
end
local aydp_spec = aydp_stream("aydp_spec", "AYDP byte stream (Spec profile)", "spec", iface_key)
local aydp_ref = aydp_stream("aydp_reference", "AYDP byte stream (Reference profile)", "reference", iface_key)
local aydp_tcp = aydp_stream("aydp_tcp", "AYDP over TCP (Reference profile)", "reference", tcp_key)
-- USER1 and USER2 are wtap encapsulations 46 and 47.
encap:add((wtap_encaps and wtap_encaps.USER1) or 46, aydp_spec)
encap:add((wtap_encaps and wtap_encaps.USER2) or 47, aydp_ref)
DissectorTable.get("tcp.port"):add(6321, aydp_tcp)
udp:add(6321, aydp)
"#;

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
        assert_eq!(&data[system_value_update::VALUE..], u.data);
    }
}
