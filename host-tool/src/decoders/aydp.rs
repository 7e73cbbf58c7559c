//! AYDP in `decode`: the rescanning decoder, each event placed by the bytes it has not
//! examined yet.

use aydp_proto::{Decode, Event as AydpEvent, Profile};
use serde_json::{Map, Value, json};

use super::{Event, StreamDecoder, error_kind};
use crate::render::{self, hex, to_json, variant};

/// Capacity of the AYDP decoder: the longest message accepted.
pub const AYDP_CAPACITY: usize = 16384;

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

/// A rendered AYDP message: its name, its meta data (type, expedited, len, time) and its fields.
pub type AydpRendered = (String, Map<String, Value>, Value);

/// An error's kind ([`error_kind`]) and its sentence.
pub type ErrorText = (String, String);

/// Splits a checked AYDP frame into its name, its meta data and its fields; a malformed typed
/// parse comes back as the error's kind ([`error_kind`]) and sentence.
///
/// ```
/// use aydp_proto::{Frame, Profile};
/// let f = Frame::new_checked(&[0xFF, 0x89, 0x08, 0, 0, 0, 0x02, 0x7C], Profile::Spec).unwrap();
/// let (name, meta, fields) = protolink::decoders::aydp_fields(&f).unwrap();
/// assert_eq!(name, "SYSTEM_CONTROL");
/// assert_eq!(meta["type"], 9);
/// assert_eq!(fields.to_string(), r#"{"command":"StoreConfiguration"}"#);
/// ```
///
/// # Errors
/// The typed parse's error, as its kind and a sentence.
pub fn aydp_fields(frame: &aydp_proto::Frame<'_>) -> std::result::Result<AydpRendered, ErrorText> {
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
        (
            error_kind(&e),
            format!(
                "type {} message is malformed: {e} (data {})",
                frame.base_type(),
                hex(frame.data())
            ),
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
type AydpOutcome = (std::result::Result<AydpRendered, ErrorText>, u64);

fn aydp_outcome(ev: aydp_proto::Result<aydp_proto::Frame<'_>>) -> AydpOutcome {
    match ev {
        Ok(frame) => (aydp_fields(&frame), frame.as_bytes().len() as u64),
        Err(e @ aydp_proto::Error::Truncated) => (
            Err((error_kind(&e), "input ends inside a message".into())),
            0,
        ),
        Err(e) => (Err((error_kind(&e), e.to_string())), 0),
    }
}

impl AydpDecoder {
    /// Places one event in the input: `fed` bytes have been pushed, and the decoder has not
    /// yet examined its last `held_bytes()`.
    fn place(&mut self, (result, len): AydpOutcome, fed: u64, out: &mut Vec<Event>) {
        let end = fed.saturating_sub(self.decoder.held_bytes() as u64);
        match result {
            Ok((name, meta, fields)) => {
                out.push(Event::message(end.saturating_sub(len), name, meta, fields));
            }
            // A good frame whose data does not parse: at its own first byte.
            Err((kind, e)) if len > 0 => {
                self.malformed = self.malformed.wrapping_add(1);
                out.push(Event::error(end.saturating_sub(len), kind, e));
            }
            // A failed candidate: its start byte was dropped just before the queued bytes.
            Err((kind, e)) => out.push(Event::error(end.saturating_sub(1), kind, e)),
        }
    }
}

impl StreamDecoder for AydpDecoder {
    fn feed(&mut self, bytes: &[u8], offset: u64, out: &mut Vec<Event>) {
        for (i, &b) in bytes.iter().enumerate() {
            let fed = offset + i as u64 + 1;
            // The pull form a byte at a time, then on nothing for what a rescan left queued:
            // each event is placed by the bytes fed so far and those still held.
            let mut input = core::slice::from_ref(&b);
            loop {
                let (used, event) = self.decoder.next_event(input);
                input = input.get(used..).unwrap_or(&[]);
                let Some(ev) = event.map(aydp_outcome) else {
                    break;
                };
                self.place(ev, fed, out);
            }
        }
    }

    fn finish(&mut self, offset: u64, out: &mut Vec<Event>) {
        loop {
            let event = match self.decoder.end() {
                None => break,
                Some(AydpEvent::Found(found)) => Ok(self.decoder.item(&[], found)),
                Some(AydpEvent::Error(e)) => Err(e),
                Some(AydpEvent::Truncated(_)) => Err(aydp_proto::Error::Truncated),
            };
            let ev = aydp_outcome(event);
            if ev.1 == 0 && ev.0.as_ref().is_err_and(|e| e.1.starts_with("input ends")) {
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
