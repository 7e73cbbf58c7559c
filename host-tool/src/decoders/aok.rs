//! AOK in `decode`: either side's decoder through the contract's adapter, each event at its
//! place (an item at its first byte, an error at the first byte of what it condemns).

use serde_json::{Value, json};

use super::aeolus::CUT_SHORT;
use super::input::Input;
use super::{Fault, Item, Placed};
use crate::proto::Side;
use crate::render::{self, to_json, variant};

/// AOK: the PC decoder (for the device's bytes) or the device decoder (for the PC's bytes).
#[derive(Debug)]
pub struct AokDecoder(Reads);

/// What an [`AokDecoder`] reads.
#[derive(Debug)]
enum Reads {
    /// What the device sends.
    FromDevice(Input<aok_proto::MessageDecoder>),
    /// What the PC sends.
    FromPc(Input<aok_proto::CommandDecoder>),
}

impl AokDecoder {
    /// A decoder for bytes sent by `side`.
    pub fn new(side: Side) -> Self {
        match side {
            Side::Device => AokDecoder(Reads::FromDevice(Input::new(
                aok_proto::MessageDecoder::new(aok_proto::FirmwareVersion::LATEST),
            ))),
            Side::Pc => AokDecoder(Reads::FromPc(Input::new(aok_proto::CommandDecoder::new()))),
        }
    }

    fn stats(&self) -> aok_proto::Stats {
        match &self.0 {
            Reads::FromDevice(d) => d.decoder().stats(),
            Reads::FromPc(d) => d.decoder().stats(),
        }
    }
}

/// An AOK device message's name, in upper snake case.
///
/// ```
/// use aok_proto::{DebugValue, Message};
/// let m = Message::Debug(DebugValue { number: 86, value: -2 });
/// assert_eq!(protolink::decoders::aok_message_name(&m), "DEBUG");
/// ```
pub fn aok_message_name(message: &aok_proto::Message) -> &'static str {
    use aok_proto::Message as M;
    match message {
        M::Debug(_) => "DEBUG",
        M::Ack(_) => "ACK",
        M::Parameter(_) => "PARAMETER",
        M::Waypoint(_) => "WAYPOINT",
    }
}

/// An AOK command's name, in upper snake case.
///
/// ```
/// let c = aok_proto::Command::ReadParameter(12);
/// assert_eq!(protolink::decoders::aok_command_name(&c), "READ_PARAMETER");
/// ```
pub fn aok_command_name(command: &aok_proto::Command) -> &'static str {
    use aok_proto::Command as C;
    match command {
        C::DebugOff => "DEBUG_OFF",
        C::DebugOn => "DEBUG_ON",
        C::Reset => "RESET",
        C::SaveWaypoints => "SAVE_WAYPOINTS",
        C::LoadWaypoints => "LOAD_WAYPOINTS",
        C::LoadSet(_) => "LOAD_SET",
        C::SaveSet(_) => "SAVE_SET",
        C::StartSet(_) => "START_SET",
        C::SetParameter(_) => "SET_PARAMETER",
        C::ReadParameter(_) => "READ_PARAMETER",
        C::BulkRead(_) => "BULK_READ",
        C::MotorTest(_) => "MOTOR_TEST",
        C::SetWaypoint(_) => "SET_WAYPOINT",
        C::ReadWaypoint(_) => "READ_WAYPOINT",
        C::ExternalControl(_) => "EXTERNAL_CONTROL",
    }
}

/// Splits an AOK device message into its name and fields.
///
/// ```
/// use aok_proto::{DebugValue, Message};
/// let (name, fields) = protolink::decoders::aok_message_fields(&Message::Debug(DebugValue { number: 86, value: -2 }));
/// assert_eq!((name.as_str(), fields.to_string()), ("DEBUG", r#"{"number":86,"value":-2}"#.to_string()));
/// ```
pub fn aok_message_fields(message: &aok_proto::Message) -> (String, Value) {
    match message {
        aok_proto::Message::Waypoint(w) => ("WAYPOINT".into(), waypoint_fields(w)),
        other => {
            let (name, fields) = variant(to_json(other));
            (render::upper_snake(&name), fields)
        }
    }
}

/// Splits an AOK command into its name and fields.
///
/// ```
/// let (name, fields) = protolink::decoders::aok_command_fields(&aok_proto::Command::ReadParameter(12));
/// assert_eq!((name.as_str(), fields.to_string()), ("READ_PARAMETER", r#"{"number":12}"#.to_string()));
/// ```
pub fn aok_command_fields(command: &aok_proto::Command) -> (String, Value) {
    match command {
        aok_proto::Command::SetWaypoint(w) => ("SET_WAYPOINT".into(), waypoint_fields(w)),
        aok_proto::Command::ReadWaypoint(s) => {
            ("READ_WAYPOINT".into(), json!({ "slot": slot_name(*s) }))
        }
        aok_proto::Command::ReadParameter(n) => ("READ_PARAMETER".into(), json!({ "number": n })),
        aok_proto::Command::BulkRead(n) => ("BULK_READ".into(), json!({ "first": n })),
        aok_proto::Command::LoadSet(n) => ("LOAD_SET".into(), json!({ "set": n })),
        aok_proto::Command::SaveSet(n) => ("SAVE_SET".into(), json!({ "set": n })),
        aok_proto::Command::StartSet(n) => ("START_SET".into(), json!({ "set": n })),
        other => {
            let (name, fields) = variant(to_json(other));
            (render::upper_snake(&name), fields)
        }
    }
}

