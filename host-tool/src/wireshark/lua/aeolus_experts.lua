aeolus.fields = {}
for _, v in pairs(F) do table.insert(aeolus.fields, v) end
local E = {
  crc_bad = ProtoExpert.new("aeolus.crc_bad", "CRC mismatch", expert.group.CHECKSUM, expert.severity.ERROR),
  no_crc = ProtoExpert.new("aeolus.no_crc", "Frame sent without CRC", expert.group.CHECKSUM, expert.severity.NOTE),
  bad_length = ProtoExpert.new("aeolus.bad_length", "Wrong data length for this message", expert.group.MALFORMED, expert.severity.ERROR),
  too_short = ProtoExpert.new("aeolus.too_short", "Frame too short", expert.group.MALFORMED, expert.severity.ERROR),
  bad_escape = ProtoExpert.new("aeolus.bad_escape", "Escape byte 0x7D at the end of a frame", expert.group.MALFORMED, expert.severity.ERROR),
}
aeolus.experts = { E.crc_bad, E.no_crc, E.bad_length, E.too_short, E.bad_escape }

