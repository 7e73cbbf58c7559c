//! AYDP in `decode`: the rescanning decoder through the contract's adapter, each event at
//! its place (a frame at its first byte, a failed candidate at its 0xFF).

use aydp_proto::Profile;
use serde_json::{Map, Value, json};

use super::input::Input;
use super::{Fault, Item, Placed};
use crate::render::{self, to_json, variant};

/// Capacity of the AYDP decoder: the longest message accepted.
pub const AYDP_CAPACITY: usize = 16384;

/// AYDP: the rescanning decoder in one profile.
#[derive(Debug)]
pub struct AydpDecoder {
    input: Input<aydp_proto::Decoder<AYDP_CAPACITY>>,
    malformed: u32,
    truncated: u32,
}

impl AydpDecoder {
    /// A decoder for `profile`.
    pub fn new(profile: Profile) -> Self {
        AydpDecoder {
            input: Input::new(aydp_proto::Decoder::new(profile)),
            malformed: 0,
            truncated: 0,
        }
    }
}

/// The facts `decode` prints about an AYDP frame before its fields: `type`, `expedited`,
/// `len` and, in a header that has one, `time` (`seconds`, `subsec`).
///
/// ```
/// use aydp_proto::{Frame, Profile};
/// let f = Frame::new_checked(&[0xFF, 0x89, 0x08, 0, 0, 0, 0x02, 0x7C], Profile::Spec).unwrap();
/// let meta = protolink::decoders::aydp_meta(&f);
/// assert_eq!(serde_json::Value::Object(meta).to_string(), r#"{"type":9,"expedited":true,"len":8}"#);
/// ```
pub fn aydp_meta(frame: &aydp_proto::Frame<'_>) -> Map<String, Value> {
    let mut meta = Map::new();
    meta.insert("type".into(), json!(frame.base_type()));
    meta.insert("expedited".into(), json!(frame.is_expedited()));
    meta.insert("len".into(), json!(frame.as_bytes().len()));
    if let Some(t) = frame.timestamp() {
        meta.insert(
            "time".into(),
            json!({ "seconds": t.seconds, "subsec": t.subsec }),
        );
    }
    meta
}

/// An AYDP message's name and fields, as `decode` prints them (raw data as hex, a system
/// control's `command` by name).
///
/// ```
/// use aydp_proto::{Message, SystemControl};
/// let m = Message::SystemControl(SystemControl::StoreConfiguration);
/// let (name, fields) = protolink::decoders::aydp_message_fields(&m);
/// assert_eq!(name, "SYSTEM_CONTROL");
/// assert_eq!(fields.to_string(), r#"{"command":"StoreConfiguration"}"#);
/// ```
pub fn aydp_message_fields(message: &aydp_proto::Message<'_>) -> (&'static str, Value) {
    use aydp_proto::Message as M;
    let mut fields = match message {
        M::DirectOutput(d) => json!({ "entries": to_json(&d.entries().collect::<Vec<_>>()) }),
        M::FixDetail(d) => json!({ "satellites": to_json(&d.satellites().collect::<Vec<_>>()) }),
        M::SystemControl(c) => {
            let (command, args) = variant(to_json(c));
            let mut m = Map::new();
            m.insert("command".into(), json!(command));
            if let Value::Object(args) = args {
                m.extend(args);
            }
            Value::Object(m)
        }
        other => variant(to_json(other)).1,
    };
    render::data_as_hex(&mut fields);
    (aydp_name(message), fields)
}

