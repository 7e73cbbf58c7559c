//! `protolink decode`: one line per message (text or JSON), errors in the stream with their byte
//! offset, and the decoder's counters at the end.
//!
//! The offset of a message is the 0-based index of its first byte in the input: the opening
//! flag of an AEOLUS frame, the 0xFF start of an AYDP message, the first byte of an AOK frame,
//! also for messages a rescan found among bytes already held. `len` is its length on the wire,
//! so its bytes are `offset..offset + len`. An AEOLUS or AYDP error is reported at the first
//! byte of the failed frame or candidate; an AOK error at the byte that revealed it.

use std::time::Duration;

use aydp_proto::Profile;
use clap::{Args, ValueEnum};
use serde_json::{Map, Value, json};

use crate::endpoint::{Endpoint, Input, Link};
use crate::error::Result;
use crate::render::{self, Out, hex, to_json, variant};
use crate::stop::Deadline;

/// Which protocol a stream carries.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Proto {
    /// AEOLUS sensor-box telemetry (7E-framed, CRC-16).
    Aeolus,
    /// AYDP, the yacht protocol (FF start, XOR checksum).
    Aydp,
    /// AOK, the copter's serial protocol.
    Aok,
}

/// Which AYDP convention applies (DECISIONS.md Y1, Y2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, ValueEnum)]
pub enum ProfileArg {
    /// The 2016 document: the length counts the whole message, sub-seconds are ms.
    #[default]
    Spec,
    /// The released AYDP software: the length counts data only, sub-seconds are µs.
    Reference,
}

impl From<ProfileArg> for Profile {
    fn from(p: ProfileArg) -> Self {
        match p {
            ProfileArg::Spec => Profile::Spec,
            ProfileArg::Reference => Profile::Reference,
        }
    }
}

/// Who sent the AOK bytes being decoded.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, ValueEnum)]
pub enum Side {
    /// The ground PC sent them: commands, read as the device reads them.
    Pc,
    /// The device sent them: debug values, acks and replies, read as the PC reads them.
    #[default]
    Device,
}

/// Arguments of `protolink decode`.
#[derive(Debug, Clone, Args)]
pub struct DecodeArgs {
    /// The protocol of the stream.
    #[arg(long, value_enum)]
    pub proto: Proto,
    /// AYDP profile.
    #[arg(long, value_enum, default_value_t = ProfileArg::Spec)]
    pub profile: ProfileArg,
    /// AOK: who sent the bytes (pc: commands; device: debug values, acks, replies).
    #[arg(long, value_enum, default_value_t = Side::Device)]
    pub side: Side,
    /// Where the bytes come from (serial:PATH@BAUD, tcp:HOST:PORT, udp:PORT, file:PATH, -).
    #[arg(long, value_name = "ENDPOINT")]
    pub from: Endpoint,
    /// One JSON object per line instead of text.
    #[arg(long)]
    pub json: bool,
    /// Stop after this long: `10` (seconds), `500ms`, `2min` (default: at the end of the input, or on Ctrl-C).
    #[arg(long, value_name = "DURATION", value_parser = crate::args::run_time)]
    pub seconds: Option<std::time::Duration>,
}

/// One thing a decoder reports.
#[derive(Debug, Clone, PartialEq)]
pub struct Event {
    /// Input offset at which it was reported.
    pub offset: u64,
    /// What it is.
    pub body: Body,
}

/// A message or an error.
#[derive(Debug, Clone, PartialEq)]
pub enum Body {
    /// A decoded message.
    Message {
        /// Its name, e.g. `GYRO`.
        name: String,
        /// Facts about the frame (id, length, CRC state, header time...).
        meta: Map<String, Value>,
        /// The message's fields.
        fields: Value,
    },
    /// An error in the stream.
    Error {
        /// One sentence.
        error: String,
    },
}

impl Event {
    fn message(
        offset: u64,
        name: impl Into<String>,
        meta: Map<String, Value>,
        fields: Value,
    ) -> Self {
        Event {
            offset,
            body: Body::Message {
                name: name.into(),
                meta,
                fields,
            },
        }
    }

    fn error(offset: u64, error: impl Into<String>) -> Self {
        Event {
            offset,
            body: Body::Error {
                error: error.into(),
            },
        }
    }

