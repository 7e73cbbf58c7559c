//! GDL90 in `decode`: the `gdl90-proto` decoder, each frame placed at its opening flag,
//! datagram boundaries honoured (EFB apps receive GDL90 on UDP port 4000).

use gdl90_proto::Decode;
use serde_json::{Map, Value, json};

use super::{Event, StreamDecoder, error_kind};
use crate::render::{to_json, variant};

/// Capacity of the GDL90 decoder: every ICD message, the UAT uplink included.
pub const GDL90_CAPACITY: usize = gdl90_proto::MAX_FRAME;

/// GDL90: the byte-at-a-time decoder (no "CRC 00 00 means none" rule, unlike AEOLUS).
#[derive(Debug)]
pub struct Gdl90Decoder {
    decoder: Box<gdl90_proto::Decoder<GDL90_CAPACITY>>,
    opened_at: u64,
    truncated: u32,
}

impl Default for Gdl90Decoder {
    fn default() -> Self {
        Gdl90Decoder {
            decoder: Box::new(gdl90_proto::Decoder::new()),
            opened_at: 0,
            truncated: 0,
        }
    }
}

/// A GDL90 message's name and fields.
///
/// ```
/// use gdl90_proto::message::{Heartbeat, Message};
/// let (name, fields) = protolink::decoders::gdl90_fields(&Message::Heartbeat(Heartbeat::default()));
/// assert_eq!(name, "HEARTBEAT");
/// assert_eq!(fields["utc_ok"], false);
/// ```
pub fn gdl90_fields(message: &gdl90_proto::message::Message<'_>) -> (String, Value) {
    let (_, fields) = variant(to_json(message));
    (message.name().to_owned(), fields)
}

impl StreamDecoder for Gdl90Decoder {
    fn feed(&mut self, bytes: &[u8], offset: u64, out: &mut Vec<Event>) {
        for (i, &b) in bytes.iter().enumerate() {
            let at = offset + i as u64;
            let opened = self.opened_at;
            if b == gdl90_proto::FLAG {
                self.opened_at = at;
            }
            self.decoder.feed(&[b], |event| match event {
                Ok(m) => {
                    let (name, fields) = gdl90_fields(&m);
                    let mut meta = Map::new();
                    meta.insert("id".into(), json!(m.id()));
                    meta.insert("len".into(), json!(at + 1 - opened));
                    out.push(Event::message(opened, name, meta, fields));
                }
                Err(e) => out.push(Event::error(opened, error_kind(&e), e.to_string())),
            });
        }
    }

    fn end_of_datagram(&mut self, offset: u64, out: &mut Vec<Event>) {
        if self.decoder.held_bytes() > 0 {
            self.truncated = self.truncated.wrapping_add(1);
            out.push(Event::error(
                self.opened_at,
                error_kind(&gdl90_proto::Error::Truncated),
                "datagram ends inside a frame",
            ));
        }
        self.decoder.reset();
        self.opened_at = offset;
    }

    fn finish(&mut self, offset: u64, out: &mut Vec<Event>) {
        if self.decoder.held_bytes() > 0 {
            self.truncated = self.truncated.wrapping_add(1);
            out.push(Event::error(
                self.opened_at.min(offset.saturating_sub(1)),
                error_kind(&gdl90_proto::Error::Truncated),
                "input ends inside a frame",
            ));
            self.decoder.reset();
        }
    }

    fn counters(&self) -> Value {
        let mut v = to_json(&self.decoder.stats());
        if let Value::Object(m) = &mut v {
            m.insert("truncated".into(), json!(self.truncated));
        }
        v
    }
}
