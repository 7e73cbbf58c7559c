aydp.fields = {}
for _, v in pairs(FY) do table.insert(aydp.fields, v) end
local EY = {
  checksum_bad = ProtoExpert.new("aydp.checksum_bad", "XOR checksum mismatch", expert.group.CHECKSUM, expert.severity.ERROR),
  bad_length = ProtoExpert.new("aydp.bad_length", "Bad length field (a false start: one byte dropped, scanning resumes)", expert.group.MALFORMED, expert.severity.ERROR),
  malformed = ProtoExpert.new("aydp.malformed", "The message's data does not parse", expert.group.MALFORMED, expert.severity.ERROR),
  truncated = ProtoExpert.new("aydp.truncated", "A message is still open at the end of this packet", expert.group.SEQUENCE, expert.severity.NOTE),
}
aydp.experts = { EY.checksum_bad, EY.bad_length, EY.malformed, EY.truncated }
local AYDP = { START = @START@, EXPEDITED = @EXPEDITED@, TYPE = @TYPE@, LENGTH = @LENGTH@, SECONDS = @SECONDS@, SUBSEC = @SUBSEC@,
  EXPEDITED_LEN = @EXPEDITED_LEN@, NORMAL_LEN = @NORMAL_LEN@, CAPACITY = @CAPACITY@, USER_FIRST = @USER_FIRST@, USER_LAST = @USER_LAST@,
  SVU_VALUE = @SVU_VALUE@, CONTROL_ADDRESS = @CONTROL_ADDRESS@, REQUEST_DATA_LEN = @REQUEST_DATA_LEN@, STORE_CONFIGURATION_LEN = @STORE_CONFIGURATION_LEN@ }
