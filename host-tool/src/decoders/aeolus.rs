//! AEOLUS in `decode`: the decoder through the contract's adapter, each frame placed at its
//! opening flag, datagram boundaries honoured.
//!
//! The decoder reports [`AeolusItem`]s first (a frame placed in the input, its typed message
//! parsed, or an error), and [`StreamDecoder`] renders them as [`Event`]s: the Python package
//! keeps the items' frames and renders the same fields only when they are read.

use serde_json::{Map, Value, json};

use super::input::Input;
use super::{Event, EventSink, StreamDecoder, error_kind};
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

    /// Feeds bytes that start at input offset `offset`, handing every item to `on_item` with
    /// the offset of its frame's opening flag (an error: of the flag that opened the frame it
    /// drops), the place the decoder gives each event.
    ///
    /// ```
    /// use protolink::decoders::{AeolusDecoder, AeolusItem};
    /// let mut d = AeolusDecoder::new();
    /// let mut seen = Vec::new();
    /// d.feed_items(&[0x00, 0x7E, 0x52, b'h', b'i', 0, 0x73, 0xEC, 0x7E], 10, |at, item| {
    ///     if let AeolusItem::Message { message, len, .. } = item { seen.push((at, message.name(), len)) }
    /// });
    /// assert_eq!(seen, [(11, "TOAST", 8)]);
    /// ```
    pub fn feed_items(
        &mut self,
        bytes: &[u8],
        offset: u64,
        mut on_item: impl FnMut(u64, AeolusItem<'_>),
    ) {
        let malformed = &mut self.malformed;
        self.input.feed(bytes, offset, |at, len, event| {
            let item = match event {
                Ok(frame) => match frame.message() {
                    Ok(message) => AeolusItem::Message {
                        frame,
                        message,
                        len,
                    },
                    Err(error) => {
                        *malformed = malformed.wrapping_add(1);
                        AeolusItem::Malformed { frame, error, len }
                    }
                },
                Err(error) => AeolusItem::Error { error, len },
            };
            on_item(at, item);
        });
    }

    /// A datagram ended: a frame in progress is given up as [`AeolusItem::Error`]
    /// (`Truncated`), and the next byte starts afresh (a frame never spans two datagrams,
    /// DECISIONS.md A9).
    pub fn end_of_datagram_items(&mut self, mut on_item: impl FnMut(u64, AeolusItem<'_>)) {
        let truncated = &mut self.truncated;
        self.input.finish(|at, len, event| {
            if let Err(error) = event {
                *truncated = truncated.wrapping_add(1);
                on_item(at, AeolusItem::Error { error, len });
            }
        });
        // The datagram's closing flag opens no frame for the next one.
        self.input.decoder_mut().reset();
    }

    /// The input ended: a frame in progress is given up as [`AeolusItem::InputEnded`].
    pub fn finish_items(&mut self, mut on_item: impl FnMut(u64, AeolusItem<'_>)) {
        let truncated = &mut self.truncated;
        self.input.finish(|at, len, event| {
            if event.is_err() {
                *truncated = truncated.wrapping_add(1);
                on_item(at, AeolusItem::InputEnded { len });
            }
        });
    }
}

/// One AEOLUS event, placed in the input but not yet rendered.
#[derive(Debug, Clone, PartialEq)]
pub enum AeolusItem<'a> {
    /// A frame (good CRC, or none) whose data parses as its message.
    Message {
        /// The frame, unescaped.
        frame: aeolus_proto::Frame<'a>,
        /// Its typed message.
        message: aeolus_proto::message::Message<'a>,
        /// Its length on the wire, both flags included.
        len: u64,
    },
    /// A frame whose data does not parse as its ID's message (counted as `malformed`).
    Malformed {
        /// The frame, unescaped.
        frame: aeolus_proto::Frame<'a>,
        /// Why it does not parse.
        error: aeolus_proto::Error,
        /// Its length on the wire, both flags included.
        len: u64,
    },
    /// An error in the stream (the frame in progress, if any, was dropped).
    Error {
        /// What went wrong.
        error: aeolus_proto::Error,
        /// The length on the wire of the bytes it condemns, from the frame's opening flag.
        len: u64,
    },
    /// The input ended inside a frame (counted as `truncated`).
    InputEnded {
        /// The frame's bytes on the wire, from its opening flag to the input's end.
        len: u64,
    },
}

impl AeolusItem<'_> {
    /// The item as `decode` prints it.
    pub fn to_event(&self, offset: u64) -> Event {
        match self {
            AeolusItem::Message {
                frame,
                message,
                len,
            } => {
                let (name, fields) = aeolus_fields(message);
                Event::message(
                    offset,
                    name,
                    aeolus_meta(frame.id(), *len, frame.has_crc()),
                    fields,
                )
            }
            AeolusItem::Malformed { len, .. }
            | AeolusItem::Error { len, .. }
            | AeolusItem::InputEnded { len } => {
                let (kind, error) = self.error().unwrap_or_default();
                Event::error(offset, *len, kind, error)
            }
        }
    }

    /// An error item's kind ([`error_kind`]) and sentence; `None` for a message.
    pub fn error(&self) -> Option<(String, String)> {
        match self {
            AeolusItem::Message { .. } => None,
            AeolusItem::Malformed { frame, error, .. } => Some((
                error_kind(error),
                format!("{error} (frame {})", hex(frame.raw())),
            )),
            AeolusItem::Error { error, .. } => Some((error_kind(error), error.to_string())),
            AeolusItem::InputEnded { .. } => Some((
                error_kind(&aeolus_proto::Error::Truncated),
                "input ends inside a frame".into(),
            )),
        }
    }
}

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

impl StreamDecoder for AeolusDecoder {
    fn feed(&mut self, bytes: &[u8], offset: u64, out: &mut Vec<Event>) {
        self.feed_items(bytes, offset, |at, item| out.push(item.to_event(at)));
    }

    fn end_of_datagram(&mut self, _offset: u64, out: &mut Vec<Event>) {
        self.end_of_datagram_items(|at, item| out.push(item.to_event(at)));
    }

    fn finish(&mut self, _offset: u64, out: &mut Vec<Event>) {
        self.finish_items(|at, item| out.push(item.to_event(at)));
    }

    fn feed_to(&mut self, bytes: &[u8], offset: u64, datagram: bool, sink: &mut dyn EventSink) {
        self.feed_items(bytes, offset, |at, item| sink.aeolus(at, &item));
        if datagram {
            self.end_of_datagram_items(|at, item| sink.aeolus(at, &item));
        }
    }

    fn finish_to(&mut self, _offset: u64, sink: &mut dyn EventSink) {
        self.finish_items(|at, item| sink.aeolus(at, &item));
    }

    fn counters(&self) -> Value {
        let mut v = to_json(&self.input.decoder().stats());
        if let Value::Object(m) = &mut v {
            m.insert("malformed".into(), json!(self.malformed));
            m.insert("truncated".into(), json!(self.truncated));
        }
        v
    }
}
