//! AOK in `decode`: either side's decoder through the contract's adapter, each event at its
//! place (an item at its first byte, an error at the first byte of what it condemns).

use serde_json::{Map, Value, json};

use super::input::Input;
use super::{Event, StreamDecoder, error_kind};
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

/// An AOK event at input offset `at`, `len` bytes on the wire, as `decode` prints it (`fields`:
/// the item's name and fields; `why`: the sentence of a frame cut short).
fn aok_event<T>(
    at: u64,
    len: u64,
    event: Result<T, aok_proto::Error>,
    fields: impl Fn(&T) -> (String, Value),
    why: &str,
) -> Event {
    match event {
        Ok(item) => {
            let (name, fields) = fields(&item);
            let mut meta = Map::new();
            meta.insert("len".into(), json!(len));
            Event::message(at, name, meta, fields)
        }
        Err(e @ aok_proto::Error::Truncated) => Event::error(at, len, error_kind(&e), why),
        Err(e) => Event::error(at, len, error_kind(&e), e.to_string()),
    }
}

/// The sentence of a frame the end of the input cut short.
const CUT_SHORT: &str = "input ends inside a frame";

impl StreamDecoder for AokDecoder {
    fn feed(&mut self, bytes: &[u8], offset: u64, out: &mut Vec<Event>) {
        match &mut self.0 {
            Reads::FromDevice(d) => d.feed(bytes, offset, |at, len, ev| {
                out.push(aok_event(at, len, ev, aok_message_fields, CUT_SHORT));
            }),
            Reads::FromPc(d) => d.feed(bytes, offset, |at, len, ev| {
                out.push(aok_event(at, len, ev, aok_command_fields, CUT_SHORT));
            }),
        }
    }

    /// The end of the stream: the bytes held are given up once, as "input ends inside a
    /// frame", then what the rescan of what followed them finds.
    fn finish(&mut self, _offset: u64, out: &mut Vec<Event>) {
        match &mut self.0 {
            Reads::FromDevice(d) => d.finish(|at, len, ev| {
                out.push(aok_event(at, len, ev, aok_message_fields, CUT_SHORT));
            }),
            Reads::FromPc(d) => d.finish(|at, len, ev| {
                out.push(aok_event(at, len, ev, aok_command_fields, CUT_SHORT));
            }),
        }
    }

    fn counters(&self) -> Value {
        to_json(&self.stats())
    }
}
