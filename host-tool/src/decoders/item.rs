//! [`Placed`]: what a decoder of any of the four protocols reports, typed, with its place in
//! the input. Every face takes these: `decode` renders them ([`Placed::to_event`]), the
//! tables write them as columns of their own types, and the Python package keeps them.

use super::{
    Event, aeolus_fields, aeolus_meta, aok_command_fields, aok_message_fields, error_kind,
};
use super::{aydp_message_fields, aydp_meta, gdl90_fields};
use crate::render::hex;

/// An item and its place in the input: the offset of its first byte and its length on the
/// wire (an error's: of the bytes it condemns).
#[derive(Debug, Clone, PartialEq)]
pub struct Placed<'a> {
    /// Input offset of its first byte.
    pub offset: u64,
    /// Its length on the wire.
    pub len: u64,
    /// What it is.
    pub item: Item<'a>,
}

/// A typed message of one of the four protocols, or an error.
#[derive(Debug, Clone, PartialEq)]
pub enum Item<'a> {
    /// An AEOLUS frame (good CRC, or none) and its message.
    Aeolus {
        /// The frame, unescaped.
        frame: aeolus_proto::Frame<'a>,
        /// Its typed message.
        message: aeolus_proto::message::Message<'a>,
    },
    /// An AYDP frame and its message.
    Aydp {
        /// The checked frame.
        frame: aydp_proto::Frame<'a>,
        /// Its typed message.
        message: aydp_proto::Message<'a>,
    },
    /// What an AOK device sends.
    AokMessage(aok_proto::Message),
    /// What an AOK PC sends.
    AokCommand(aok_proto::Command),
    /// A GDL90 message.
    Gdl90(gdl90_proto::message::Message<'a>),
    /// An error in the stream.
    Error(Fault<'a>),
}

/// An error in a stream, of the protocol crate that found it.
#[derive(Debug, Clone, PartialEq)]
pub enum Fault<'a> {
    /// An AEOLUS framing or CRC error.
    Aeolus(aeolus_proto::Error),
    /// An AEOLUS frame whose data does not parse as its ID's message (counted as `malformed`).
    AeolusMalformed {
        /// The frame, unescaped.
        frame: aeolus_proto::Frame<'a>,
        /// Why it does not parse.
        error: aeolus_proto::Error,
    },
    /// An AYDP framing or checksum error.
    Aydp(aydp_proto::Error),
    /// An AYDP frame whose data does not parse as its type's message (counted as `malformed`).
    AydpMalformed {
        /// The checked frame.
        frame: aydp_proto::Frame<'a>,
        /// Why it does not parse.
        error: aydp_proto::Error,
    },
    /// An AOK error.
    Aok(aok_proto::Error),
    /// A GDL90 error.
    Gdl90(gdl90_proto::Error),
    /// The stream (the input, or a datagram) ended inside a frame (counted as `truncated`): the
    /// sentence that says which.
    Cut(&'static str),
    /// An error rendered before (a [`super::Kept`] one): its kind and sentence.
    Rendered {
        /// Its kind.
        kind: &'a str,
        /// Its sentence.
        sentence: &'a str,
    },
}

impl Fault<'_> {
    /// What went wrong, as a short name: the protocol crate's error variant in snake case.
    ///
    /// ```
    /// use protolink::decoders::Fault;
    /// assert_eq!(Fault::Aydp(aydp_proto::Error::BadLength(3)).kind(), "bad_length");
    /// assert_eq!(Fault::Cut("input ends inside a frame").kind(), "truncated");
    /// ```
    pub fn kind(&self) -> String {
        match self {
            Fault::Aeolus(e) | Fault::AeolusMalformed { error: e, .. } => error_kind(e),
            Fault::Aydp(e) | Fault::AydpMalformed { error: e, .. } => error_kind(e),
            Fault::Aok(e) => error_kind(e),
            Fault::Gdl90(e) => error_kind(e),
            Fault::Cut(_) => "truncated".into(),
            Fault::Rendered { kind, .. } => (*kind).to_owned(),
        }
    }

    /// One sentence, as `decode` prints it.
    ///
    /// ```
    /// use protolink::decoders::Fault;
    /// assert_eq!(Fault::Cut("input ends inside a frame").sentence(), "input ends inside a frame");
    /// ```
    pub fn sentence(&self) -> String {
        match self {
            Fault::Aeolus(e) => e.to_string(),
            Fault::AeolusMalformed { frame, error } => {
                format!("{error} (frame {})", hex(frame.raw()))
            }
            Fault::Aydp(e) => e.to_string(),
            Fault::AydpMalformed { frame, error } => format!(
                "type {} message is malformed: {error} (data {})",
                frame.base_type(),
                hex(frame.data())
            ),
            Fault::Aok(e) => e.to_string(),
            Fault::Gdl90(e) => e.to_string(),
            Fault::Cut(why) => (*why).to_owned(),
            Fault::Rendered { sentence, .. } => (*sentence).to_owned(),
        }
    }
}

impl Placed<'_> {
    /// The item as `decode` prints it: a message's name, metadata and fields as JSON, or an
    /// error's kind and sentence.
    ///
    /// ```
    /// use protolink::decoders::{Decoder, Placed};
    /// use protolink::proto::Proto;
    /// let mut d = Decoder::new(Proto::Aeolus, Default::default(), Default::default());
    /// let mut lines = Vec::new();
    /// d.feed(&[0x7E, 0x52, b'h', b'i', 0, 0x73, 0xEC, 0x7E], 0, |p: Placed| lines.push(p.to_event().to_text()));
    /// assert_eq!(lines, ["@0 TOAST id=82 len=8 crc=ok text=hi"]);
    /// ```
    pub fn to_event(&self) -> Event {
        let (offset, len) = (self.offset, self.len);
        match &self.item {
            Item::Aeolus { frame, message } => {
                let (name, fields) = aeolus_fields(message);
                let meta = aeolus_meta(frame.id(), len, frame.has_crc());
                Event::message(offset, name, meta, fields)
            }
            Item::Aydp { frame, message } => {
                let (name, fields) = aydp_message_fields(message);
                Event::message(offset, name, aydp_meta(frame), fields)
            }
            Item::AokMessage(m) => {
                let (name, fields) = aok_message_fields(m);
                Event::message(offset, name, len_meta(len), fields)
            }
            Item::AokCommand(c) => {
                let (name, fields) = aok_command_fields(c);
                Event::message(offset, name, len_meta(len), fields)
            }
            Item::Gdl90(m) => {
                let (name, fields) = gdl90_fields(m);
                let mut meta = serde_json::Map::new();
                meta.insert("id".into(), m.id().into());
                meta.insert("len".into(), len.into());
                Event::message(offset, name, meta, fields)
            }
            Item::Error(fault) => Event::error(offset, len, fault.kind(), fault.sentence()),
        }
    }
}

/// The metadata of a message that has only its length.
fn len_meta(len: u64) -> serde_json::Map<String, serde_json::Value> {
    let mut meta = serde_json::Map::new();
    meta.insert("len".into(), len.into());
    meta
}