    /// The event as one JSON object.
    ///
    /// ```
    /// # use protolink::decode::{Body, Event};
    /// let e = Event { offset: 7, body: Body::Error { error: "checksum mismatch".into() } };
    /// assert_eq!(e.to_json().to_string(), r#"{"offset":7,"kind":"error","error":"checksum mismatch"}"#);
    /// ```
    pub fn to_json(&self) -> Value {
        let mut m = Map::new();
        m.insert("offset".into(), json!(self.offset));
        match &self.body {
            Body::Message { name, meta, fields } => {
                m.insert("kind".into(), json!("message"));
                m.insert("name".into(), json!(name));
                m.extend(meta.clone());
                m.insert("fields".into(), fields.clone());
            }
            Body::Error { error } => {
                m.insert("kind".into(), json!("error"));
                m.insert("error".into(), json!(error));
            }
        }
        Value::Object(m)
    }

    /// The event as one readable line.
    ///
    /// ```
    /// # use protolink::decode::{Body, Event};
    /// let e = Event { offset: 7, body: Body::Error { error: "checksum mismatch".into() } };
    /// assert_eq!(e.to_text(), "@7 error: checksum mismatch");
    /// ```
    pub fn to_text(&self) -> String {
        match &self.body {
            Body::Message { name, meta, fields } => {
                let meta = render::text(&Value::Object(meta.clone()));
                let fields = render::text(fields);
                let mut line = format!("@{} {name}", self.offset);
                for part in [meta, fields] {
                    if !part.is_empty() {
                        line.push(' ');
                        line.push_str(&part);
                    }
                }
                line
            }
            Body::Error { error } => format!("@{} error: {error}", self.offset),
        }
    }
}

/// A stream decoder for one protocol, reporting [`Event`]s.
pub trait StreamDecoder {
    /// Feeds bytes that start at input offset `offset`.
    fn feed(&mut self, bytes: &[u8], offset: u64, out: &mut Vec<Event>);
    /// A datagram ended at `offset` (the next byte starts a new one).
    fn end_of_datagram(&mut self, _offset: u64, _out: &mut Vec<Event>) {}
    /// The input ended at `offset` (its length).
    fn finish(&mut self, _offset: u64, _out: &mut Vec<Event>) {}
    /// The counters, as a JSON object.
    fn counters(&self) -> Value;
}

/// Capacity of the AEOLUS deframer: every message, long LOG messages included.
pub const AEOLUS_CAPACITY: usize = 8192;
/// Capacity of the AYDP decoder: the longest message accepted.
pub const AYDP_CAPACITY: usize = 16384;

/// AEOLUS: the byte-at-a-time deframer, with datagram boundaries honoured.
#[derive(Debug)]
pub struct AeolusDecoder {
    deframer: Box<aeolus_proto::Deframer<AEOLUS_CAPACITY>>,
    /// Offset of the latest flag: the opening flag of the frame being collected.
    opened_at: u64,
    malformed: u32,
    truncated: u32,
}

impl Default for AeolusDecoder {
    fn default() -> Self {
        Self::new()
    }
}

impl AeolusDecoder {
    /// A decoder that accepts frames without CRC (as the spec allows).
    pub fn new() -> Self {
        AeolusDecoder {
            deframer: Box::new(aeolus_proto::Deframer::new()),
            opened_at: 0,
            malformed: 0,
            truncated: 0,
        }
    }

    /// The deframer's counters.
    pub fn stats(&self) -> &aeolus_proto::Stats {
        self.deframer.stats()
    }
}

/// Splits an AEOLUS message into its name and fields (texts as strings, raw data as hex).
///
/// ```
/// use aeolus_proto::message::{Message, Text};
/// let (name, fields) = protolink::decode::aeolus_fields(&Message::Toast(Text::new("hi").unwrap()));
/// assert_eq!((name, fields.to_string()), ("TOAST", r#"{"text":"hi"}"#.to_string()));
/// ```
pub fn aeolus_fields(message: &aeolus_proto::message::Message<'_>) -> (&'static str, Value) {
    use aeolus_proto::message::Message as M;
    let fields = match message {
        M::Toast(t) | M::Command(t) => text_fields(t.as_bytes()),
        M::CalibInfo(d) | M::DebugInfo(d) | M::Log(d) | M::Unknown { data: d, .. } => {
            json!({ "len": d.len(), "data": hex(d) })
        }
        other => variant(to_json(other)).1,
    };
    (message.name(), fields)
}

