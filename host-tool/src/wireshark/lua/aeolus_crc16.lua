local function xor16(a, b)
  local r, p = 0, 1
  for _ = 1, 16 do
    local x, y = a % 2, b % 2
    if x ~= y then r = r + p end
    a = (a - x) / 2; b = (b - y) / 2; p = p * 2
  end
  return math.floor(r)
end
local function crc16(t, n)
  local crc = 0
  for i = 0, n - 1 do
    crc = xor16(xor16(CRC[math.floor(crc / 256)], (crc * 256) % 65536), t(i, 1):uint())
  end
  return crc
end

