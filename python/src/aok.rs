//! `protolink.aok`: the AOK `Decoder` for either side's bytes, and `encode` for the PC's
//! commands and the device's messages.

use aok_proto::{ActionWord, Command, EncodeError, Message, ReplyForm, Waypoint, WaypointSlot};
use protolink::commands::aok::{parse_action, parse_slot};
use protolink::decoders::{
    AokDecoder, Decoder as Core, Item, aok_command_fields, aok_message_fields,
};
use protolink::proto::{ProfileArg, Proto, Side};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};
use serde::de::DeserializeOwned;
use serde_json::{Map, Value, json};

use crate::decoder::{SIDES, protocol_decoder};
use crate::encode::{self, camel, check_decodes, check_names, invalid, needed, read};

protocol_decoder!(
    /// The AOK stream decoder, as `protolink decode --proto aok --side ...` runs it. `finish()`
    /// (the line went quiet, or the input ended): a partial frame is given up (`truncated`) and
    /// what followed its first byte is rescanned.
    AokPyDecoder,
    "protolink.aok",
    Proto::Aok,
    /// `side`: who sent the bytes, `"device"` (debug values, acks, parameter and waypoint
    /// replies, read as the PC reads them) or `"pc"` (commands, read as the device reads them).
    side in SIDES => |s| (ProfileArg::Spec, s),
    /// Who sent the bytes: `"device"` or `"pc"`.
);

/// The names `encode` takes: the PC's commands, then the device's messages.
const NAMES: &str = "DEBUG_OFF, DEBUG_ON, RESET, SAVE_WAYPOINTS, LOAD_WAYPOINTS, LOAD_SET, \
                     SAVE_SET, START_SET, SET_PARAMETER, READ_PARAMETER, BULK_READ, MOTOR_TEST, \
                     SET_WAYPOINT, READ_WAYPOINT, EXTERNAL_CONTROL (commands); DEBUG, ACK, \
                     PARAMETER, WAYPOINT (messages)";

/// A frame in one direction.
enum Frame {
    /// What the PC sends.
    Command(Command),
    /// What the device sends.
    Message(Message),
}

/// A slot as the host tool names it (`1`..`31`, `poi`, `ram-poi`, `fbc`).
fn slot(name: &str, given: &Map<String, Value>) -> PyResult<WaypointSlot> {
    match needed(name, given, "slot")? {
        Value::String(s) => parse_slot(s).map_err(|e| invalid(name, e)),
        Value::Number(n) => parse_slot(&n.to_string()).map_err(|e| invalid(name, e)),
        other => Err(PyTypeError::new_err(format!(
            "cannot encode {name}: `slot` is 1..=31, 'poi', 'ram-poi' or 'fbc', not {other}"
        ))),
    }
}

/// An action word as the host tool writes it: `action:value`, or `raw:0x...` for a word whose
/// action no firmware defines.
fn action(name: &str, given: &Map<String, Value>, key: &str) -> PyResult<ActionWord> {
    let Some(v) = given.get(key) else {
        return Ok(ActionWord::NONE);
    };
    let Some(text) = v.as_str() else {
        return Err(PyTypeError::new_err(format!(
            "cannot encode {name}: `{key}` is a string such as 'hold-and-climb:15'"
        )));
    };
    if let Some(raw) = text.strip_prefix("raw:") {
        let digits = raw.strip_prefix("0x").unwrap_or(raw);
        return u32::from_str_radix(digits, 16)
            .map(ActionWord)
            .map_err(|_| {
                invalid(
                    name,
                    format!("`{key}` '{text}' is not raw:0x and 8 hex digits"),
                )
            });
    }
    parse_action(text).map_err(|e| invalid(name, e))
}

fn waypoint(name: &str, given: &Map<String, Value>) -> PyResult<Waypoint> {
    check_names(
        name,
        given,
        ["slot", "longitude", "latitude", "action1", "action2"],
    )?;
    Ok(Waypoint {
        slot: slot(name, given)?,
        longitude: read(name, needed(name, given, "longitude")?.clone())?,
        latitude: read(name, needed(name, given, "latitude")?.clone())?,
        action1: action(name, given, "action1")?,
        action2: action(name, given, "action2")?,
    })
}

/// A one-number command's number, under the name the host tool gives it.
fn number(name: &str, given: &Map<String, Value>, key: &str) -> PyResult<u8> {
    check_names(name, given, [key])?;
    read(name, needed(name, given, key)?.clone())
}