/// A text field: `{"text": ...}` escaped with [`render::escape_text`], plus `"hex"` of the raw
/// bytes whenever the text is not clean UTF-8 (DECISIONS.md A6: the raw bytes are kept).
///
/// ```
/// let v = protolink::decode::text_fields(b"\x1b[2J");
/// assert_eq!(v.to_string(), r#"{"text":"\\x1b[2J","hex":"1b5b324a"}"#);
/// ```
pub fn text_fields(bytes: &[u8]) -> Value {
    let mut m = Map::new();
    m.insert("text".into(), json!(render::escape_text(bytes)));
    if !render::is_clean_text(bytes) {
        m.insert("hex".into(), json!(hex(bytes)));
    }
    Value::Object(m)
}

impl StreamDecoder for AeolusDecoder {
    fn feed(&mut self, bytes: &[u8], offset: u64, out: &mut Vec<Event>) {
        for (i, &b) in bytes.iter().enumerate() {
            let at = offset + i as u64;
            // A frame holds no flag, so the flag before its closing one opened it.
            let opened = self.opened_at;
            if b == aeolus_proto::FLAG {
                self.opened_at = at;
            }
            let Some(event) = self.deframer.push(b) else {
                continue;
            };
            match event {
                Ok(frame) => {
                    let mut meta = Map::new();
                    meta.insert("id".into(), json!(frame.id()));
                    meta.insert("len".into(), json!(at + 1 - opened));
                    meta.insert(
                        "crc".into(),
                        json!(if frame.has_crc() { "ok" } else { "none" }),
                    );
                    match frame.message() {
                        Ok(m) => {
                            let (name, fields) = aeolus_fields(&m);
                            out.push(Event::message(opened, name, meta, fields));
                        }
                        Err(e) => {
                            self.malformed = self.malformed.wrapping_add(1);
                            out.push(Event::error(
                                opened,
                                format!("{e} (frame {})", hex(frame.raw())),
                            ));
                        }
                    }
                }
                Err(e) => out.push(Event::error(opened, e.to_string())),
            }
        }
    }

    fn end_of_datagram(&mut self, offset: u64, out: &mut Vec<Event>) {
        if self.deframer.pending_bytes() > 0 {
            self.truncated = self.truncated.wrapping_add(1);
            out.push(Event::error(
                self.opened_at,
                aeolus_proto::Error::Truncated.to_string(),
            ));
        }
        self.opened_at = offset;
        // A frame never spans two datagrams (DECISIONS.md A9): start afresh.
        self.deframer.reset();
    }

    fn finish(&mut self, offset: u64, out: &mut Vec<Event>) {
        if self.deframer.pending_bytes() > 0 {
            self.truncated = self.truncated.wrapping_add(1);
            out.push(Event::error(
                self.opened_at.min(offset.saturating_sub(1)),
                "input ends inside a frame".to_string(),
            ));
            self.deframer.reset();
        }
    }

    fn counters(&self) -> Value {
        let mut v = to_json(self.deframer.stats());
        if let Value::Object(m) = &mut v {
            m.insert("malformed".into(), json!(self.malformed));
            m.insert("truncated".into(), json!(self.truncated));
        }
        v
    }
}

/// AYDP: the rescanning decoder in one profile.
#[derive(Debug)]
pub struct AydpDecoder {
    decoder: Box<aydp_proto::Decoder<AYDP_CAPACITY>>,
    malformed: u32,
    truncated: u32,
}

impl AydpDecoder {
    /// A decoder for `profile`.
    pub fn new(profile: Profile) -> Self {
        AydpDecoder {
            decoder: Box::new(aydp_proto::Decoder::new(profile)),
            malformed: 0,
            truncated: 0,
        }
    }
}

