//! Interleaved and corrupted streams, split at every byte boundary.

use crate::events;
use events::{feed_byte, finish_all};

use aok_proto::{
    Ack, Action, ActionWord, Command, CommandDecoder, DebugValue, Error, ExternalControl,
    FirmwareVersion, Message, Motor, MotorTest, ParameterValue, ReplyForm, Stick, Waypoint,
    WaypointSlot,
};
use aok_proto::{Decode, Event, Expect, MessageDecoder};

/// The item of a pull-form event, if it is one.
fn found<T>(event: Event<T, aok_proto::Error>) -> Option<T> {
    match event {
        Event::Found(item) => Some(item),
        _ => None,
    }
}

fn emit_msg(m: Message, form: ReplyForm) -> Vec<u8> {
    let mut buf = [0u8; 19];
    let n = m.emit(&mut buf, form).unwrap();
    buf[..n].to_vec()
}

fn emit_cmd(c: Command) -> Vec<u8> {
    let mut buf = [0u8; 19];
    let n = c.emit(&mut buf).unwrap();
    buf[..n].to_vec()
}

fn debug(number: u8, value: i32) -> Message {
    Message::Debug(DebugValue { number, value })
}

fn param(number: u8, value: i32) -> Message {
    Message::Parameter(ParameterValue { number, value })
}

fn waypoint() -> Waypoint {
    Waypoint {
        slot: WaypointSlot::RamPoi,
        longitude: 0x4f4f_4f4f,
        latitude: -7,
        action1: ActionWord::new(Action::Pause, 3),
        action2: ActionWord::new(Action::FlyAndSink, -2),
    }
}

/// A stream of the device: the bytes, where the PC sets what it expects, and the messages in order.
struct Script {
    bytes: Vec<u8>,
    expects: Vec<(usize, Expect)>,
    messages: Vec<Message>,
}

impl Script {
    fn new() -> Self {
        Self {
            bytes: Vec::new(),
            expects: Vec::new(),
            messages: Vec::new(),
        }
    }
    fn expect(&mut self, e: Expect) -> &mut Self {
        self.expects.push((self.bytes.len(), e));
        self
    }
    fn msg(&mut self, m: Message, form: ReplyForm) -> &mut Self {
        self.bytes.extend(emit_msg(m, form));
        self.messages.push(m);
        self
    }
    /// Feed everything (messages only), handing the decoder over (cloned, with events the pull
    /// form has not handed out yet) at `split`.
    fn run(&self, fw: FirmwareVersion, split: usize) -> Vec<Message> {
        let mut dec = MessageDecoder::new(fw);
        let mut out = Vec::new();
        for (i, &b) in self.bytes.iter().enumerate() {
            for (_, e) in self.expects.iter().filter(|(at, _)| *at == i) {
                dec.expect(*e);
            }
            if i + 1 == split {
                // Take the first event, move the decoder, take the rest from the copy.
                out.extend(dec.decode(&[b]).1.and_then(found));
                let mut moved = dec.clone();
                while let (_, Some(ev)) = moved.decode(&[]) {
                    out.extend(found(ev));
                }
                dec = moved;
            } else {
                out.extend(feed_byte(&mut dec, b).into_iter().filter_map(Result::ok));
            }
        }
        out
    }
}

fn interleaved(form: ReplyForm) -> Script {
    let mut s = Script::new();
    s.msg(debug(86, 3), form)
        .msg(debug(1, -1), form)
        .expect(Expect::Ack)
        // 'O' bytes inside a debug frame while an ack is pending are not acks.
        .msg(debug(b'O', 0x4f4f_4f4f), form)
        .msg(Message::Ack(Ack::Ok), form)
        .msg(debug(86, 0x1c1c_1c1c), form)
        .expect(Expect::Parameter(12))
        .msg(debug(2, 0x45), form)
        .msg(param(12, 1500), form)
        .msg(debug(86, 4), form)
        .expect(Expect::Ack)
        .msg(Message::Ack(Ack::InFlight), form)
        .expect(Expect::Waypoint(WaypointSlot::RamPoi))
        .msg(debug(3, 77), form)
        .msg(Message::Waypoint(waypoint()), form)
        .expect(Expect::Ack)
        .msg(Message::Ack(Ack::Error), form)
        .msg(debug(86, 5), form);
    s
}

#[test]
fn pc_stream_interleaved_split_everywhere() {
    let fw = FirmwareVersion::LATEST;
    let s = interleaved(ReplyForm::Headed);
    for split in 0..=s.bytes.len() {
        assert_eq!(s.run(fw, split), s.messages, "split at {split}");
    }
}

