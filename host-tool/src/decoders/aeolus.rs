//! AEOLUS in `decode`: the decoder through the contract's adapter, each frame placed at its
//! opening flag, datagram boundaries honoured.

use serde_json::{Map, Value, json};

use super::input::Input;
use super::{Fault, Item, Placed};
use crate::render::{self, hex, to_json, variant};

/// Capacity of the AEOLUS decoder: every message, long LOG messages included.
pub const AEOLUS_CAPACITY: usize = 8192;

/// AEOLUS: the byte-at-a-time decoder, with datagram boundaries honoured.
#[derive(Debug)]
pub struct AeolusDecoder {
    input: Input<aeolus_proto::Decoder<AEOLUS_CAPACITY>>,
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
            input: Input::new(aeolus_proto::Decoder::new()),
            malformed: 0,
            truncated: 0,
        }
    }

    /// Feeds bytes that start at input offset `offset`, handing every item to `on_item`
    /// placed at its frame's opening flag (an error: at the flag that opened the frame it
    /// drops).
    ///
    /// ```
    /// use protolink::decoders::{AeolusDecoder, Item};
    /// let mut d = AeolusDecoder::new();
    /// let mut seen = Vec::new();
    /// d.feed(&[0x00, 0x7E, 0x52, b'h', b'i', 0, 0x73, 0xEC, 0x7E], 10, |p| {
    ///     if let Item::Aeolus { message, .. } = p.item { seen.push((p.offset, message.name(), p.len)) }
    /// });
    /// assert_eq!(seen, [(11, "TOAST", 8)]);
    /// ```
    pub fn feed(&mut self, bytes: &[u8], offset: u64, mut on_item: impl FnMut(Placed<'_>)) {
        let malformed = &mut self.malformed;
        self.input.feed(bytes, offset, |at, len, event| {
            let item = match event {
                Ok(frame) => match frame.message() {
                    Ok(message) => Item::Aeolus { frame, message },
                    Err(error) => {
                        *malformed = malformed.wrapping_add(1);
                        Item::Error(Fault::AeolusMalformed { frame, error })
                    }
                },
                Err(error) => Item::Error(Fault::Aeolus(error)),
            };
            on_item(Placed {
                offset: at,
                len,
                item,
            });
        });
    }

    /// A datagram ended: a frame in progress is given up (`Truncated`), and the next byte
    /// starts afresh (a frame never spans two datagrams, DECISIONS.md A9).
    ///
    /// ```
    /// use protolink::decoders::{AeolusDecoder, Item};
    /// let mut d = AeolusDecoder::new();
    /// d.feed(&[0x7E, 0x52, b'h'], 0, |_| {});
    /// let mut seen = Vec::new();
    /// d.end_of_datagram(|p| seen.push((p.offset, p.len, matches!(p.item, Item::Error(_)))));
    /// assert_eq!(seen, [(0, 3, true)]);
    /// ```
    pub fn end_of_datagram(&mut self, mut on_item: impl FnMut(Placed<'_>)) {
        let truncated = &mut self.truncated;
        self.input.finish(|at, len, event| {
            if let Err(error) = event {
                *truncated = truncated.wrapping_add(1);
                on_item(Placed {
                    offset: at,
                    len,
                    item: Item::Error(Fault::Aeolus(error)),
                });
            }
        });
        // The datagram's closing flag opens no frame for the next one.
        self.input.decoder_mut().reset();
    }

    /// The input ended: a frame in progress is given up as "input ends inside a frame".
    ///
    /// ```
    /// use protolink::decoders::AeolusDecoder;
    /// let mut d = AeolusDecoder::new();
    /// d.feed(&[0x7E, 0x52, b'h'], 0, |_| {});
    /// let mut seen = Vec::new();
    /// d.finish(|p| seen.push(p.to_event().to_text()));
    /// assert_eq!(seen, ["@0 error: input ends inside a frame"]);
    /// ```
    pub fn finish(&mut self, on_item: impl FnMut(Placed<'_>)) {
        self.input
            .cut_short(CUT_SHORT, &mut self.truncated, on_item);
    }

    /// The counters, as `decode` prints them in its summary: the crate's `Stats` plus
    /// `malformed` and `truncated`.
    ///
    /// ```
    /// let c = protolink::decoders::AeolusDecoder::new().counters();
    /// assert_eq!(c["malformed"], 0);
    /// ```
    pub fn counters(&self) -> Value {
        let mut v = to_json(&self.input.decoder().stats());
        if let Value::Object(m) = &mut v {
            m.insert("malformed".into(), json!(self.malformed));
            m.insert("truncated".into(), json!(self.truncated));
        }
        v
    }
}

/// The sentence of a frame the end of the input cut short.
pub(crate) const CUT_SHORT: &str = "input ends inside a frame";

/// The facts `decode` prints about an AEOLUS frame before its fields: `id`, `len` (on the
/// wire, both flags included) and `crc` (`ok`, or `none` for a frame sent without one).
///
/// ```
/// let m = protolink::decoders::aeolus_meta(62, 37, true);
/// assert_eq!(serde_json::Value::Object(m).to_string(), r#"{"id":62,"len":37,"crc":"ok"}"#);
/// ```
pub fn aeolus_meta(id: u8, len: u64, has_crc: bool) -> Map<String, Value> {
    let mut meta = Map::new();
    meta.insert("id".into(), json!(id));
    meta.insert("len".into(), json!(len));
    meta.insert("crc".into(), json!(if has_crc { "ok" } else { "none" }));
    meta
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