/// Splits a checked AYDP frame into its name, its meta data and its fields; a malformed typed
/// parse comes back as the error sentence.
///
/// ```
/// use aydp_proto::{Frame, Profile};
/// let f = Frame::new_checked(&[0xFF, 0x89, 0x08, 0, 0, 0, 0x02, 0x7C], Profile::Spec).unwrap();
/// let (name, meta, fields) = protolink::decode::aydp_fields(&f).unwrap();
/// assert_eq!(name, "SYSTEM_CONTROL");
/// assert_eq!(meta["type"], 9);
/// assert_eq!(fields.to_string(), r#"{"command":"StoreConfiguration"}"#);
/// ```
///
/// # Errors
/// The typed parse's error, as a sentence.
pub fn aydp_fields(
    frame: &aydp_proto::Frame<'_>,
) -> std::result::Result<(String, Map<String, Value>, Value), String> {
    use aydp_proto::Message as M;
    let mut meta = Map::new();
    meta.insert("type".into(), json!(frame.base_type()));
    meta.insert("expedited".into(), json!(frame.is_expedited()));
    meta.insert("len".into(), json!(frame.as_bytes().len()));
    if let Some(t) = frame.timestamp() {
        meta.insert(
            "time".into(),
            json!({ "seconds": t.seconds, "subsec": t.subsec }),
        );
    }
    let message = frame.message().map_err(|e| {
        format!(
            "type {} message is malformed: {e} (data {})",
            frame.base_type(),
            hex(frame.data())
        )
    })?;
    let mut fields = match &message {
        M::DirectOutput(d) => json!({ "entries": to_json(&d.entries().collect::<Vec<_>>()) }),
        M::FixDetail(d) => json!({ "satellites": to_json(&d.satellites().collect::<Vec<_>>()) }),
        M::SystemControl(c) => {
            let (command, args) = variant(to_json(c));
            let mut m = Map::new();
            m.insert("command".into(), json!(command));
            if let Value::Object(args) = args {
                m.extend(args);
            }
            Value::Object(m)
        }
        other => variant(to_json(other)).1,
    };
    render::data_as_hex(&mut fields);
    let name = render::upper_snake(&variant(to_json(&message)).0);
    Ok((name, meta, fields))
}

/// What an AYDP event becomes once its frame is let go: the printed parts, and the frame's
/// length on the wire (0 for a failure).
type AydpOutcome = (
    std::result::Result<(String, Map<String, Value>, Value), String>,
    u64,
);

fn aydp_outcome(ev: aydp_proto::Result<aydp_proto::Frame<'_>>) -> AydpOutcome {
    match ev {
        Ok(frame) => (aydp_fields(&frame), frame.as_bytes().len() as u64),
        Err(aydp_proto::Error::Truncated) => (Err("input ends inside a message".into()), 0),
        Err(e) => (Err(e.to_string()), 0),
    }
}

impl AydpDecoder {
    /// Places one event in the input: `fed` bytes have been pushed, and the decoder has not
    /// yet examined its last `unscanned_bytes()`.
    fn place(&mut self, (result, len): AydpOutcome, fed: u64, out: &mut Vec<Event>) {
        let end = fed.saturating_sub(self.decoder.unscanned_bytes() as u64);
        match result {
            Ok((name, meta, fields)) => {
                out.push(Event::message(end.saturating_sub(len), name, meta, fields));
            }
            // A good frame whose data does not parse: at its own first byte.
            Err(e) if len > 0 => {
                self.malformed = self.malformed.wrapping_add(1);
                out.push(Event::error(end.saturating_sub(len), e));
            }
            // A failed candidate: its start byte was dropped just before the queued bytes.
            Err(e) => out.push(Event::error(end.saturating_sub(1), e)),
        }
    }
}

impl StreamDecoder for AydpDecoder {
    fn feed(&mut self, bytes: &[u8], offset: u64, out: &mut Vec<Event>) {
        for (i, &b) in bytes.iter().enumerate() {
            let fed = offset + i as u64 + 1;
            let mut event = self.decoder.push(b).map(aydp_outcome);
            while let Some(ev) = event {
                self.place(ev, fed, out);
                event = self.decoder.poll().map(aydp_outcome);
            }
        }
    }

    fn finish(&mut self, offset: u64, out: &mut Vec<Event>) {
        while let Some(ev) = self.decoder.flush_next().map(aydp_outcome) {
            if ev.1 == 0 && ev.0.as_ref().is_err_and(|e| e.starts_with("input ends")) {
                self.truncated = self.truncated.wrapping_add(1);
            }
            self.place(ev, offset, out);
        }
    }

