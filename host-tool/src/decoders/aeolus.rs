//! AEOLUS in `decode`: the decoder, each frame placed at its opening flag, datagram
//! boundaries honoured.

use serde_json::{Map, Value, json};

use super::{Event, StreamDecoder};
use crate::render::{self, hex, to_json, variant};

/// Capacity of the AEOLUS decoder: every message, long LOG messages included.
pub const AEOLUS_CAPACITY: usize = 8192;

/// AEOLUS: the byte-at-a-time decoder, with datagram boundaries honoured.
#[derive(Debug)]
pub struct AeolusDecoder {
    decoder: Box<aeolus_proto::Decoder<AEOLUS_CAPACITY>>,
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
            decoder: Box::new(aeolus_proto::Decoder::new()),
            opened_at: 0,
            malformed: 0,
            truncated: 0,
        }
    }

    /// The decoder's counters.
    pub fn stats(&self) -> aeolus_proto::Stats {
        self.decoder.stats()
    }
}

/// Splits an AEOLUS message into its name and fields (texts as strings, raw data as hex).
///
/// ```
/// use aeolus_proto::message::{Message, Text};
/// let (name, fields) = protolink::decoders::aeolus_fields(&Message::Toast(Text::new("hi").unwrap()));
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
/// let v = protolink::decoders::text_fields(b"\x1b[2J");
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
            let Some(event) = self.decoder.push(b) else {
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
        if self.decoder.held_bytes() > 0 {
            self.truncated = self.truncated.wrapping_add(1);
            out.push(Event::error(
                self.opened_at,
                aeolus_proto::Error::Truncated.to_string(),
            ));
        }
        self.opened_at = offset;
        // A frame never spans two datagrams (DECISIONS.md A9): start afresh.
        self.decoder.reset();
    }

    fn finish(&mut self, offset: u64, out: &mut Vec<Event>) {
        if self.decoder.held_bytes() > 0 {
            self.truncated = self.truncated.wrapping_add(1);
            out.push(Event::error(
                self.opened_at.min(offset.saturating_sub(1)),
                "input ends inside a frame".to_string(),
            ));
            self.decoder.reset();
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
