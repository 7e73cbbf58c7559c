//! [`Kept`]: a [`Placed`] item that owns its bytes, for a face that holds items after the
//! decoder has moved on (a capture's records, the Python package's messages). It keeps what
//! the typed item is made of (the frame's bytes, or the owned message) and lends the typed
//! item back ([`Kept::with`]), so that every face renders and tabulates the same value.

use super::{Item, Placed, aok_command_name, aok_message_name, aydp_name};

/// A placed item that owns its bytes.
#[derive(Debug, Clone, PartialEq)]
pub struct Kept {
    /// Input offset of its first byte.
    pub offset: u64,
    /// Its length on the wire.
    pub len: u64,
    body: Body,
}

/// What a kept item is made of.
#[derive(Debug, Clone, PartialEq)]
enum Body {
    /// An AEOLUS frame, unescaped (ID, data, CRC).
    Aeolus(Box<[u8]>),
    /// An AYDP frame as received, and the profile it was checked in.
    Aydp(Box<[u8]>, aydp_proto::Profile),
    /// What an AOK device sends.
    AokMessage(aok_proto::Message),
    /// What an AOK PC sends.
    AokCommand(aok_proto::Command),
    /// A GDL90 message that borrows nothing.
    Gdl90(gdl90_proto::message::Message<'static>),
    /// A GDL90 message of an ID the ICD does not define: its ID and data.
    Gdl90Unknown(u8, Box<[u8]>),
    /// An error: its kind and sentence.
    Error(String, String),
}

impl Kept {
    /// The item `placed`, its bytes copied.
    ///
    /// ```
    /// use protolink::decoders::{Decoder, Kept};
    /// use protolink::proto::Proto;
    /// let mut d = Decoder::new(Proto::Aeolus, Default::default(), Default::default());
    /// let mut kept = Vec::new();
    /// d.feed(&[0x7E, 0x52, b'h', b'i', 0, 0x73, 0xEC, 0x7E], 0, |p| kept.push(Kept::new(&p)));
    /// assert_eq!(kept[0].with(|p| p.to_event().to_text()), "@0 TOAST id=82 len=8 crc=ok text=hi");
    /// ```
    pub fn new(placed: &Placed<'_>) -> Kept {
        use gdl90_proto::message::Message as G;
        let body = match &placed.item {
            Item::Aeolus { frame, .. } => Body::Aeolus(frame.raw().into()),
            Item::Aydp { frame, .. } => Body::Aydp(frame.as_bytes().into(), frame.profile()),
            Item::AokMessage(m) => Body::AokMessage(*m),
            Item::AokCommand(c) => Body::AokCommand(*c),
            Item::Gdl90(m) => match m {
                G::Heartbeat(v) => Body::Gdl90(G::Heartbeat(*v)),
                G::Ownship(v) => Body::Gdl90(G::Ownship(*v)),
                G::GeoAltitude(v) => Body::Gdl90(G::GeoAltitude(*v)),
                G::Traffic(v) => Body::Gdl90(G::Traffic(*v)),
                G::ForeFlightId(v) => Body::Gdl90(G::ForeFlightId(*v)),
                G::Ahrs(v) => Body::Gdl90(G::Ahrs(*v)),
                G::StratuxAhrs(v) => Body::Gdl90(G::StratuxAhrs(*v)),
                G::Unknown { id, data } => Body::Gdl90Unknown(*id, (*data).into()),
            },
            Item::Error(fault) => Body::Error(fault.kind(), fault.sentence()),
        };
        Kept {
            offset: placed.offset,
            len: placed.len,
            body,
        }
    }

    /// Whether it is an error.
    ///
    /// ```
    /// use protolink::decoders::{Fault, Item, Kept, Placed};
    /// let cut = Placed { offset: 0, len: 2, item: Item::Error(Fault::Cut("input ends inside a frame")) };
    /// assert!(Kept::new(&cut).is_error());
    /// ```
    pub fn is_error(&self) -> bool {
        matches!(self.body, Body::Error(..))
    }

