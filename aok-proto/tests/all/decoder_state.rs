//! What the two decoders tell of themselves: the bytes they hold, `reset` (which forgets them
//! and keeps the counters), and the PC decoder's reply form, which follows the firmware.

use aok_proto::{Command, CommandDecoder, FirmwareVersion, ReplyForm, Stats};
use aok_proto::{Decode, Expect, MessageDecoder};

fn commands(d: &mut CommandDecoder, bytes: &[u8]) -> Vec<Result<Command, aok_proto::Error>> {
    let mut out = Vec::new();
    d.feed(bytes, |ev| out.push(ev));
    out
}

#[test]
fn the_device_decoder_holds_a_command_until_it_is_whole() {
    let mut d = CommandDecoder::new();
    let mut held = Vec::new();
    for b in [0x63, 0x04, 0x02] {
        let ev = commands(&mut d, &[b]);
        held.push((ev, d.held_bytes()));
    }
    assert_eq!(
        held,
        [(vec![], 1), (vec![], 2), (vec![Ok(Command::SaveSet(2))], 0)]
    );
}

#[test]
fn reset_forgets_the_bytes_held_and_keeps_the_counters() {
    let mut d = CommandDecoder::new();
    assert_eq!(commands(&mut d, &[0x63, 0x01]), [Ok(Command::DebugOff)]);
    assert_eq!(commands(&mut d, &[0x63, 0x04]), []);
    d.reset();
    assert_eq!(d.held_bytes(), 0);
    // What follows is read afresh: 0x02 is no command.
    assert_eq!(
        commands(&mut d, &[0x02, 0x63, 0x02]),
        [Ok(Command::DebugOn)]
    );
    let want = Stats {
        frames_ok: 2,
        unknown_bytes: 1,
        bytes_discarded: 1,
        ..Stats::default()
    };
    assert_eq!(d.stats(), want);
}

#[test]
fn the_pc_decoder_reads_the_reply_form_of_its_firmware() {
    let mut d = MessageDecoder::new(FirmwareVersion::new(0, 30));
    assert_eq!(d.reply_form(), ReplyForm::Headerless);
    d.set_firmware(FirmwareVersion::new(0, 31));
    assert_eq!(d.reply_form(), ReplyForm::Headed);
    d.set_firmware(FirmwareVersion::new(0, 12));
    assert_eq!(d.reply_form(), ReplyForm::Headerless);
    d.expect(Expect::Ack);
    assert_eq!(d.expecting(), Expect::Ack);
}

#[test]
fn the_pc_decoder_reset_forgets_the_bytes_held() {
    let mut d = MessageDecoder::new(FirmwareVersion::LATEST);
    let mut got = Vec::new();
    d.feed(&[0x1c, 0x56, 0xff], |ev| got.push(ev));
    assert_eq!((got.len(), d.held_bytes()), (0, 3));
    d.reset();
    assert_eq!(d.held_bytes(), 0);
    assert_eq!(d.stats(), Stats::default());
}

/// The reply each request awaits, as the device sends it (headed form).
fn reply(m: aok_proto::Message) -> Vec<u8> {
    let mut buf = [0u8; 19];
    let n = m.emit(&mut buf, ReplyForm::Headed).unwrap();
    buf[..n].to_vec()
}

