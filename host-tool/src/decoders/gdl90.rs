//! GDL90 in `decode`: the `gdl90-proto` decoder through the contract's adapter, each frame
//! placed at its opening flag, datagram boundaries honoured (EFB apps receive GDL90 on UDP
//! port 4000).

use serde_json::{Value, json};

use super::aeolus::CUT_SHORT;
use super::input::Input;
use super::{Fault, Item, Placed};
use crate::render::{self, to_json, variant};

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

/// A GDL90 message's name and fields (an unknown message's `data` as hex).
///
/// ```
/// use gdl90_proto::message::{Heartbeat, Message};
/// let (name, fields) = protolink::decoders::gdl90_fields(&Message::Heartbeat(Heartbeat::default()));
/// assert_eq!(name, "HEARTBEAT");
/// assert_eq!(fields["utc_ok"], false);
/// ```
pub fn gdl90_fields(message: &gdl90_proto::message::Message<'_>) -> (String, Value) {
    let (_, mut fields) = variant(to_json(message));
    render::data_as_hex(&mut fields);
    (message.name().to_owned(), fields)
}

impl Gdl90Decoder {
    /// Feeds bytes that start at input offset `offset`, handing every item to `on_item`
    /// placed at its frame's opening flag.
    ///
    /// ```
    /// use protolink::decoders::{Gdl90Decoder, Item};
    /// let mut d = Gdl90Decoder::default();
    /// let mut frame = [0u8; 32];
    /// let n = gdl90_proto::encode_frame(0x00, &[0x81, 0, 0, 0, 0, 0], &mut frame).unwrap();
    /// let mut seen = Vec::new();
    /// d.feed(&frame[..n], 7, |p| seen.push((p.offset, p.len, matches!(p.item, Item::Gdl90(_)))));
    /// assert_eq!(seen, [(7, n as u64, true)]);
    /// ```
    pub fn feed(&mut self, bytes: &[u8], offset: u64, mut on_item: impl FnMut(Placed<'_>)) {
        self.input.feed(bytes, offset, |at, len, event| {
            let item = match event {
                Ok(m) => Item::Gdl90(m),
                Err(e) => Item::Error(Fault::Gdl90(e)),
            };
            on_item(Placed {
                offset: at,
                len,
                item,
            });
        });
    }

    /// A datagram ended: a frame in progress is given up as "datagram ends inside a frame",
    /// and the next byte starts afresh.
    ///
    /// ```
    /// use protolink::decoders::Gdl90Decoder;
    /// let mut d = Gdl90Decoder::default();
    /// d.feed(&[0x7E, 0x00, 0x81], 0, |_| {});
    /// let mut seen = Vec::new();
    /// d.end_of_datagram(|p| seen.push(p.to_event().to_text()));
    /// assert_eq!(seen, ["@0 error: datagram ends inside a frame"]);
    /// ```
    pub fn end_of_datagram(&mut self, on_item: impl FnMut(Placed<'_>)) {
        self.input
            .cut_short("datagram ends inside a frame", &mut self.truncated, on_item);
        // The datagram's closing flag opens no frame for the next one.
        self.input.decoder_mut().reset();
    }

    /// The input ended: a frame in progress is given up as "input ends inside a frame".
    ///
    /// ```
    /// let mut d = protolink::decoders::Gdl90Decoder::default();
    /// d.feed(&[0x7E, 0x00, 0x81], 0, |_| {});
    /// let mut n = 0;
    /// d.finish(|_| n += 1);
    /// assert_eq!((n, d.counters()["truncated"].as_u64()), (1, Some(1)));
    /// ```
    pub fn finish(&mut self, on_item: impl FnMut(Placed<'_>)) {
        self.input
            .cut_short(CUT_SHORT, &mut self.truncated, on_item);
    }

    /// The counters, as `decode` prints them in its summary: the crate's `Stats` plus
    /// `truncated`.
    ///
    /// ```
    /// assert_eq!(protolink::decoders::Gdl90Decoder::default().counters()["truncated"], 0);
    /// ```
    pub fn counters(&self) -> Value {
        let mut v = to_json(&self.input.decoder().stats());
        if let Value::Object(m) = &mut v {
            m.insert("truncated".into(), json!(self.truncated));
        }
        v
    }
}
