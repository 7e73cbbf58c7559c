//! The value types at their edges: every range check one step inside and outside, every wire
//! byte of a motor, slot and ack, the action word's two halves, and the firmware versions
//! where the reply form and bulk read change.

use aok_proto::{
    Ack, Action, ActionWord, Error, FirmwareVersion, Motor, ReplyForm, Stick, WaypointNumber,
    WaypointSlot,
};

#[test]
fn motors_are_1_to_12_and_test_bytes_are_1_to_9_then_a_to_c() {
    assert_eq!(Motor::new(0), Err(Error::InvalidMotor(0)));
    assert_eq!(Motor::new(13), Err(Error::InvalidMotor(13)));
    assert_eq!(Motor::try_from(0), Err(Error::InvalidMotor(0)));
    let bytes: Vec<u8> = (1..=12)
        .map(|n| Motor::new(n).unwrap().command_byte())
        .collect();
    assert_eq!(bytes, b"123456789ABC");
    for n in 1..=12 {
        let m = Motor::try_from(n).unwrap();
        assert_eq!((m.get(), u8::from(m)), (n, n));
        assert_eq!(Motor::from_command_byte(m.command_byte()), Some(m));
    }
    let known = (0..=255u8).filter_map(Motor::from_command_byte).count();
    assert_eq!(known, 12);
}

#[test]
fn sticks_are_minus_200_to_200_and_saturate_there() {
    assert_eq!(Stick::new(-201), Err(Error::StickOutOfRange(-201)));
    assert_eq!(Stick::new(201), Err(Error::StickOutOfRange(201)));
    assert_eq!(Stick::try_from(201), Err(Error::StickOutOfRange(201)));
    for v in [-200, -1, 0, 1, 200] {
        let s = Stick::try_from(v).unwrap();
        assert_eq!((s.get(), i16::from(s)), (v, v));
        assert_eq!(Stick::saturating(v), s);
    }
    let clamped = [i16::MIN, -201, 201, i16::MAX].map(|v| Stick::saturating(v).get());
    assert_eq!(clamped, [-200, -200, 200, 200]);
    assert_eq!(Stick::CENTER.get(), 0);
}

#[test]
fn waypoints_are_1_to_31_on_wire_slots_0_to_30() {
    assert_eq!(WaypointNumber::new(0), Err(Error::InvalidWaypoint(0)));
    assert_eq!(WaypointNumber::new(32), Err(Error::InvalidWaypoint(32)));
    assert_eq!(
        WaypointNumber::try_from(32),
        Err(Error::InvalidWaypoint(32))
    );
    for n in [1, 2, 30, 31] {
        let w = WaypointNumber::try_from(n).unwrap();
        assert_eq!((w.get(), u8::from(w), w.wire()), (n, n, n - 1));
    }
}

#[test]
fn every_slot_byte_is_a_waypoint_a_poi_the_target_or_invalid() {
    let mut valid = 0;
    for b in 0..=255u8 {
        let want = match b {
            0..=30 => Ok(WaypointSlot::Waypoint(WaypointNumber::new(b + 1).unwrap())),
            31 => Ok(WaypointSlot::MissionPoi),
            254 => Ok(WaypointSlot::RamPoi),
            255 => Ok(WaypointSlot::FbcTarget),
            _ => Err(Error::InvalidSlot(b)),
        };
        let got = WaypointSlot::from_wire(b);
        assert_eq!(got, want, "byte {b}");
        if let Ok(slot) = got {
            assert_eq!(slot.wire(), b);
            valid += 1;
        }
    }
    assert_eq!(valid, 34);
}

#[test]
fn actions_are_codes_0_to_6() {
    for (code, a) in Action::ALL.into_iter().enumerate() {
        assert_eq!(a.code(), code as u16);
        assert_eq!(Action::from_code(code as u16), Ok(a));
    }
    assert_eq!(Action::from_code(7), Err(Error::InvalidAction(7)));
    assert_eq!(Action::SetFlySpeed.code(), 6);
}

#[test]
fn an_action_word_is_the_action_above_the_value_plus_32768() {
    let cases = [
        (Action::None, 0, 0x0000_8000),
        (Action::Pause, -1, 0x0001_7FFF),
        (Action::HoldAndSink, i16::MIN, 0x0003_0000),
        (Action::SetFlySpeed, i16::MAX, 0x0006_FFFF),
        (Action::FlyAndClimb, 250, 0x0004_80FA),
    ];
    for (action, value, raw) in cases {
        let w = ActionWord::new(action, value);
        assert_eq!(w.raw(), raw, "{action:?} {value}");
        assert_eq!((w.action(), w.value()), (Ok(action), value));
        assert_eq!(ActionWord(raw), w);
    }
    assert_eq!(ActionWord::NONE.raw(), 0x0000_8000);
    assert_eq!(ActionWord::OFFSET, 32768);
    assert_eq!(
        ActionWord(0x0007_8005).action(),
        Err(Error::InvalidAction(7))
    );
    assert_eq!(ActionWord(0x0007_8005).value(), 5);
}

#[test]
fn acks_are_the_bytes_o_e_and_i() {
    let acks: Vec<(u8, Ack)> = (0..=255u8)
        .filter_map(|b| Ack::from_byte(b).map(|a| (b, a)))
        .collect();
    assert_eq!(
        acks,
        [(b'E', Ack::Error), (b'I', Ack::InFlight), (b'O', Ack::Ok)]
    );
    for (b, a) in acks {
        assert_eq!(a.byte(), b);
    }
}

#[test]
fn replies_are_headed_from_0_31_and_bulk_read_exists_from_0_35() {
    let v = FirmwareVersion::new;
    let forms = [v(0, 0), v(0, 30), v(0, 31), v(1, 0), v(1, 30)].map(|f| f.reply_form());
    use ReplyForm::{Headed, Headerless};
    assert_eq!(forms, [Headerless, Headerless, Headed, Headed, Headed]);
    let bulk =
        [v(0, 0), v(0, 34), v(0, 35), v(0, 36), v(1, 0), v(1, 34)].map(|f| f.has_bulk_read());
    assert_eq!(bulk, [false, false, true, true, true, true]);
    assert_eq!(FirmwareVersion::LATEST, v(0, 35));
    assert_eq!((v(2, 7).major, v(2, 7).minor), (2, 7));
}
