//! What the two decoders tell of themselves: the bytes they hold, `reset` (which forgets them
//! and keeps the counters), and the PC decoder's reply form, which follows the firmware.

use aok_proto::pc::{Expect, PcDecoder};
use aok_proto::{Command, DeviceDecoder, FirmwareVersion, ReplyForm, Stats};

fn commands(d: &mut DeviceDecoder, bytes: &[u8]) -> Vec<Result<Command, aok_proto::Error>> {
    let mut out = Vec::new();
    d.feed(bytes, |ev| out.push(ev));
    out
}

#[test]
fn the_device_decoder_holds_a_command_until_it_is_whole() {
    let mut d = DeviceDecoder::new();
    let mut held = Vec::new();
    for b in [0x63, 0x04, 0x02] {
        let ev = d.push(b);
        held.push((ev, d.buffered()));
    }
    assert_eq!(
        held,
        [(None, 1), (None, 2), (Some(Ok(Command::SaveSet(2))), 0)]
    );
}

#[test]
fn reset_forgets_the_bytes_held_and_keeps_the_counters() {
    let mut d = DeviceDecoder::new();
    assert_eq!(commands(&mut d, &[0x63, 0x01]), [Ok(Command::DebugOff)]);
    assert_eq!(commands(&mut d, &[0x63, 0x04]), []);
    d.reset();
    assert_eq!(d.buffered(), 0);
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
    assert_eq!(*d.stats(), want);
}

#[test]
fn the_pc_decoder_reads_the_reply_form_of_its_firmware() {
    let mut d = PcDecoder::new(FirmwareVersion::new(0, 30));
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
    let mut d = PcDecoder::new(FirmwareVersion::LATEST);
    let mut got = Vec::new();
    d.feed(&[0x1c, 0x56, 0xff], |ev| got.push(ev));
    assert_eq!((got.len(), d.buffered()), (0, 3));
    d.reset();
    assert_eq!(d.buffered(), 0);
    assert_eq!(*d.stats(), Stats::default());
}