#[test]
fn the_awaited_reply_settles_the_pc_decoder_byte_by_byte_and_by_feed() {
    use aok_proto::{Ack, Message, ParameterValue};
    let p = |number| Message::Parameter(ParameterValue { number, value: 5 });
    let cases = [
        (Expect::Ack, reply(Message::Ack(Ack::Ok))),
        (Expect::Parameter(40), reply(p(40))),
        (Expect::Bulk(32), reply(p(32 + 15))),
    ];
    for (expect, bytes) in cases {
        // Byte by byte.
        let mut d = MessageDecoder::new(FirmwareVersion::LATEST);
        d.expect(expect);
        let mut events = Vec::new();
        for b in &bytes {
            d.feed(core::slice::from_ref(b), |ev| events.push(ev));
        }
        assert_eq!(events.len(), 1, "{expect:?}");
        assert!(events[0].is_ok(), "{expect:?}");
        assert_eq!(d.expecting(), Expect::Nothing, "{expect:?} byte by byte");
        // In one slice.
        let mut d = MessageDecoder::new(FirmwareVersion::LATEST);
        d.expect(expect);
        let mut got = Vec::new();
        d.feed(&bytes, |ev| got.push(ev));
        assert_eq!(got.len(), 1, "{expect:?}");
        assert_eq!(d.expecting(), Expect::Nothing, "{expect:?} by feed");
    }
    // A parameter of another number, or a bulk reply's earlier entry, settles nothing.
    let mut d = MessageDecoder::new(FirmwareVersion::LATEST);
    d.expect(Expect::Parameter(40));
    let mut got = Vec::new();
    d.feed(&reply(p(41)), |ev| got.push(ev));
    assert_eq!(got.len(), 1);
    assert_eq!(d.expecting(), Expect::Parameter(40));
    d.expect(Expect::Bulk(32));
    d.feed(&reply(p(33)), |ev| got.push(ev));
    assert_eq!(d.expecting(), Expect::Bulk(32));
}

#[test]
fn once_the_ack_came_an_ack_letter_is_an_unknown_byte() {
    let mut d = MessageDecoder::new(FirmwareVersion::LATEST);
    d.expect(Expect::Ack);
    let mut got = Vec::new();
    d.feed(b"O", |ev| got.push(ev));
    assert!(matches!(got[..], [Ok(_)]));
    d.feed(b"O", |ev| got.push(ev));
    assert_eq!(got.len(), 1);
    assert_eq!(d.stats().frames_ok, 1);
    assert_eq!(d.stats().unknown_bytes, 1);
}

#[test]
fn a_lone_first_byte_is_given_up_when_the_line_goes_quiet() {
    // 73 (set parameter) announces 7 bytes; only it arrives.
    let mut d = CommandDecoder::new();
    assert_eq!(commands(&mut d, &[0x73]), []);
    assert_eq!(d.held_bytes(), 1);
    let mut got = Vec::new();
    d.finish(|ev| got.push(ev));
    assert_eq!(got, [Err(aok_proto::Error::Truncated)]);
    assert_eq!((d.held_bytes(), d.stats().abandoned), (0, 1));
}

#[test]
fn the_pc_decoder_gives_up_a_lone_first_byte_when_the_line_goes_quiet() {
    // 1C (a debug frame) announces 7 bytes; only it arrives.
    let mut d = MessageDecoder::new(FirmwareVersion::LATEST);
    let mut got = Vec::new();
    d.feed(&[0x1c], |ev| got.push(ev));
    assert_eq!(got, []);
    d.finish(|ev| got.push(ev));
    assert_eq!(got, [Err(aok_proto::Error::Truncated)]);
    assert_eq!(d.held_bytes(), 0);
}

#[test]
fn a_waypoint_reply_settles_only_the_slot_asked_for() {
    use aok_proto::{ActionWord, Message, Waypoint, WaypointSlot};
    let w = |slot| {
        reply(Message::Waypoint(Waypoint {
            slot,
            longitude: 1,
            latitude: 2,
            action1: ActionWord::NONE,
            action2: ActionWord::NONE,
        }))
    };
    let mut d = MessageDecoder::new(FirmwareVersion::LATEST);
    d.expect(Expect::Waypoint(WaypointSlot::FbcTarget));
    let mut got = Vec::new();
    d.feed(&w(WaypointSlot::MissionPoi), |ev| got.push(ev));
    assert_eq!(got.len(), 1);
    assert_eq!(d.expecting(), Expect::Waypoint(WaypointSlot::FbcTarget));
    d.feed(&w(WaypointSlot::FbcTarget), |ev| got.push(ev));
    assert_eq!(got.len(), 2);
    assert_eq!(d.expecting(), Expect::Nothing);
}
