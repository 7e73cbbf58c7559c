//! AYDP in `decode`: the rescanning decoder through the contract's adapter, each event at
//! its place (a frame at its first byte, a failed candidate at its 0xFF).

use aydp_proto::Profile;
use serde_json::{Map, Value, json};

use super::input::Input;
use super::{Event, StreamDecoder, error_kind};
use crate::render::{self, hex, to_json, variant};

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

/// A rendered AYDP message: its name, its meta data (type, expedited, len, time) and its fields.
pub type AydpRendered = (String, Map<String, Value>, Value);

/// An error's kind ([`error_kind`]) and its sentence.
pub type ErrorText = (String, String);

/// Splits a checked AYDP frame into its name, its meta data and its fields; a malformed typed
/// parse comes back as the error's kind ([`error_kind`]) and sentence.
///
/// ```
/// use aydp_proto::{Frame, Profile};
/// let f = Frame::new_checked(&[0xFF, 0x89, 0x08, 0, 0, 0, 0x02, 0x7C], Profile::Spec).unwrap();
/// let (name, meta, fields) = protolink::decoders::aydp_fields(&f).unwrap();
/// assert_eq!(name, "SYSTEM_CONTROL");
/// assert_eq!(meta["type"], 9);
/// assert_eq!(fields.to_string(), r#"{"command":"StoreConfiguration"}"#);
/// ```
///
/// # Errors
/// The typed parse's error, as its kind and a sentence.
pub fn aydp_fields(frame: &aydp_proto::Frame<'_>) -> std::result::Result<AydpRendered, ErrorText> {
    use aydp_proto::Message as M;
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
    let message = frame.message().map_err(|e| {
        (
            error_kind(&e),
            format!(
                "type {} message is malformed: {e} (data {})",
                frame.base_type(),
                hex(frame.data())
            ),
        )
    })?;
    let mut fields = match &message {
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
    let name = render::upper_snake(&variant(to_json(&message)).0);
    Ok((name, meta, fields))
}

/// An AYDP event at input offset `at`, `len` bytes on the wire, as `decode` prints it; a
/// frame whose data does not parse counts as `malformed`, a candidate the input ended inside
/// as `truncated`.
fn aydp_event(
    (at, len): (u64, u64),
    event: aydp_proto::Result<aydp_proto::Frame<'_>>,
    malformed: &mut u32,
    truncated: &mut u32,
) -> Event {
    match event {
        Ok(frame) => match aydp_fields(&frame) {
            Ok((name, meta, fields)) => Event::message(at, name, meta, fields),
            Err((kind, e)) => {
                *malformed = malformed.wrapping_add(1);
                Event::error(at, len, kind, e)
            }
        },
        Err(e @ aydp_proto::Error::Truncated) => {
            *truncated = truncated.wrapping_add(1);
            Event::error(at, len, error_kind(&e), "input ends inside a message")
        }
        Err(e) => Event::error(at, len, error_kind(&e), e.to_string()),
    }
}

impl StreamDecoder for AydpDecoder {
    fn feed(&mut self, bytes: &[u8], offset: u64, out: &mut Vec<Event>) {
        let (malformed, truncated) = (&mut self.malformed, &mut self.truncated);
        self.input.feed(bytes, offset, |at, len, event| {
            out.push(aydp_event((at, len), event, malformed, truncated));
        });
    }

    fn finish(&mut self, _offset: u64, out: &mut Vec<Event>) {
        let (malformed, truncated) = (&mut self.malformed, &mut self.truncated);
        self.input.finish(|at, len, event| {
            out.push(aydp_event((at, len), event, malformed, truncated));
        });
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