/// An AYDP message's name, in upper snake case (`SYSTEM_VALUE_UPDATE`).
///
/// ```
/// assert_eq!(protolink::decoders::aydp_name(&aydp_proto::Message::Heartbeat), "HEARTBEAT");
/// ```
pub fn aydp_name(message: &aydp_proto::Message<'_>) -> &'static str {
    use aydp_proto::Message as M;
    match message {
        M::TimeSync => "TIME_SYNC",
        M::Heartbeat => "HEARTBEAT",
        M::NoOp => "NO_OP",
        M::Position(_) => "POSITION",
        M::FixQuality(_) => "FIX_QUALITY",
        M::FixDetail(_) => "FIX_DETAIL",
        M::DirectOutput(_) => "DIRECT_OUTPUT",
        M::SystemValueUpdate(_) => "SYSTEM_VALUE_UPDATE",
        M::SystemControl(_) => "SYSTEM_CONTROL",
        M::WindSpeed(_) => "WIND_SPEED",
        M::WindDirection(_) => "WIND_DIRECTION",
        M::VesselData(_) => "VESSEL_DATA",
        M::Tbd(_) => "TBD",
        M::UserDefined(_) => "USER_DEFINED",
        M::Unknown(_) => "UNKNOWN",
    }
}

impl AydpDecoder {
    /// Feeds bytes that start at input offset `offset`, handing every item to `on_item`
    /// placed at its first byte (a failed candidate: at its 0xFF).
    ///
    /// ```
    /// use protolink::decoders::{AydpDecoder, Item};
    /// let mut d = AydpDecoder::new(aydp_proto::Profile::Spec);
    /// let mut seen = Vec::new();
    /// d.feed(&[0x00, 0xFF, 0x80, 0x07, 0x00, 0x00, 0x00, 0x78], 5, |p| {
    ///     seen.push((p.offset, p.len, matches!(p.item, Item::Aydp { .. })))
    /// });
    /// assert_eq!(seen, [(6, 7, true)]);
    /// ```
    pub fn feed(&mut self, bytes: &[u8], offset: u64, mut on_item: impl FnMut(Placed<'_>)) {
        let (malformed, truncated) = (&mut self.malformed, &mut self.truncated);
        self.input.feed(bytes, offset, |at, len, event| {
            on_item(placed((at, len), event, malformed, truncated));
        });
    }

    /// The input ended: what is held is given up as "input ends inside a message" and
    /// rescanned.
    ///
    /// ```
    /// use protolink::decoders::AydpDecoder;
    /// let mut d = AydpDecoder::new(aydp_proto::Profile::Spec);
    /// d.feed(&[0xFF, 0x80, 0x07], 0, |_| {});
    /// let mut seen = Vec::new();
    /// d.finish(|p| seen.push(p.to_event().to_text()));
    /// assert_eq!(seen[0], "@0 error: input ends inside a message");
    /// ```
    pub fn finish(&mut self, mut on_item: impl FnMut(Placed<'_>)) {
        let (malformed, truncated) = (&mut self.malformed, &mut self.truncated);
        self.input.finish(|at, len, event| {
            on_item(placed((at, len), event, malformed, truncated));
        });
    }

    /// The counters, as `decode` prints them in its summary: the crate's `Stats` plus
    /// `malformed` and `truncated`.
    ///
    /// ```
    /// let d = protolink::decoders::AydpDecoder::new(aydp_proto::Profile::Spec);
    /// assert_eq!(d.counters()["truncated"], 0);
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

/// An AYDP event at input offset `at`, `len` bytes on the wire, typed; a frame whose data
/// does not parse counts as `malformed`, a candidate the input ended inside as `truncated`.
fn placed<'a>(
    (at, len): (u64, u64),
    event: aydp_proto::Result<aydp_proto::Frame<'a>>,
    malformed: &mut u32,
    truncated: &mut u32,
) -> Placed<'a> {
    let item = match event {
        Ok(frame) => match frame.message() {
            Ok(message) => Item::Aydp { frame, message },
            Err(error) => {
                *malformed = malformed.wrapping_add(1);
                Item::Error(Fault::AydpMalformed { frame, error })
            }
        },
        Err(aydp_proto::Error::Truncated) => {
            *truncated = truncated.wrapping_add(1);
            Item::Error(Fault::Cut("input ends inside a message"))
        }
        Err(e) => Item::Error(Fault::Aydp(e)),
    };
    Placed {
        offset: at,
        len,
        item,
    }
}