    fn counters(&self) -> Value {
        let mut v = to_json(&self.decoder.stats());
        if let Value::Object(m) = &mut v {
            m.insert("malformed".into(), json!(self.malformed));
            m.insert("truncated".into(), json!(self.truncated));
        }
        v
    }
}

/// AOK: the PC decoder (for the device's bytes) or the device decoder (for the PC's bytes).
#[derive(Debug)]
pub enum AokDecoder {
    /// Reads what the device sends.
    FromDevice(aok_proto::PcDecoder),
    /// Reads what the PC sends.
    FromPc(aok_proto::DeviceDecoder),
}

impl AokDecoder {
    /// A decoder for bytes sent by `side`.
    pub fn new(side: Side) -> Self {
        match side {
            Side::Device => AokDecoder::FromDevice(aok_proto::PcDecoder::new(
                aok_proto::FirmwareVersion::LATEST,
            )),
            Side::Pc => AokDecoder::FromPc(aok_proto::DeviceDecoder::new()),
        }
    }

    fn stats(&self) -> aok_proto::DecoderStats {
        match self {
            AokDecoder::FromDevice(d) => *d.stats(),
            AokDecoder::FromPc(d) => *d.stats(),
        }
    }
}

/// Splits an AOK device message into its name and fields.
///
/// ```
/// use aok_proto::{DebugValue, Message};
/// let (name, fields) = protolink::decode::aok_message_fields(&Message::Debug(DebugValue { number: 86, value: -2 }));
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
/// let (name, fields) = protolink::decode::aok_command_fields(&aok_proto::Command::ReadParameter(12));
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
/// assert_eq!(protolink::decode::slot_name(WaypointSlot::from_wire(0).unwrap()), "1");
/// assert_eq!(protolink::decode::slot_name(WaypointSlot::FbcTarget), "fbc");
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
/// assert_eq!(protolink::decode::action_name(ActionWord::new(Action::SetFlySpeed, 250)), "set-fly-speed:250");
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
    fn buffered(&self) -> u64 {
        match self {
            AokDecoder::FromDevice(d) => d.buffered() as u64,
            AokDecoder::FromPc(d) => d.buffered() as u64,
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
            let before = self.stats();
            let first = out.len();
            lens.clear();
            match self {
                AokDecoder::FromDevice(d) => {
                    for m in d.push(b) {
                        let (name, fields) = aok_message_fields(&m);
                        let len = m.buffer_len(aok_proto::ReplyForm::Headed);
                        let mut meta = Map::new();
                        meta.insert("len".into(), json!(len));
                        out.push(Event::message(at, name, meta, fields));
                        lens.push(len as u64);
                    }
                }
                AokDecoder::FromPc(d) => {
                    for item in d.push(b) {
                        match item {
                            Ok(c) => {
                                let (name, fields) = aok_command_fields(&c);
                                let mut meta = Map::new();
                                meta.insert("len".into(), json!(c.buffer_len()));
                                out.push(Event::message(at, name, meta, fields));
                                lens.push(c.buffer_len() as u64);
                            }
                            Err(e) => {
                                out.push(Event::error(at, e.to_string()));
                                lens.push(0);
                            }
                        }
                    }
                }
            }
            let end = at + 1 - self.buffered();
            if let Some(events) = out.get_mut(first..) {
                place_backwards(events, &lens, end);
            }
            if let AokDecoder::FromDevice(_) = self {
                // The PC decoder only counts its failures: report them from the counters.
                let after = self.stats();
                for _ in before.checksum_errors..after.checksum_errors {
                    out.push(Event::error(at, aok_proto::Error::Checksum.to_string()));
                }
                for _ in before.invalid..after.invalid {
                    out.push(Event::error(at, "intact frame with an out-of-range field"));
                }
            }
        }
    }

    fn finish(&mut self, offset: u64, out: &mut Vec<Event>) {
        let at = offset.saturating_sub(1);
        let mut lens = Vec::new();
        loop {
            let before = self.stats();
            let first = out.len();
            lens.clear();
            match self {
                AokDecoder::FromDevice(d) => {
                    if d.buffered() == 0 {
                        break;
                    }
                    for m in d.idle() {
                        let (name, fields) = aok_message_fields(&m);
                        let len = m.buffer_len(aok_proto::ReplyForm::Headed);
                        let mut meta = Map::new();
                        meta.insert("len".into(), json!(len));
                        out.push(Event::message(at, name, meta, fields));
                        lens.push(len as u64);
                    }
                }
                AokDecoder::FromPc(d) => {
                    if d.buffered() == 0 {
                        break;
                    }
                    for item in d.idle() {
                        match item {
                            Ok(c) => {
                                let (name, fields) = aok_command_fields(&c);
                                let mut meta = Map::new();
                                meta.insert("len".into(), json!(c.buffer_len()));
                                out.push(Event::message(at, name, meta, fields));
                                lens.push(c.buffer_len() as u64);
                            }
                            Err(e) => {
                                out.push(Event::error(at, e.to_string()));
                                lens.push(0);
                            }
                        }
                    }
                }
            }
            let got = out.len() > first;
            let end = offset.saturating_sub(self.buffered());
            if let Some(events) = out.get_mut(first..) {
                place_backwards(events, &lens, end);
            }
            let after = self.stats();
            if after.abandoned > before.abandoned {
                out.push(Event::error(at, "input ends inside a frame"));
            }
            if !got && after == before {
                break;
            }
        }
    }

    fn counters(&self) -> Value {
        to_json(&self.stats())
    }
}

