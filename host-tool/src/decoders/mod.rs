//! The stream decoders of the four protocols behind one trait ([`StreamDecoder`]): bytes in,
//! [`Event`]s out (a message with its fields as JSON, or an error with its kind, at its input
//! offset), and the decoder's counters. `decode` prints them; the field renderers are shared
//! with `aok`, the Wireshark generators' tests and the Python package (`python/`), which also
//! builds on the AEOLUS decoder's placed events ([`AeolusItem`]) before they are rendered.

use serde_json::{Map, Value, json};

mod aeolus;
mod aok;
mod aydp;
mod gdl90;
mod input;

pub use aeolus::{
    AEOLUS_CAPACITY, AeolusDecoder, AeolusItem, aeolus_fields, aeolus_meta, text_fields,
};
pub use aok::{
    AokDecoder, action_name, aok_command_fields, aok_message_fields, slot_name, waypoint_fields,
};
pub use aydp::{AYDP_CAPACITY, AydpDecoder, AydpRendered, ErrorText, aydp_fields};
pub use gdl90::{GDL90_CAPACITY, Gdl90Decoder, gdl90_fields};

use crate::proto::{ProfileArg, Proto, Side};
use crate::render;

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
        /// What went wrong, as a short name: the protocol crate's error variant in snake case
        /// (`checksum_mismatch`, `invalid_escape`, `truncated`, ...; see [`error_kind`]).
        kind: String,
        /// One sentence.
        error: String,
        /// The length on the wire of the bytes it condemns (from the event's offset).
        len: u64,
    },
}

/// The kind of a protocol crate's error: its variant's name in snake case.
pub(crate) fn error_kind<E: serde::Serialize>(error: &E) -> String {
    render::upper_snake(&render::variant(render::to_json(error)).0).to_lowercase()
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

    fn error(offset: u64, len: u64, kind: impl Into<String>, error: impl Into<String>) -> Self {
        Event {
            offset,
            body: Body::Error {
                kind: kind.into(),
                error: error.into(),
                len,
            },
        }
    }

    /// The event as one JSON object.
    pub(crate) fn to_json(&self) -> Value {
        let mut m = Map::new();
        m.insert("offset".into(), json!(self.offset));
        match &self.body {
            Body::Message { name, meta, fields } => {
                m.insert("kind".into(), json!("message"));
                m.insert("name".into(), json!(name));
                m.extend(meta.clone());
                m.insert("fields".into(), fields.clone());
            }
            Body::Error { error, len, .. } => {
                m.insert("kind".into(), json!("error"));
                m.insert("len".into(), json!(len));
                m.insert("error".into(), json!(error));
            }
        }
        Value::Object(m)
    }

    /// The event as one readable line.
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
            Body::Error { error, .. } => format!("@{} error: {error}", self.offset),
        }
    }
}

/// A stream decoder for one protocol, reporting [`Event`]s. `Send`, so that a decoder can work
/// on another thread (the Python package decodes with the GIL released).
pub trait StreamDecoder: Send {
    /// Feeds bytes that start at input offset `offset`.
    fn feed(&mut self, bytes: &[u8], offset: u64, out: &mut Vec<Event>);
    /// A datagram ended at `offset` (the next byte starts a new one).
    fn end_of_datagram(&mut self, _offset: u64, _out: &mut Vec<Event>) {}
    /// The input ended at `offset` (its length).
    fn finish(&mut self, _offset: u64, _out: &mut Vec<Event>) {}
    /// The counters, as a JSON object.
    fn counters(&self) -> Value;
    /// Feeds bytes that start at input offset `offset` (`datagram`: they are one whole
    /// datagram), each event handed to `sink` as it comes. AEOLUS hands its typed messages over
    /// unrendered ([`EventSink::aeolus`]).
    fn feed_to(&mut self, bytes: &[u8], offset: u64, datagram: bool, sink: &mut dyn EventSink) {
        let mut events = Vec::new();
        self.feed(bytes, offset, &mut events);
        if datagram {
            self.end_of_datagram(offset + bytes.len() as u64, &mut events);
        }
        for e in &events {
            sink.event(e);
        }
    }
    /// The input ended at `offset`: what is held is given up as [`StreamDecoder::finish`]
    /// does, into `sink`.
    fn finish_to(&mut self, offset: u64, sink: &mut dyn EventSink) {
        let mut events = Vec::new();
        self.finish(offset, &mut events);
        for e in &events {
            sink.event(e);
        }
    }
}

/// Where a decoder's events go when they are not collected (the tables of
/// [`crate::columns`]): rendered events, and AEOLUS's items before they are rendered.
pub trait EventSink {
    /// An event, rendered.
    fn event(&mut self, event: &Event);
    /// An AEOLUS item placed at `offset`, not rendered.
    fn aeolus(&mut self, offset: u64, item: &AeolusItem<'_>);
}

/// Builds the decoder the arguments ask for.
pub fn decoder_for(proto: Proto, profile: ProfileArg, side: Side) -> Box<dyn StreamDecoder> {
    match proto {
        Proto::Aeolus => Box::new(AeolusDecoder::new()),
        Proto::Aydp => Box::new(AydpDecoder::new(profile.into())),
        Proto::Aok => Box::new(AokDecoder::new(side)),
        Proto::Gdl90 => Box::new(Gdl90Decoder::default()),
    }
}

/// The examples of this module's items, as tests (the items are crate-private, so rustdoc
/// does not run them).
#[cfg(test)]
#[allow(unused_imports, clippy::unnecessary_wraps)]
mod examples {
    use super::*;

    #[test]
    fn error_kind_example() -> Result<(), Box<dyn std::error::Error>> {
        assert_eq!(
            error_kind(&aeolus_proto::Error::InvalidEscape),
            "invalid_escape"
        );
        assert_eq!(error_kind(&aydp_proto::Error::BadLength(3)), "bad_length");
        assert_eq!(
            error_kind(&aok_proto::Error::ChecksumMismatch {
                id: 0x73,
                computed: 1,
                received: 2
            }),
            "checksum_mismatch"
        );
        Ok(())
    }

    #[test]
    fn to_json_example() -> Result<(), Box<dyn std::error::Error>> {
        let e = Event {
            offset: 7,
            body: Body::Error {
                kind: "checksum_mismatch".into(),
                error: "checksum mismatch".into(),
                len: 11,
            },
        };
        assert_eq!(
            e.to_json().to_string(),
            r#"{"offset":7,"kind":"error","len":11,"error":"checksum mismatch"}"#
        );
        Ok(())
    }

    #[test]
    fn to_text_example() -> Result<(), Box<dyn std::error::Error>> {
        let e = Event {
            offset: 7,
            body: Body::Error {
                kind: "checksum_mismatch".into(),
                error: "checksum mismatch".into(),
                len: 11,
            },
        };
        assert_eq!(e.to_text(), "@7 error: checksum mismatch");
        Ok(())
    }
}
