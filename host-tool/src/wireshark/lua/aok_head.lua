
-- AOK ----------------------------------------------------------------------------------------
-- From aok_proto::layout. USER3 (150): what the PC sends, read as the device reads it; USER4
-- (151): what the device sends, read as the PC reads it (firmware >= 0.31: headed replies).
-- A lone O/E/I ack is not decodable passively (only a PC that sent a command expects one):
-- such bytes are skipped, as `protolink decode` skips them, and shown as not decoded.
local aok = Proto("aok", "AOK copter serial protocol")
local FK = {}
FK.status = ProtoField.string("aok.status", "Status")
FK.error = ProtoField.string("aok.error", "Error")
FK.direction = ProtoField.string("aok.direction", "Sent by")
FK.name = ProtoField.string("aok.name", "Message")
FK.start = ProtoField.uint8("aok.start", "Start byte", base.HEX)
FK.len = ProtoField.uint32("aok.len", "Length on the wire", base.DEC)
FK.checksum = ProtoField.uint8("aok.checksum", "Checksum", base.HEX)
FK.checksum_computed = ProtoField.uint8("aok.checksum_computed", "Checksum computed", base.HEX)
FK.checksum_status = ProtoField.string("aok.checksum_status", "Checksum status")
FK.skipped = ProtoField.bytes("aok.skipped", "Bytes not decoded")
FK["aok.motor_test.motor"] = ProtoField.uint8("aok.motor_test.motor", "motor", base.DEC)
FK["aok.motor_test.value"] = ProtoField.uint8("aok.motor_test.value", "value", base.DEC)
