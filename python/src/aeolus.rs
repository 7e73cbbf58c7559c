//! `protolink.aeolus`: the AEOLUS `Decoder` (the host tool's, on the crate's slice path) and
//! `encode`.

use aeolus_proto::message::{self as msg, Message, Text};
use aeolus_proto::{CrcMode, max_encoded_len};
use protolink::decoders::{AeolusDecoder, Decoder as Core, aeolus_fields};
use protolink::proto::Proto;
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};
use serde_json::{Map, Value};

use crate::decoder::protocol_decoder;
use crate::encode::{self, check_decodes, check_names, data_bytes, invalid, keys, needed, read};

protocol_decoder!(
    /// The AEOLUS stream decoder, as `protolink decode --proto aeolus` runs it: frames with or
    /// without a CRC, every message type, errors as events. `finish()`: a frame still open is a
    /// `truncated` error.
    AeolusPyDecoder,
    "protolink.aeolus",
    Proto::Aeolus
);

/// The messages of a fixed layout, for `encode`: the spec's name and the message read from
/// its fields through serde; `None` for another name.
fn typed(name: &str, fields: Value) -> PyResult<Option<Message<'static>>> {
    Ok(Some(match name {
        "AEOLUSINFO" => Message::AeolusInfo(read::<msg::AeolusInfo>(name, fields)?),
        "PRESSURE" => Message::Pressure(read::<msg::Pressure>(name, fields)?),
        "GYRO" => Message::Gyro(read::<msg::Gyro>(name, fields)?),
        "ACCEL" => Message::Accel(read::<msg::Accel>(name, fields)?),
        "MAGNET" => Message::Magnet(read::<msg::Magnet>(name, fields)?),
        "TEMP" => Message::Temp(read::<msg::Temp>(name, fields)?),
        "GPS" => Message::Gps(read::<msg::Gps>(name, fields)?),
        "ATTITUDE" => Message::Attitude(read::<msg::Attitude>(name, fields)?),
        "COMPASS" => Message::Compass(read::<msg::Compass>(name, fields)?),
        "WIND" => Message::Wind(read::<msg::Wind>(name, fields)?),
        "SETTIME" => Message::SetTime(read::<msg::SetTime>(name, fields)?),
        _ => return Ok(None),
    }))
}

/// The message names `encode` takes.
const NAMES: &str = "AEOLUSINFO, PRESSURE, GYRO, ACCEL, MAGNET, TEMP, GPS, ATTITUDE, COMPASS, WIND, \
                     CALIBINFO, DEBUGINFO, LOG, TOAST, COMMAND, SETTIME or UNKNOWN";

/// A text field's bytes: `hex` (the raw bytes, which `to_dict()` adds when the text is not
/// clean UTF-8) wins over `text`.
fn text_bytes(name: &str, given: &Map<String, Value>) -> PyResult<Vec<u8>> {
    check_names(name, given, ["text", "hex"])?;
    if let Some(h) = given.get("hex") {
        return data_bytes(name, "hex", h);
    }
    match needed(name, given, "text")? {
        Value::String(s) => Ok(s.as_bytes().to_vec()),
        _ => Err(pyo3::exceptions::PyTypeError::new_err(format!(
            "cannot encode {name}: `text` is a string"
        ))),
    }
}

/// Raw data (`data`, hex or bytes), checked against `len` when it is given.
fn raw_data(name: &str, given: &Map<String, Value>) -> PyResult<Vec<u8>> {
    let data = data_bytes(name, "data", needed(name, given, "data")?)?;
    if let Some(len) = given.get("len")
        && len.as_u64() != Some(data.len() as u64)
    {
        return Err(invalid(
            name,
            format!("`len` is {len} but `data` holds {} bytes", data.len()),
        ));
    }
    Ok(data)
}

/// One AEOLUS frame, flags, escapes and CRC included, from the message's name and its fields
/// as `to_dict()` gives them (`UNKNOWN` also takes `id`). `crc=False` sends `00 00`, "no CRC"
/// (`meta["crc"] == "none"`).
#[pyfunction(name = "aeolus_encode")]
#[pyo3(signature = (name, /, crc = true, **fields))]
pub(crate) fn encode_aeolus<'py>(
    py: Python<'py>,
    name: &str,
    crc: bool,
    fields: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyBytes>> {
    let given = encode::fields(fields)?;
    let data;
    let text;
    let message = match name {
        "TOAST" | "COMMAND" => {
            text = Text::from_bytes(&text_bytes(name, &given)?).map_err(|e| invalid(name, e))?;
            if name == "TOAST" {
                Message::Toast(text)
            } else {
                Message::Command(text)
            }
        }
        "CALIBINFO" | "DEBUGINFO" | "LOG" => {
            check_names(name, &given, ["len", "data"])?;
            data = raw_data(name, &given)?;
            match name {
                "CALIBINFO" => Message::CalibInfo(&data),
                "DEBUGINFO" => Message::DebugInfo(&data),
                _ => Message::Log(&data),
            }
        }
        "UNKNOWN" => {
            check_names(name, &given, ["id", "len", "data"])?;
            let id = needed(name, &given, "id")?
                .as_u64()
                .and_then(|id| u8::try_from(id).ok())
                .ok_or_else(|| invalid(name, "`id` is a message ID, 0..=255"))?;
            data = raw_data(name, &given)?;
            Message::Unknown { id, data: &data }
        }
        _ => match typed(name, Value::Object(given.clone()))? {
            Some(m) => {
                check_names(name, &given, keys(&aeolus_fields(&m).1))?;
                m
            }
            None => {
                return Err(pyo3::exceptions::PyValueError::new_err(format!(
                    "AEOLUS has no message '{name}': the names are {NAMES}"
                )));
            }
        },
    };
    let mut buf = vec![0u8; max_encoded_len(message.buffer_len())];
    let n = message
        .encode(&mut buf, if crc { CrcMode::Compute } else { CrcMode::Omit })
        .map_err(|e| invalid(name, e))?;
    buf.truncate(n);
    // An ID the spec defines sent as UNKNOWN, a LOG longer than a decoder holds, a malformed
    // layout: refused.
    let decoder = Core::Aeolus(AeolusDecoder::new());
    check_decodes(name, &buf, decoder, &format!(", not {name}"), false)?;
    Ok(PyBytes::new(py, &buf))
}
