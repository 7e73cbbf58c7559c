//! AOK in `decode`: either side's decoder, each message placed where the decoder's held bytes
//! begin.

use aok_proto::{Decode, Event as AokEvent};
use serde_json::{Map, Value, json};

use super::{Event, StreamDecoder, error_kind};
use crate::proto::Side;
use crate::render::{self, to_json, variant};

/// AOK: the PC decoder (for the device's bytes) or the device decoder (for the PC's bytes).
#[derive(Debug)]
pub enum AokDecoder {
    /// Reads what the device sends.
    FromDevice(aok_proto::MessageDecoder),
    /// Reads what the PC sends.
    FromPc(aok_proto::CommandDecoder),
}

impl AokDecoder {
    /// A decoder for bytes sent by `side`.
    pub fn new(side: Side) -> Self {
        match side {
            Side::Device => AokDecoder::FromDevice(aok_proto::MessageDecoder::new(
                aok_proto::FirmwareVersion::LATEST,
            )),
            Side::Pc => AokDecoder::FromPc(aok_proto::CommandDecoder::new()),
        }
    }

    fn stats(&self) -> aok_proto::Stats {
        match self {
            AokDecoder::FromDevice(d) => d.stats(),
            AokDecoder::FromPc(d) => d.stats(),
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

impl AokDecoder {
    fn held_bytes(&self) -> u64 {
        match self {
            AokDecoder::FromDevice(d) => d.held_bytes() as u64,
            AokDecoder::FromPc(d) => d.held_bytes() as u64,
        }
    }
}

/// Gives the messages among `events` (each with its wire length in `lens`, 0 for an error)
/// their first byte: the last one ends where the decoder's held bytes begin (`end`), and
/// each earlier one ends where the next begins. Errors keep the offset they have.
fn place_backwards(events: &mut [Event], lens: &[u64], mut end: u64) {
    for (e, &len) in events.iter_mut().zip(lens).rev() {
        if len > 0 {
            end = end.saturating_sub(len);
            e.offset = end;
        }
    }
}

impl StreamDecoder for AokDecoder {
    fn feed(&mut self, bytes: &[u8], offset: u64, out: &mut Vec<Event>) {
        let mut lens = Vec::new();
        for (i, &b) in bytes.iter().enumerate() {
            let at = offset + i as u64;
            let first = out.len();
            lens.clear();
            match self {
                AokDecoder::FromDevice(d) => {
                    d.feed(&[b], |item| match item {
                        Ok(m) => {
                            let (name, fields) = aok_message_fields(&m);
                            let len = m.buffer_len(aok_proto::ReplyForm::Headed);
                            let mut meta = Map::new();
                            meta.insert("len".into(), json!(len));
                            out.push(Event::message(at, name, meta, fields));
                            lens.push(len as u64);
                        }
                        Err(e) => {
                            out.push(Event::error(at, error_kind(&e), e.to_string()));
                            lens.push(0);
                        }
                    });
                }
                AokDecoder::FromPc(d) => {
                    let mut items = Vec::new();
                    d.feed(&[b], |item| items.push(item));
                    for item in items {
                        match item {
                            Ok(c) => {
                                let (name, fields) = aok_command_fields(&c);
                                let mut meta = Map::new();
                                meta.insert("len".into(), json!(c.buffer_len()));
                                out.push(Event::message(at, name, meta, fields));
                                lens.push(c.buffer_len() as u64);
                            }
                            Err(e) => {
                                out.push(Event::error(at, error_kind(&e), e.to_string()));
                                lens.push(0);
                            }
                        }
                    }
                }
            }
            let end = at + 1 - self.held_bytes();
            if let Some(events) = out.get_mut(first..) {
                place_backwards(events, &lens, end);
            }
        }
    }

    /// The end of the stream through the pull form's `end`, one event at a time (so each is
    /// placed by the bytes still held after it): the bytes held are given up once, as
    /// "input ends inside a frame", then what the rescan of what followed them finds.
    fn finish(&mut self, offset: u64, out: &mut Vec<Event>) {
        let at = offset.saturating_sub(1);
        loop {
            let first = out.len();
            let mut len = 0;
            let item = match self {
                AokDecoder::FromDevice(d) => d.end().map(|event| match event {
                    AokEvent::Found(m) => {
                        let (name, fields) = aok_message_fields(&m);
                        len = m.buffer_len(aok_proto::ReplyForm::Headed);
                        let mut meta = Map::new();
                        meta.insert("len".into(), json!(len));
                        Ok(Event::message(at, name, meta, fields))
                    }
                    AokEvent::Error(e) => Err(e),
                    AokEvent::Truncated(_) => Err(aok_proto::Error::Truncated),
                }),
                AokDecoder::FromPc(d) => d.end().map(|event| match event {
                    AokEvent::Found(c) => {
                        let (name, fields) = aok_command_fields(&c);
                        len = c.buffer_len();
                        let mut meta = Map::new();
                        meta.insert("len".into(), json!(len));
                        Ok(Event::message(at, name, meta, fields))
                    }
                    AokEvent::Error(e) => Err(e),
                    AokEvent::Truncated(_) => Err(aok_proto::Error::Truncated),
                }),
            };
            match item {
                None => break,
                Some(Ok(event)) => out.push(event),
                Some(Err(e @ aok_proto::Error::Truncated)) => {
                    out.push(Event::error(
                        at,
                        error_kind(&e),
                        "input ends inside a frame",
                    ));
                }
                Some(Err(e)) => out.push(Event::error(at, error_kind(&e), e.to_string())),
            }
            let end = offset.saturating_sub(self.held_bytes());
            if let Some(events) = out.get_mut(first..) {
                place_backwards(events, &[len as u64], end);
            }
        }
    }

    fn counters(&self) -> Value {
        to_json(&self.stats())
    }
}
