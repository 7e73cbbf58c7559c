//! The encoders (`Command::emit`, `Message::emit`, ...) and the decoders' `finish`: the bytes
//! each writes and the events each delivers, as their callers (the desk tool, the sensor box)
//! rely on them.

use aok_proto::{
    Ack, ActionWord, Command, CommandDecoder, Decode, Error, Expect, FirmwareVersion, Message,
    MessageDecoder, ParameterValue, Waypoint, WaypointSlot,
};

#[test]
fn pc_encode_writes_the_commands_bytes() {
    let mut buf = [0u8; 19];
    let set = Command::SetParameter(ParameterValue {
        number: 12,
        value: 1500,
    });
    let n = set.emit(&mut buf).unwrap();
    assert_eq!(&buf[..n], &[0x73, 0x0c, 0x00, 0x00, 0x05, 0xdc, 0xd5]);
    let n = Command::DebugOff.emit(&mut buf).unwrap();
    assert_eq!(&buf[..n], &aok_proto::DEBUG_OFF);
    assert_eq!(aok_proto::DEBUG_OFF, [0x63, 0x01]);
}

#[test]
fn device_ack_emit_writes_its_letter() {
    for (ack, letter) in [(Ack::Ok, b'O'), (Ack::Error, b'E'), (Ack::InFlight, b'I')] {
        let mut buf = [0u8; 4];
        assert_eq!(
            Message::Ack(ack).emit(&mut buf, aok_proto::ReplyForm::Headed),
            Ok(1)
        );
        assert_eq!(buf, [letter, 0, 0, 0]);
    }
}

#[test]
fn device_waypoint_emit_writes_a_reply_the_pc_reads_back() {
    let w = Waypoint {
        slot: WaypointSlot::FbcTarget,
        longitude: 1,
        latitude: 2,
        action1: ActionWord::NONE,
        action2: ActionWord::NONE,
    };
    let mut buf = [0u8; 19];
    assert_eq!(
        Message::Waypoint(w).emit(&mut buf, aok_proto::ReplyForm::Headed),
        Ok(19)
    );
    assert_eq!(&buf[..2], &[0x77, 0xff]);
    let mut dec = MessageDecoder::new(FirmwareVersion::LATEST);
    let mut got = Vec::new();
    dec.feed(&buf, |ev| got.push(ev));
    assert_eq!(got, [Ok(Message::Waypoint(w))]);
}

#[test]
fn device_finish_gives_up_a_cut_command_and_rescans_what_it_hid() {
    let mut dec = CommandDecoder::new();
    // 73 (set parameter) waits for 6 more bytes; the line goes quiet after two.
    dec.feed(&[0x73, 0x63, 0x02], |_| {
        panic!("no event before the line is quiet")
    });
    let mut got = Vec::new();
    dec.finish(|ev| got.push(ev));
    assert_eq!(got, [Err(Error::Truncated), Ok(Command::DebugOn)]);
    assert_eq!(dec.stats().abandoned, 1);
    assert_eq!(dec.held_bytes(), 0);
}

#[test]
fn pc_finish_gives_up_a_cut_debug_frame_and_finds_the_ack_inside() {
    let mut dec = MessageDecoder::new(FirmwareVersion::LATEST);
    dec.expect(Expect::Ack);
    let mut got = Vec::new();
    for b in [0x1c, 0x56, b'O'] {
        dec.feed(&[b], |ev| got.push(ev));
    }
    assert_eq!(got, []);
    dec.finish(|ev| got.push(ev));
    assert_eq!(got, [Err(Error::Truncated), Ok(Message::Ack(Ack::Ok))]);
    assert_eq!(dec.held_bytes(), 0);
}