#[test]
fn pc_stream_headerless_split_everywhere() {
    // Firmware 0.30: the reply has no header. The debug frames before it (late ones, after debug-off)
    // must not be read as the reply; the reply itself starts with 1C, like a debug frame.
    let fw = FirmwareVersion::new(0, 30);
    let form = ReplyForm::Headerless;
    let late = debug(86, 0x0102_0304);
    let late_bytes = emit_msg(late, form);
    // Precondition: its first five bytes are not a valid headerless reply.
    assert_ne!(late_bytes[..4].iter().fold(0, |a, b| a ^ b), late_bytes[4]);
    let mut s = Script::new();
    s.msg(debug(86, 1), form)
        .expect(Expect::Parameter(9))
        .msg(late, form)
        .msg(param(9, 0x1c00_00aa), form)
        .msg(debug(86, 2), form)
        .expect(Expect::Parameter(10))
        .msg(param(10, -1), form) // FF FF FF FF 00: not a headed reply on this firmware
        .expect(Expect::Ack)
        .msg(Message::Ack(Ack::Ok), form);
    assert_eq!(emit_msg(param(9, 0x1c00_00aa), form)[0], 0x1c);
    for split in 0..=s.bytes.len() {
        assert_eq!(s.run(fw, split), s.messages, "split at {split}");
    }
}

#[test]
fn headerless_ambiguity_prefers_the_reply() {
    // Pinned decision: with a <= 0.30 read pending, a 1C whose next four bytes satisfy the reply
    // checksum is the reply, even if two more bytes would have made a valid debug frame.
    // Debug 1C 00 00 00 00 1C ?? has reply-CRC 1C^0^0^0 = 1C at position 4.
    let mut dec = MessageDecoder::new(FirmwareVersion::new(0, 30));
    dec.expect(Expect::Parameter(5));
    let got: Vec<_> = [0x1c, 0x00, 0x00, 0x00, 0x1c]
        .iter()
        .flat_map(|&b| feed_byte(&mut dec, b))
        .collect();
    assert_eq!(got, vec![Ok(param(5, 0x1c00_0000))]);
}

#[test]
fn ack_bytes_are_unknown_without_a_pending_ack() {
    let mut dec = MessageDecoder::new(FirmwareVersion::LATEST);
    let got: Vec<_> = b"OEI"
        .iter()
        .flat_map(|&b| feed_byte(&mut dec, b))
        .collect();
    assert!(got.is_empty());
    assert_eq!(dec.stats().unknown_bytes, 3);
}

#[test]
fn pc_corrupted_debug_frame_hides_an_ack() {
    // A debug frame with a broken checksum whose body holds 'O': after the failure the rescan finds
    // the 'O' as the pending ack, and the next good frame.
    let mut bytes = emit_msg(debug(b'O', 1), ReplyForm::Headed);
    bytes[6] ^= 0x55;
    bytes.extend(emit_msg(debug(86, 9), ReplyForm::Headed));
    let mut dec = MessageDecoder::new(FirmwareVersion::LATEST);
    dec.expect(Expect::Ack);
    let got: Vec<_> = bytes.iter().flat_map(|&b| feed_byte(&mut dec, b)).collect();
    assert_eq!(
        got,
        vec![
            // NUM 'O' and value 1 XOR to 0x4E; the checksum byte became 0x4E ^ 0x55.
            Err(Error::ChecksumMismatch {
                id: 0x1c,
                computed: 0x4E,
                received: 0x1B
            }),
            Ok(Message::Ack(Ack::Ok)),
            Ok(debug(86, 9))
        ]
    );
    assert_eq!(dec.stats().checksum_errors, 1);
}

#[test]
fn pc_idle_releases_a_stuck_ack() {
    let mut dec = MessageDecoder::new(FirmwareVersion::LATEST);
    dec.expect(Expect::Ack);
    // Garbage FF starts a 7-byte reply candidate; the ack after it waits inside.
    assert_eq!(feed_byte(&mut dec, 0xff), vec![]);
    assert_eq!(feed_byte(&mut dec, b'E'), vec![]);
    assert_eq!(
        finish_all(&mut dec),
        vec![Err(Error::Truncated), Ok(Message::Ack(Ack::Error))]
    );
    assert_eq!(dec.stats().abandoned, 1);
    assert_eq!(dec.held_bytes(), 0);
}

fn all_commands() -> Vec<Command> {
    vec![
        Command::DebugOff,
        Command::SetParameter(ParameterValue {
            number: 0x73,
            value: -0x7300_0073,
        }),
        Command::ReadParameter(12),
        Command::BulkRead(32),
        Command::MotorTest(MotorTest {
            motor: Motor::new(12).unwrap(),
            value: 0x77,
        }),
        Command::SetWaypoint(waypoint()),
        Command::ReadWaypoint(WaypointSlot::FbcTarget),
        Command::ExternalControl(ExternalControl {
            roll: Stick::new(-200).unwrap(),
            nick: Stick::new(200).unwrap(),
            yaw: Stick::new(99).unwrap(),
            pitch: 0x6363,
            expiry_ms: 0x6767,
        }),
        Command::LoadSet(1),
        Command::SaveSet(2),
        Command::StartSet(3),
        Command::SaveWaypoints,
        Command::LoadWaypoints,
        Command::Reset,
        Command::DebugOn,
    ]
}