    /// An error's kind and sentence; `None` for a message.
    ///
    /// ```
    /// use protolink::decoders::{Fault, Item, Kept, Placed};
    /// let cut = Placed { offset: 0, len: 2, item: Item::Error(Fault::Cut("input ends inside a frame")) };
    /// assert_eq!(Kept::new(&cut).error(), Some(("truncated", "input ends inside a frame")));
    /// ```
    pub fn error(&self) -> Option<(&str, &str)> {
        match &self.body {
            Body::Error(kind, sentence) => Some((kind, sentence)),
            _ => None,
        }
    }

    /// The message's name (`GYRO`, `POSITION`, `SET_PARAMETER`, ...), `ERROR` for an error.
    ///
    /// ```
    /// use protolink::decoders::{Decoder, Kept};
    /// let mut d = Decoder::new(protolink::proto::Proto::Aydp, Default::default(), Default::default());
    /// let mut names = Vec::new();
    /// d.feed(&[0xFF, 0x80, 0x07, 0x00, 0x00, 0x00, 0x78], 0, |p| names.push(Kept::new(&p).name()));
    /// assert_eq!(names, ["HEARTBEAT"]);
    /// ```
    pub fn name(&self) -> &'static str {
        self.with(|p| match &p.item {
            Item::Aeolus { message, .. } => message.name(),
            Item::Aydp { message, .. } => aydp_name(message),
            Item::AokMessage(m) => aok_message_name(m),
            Item::AokCommand(c) => aok_command_name(c),
            Item::Gdl90(m) => m.name(),
            Item::Error(_) => "ERROR",
        })
    }

    /// Lends the typed item to `f`, placed as it was.
    ///
    /// ```
    /// use protolink::decoders::{Decoder, Item, Kept};
    /// let mut d = Decoder::new(protolink::proto::Proto::Gdl90, Default::default(), Default::default());
    /// let mut frame = [0u8; 32];
    /// let n = gdl90_proto::encode_frame(0x00, &[0x81, 0, 0, 0, 0, 0], &mut frame).unwrap();
    /// let mut kept = Vec::new();
    /// d.feed(&frame[..n], 0, |p| kept.push(Kept::new(&p)));
    /// assert!(kept[0].with(|p| matches!(p.item, Item::Gdl90(_))));
    /// ```
    pub fn with<R>(&self, f: impl FnOnce(&Placed<'_>) -> R) -> R {
        use super::Fault;
        let item = match &self.body {
            Body::Aeolus(raw) => match aeolus_proto::Frame::new_checked(raw, false)
                .and_then(|frame| frame.message().map(|message| (frame, message)))
            {
                Ok((frame, message)) => Item::Aeolus { frame, message },
                // Kept only from a frame that was checked and parsed: checking and parsing are
                // pure functions of the bytes.
                Err(e) => Item::Error(Fault::Aeolus(e)),
            },
            Body::Aydp(bytes, profile) => match aydp_proto::Frame::new_checked(bytes, *profile)
                .and_then(|frame| frame.message().map(|message| (frame, message)))
            {
                Ok((frame, message)) => Item::Aydp { frame, message },
                Err(e) => Item::Error(Fault::Aydp(e)),
            },
            Body::AokMessage(m) => Item::AokMessage(*m),
            Body::AokCommand(c) => Item::AokCommand(*c),
            Body::Gdl90(m) => Item::Gdl90(*m),
            Body::Gdl90Unknown(id, data) => {
                Item::Gdl90(gdl90_proto::message::Message::Unknown { id: *id, data })
            }
            Body::Error(kind, sentence) => {
                // Rendered once when kept: handed back as they were.
                return f(&Placed {
                    offset: self.offset,
                    len: self.len,
                    item: Item::Error(Fault::Rendered { kind, sentence }),
                });
            }
        };
        f(&Placed {
            offset: self.offset,
            len: self.len,
            item,
        })
    }
}
