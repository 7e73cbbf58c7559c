//! Property tests: every command and every device message round-trips through emit, parse and the
//! byte-at-a-time decoders.

use crate::events;
use events::feed_byte;

use aok_proto::{
    Ack, ActionWord, Command, CommandDecoder, DebugValue, ExternalControl, FirmwareVersion,
    Message, Motor, MotorTest, ParameterValue, ReplyForm, Stick, Waypoint, WaypointSlot,
};
use aok_proto::{Expect, MessageDecoder};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};

/// Any waypoint slot: the 32 numbered ones, the RAM POI and the FBC target.
fn slot() -> impl Strategy<Value = WaypointSlot> {
    prop_oneof![
        (0u8..=31).prop_map(|b| WaypointSlot::from_wire(b).unwrap()),
        Just(WaypointSlot::RamPoi),
        Just(WaypointSlot::FbcTarget),
    ]
}

/// Any waypoint.
pub(crate) fn waypoint() -> impl Strategy<Value = Waypoint> {
    (
        slot(),
        any::<i32>(),
        any::<i32>(),
        any::<u32>(),
        any::<u32>(),
    )
        .prop_map(|(slot, longitude, latitude, a1, a2)| Waypoint {
            slot,
            longitude,
            latitude,
            action1: ActionWord(a1),
            action2: ActionWord(a2),
        })
}

fn stick() -> impl Strategy<Value = Stick> {
    (-200i16..=200).prop_map(|v| Stick::new(v).unwrap())
}

/// A valid command of any kind.
pub(crate) fn command() -> impl Strategy<Value = Command> {
    prop_oneof![
        Just(Command::DebugOff),
        Just(Command::DebugOn),
        Just(Command::Reset),
        Just(Command::SaveWaypoints),
        Just(Command::LoadWaypoints),
        any::<u8>().prop_map(Command::LoadSet),
        any::<u8>().prop_map(Command::SaveSet),
        any::<u8>().prop_map(Command::StartSet),
        (any::<u8>(), any::<i32>())
            .prop_map(|(number, value)| Command::SetParameter(ParameterValue { number, value })),
        any::<u8>().prop_map(Command::ReadParameter),
        any::<u8>().prop_map(Command::BulkRead),
        (1u8..=12, any::<u8>()).prop_map(|(m, value)| Command::MotorTest(MotorTest {
            motor: Motor::new(m).unwrap(),
            value
        })),
        waypoint().prop_map(Command::SetWaypoint),
        slot().prop_map(Command::ReadWaypoint),
        (stick(), stick(), stick(), any::<i16>(), any::<u16>()).prop_map(
            |(roll, nick, yaw, pitch, expiry_ms)| Command::ExternalControl(ExternalControl {
                roll,
                nick,
                yaw,
                pitch,
                expiry_ms
            })
        ),
    ]
}

fn message() -> impl Strategy<Value = Message> {
    prop_oneof![
        (any::<u8>(), any::<i32>())
            .prop_map(|(number, value)| Message::Debug(DebugValue { number, value })),
        prop_oneof![Just(Ack::Ok), Just(Ack::Error), Just(Ack::InFlight)].prop_map(Message::Ack),
        (any::<u8>(), any::<i32>())
            .prop_map(|(number, value)| Message::Parameter(ParameterValue { number, value })),
        waypoint().prop_map(Message::Waypoint),
    ]
}

fn runner() -> TestRunner {
    TestRunner::new_with_rng(
        Config {
            cases: 2000,
            failure_persistence: None,
            ..Config::default()
        },
        TestRng::from_seed(RngAlgorithm::ChaCha, &[7; 32]),
    )
}

#[test]
fn commands_round_trip() {
    runner()
        .run(&command(), |cmd| {
            let mut buf = [0u8; 19];
            let n = cmd.emit(&mut buf).unwrap();
            prop_assert_eq!(n, cmd.buffer_len());
            prop_assert_eq!(Command::parse(&buf[..n]), Ok((cmd, n)));
            // Too short a buffer is an error, not a panic.
            prop_assert!(cmd.emit(&mut buf[..n - 1]).is_err());
            prop_assert!(Command::parse(&buf[..n - 1]).is_err());
            let mut dec = CommandDecoder::new();
            let items: Vec<_> = buf[..n]
                .iter()
                .flat_map(|&b| feed_byte(&mut dec, b))
                .collect();
            prop_assert_eq!(items, vec![Ok(cmd)]);
            prop_assert_eq!(dec.held_bytes(), 0);
            Ok(())
        })
        .unwrap();
}

#[test]
fn messages_round_trip_in_both_forms() {
    let strategy = (message(), any::<bool>());
    runner()
        .run(&strategy, |(msg, old)| {
            let fw = if old {
                FirmwareVersion::new(0, 30)
            } else {
                FirmwareVersion::new(0, 31)
            };
            let form = fw.reply_form();
            let mut buf = [0u8; 19];
            let n = msg.emit(&mut buf, form).unwrap();
            prop_assert_eq!(n, msg.buffer_len(form));
            let expect = match msg {
                Message::Ack(_) => Expect::Ack,
                Message::Parameter(p) => Expect::Parameter(p.number),
                Message::Waypoint(w) => Expect::Waypoint(w.slot),
                Message::Debug(_) => Expect::Nothing,
            };
            if form == ReplyForm::Headed || !matches!(msg, Message::Parameter(_)) {
                prop_assert_eq!(Message::parse(&buf[..n]), Ok((msg, n)));
            }
            let mut dec = MessageDecoder::new(fw);
            dec.expect(expect);
            let items: Vec<_> = buf[..n]
                .iter()
                .flat_map(|&b| feed_byte(&mut dec, b))
                .collect();
            prop_assert_eq!(items, vec![Ok(msg)]);
            prop_assert_eq!(dec.expecting(), Expect::Nothing);
            Ok(())
        })
        .unwrap();
}

#[test]
fn command_streams_with_noise_round_trip() {
    // Noise bytes that can start no command; every command must come out in order.
    let noise = prop_oneof![Just(0x00u8), Just(0x10), Just(0xaa), Just(0xfe), Just(0x64)];
    let strategy =
        proptest::collection::vec((command(), proptest::collection::vec(noise, 0..4)), 1..20);
    runner()
        .run(&strategy, |items| {
            let mut bytes = Vec::new();
            for (cmd, noise) in &items {
                bytes.extend(noise);
                let mut buf = [0u8; 19];
                let n = cmd.emit(&mut buf).unwrap();
                bytes.extend_from_slice(&buf[..n]);
            }
            let mut dec = CommandDecoder::new();
            let got: Vec<_> = bytes.iter().flat_map(|&b| feed_byte(&mut dec, b)).collect();
            let want: Vec<_> = items.iter().map(|(c, _)| Ok(*c)).collect();
            prop_assert_eq!(got, want);
            Ok(())
        })
        .unwrap();
}

#[test]
fn action_words_round_trip() {
    runner()
        .run(&(0u16..=6, any::<i16>()), |(code, value)| {
            let action = aok_proto::Action::from_code(code).unwrap();
            let w = ActionWord::new(action, value);
            prop_assert_eq!(w.action(), Ok(action));
            prop_assert_eq!(w.value(), value);
            prop_assert_eq!(
                i32::from(w.raw() as u16),
                i32::from(value) + ActionWord::OFFSET
            );
            Ok(())
        })
        .unwrap();
}
