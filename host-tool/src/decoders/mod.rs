//! The stream decoders of the four protocols behind one type ([`Decoder`]): bytes in, typed
//! items out, each [`Placed`] in the input (the offset of its first byte and its length on the
//! wire), and the decoder's counters. Every face takes the items: `decode` renders them as
//! [`Event`]s (a message with its fields as JSON, or an error with its kind), the tables of
//! [`crate::columns`] write them as columns of their own types, and the Python package keeps
//! them. The field renderers are shared with `aok`, the Wireshark generators' tests and the
//! Python package (`python/`).

use serde_json::{Map, Value, json};

mod aeolus;
mod aok;
mod aydp;
mod gdl90;
mod input;
mod item;
mod kept;

pub use aeolus::{AEOLUS_CAPACITY, AeolusDecoder, aeolus_fields, aeolus_meta, text_fields};
pub use aok::{
    AokDecoder, action_name, aok_command_fields, aok_command_name, aok_message_fields,
    aok_message_name, slot_name, waypoint_fields,
};
pub use aydp::{AYDP_CAPACITY, AydpDecoder, aydp_message_fields, aydp_meta, aydp_name};
pub use gdl90::{GDL90_CAPACITY, Gdl90Decoder, gdl90_fields};
pub use item::{Fault, Item, Placed};
pub use kept::Kept;

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
    pub(crate) fn message(
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

    pub(crate) fn error(
        offset: u64,
        len: u64,
        kind: impl Into<String>,
        error: impl Into<String>,
    ) -> Self {
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

/// The decoder of one of the four protocols: bytes in, each item [`Placed`] in the input.
/// `Send`, so that it can work on another thread (the Python package decodes with the GIL
/// released).
#[derive(Debug)]
pub enum Decoder {
    /// AEOLUS.
    Aeolus(AeolusDecoder),
    /// AYDP, in one profile.
    Aydp(AydpDecoder),
    /// AOK, of one side.
    Aok(AokDecoder),
    /// GDL90.
    Gdl90(Gdl90Decoder),
}

impl Decoder {
    /// The decoder for `proto`, as `decode --proto ... --profile ... --side ...` builds it (the
    /// profile counts only for AYDP, the side only for AOK).
    ///
    /// ```
    /// use protolink::decoders::Decoder;
    /// use protolink::proto::Proto;
    /// let d = Decoder::new(Proto::Gdl90, Default::default(), Default::default());
    /// assert!(matches!(d, Decoder::Gdl90(_)));
    /// ```
    pub fn new(proto: Proto, profile: ProfileArg, side: Side) -> Self {
        match proto {
            Proto::Aeolus => Decoder::Aeolus(AeolusDecoder::new()),
            Proto::Aydp => Decoder::Aydp(AydpDecoder::new(profile.into())),
            Proto::Aok => Decoder::Aok(AokDecoder::new(side)),
            Proto::Gdl90 => Decoder::Gdl90(Gdl90Decoder::default()),
        }
    }

    /// Feeds bytes that start at input offset `offset`, handing every item to `on_item`.
    ///
    /// ```
    /// use protolink::decoders::Decoder;
    /// use protolink::proto::Proto;
    /// let mut d = Decoder::new(Proto::Aydp, Default::default(), Default::default());
    /// let mut seen = Vec::new();
    /// d.feed(&[0xFF, 0x80, 0x07, 0x00, 0x00, 0x00, 0x78], 3, |p| seen.push((p.offset, p.len)));
    /// assert_eq!(seen, [(3, 7)]);
    /// ```
    pub fn feed(&mut self, bytes: &[u8], offset: u64, on_item: impl FnMut(Placed<'_>)) {
        match self {
            Decoder::Aeolus(d) => d.feed(bytes, offset, on_item),
            Decoder::Aydp(d) => d.feed(bytes, offset, on_item),
            Decoder::Aok(d) => d.feed(bytes, offset, on_item),
            Decoder::Gdl90(d) => d.feed(bytes, offset, on_item),
        }
    }

    /// A datagram ended: AEOLUS and GDL90 give up a frame in progress (a frame never spans
    /// two datagrams) and start afresh; AYDP and AOK, whose links are serial, go on.
    ///
    /// ```
    /// use protolink::decoders::Decoder;
    /// use protolink::proto::Proto;
    /// let mut d = Decoder::new(Proto::Aeolus, Default::default(), Default::default());
    /// d.feed(&[0x7E, 0x52], 0, |_| {});
    /// let mut n = 0;
    /// d.end_of_datagram(|_| n += 1);
    /// assert_eq!(n, 1);
    /// ```
    pub fn end_of_datagram(&mut self, on_item: impl FnMut(Placed<'_>)) {
        match self {
            Decoder::Aeolus(d) => d.end_of_datagram(on_item),
            Decoder::Gdl90(d) => d.end_of_datagram(on_item),
            Decoder::Aydp(_) | Decoder::Aok(_) => {}
        }
    }

    /// The input ended: what is held is given up (AYDP and AOK: then rescanned).
    ///
    /// ```
    /// use protolink::decoders::Decoder;
    /// use protolink::proto::Proto;
    /// let mut d = Decoder::new(Proto::Aeolus, Default::default(), Default::default());
    /// d.feed(&[0x7E, 0x52], 0, |_| {});
    /// let mut events = Vec::new();
    /// d.finish(|p| events.push(p.to_event().to_text()));
    /// assert_eq!(events, ["@0 error: input ends inside a frame"]);
    /// ```
    pub fn finish(&mut self, on_item: impl FnMut(Placed<'_>)) {
        match self {
            Decoder::Aeolus(d) => d.finish(on_item),
            Decoder::Aydp(d) => d.finish(on_item),
            Decoder::Aok(d) => d.finish(on_item),
            Decoder::Gdl90(d) => d.finish(on_item),
        }
    }

    /// The counters, as `decode` prints them in its summary.
    ///
    /// ```
    /// use protolink::decoders::Decoder;
    /// let d = Decoder::new(protolink::proto::Proto::Aeolus, Default::default(), Default::default());
    /// assert_eq!(d.counters()["malformed"], 0);
    /// ```
    pub fn counters(&self) -> Value {
        match self {
            Decoder::Aeolus(d) => d.counters(),
            Decoder::Aydp(d) => d.counters(),
            Decoder::Aok(d) => d.counters(),
            Decoder::Gdl90(d) => d.counters(),
        }
    }

    /// Feeds bytes as [`Decoder::feed`] does (`datagram`: they are one whole datagram, then
    /// ended), the items rendered as `decode` prints them.
    ///
    /// ```
    /// use protolink::decoders::Decoder;
    /// let mut d = Decoder::new(protolink::proto::Proto::Aeolus, Default::default(), Default::default());
    /// let events = d.events(&[0x7E, 0x52, b'h', b'i', 0, 0x73, 0xEC, 0x7E], 0, false);
    /// assert_eq!(events[0].to_text(), "@0 TOAST id=82 len=8 crc=ok text=hi");
    /// ```
    pub fn events(&mut self, bytes: &[u8], offset: u64, datagram: bool) -> Vec<Event> {
        let mut events = Vec::new();
        self.feed(bytes, offset, |p| events.push(p.to_event()));
        if datagram {
            self.end_of_datagram(|p| events.push(p.to_event()));
        }
        events
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