/// A command or message whose variant holds a struct, read through serde's form of it
/// (`{"Variant": {fields}}`); refused if `given` has a field that `render` (the host tool's
/// renderer) does not give it.
fn variant<T: DeserializeOwned>(
    name: &str,
    given: &Map<String, Value>,
    render: fn(&T) -> (String, Value),
) -> PyResult<T> {
    let mut m = Map::new();
    m.insert(camel(name), Value::Object(given.clone()));
    let v: T = read(name, Value::Object(m))?;
    check_names(name, given, encode::keys(&render(&v).1))?;
    Ok(v)
}

/// The frame a name and fields describe.
fn frame(name: &str, given: &Map<String, Value>) -> PyResult<Frame> {
    Ok(match name {
        "LOAD_SET" => Frame::Command(Command::LoadSet(number(name, given, "set")?)),
        "SAVE_SET" => Frame::Command(Command::SaveSet(number(name, given, "set")?)),
        "START_SET" => Frame::Command(Command::StartSet(number(name, given, "set")?)),
        "READ_PARAMETER" => Frame::Command(Command::ReadParameter(number(name, given, "number")?)),
        "BULK_READ" => Frame::Command(Command::BulkRead(number(name, given, "first")?)),
        "READ_WAYPOINT" => {
            check_names(name, given, ["slot"])?;
            Frame::Command(Command::ReadWaypoint(slot(name, given)?))
        }
        "SET_WAYPOINT" => Frame::Command(Command::SetWaypoint(waypoint(name, given)?)),
        "WAYPOINT" => Frame::Message(Message::Waypoint(waypoint(name, given)?)),
        "ACK" => {
            check_names(name, given, ["value"])?;
            let v = needed(name, given, "value")?.clone();
            Frame::Message(read(name, json!({ "Ack": v }))?)
        }
        "DEBUG_OFF" | "DEBUG_ON" | "RESET" | "SAVE_WAYPOINTS" | "LOAD_WAYPOINTS" => {
            check_names(name, given, [])?;
            Frame::Command(read(name, json!(camel(name)))?)
        }
        "SET_PARAMETER" | "MOTOR_TEST" | "EXTERNAL_CONTROL" => {
            Frame::Command(variant(name, given, aok_command_fields)?)
        }
        "DEBUG" | "PARAMETER" => Frame::Message(variant(name, given, aok_message_fields)?),
        _ => {
            return Err(PyValueError::new_err(format!(
                "AOK has no message '{name}': the names are {NAMES}"
            )));
        }
    })
}

/// The frame's bytes: a command as the PC sends it, a message as a device of firmware 0.31 or
/// later sends it (parameter replies headed).
fn bytes(f: &Frame) -> Result<Vec<u8>, EncodeError> {
    let mut buf = [0u8; 32];
    let n = match f {
        Frame::Command(c) => c.emit(&mut buf),
        Frame::Message(m) => m.emit(&mut buf, ReplyForm::Headed),
    }?;
    Ok(buf.get(..n).unwrap_or(&[]).to_vec())
}

/// One AOK frame from the name of a command (what the PC sends) or a message (what the device
/// sends) and its fields as `to_dict()` gives them.
#[pyfunction(name = "aok_encode")]
#[pyo3(signature = (name, /, **fields))]
pub(crate) fn encode_aok<'py>(
    py: Python<'py>,
    name: &str,
    fields: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyBytes>> {
    let given = encode::fields(fields)?;
    let f = frame(name, &given)?;
    let out = bytes(&f).map_err(|e| invalid(name, e))?;
    let side = match f {
        Frame::Command(_) => Side::Pc,
        Frame::Message(_) => Side::Device,
    };
    // A lone ack byte is not decodable passively: only a PC that sent a command expects one.
    check_decodes(
        name,
        &out,
        Core::Aok(AokDecoder::new(side)),
        "",
        name == "ACK",
    )?;
    Ok(PyBytes::new(py, &out))
}

/// The first byte of the frame a decoded AOK command or message came in, as `encode` writes
/// it (its command letter, or the reply's start byte): `Message.id` for AOK; `None` for an item
/// of another protocol.
pub(crate) fn first_byte(item: &Item<'_>) -> Option<u8> {
    let f = match item {
        Item::AokCommand(c) => Frame::Command(*c),
        Item::AokMessage(m) => Frame::Message(*m),
        _ => return None,
    };
    bytes(&f).ok()?.first().copied()
}
