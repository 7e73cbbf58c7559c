aok.fields = {}
for _, v in pairs(FK) do table.insert(aok.fields, v) end
local EK = {
  checksum_bad = ProtoExpert.new("aok.checksum_bad", "XOR checksum mismatch (one byte dropped, scanning resumes)", expert.group.CHECKSUM, expert.severity.ERROR),
  invalid = ProtoExpert.new("aok.invalid", "A frame with a good checksum and a value out of range (one byte dropped)", expert.group.MALFORMED, expert.severity.ERROR),
  skipped = ProtoExpert.new("aok.skipped", "Not decodable passively (noise, or a lone O/E/I ack)", expert.group.UNDECODED, expert.severity.NOTE),
}
aok.experts = { EK.checksum_bad, EK.invalid, EK.skipped }
local AOK_CONTROL = @CONTROL@
local AOK_CONTROL_SUB = {
