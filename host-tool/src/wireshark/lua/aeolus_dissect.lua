
-- One frame: `ft` holds the unescaped bytes between the flags (ID, data, CRC).
local function message(ft, wire, tree, pinfo)
  local n = ft:len()
  local sub = tree:add(aeolus, wire)
  sub:add(F.len, wire, wire:len())
  if n < 3 then
    sub:add_proto_expert_info(E.too_short)
    sub:append_text(": frame too short")
    return "short"
  end
  local id = ft(0, 1):uint()
  sub:add(F.id, ft(0, 1))
  local received = ft(n - 2, 2):le_uint()
  local computed = crc16(ft, n - 2)
  local status
  if received == computed then status = "ok" elseif received == 0 then status = "none" else status = "bad" end
  sub:add_le(F.crc, ft(n - 2, 2))
  sub:add(F.crc_computed, ft(n - 2, 2), computed)
  local st = sub:add(F.crc_status, ft(n - 2, 2), status)
  local name = (FIXED[id] and FIXED[id].name) or TEXT[id] or (RAW[id] and RAW[id].name) or "UNKNOWN"
  sub:add(F.name, ft(0, 1), name)
  sub:append_text(", " .. name .. " (" .. id .. "), CRC " .. status)
  if status == "bad" then
    st:add_proto_expert_info(E.crc_bad)
    return name .. "[bad CRC]"
  end
  if status == "none" then st:add_proto_expert_info(E.no_crc) end
  local dlen = n - 3
  local data = (dlen > 0) and ft(1, dlen) or nil
  local fixed = FIXED[id]
  if fixed then
    if dlen ~= fixed.len then
      sub:add_proto_expert_info(E.bad_length)
      return name .. "[bad length]"
    end
    for _, f in ipairs(fixed.fields) do
      local key, off, size, count, is_bool = f[1], f[2], f[3], f[4], f[5]
      for k = 0, count - 1 do
        local r = ft(1 + off + k * size, size)
        if is_bool then sub:add(F[key], r, r:uint() ~= 0) else sub:add_le(F[key], r) end
      end
    end
  elseif TEXT[id] then
    local len = 0
    while len < dlen and ft(1 + len, 1):uint() ~= 0 do len = len + 1 end
    if len > 0 then sub:add(F.text, ft(1, len)) else sub:add(F.text, ft(0, 1), "") end
  else
    local raw = RAW[id]
    if raw and raw.len and dlen ~= raw.len then
      sub:add_proto_expert_info(E.bad_length)
      return name .. "[bad length]"
    end
    sub:add(F.data_len, ft(0, 1), dlen)
    if data then sub:add(F.data, data) end
  end
  return name
end

-- Dissects every frame between flags in `tvb`; returns the offset of the last flag (nil: none).
local function frames(tvb, pinfo, tree)
  local n = tvb:len()
  pinfo.cols.protocol = "AEOLUS"
  local names = {}
  local open = nil
  for i = 0, n - 1 do
    if tvb(i, 1):uint() == 0x7E then
      if open and i > open + 1 then
        local wire = tvb(open, i - open + 1)
        local body = tvb(open + 1, i - open - 1)
        local ft
        local escaped = false
        for j = 0, body:len() - 1 do
          if body(j, 1):uint() == 0x7D then escaped = true; break end
        end
        local bad_escape = false
        if escaped then
          local ba = ByteArray.new()
          local j, blen = 0, body:len()
          while j < blen do
            local b = body(j, 1):uint()
            if b == 0x7D then
              if j + 1 >= blen then bad_escape = true; break end
              b = body(j + 1, 1):uint()
              b = ((b % 64) >= 32) and (b - 32) or (b + 32)
              j = j + 2
            else
              j = j + 1
            end
            ba:append(ByteArray.new(string.format("%02x", b)))
          end
          if not bad_escape then ft = ba:tvb("AEOLUS frame (unescaped)") end
        else
          ft = body:tvb()
        end
        if bad_escape then
          local sub = tree:add(aeolus, wire)
          sub:add_proto_expert_info(E.bad_escape)
          table.insert(names, "[bad escape]")
        else
          table.insert(names, message(ft, wire, tree, pinfo))
        end
      end
      open = i
    end
  end
  pinfo.cols.info = table.concat(names, ", ")
  return open
end

function aeolus.dissector(tvb, pinfo, tree)
  frames(tvb, pinfo, tree)
  return tvb:len()
end

-- A byte stream (link type USER0): a frame may span chunks. The bytes after a chunk's last flag
-- are carried into the next chunk of the same interface, so a frame is dissected in the packet
-- that closes it (as `protolink decode` reports it).
local aeolus_stream = Proto("aeolus_stream", "AEOLUS byte stream")
local interface_id = Field.new("frame.interface_id")
local CARRY_MAX = 2 * 8200
local carry = {}
local carry_in = {}
function aeolus_stream.dissector(tvb, pinfo, tree)
  local iface = 0
  local f = interface_id()
  if f then iface = f.value end
  if not pinfo.visited then carry_in[pinfo.number] = carry[iface] or "" end
  local prefix = carry_in[pinfo.number] or ""
  local t = tvb
  if #prefix > 0 then
    t = (ByteArray.new(prefix) .. tvb:bytes()):tvb("AEOLUS stream (this chunk after the previous one's open frame)")
  end
  local last = frames(t, pinfo, tree)
  if not pinfo.visited then
    local tail = ""
    if last then
      tail = t:bytes():subset(last, t:len() - last):tohex()
    elseif #prefix > 0 then
      tail = t:bytes():tohex()
    end
    if #tail > CARRY_MAX then tail = "" end
    carry[iface] = tail
  end
  return tvb:len()
end

local udp = DissectorTable.get("udp.port")
udp:add(5001, aeolus)
udp:add(5002, aeolus)
local encap = DissectorTable.get("wtap_encap")
-- USER0 is wtap encapsulation 45 (WTAP_ENCAP_USER0) in Wireshark.
encap:add((wtap_encaps and wtap_encaps.USER0) or 45, aeolus_stream)