/// Builds the decoder the arguments ask for.
pub fn decoder_for(proto: Proto, profile: ProfileArg, side: Side) -> Box<dyn StreamDecoder> {
    match proto {
        Proto::Aeolus => Box::new(AeolusDecoder::new()),
        Proto::Aydp => Box::new(AydpDecoder::new(profile.into())),
        Proto::Aok => Box::new(AokDecoder::new(side)),
    }
}

/// The summary line printed at the end.
pub fn summary(bytes: u64, counters: &Value, json_out: bool) -> String {
    if json_out {
        json!({ "kind": "summary", "bytes": bytes, "counters": counters }).to_string()
    } else {
        format!("summary: bytes={bytes} {}", render::text(counters))
    }
}

/// Runs `protolink decode`.
///
/// # Errors
/// Opening or reading the endpoint, or writing the output.
pub fn run(args: &DecodeArgs) -> Result<()> {
    let mut link = args.from.open()?;
    let mut decoder = decoder_for(args.proto, args.profile, args.side);
    // Ctrl-C ends the input: the counters are still printed.
    crate::stop::install_ctrl_c();
    let deadline = Deadline::after(args.seconds);
    let mut out = Out::new();
    let offset = pump(&mut link, decoder.as_mut(), deadline, |events| {
        for e in events {
            let line = if args.json {
                e.to_json().to_string()
            } else {
                e.to_text()
            };
            out.line(&line)?;
        }
        out.flush()
    })?;
    out.line(&summary(offset, &decoder.counters(), args.json))?;
    out.flush()
}

/// Reads `link` until it ends or `deadline` passes, feeding `decoder` and handing every batch of
/// events to `emit`. Returns the number of bytes read.
///
/// # Errors
/// Reading the endpoint, or whatever `emit` returns.
pub fn pump(
    link: &mut Link,
    decoder: &mut dyn StreamDecoder,
    deadline: Deadline,
    mut emit: impl FnMut(&[Event]) -> Result<()>,
) -> Result<u64> {
    let mut buf = vec![0u8; 65_536];
    let mut offset = 0u64;
    let mut events = Vec::new();
    while !deadline.reached() {
        match link.read(&mut buf, deadline.left(Duration::from_millis(100)))? {
            Input::Data(n) => {
                decoder.feed(&buf[..n], offset, &mut events);
                offset += n as u64;
                if link.is_datagram() {
                    decoder.end_of_datagram(offset, &mut events);
                }
            }
            Input::Idle => continue,
            Input::End => break,
        }
        if !events.is_empty() {
            emit(&events)?;
            events.clear();
        }
    }
    decoder.finish(offset, &mut events);
    emit(&events)?;
    Ok(offset)
}
