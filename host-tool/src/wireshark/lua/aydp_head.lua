
-- AYDP ---------------------------------------------------------------------------------------
-- From aydp_proto::layout. Profiles (DECISIONS Y1, Y2): spec (USER1, 148): the length counts
-- the whole message, sub-seconds in ms; reference (USER2, 149, and TCP/UDP 6321 as in the AYDP
-- reference software): the length counts data only, sub-seconds in µs.
local aydp = Proto("aydp", "AYDP yacht protocol")
local FY = {}
FY.status = ProtoField.string("aydp.status", "Status")
FY.error = ProtoField.string("aydp.error", "Error")
FY.profile = ProtoField.string("aydp.profile", "Profile")
FY.name = ProtoField.string("aydp.name", "Message")
FY.start = ProtoField.uint8("aydp.start", "Start", base.HEX)
FY.type_byte = ProtoField.uint8("aydp.type_byte", "Type byte", base.HEX)
FY.type = ProtoField.uint8("aydp.type", "Type", base.DEC, nil, 0x7F)
FY.expedited = ProtoField.bool("aydp.expedited", "Expedited", 8, nil, @EXPEDITED@)
FY.length = ProtoField.uint32("aydp.length", "Length field", base.DEC)
FY.len = ProtoField.uint32("aydp.len", "Length on the wire", base.DEC)
FY.seconds = ProtoField.int64("aydp.seconds", "Seconds", base.DEC)
FY.subsec = ProtoField.int64("aydp.subsec", "Sub-seconds", base.DEC)
FY.checksum = ProtoField.uint8("aydp.checksum", "Checksum", base.HEX)
FY.checksum_computed = ProtoField.uint8("aydp.checksum_computed", "Checksum computed", base.HEX)
FY.checksum_status = ProtoField.string("aydp.checksum_status", "Checksum status")
FY.msg_type = ProtoField.uint8("aydp.msg_type", "Type (raw message)", base.DEC)
FY.data = ProtoField.bytes("aydp.data", "Data")
FY.data_len = ProtoField.uint32("aydp.data_len", "Data length", base.DEC)
FY["aydp.system_value_update.data"] = ProtoField.bytes("aydp.system_value_update.data", "data")
FY["aydp.system_control.command"] = ProtoField.uint8("aydp.system_control.command", "command", base.DEC, { [1] = "RequestData", [2] = "StoreConfiguration" })
FY["aydp.system_control.address"] = ProtoField.uint16("aydp.system_control.address", "address", base.DEC)
