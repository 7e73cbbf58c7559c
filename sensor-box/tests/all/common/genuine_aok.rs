//! Genuine AOK commands, as a PC sends them: every command type, with its bytes from
//! `aok_proto`'s encoder (`Command::emit`), for the bit-flip and lost-byte models of
//! `noise.rs`.

use aok_proto::{
    ActionWord, Command, ExternalControl, Motor, MotorTest, ParameterValue, Stick, Waypoint,
    WaypointSlot,
};

/// The genuine commands: 156 of them, every command type of K5..K9.
pub fn commands() -> Vec<Command> {
    let mut out = vec![
        Command::DebugOff,
        Command::DebugOn,
        Command::Reset,
        Command::SaveWaypoints,
        Command::LoadWaypoints,
    ];
    for n in 0..5 {
        out.push(Command::LoadSet(n));
        out.push(Command::SaveSet(n));
        out.push(Command::StartSet(n));
    }
    // Reads: every parameter number a PC reads, and the bulk reads of its two halves.
    for number in 0..32 {
        out.push(Command::ReadParameter(number));
    }
    out.push(Command::BulkRead(0));
    out.push(Command::BulkRead(16));
    let slots = [0u8, 1, 7, 9, 15, 30, 31, 254, 255];
    for &wire in &slots {
        if let Ok(slot) = WaypointSlot::from_wire(wire) {
            out.push(Command::ReadWaypoint(slot));
        }
    }
    // Sets: in-flight settable (0..=15) and not (16..=31), positive, negative and zero values.
    for (i, number) in (0u8..32).enumerate() {
        let value = match i % 4 {
            0 => 1500,
            1 => -250,
            2 => 0,
            _ => 0x0102_0304,
        };
        out.push(Command::SetParameter(ParameterValue { number, value }));
    }
    for (i, &wire) in slots.iter().enumerate() {
        if let Ok(slot) = WaypointSlot::from_wire(wire) {
            let k = i as i32;
            out.push(Command::SetWaypoint(Waypoint {
                slot,
                longitude: 113_456_789 + k,
                latitude: 475_123_456 - k,
                action1: ActionWord::new(aok_proto::Action::FlyAndClimb, 20 + k as i16),
                action2: ActionWord::NONE,
            }));
        }
    }
    // Motor tests: every motor, four values each.
    for motor in Motor::MIN..=Motor::MAX {
        for value in [1u8, 40, 128, 200] {
            if let Ok(motor) = Motor::new(motor) {
                out.push(Command::MotorTest(MotorTest { motor, value }));
            }
        }
    }
    for (roll, nick, yaw) in [(32, -32, 0), (0, 0, 0), (-200, 200, 100), (150, 0, -150)] {
        out.push(Command::ExternalControl(ExternalControl {
            roll: Stick::saturating(roll),
            nick: Stick::saturating(nick),
            yaw: Stick::saturating(yaw),
            pitch: 0,
            expiry_ms: 500,
        }));
    }
    out
}

/// The bytes of `command` as the encoder writes them.
pub fn bytes(command: &Command) -> Vec<u8> {
    let mut frame = [0u8; aok_proto::command::MAX_COMMAND_LEN];
    let n = command.emit(&mut frame).unwrap();
    frame[..n].to_vec()
}

/// Every variant of `bytes` with one bit flipped, then every variant with one byte lost.
pub fn variants(bytes: &[u8]) -> Vec<Vec<u8>> {
    let mut out = Vec::new();
    for i in 0..bytes.len() {
        for bit in 0..8 {
            let mut v = bytes.to_vec();
            v[i] ^= 1 << bit;
            out.push(v);
        }
    }
    for i in 0..bytes.len() {
        let mut v = bytes.to_vec();
        v.remove(i);
        out.push(v);
    }
    out
}
