
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
