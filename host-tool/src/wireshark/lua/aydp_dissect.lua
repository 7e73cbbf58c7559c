
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