/// A waypoint slot as people name it: `1`..`31`, `poi`, `ram-poi`, `fbc`.
///
/// ```
/// use aok_proto::WaypointSlot;
/// assert_eq!(protolink::decoders::slot_name(WaypointSlot::from_wire(0).unwrap()), "1");
/// assert_eq!(protolink::decoders::slot_name(WaypointSlot::FbcTarget), "fbc");
/// ```
pub fn slot_name(slot: aok_proto::WaypointSlot) -> String {
    match slot {
        aok_proto::WaypointSlot::Waypoint(n) => n.get().to_string(),
        aok_proto::WaypointSlot::MissionPoi => "poi".into(),
        aok_proto::WaypointSlot::RamPoi => "ram-poi".into(),
        aok_proto::WaypointSlot::FbcTarget => "fbc".into(),
    }
}

/// An action word as `action:value` (`hold-and-climb:15`), or `raw:0x...` for an unknown action.
///
/// ```
/// use aok_proto::{Action, ActionWord};
/// assert_eq!(protolink::decoders::action_name(ActionWord::new(Action::SetFlySpeed, 250)), "set-fly-speed:250");
/// ```
pub fn action_name(word: aok_proto::ActionWord) -> String {
    match word.action() {
        Ok(a) => {
            let name = match a {
                aok_proto::Action::None => "none",
                aok_proto::Action::Pause => "pause",
                aok_proto::Action::HoldAndClimb => "hold-and-climb",
                aok_proto::Action::HoldAndSink => "hold-and-sink",
                aok_proto::Action::FlyAndClimb => "fly-and-climb",
                aok_proto::Action::FlyAndSink => "fly-and-sink",
                aok_proto::Action::SetFlySpeed => "set-fly-speed",
            };
            format!("{name}:{}", word.value())
        }
        Err(_) => format!("raw:{:#010x}", word.raw()),
    }
}

/// A waypoint's fields: slot, raw coordinates and the two actions.
pub fn waypoint_fields(w: &aok_proto::Waypoint) -> Value {
    json!({
        "slot": slot_name(w.slot),
        "longitude": w.longitude,
        "latitude": w.latitude,
        "action1": action_name(w.action1),
        "action2": action_name(w.action2),
    })
}

impl AokDecoder {
    /// Feeds bytes that start at input offset `offset`, handing every item to `on_item`
    /// placed at its first byte (an error: at the first byte of what it condemns).
    ///
    /// ```
    /// use protolink::decoders::{AokDecoder, Item};
    /// use protolink::proto::Side;
    /// let mut d = AokDecoder::new(Side::Pc);
    /// let mut frame = [0u8; 16];
    /// let n = aok_proto::Command::ReadParameter(12).emit(&mut frame).unwrap();
    /// let mut seen = Vec::new();
    /// d.feed(&frame[..n], 0, |p| seen.push(p.item == Item::AokCommand(aok_proto::Command::ReadParameter(12))));
    /// assert_eq!(seen, [true]);
    /// ```
    pub fn feed(&mut self, bytes: &[u8], offset: u64, mut on_item: impl FnMut(Placed<'_>)) {
        match &mut self.0 {
            Reads::FromDevice(d) => d.feed(bytes, offset, |at, len, ev| {
                on_item(placed(at, len, ev.map(Item::AokMessage)));
            }),
            Reads::FromPc(d) => d.feed(bytes, offset, |at, len, ev| {
                on_item(placed(at, len, ev.map(Item::AokCommand)));
            }),
        }
    }

    /// The end of the stream: the bytes held are given up once, as "input ends inside a
    /// frame", then what the rescan of what followed them finds.
    ///
    /// ```
    /// use protolink::decoders::AokDecoder;
    /// let mut d = AokDecoder::new(protolink::proto::Side::Pc);
    /// let mut frame = [0u8; 16];
    /// let n = aok_proto::Command::ReadParameter(12).emit(&mut frame).unwrap();
    /// d.feed(&frame[..n - 1], 0, |_| {});
    /// let mut seen = Vec::new();
    /// d.finish(|p| seen.push(p.to_event().to_text()));
    /// assert_eq!(seen, ["@0 error: input ends inside a frame"]);
    /// ```
    pub fn finish(&mut self, mut on_item: impl FnMut(Placed<'_>)) {
        match &mut self.0 {
            Reads::FromDevice(d) => d.finish(|at, len, ev| {
                on_item(placed(at, len, ev.map(Item::AokMessage)));
            }),
            Reads::FromPc(d) => d.finish(|at, len, ev| {
                on_item(placed(at, len, ev.map(Item::AokCommand)));
            }),
        }
    }

    /// The counters, as `decode` prints them in its summary: the crate's `Stats`.
    ///
    /// ```
    /// let d = protolink::decoders::AokDecoder::new(protolink::proto::Side::Pc);
    /// assert!(d.counters().is_object());
    /// ```
    pub fn counters(&self) -> Value {
        to_json(&self.stats())
    }
}

/// An AOK event at input offset `at`, `len` bytes on the wire, typed.
fn placed(at: u64, len: u64, event: Result<Item<'static>, aok_proto::Error>) -> Placed<'static> {
    let item = match event {
        Ok(item) => item,
        Err(aok_proto::Error::Truncated) => Item::Error(Fault::Cut(CUT_SHORT)),
        Err(e) => Item::Error(Fault::Aok(e)),
    };
    Placed {
        offset: at,
        len,
        item,
    }
}
