//! GDL90 in `decode`: the `gdl90-proto` decoder through the contract's adapter, each frame
//! placed at its opening flag, datagram boundaries honoured (EFB apps receive GDL90 on UDP
//! port 4000).

use serde_json::{Map, Value, json};

use super::input::Input;
use super::{Event, StreamDecoder, error_kind};
use crate::render::{to_json, variant};

/// Capacity of the GDL90 decoder: every ICD message, the UAT uplink included.
pub const GDL90_CAPACITY: usize = gdl90_proto::MAX_FRAME;

/// GDL90: the byte-at-a-time decoder (no "CRC 00 00 means none" rule, unlike AEOLUS).
#[derive(Debug)]
pub struct Gdl90Decoder {
    input: Input<gdl90_proto::Decoder<GDL90_CAPACITY>>,
    truncated: u32,
}

impl Default for Gdl90Decoder {
    fn default() -> Self {
        Gdl90Decoder {
            input: Input::new(gdl90_proto::Decoder::new()),
            truncated: 0,
        }
    }
}

impl Gdl90Decoder {
    /// The end of a stream (`why`: of the datagram, of the input): a frame in progress is
    /// given up as `truncated`.
    fn give_up(&mut self, why: &str, out: &mut Vec<Event>) {
        let truncated = &mut self.truncated;
        self.input.finish(|at, len, event| {
            if let Err(e) = event {
                *truncated = truncated.wrapping_add(1);
                out.push(Event::error(at, len, error_kind(&e), why));
            }
        });
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
        self.input
            .feed(bytes, offset, |at, len, event| match event {
                Ok(m) => {
                    let (name, fields) = gdl90_fields(&m);
                    let mut meta = Map::new();
                    meta.insert("id".into(), json!(m.id()));
                    meta.insert("len".into(), json!(len));
                    out.push(Event::message(at, name, meta, fields));
                }
                Err(e) => out.push(Event::error(at, len, error_kind(&e), e.to_string())),
            });
    }

    fn end_of_datagram(&mut self, _offset: u64, out: &mut Vec<Event>) {
        self.give_up("datagram ends inside a frame", out);
        // The datagram's closing flag opens no frame for the next one.
        self.input.decoder_mut().reset();
    }

    fn finish(&mut self, _offset: u64, out: &mut Vec<Event>) {
        self.give_up("input ends inside a frame", out);
    }

    fn counters(&self) -> Value {
        let mut v = to_json(&self.input.decoder().stats());
        if let Value::Object(m) = &mut v {
            m.insert("truncated".into(), json!(self.truncated));
        }
        v
    }
}