/// Garbage before each command: unknown bytes and false starts of checksummed commands.
fn garbage(i: usize) -> &'static [u8] {
    const G: [&[u8]; 6] = [
        &[0x00],
        &[0x73],       // false set-parameter start
        &[0x77, 0xaa], // false waypoint start (19 bytes to disprove)
        &[0x53],       // false external-control start
        &[0x31, 0xee], // false motor test
        &[0x63, 0x00], // 63 with an unknown sub-command
    ];
    G[i % G.len()]
}

#[test]
fn device_stream_with_garbage_split_everywhere() {
    let cmds = all_commands();
    let mut bytes = Vec::new();
    for (i, c) in cmds.iter().enumerate() {
        bytes.extend_from_slice(garbage(i));
        bytes.extend(emit_cmd(*c));
    }
    // Trailing bytes to push the last false starts out.
    bytes.extend_from_slice(&[0u8; 19]);
    for split in 0..=bytes.len() {
        let mut dec = CommandDecoder::new();
        let mut ok = Vec::new();
        for (i, &b) in bytes.iter().enumerate() {
            if i + 1 == split {
                ok.extend(dec.decode(&[b]).1.and_then(found));
                let mut moved = dec.clone();
                while let (_, Some(ev)) = moved.decode(&[]) {
                    ok.extend(found(ev));
                }
                dec = moved;
            } else {
                ok.extend(feed_byte(&mut dec, b).into_iter().filter_map(Result::ok));
            }
        }
        assert_eq!(ok, cmds, "split at {split}");
        assert!(dec.stats().checksum_errors > 0);
        assert!(dec.stats().unknown_bytes > 0);
    }
}

#[test]
fn device_reports_checksum_errors_and_invalid_fields() {
    let mut dec = CommandDecoder::new();
    // Bad set-parameter checksum, then a read: the read is not lost.
    let mut bad = emit_cmd(Command::SetParameter(ParameterValue {
        number: 1,
        value: 2,
    }));
    bad[6] ^= 1;
    let mut items = Vec::new();
    for &b in bad.iter().chain(&[0x67, 0x05]) {
        items.extend(feed_byte(&mut dec, b));
    }
    let mismatch = Error::ChecksumMismatch {
        id: 0x73,
        computed: 0x03,
        received: 0x02,
    };
    assert_eq!(items.first(), Some(&Err(mismatch)));
    assert_eq!(items.last(), Some(&Ok(Command::ReadParameter(5))));
    // A waypoint read of slot 100: a good checksum, invalid; its first byte dropped, the
    // rest (0x64) unknown.
    let items: Vec<_> = [0x78, 100, 0x63, 0x02]
        .iter()
        .flat_map(|&b| feed_byte(&mut dec, b))
        .collect();
    assert_eq!(
        items,
        vec![Err(Error::InvalidSlot(100)), Ok(Command::DebugOn)]
    );
    // External control with roll 201 and a good checksum.
    let mut f = vec![0x53, 201, 0, 0, 0, 0, 0, 0, 0, 0xf4, 0x01];
    f.push(f[1..].iter().fold(0, |a, b| a ^ b));
    let items: Vec<_> = f.iter().flat_map(|&b| feed_byte(&mut dec, b)).collect();
    assert_eq!(items, vec![Err(Error::StickOutOfRange(201))]);
    assert_eq!(dec.stats().invalid, 2);
    assert_eq!(dec.held_bytes(), 0);
}

#[test]
fn device_idle_rescans_a_dead_partial_frame() {
    let mut dec = CommandDecoder::new();
    // A stray 77 holds a read request hostage until 19 bytes are in...
    for &b in &[0x77, 0x67, 0x0c] {
        assert_eq!(feed_byte(&mut dec, b), vec![]);
    }
    // ...or until the line is idle.
    assert_eq!(
        finish_all(&mut dec),
        vec![Err(Error::Truncated), Ok(Command::ReadParameter(12))]
    );
    assert_eq!(dec.stats().abandoned, 1);
}

#[test]
fn bulk_pending_ends_at_the_sixteenth_reply() {
    let mut dec = MessageDecoder::new(FirmwareVersion::LATEST);
    dec.expect(Expect::Bulk(250));
    let mut buf = [0u8; 112];
    aok_proto::BulkReply {
        first: 250,
        values: [1; 16],
    }
    .emit(&mut buf)
    .unwrap();
    let mut numbers = Vec::new();
    for (i, &b) in buf.iter().enumerate() {
        for m in feed_byte(&mut dec, b) {
            if let Ok(Message::Parameter(p)) = m {
                numbers.push(p.number);
            }
        }
        if i < 105 {
            assert_eq!(dec.expecting(), Expect::Bulk(250));
        }
    }
    let want: Vec<u8> = (0..16u8).map(|i| 250u8.wrapping_add(i)).collect();
    assert_eq!(numbers, want);
    assert_eq!(dec.expecting(), Expect::Nothing);
}
