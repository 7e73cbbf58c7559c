//! What the encoders share: turning keyword arguments into the crates' types through serde,
//! refusing fields a message does not have, and one sentence for every refusal.

use protolink::decoders::{Body, Decoder as Core};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use serde::de::DeserializeOwned;
use serde_json::{Map, Value};

use crate::value;

/// The keyword arguments of an encoder as a JSON object (none: an empty one).
pub(crate) fn fields(kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<Map<String, Value>> {
    kwargs.map_or_else(|| Ok(Map::new()), |d| value::map_from_py(d, ""))
}

/// `value` read as `T` (a crate type with serde), or the refusal as a Python exception: a
/// value of the wrong type is a `TypeError`, anything else (a missing field, a number out of
/// range) a `ValueError`.
pub(crate) fn read<T: DeserializeOwned>(name: &str, value: Value) -> PyResult<T> {
    serde_json::from_value(value).map_err(|e| refusal(name, &e.to_string()))
}

/// A serde refusal as one sentence.
pub(crate) fn refusal(name: &str, why: &str) -> PyErr {
    let text = format!("cannot encode {name}: {why}");
    if why.starts_with("invalid type") {
        PyTypeError::new_err(text)
    } else {
        PyValueError::new_err(text)
    }
}

/// A `ValueError` saying why `name` cannot be encoded.
pub(crate) fn invalid(name: &str, why: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(format!("cannot encode {name}: {why}"))
}

/// Refuses a keyword that is not one of `known` (the fields the message renders).
pub(crate) fn check_names<'a>(
    name: &str,
    given: &Map<String, Value>,
    known: impl IntoIterator<Item = &'a str> + Clone,
) -> PyResult<()> {
    for key in given.keys() {
        if !known.clone().into_iter().any(|k| k == key) {
            let list: Vec<&str> = known.into_iter().collect();
            let fields = if list.is_empty() {
                "it has no fields".to_owned()
            } else {
                format!("its fields are {}", list.join(", "))
            };
            return Err(PyValueError::new_err(format!(
                "{name} has no field '{key}': {fields}"
            )));
        }
    }
    Ok(())
}

/// The keys of a rendered object.
pub(crate) fn keys(v: &Value) -> Vec<&str> {
    v.as_object()
        .map(|m| m.keys().map(String::as_str).collect())
        .unwrap_or_default()
}

/// The field `key` of `given`, or a `ValueError` saying it is needed.
pub(crate) fn needed<'a>(
    name: &str,
    given: &'a Map<String, Value>,
    key: &str,
) -> PyResult<&'a Value> {
    given
        .get(key)
        .ok_or_else(|| invalid(name, format!("missing field `{key}`")))
}

/// Raw data given as a hex string (the form `to_dict()` gives it in) or as bytes (which the
/// keyword conversion turned into hex already).
pub(crate) fn data_bytes(name: &str, key: &str, v: &Value) -> PyResult<Vec<u8>> {
    let Some(text) = v.as_str() else {
        return Err(PyTypeError::new_err(format!(
            "cannot encode {name}: `{key}` is bytes or a hex string"
        )));
    };
    from_hex(text).ok_or_else(|| {
        invalid(
            name,
            format!("`{key}` is not a hex string of whole bytes: '{text}'"),
        )
    })
}

/// Bytes from lower- or upper-case hex without separators.
pub(crate) fn from_hex(text: &str) -> Option<Vec<u8>> {
    if !text.len().is_multiple_of(2) {
        return None;
    }
    (0..text.len())
        .step_by(2)
        .map(|i| {
            text.get(i..i + 2)
                .and_then(|pair| u8::from_str_radix(pair, 16).ok())
        })
        .collect()
}

/// `CamelCase` from `UPPER_SNAKE`: the serde variant of a message the host tool names in
/// upper snake case (`SET_PARAMETER` -> `SetParameter`).
pub(crate) fn camel(name: &str) -> String {
    name.split('_')
        .map(|part| {
            let mut chars = part.chars();
            match chars.next() {
                Some(first) => first
                    .to_uppercase()
                    .chain(chars.flat_map(char::to_lowercase))
                    .collect::<String>(),
                None => String::new(),
            }
        })
        .collect()
}

/// Refuses a frame that `decoder` (a fresh one, for the frame's direction and profile) would
/// not give back as a `name` message: `form` ends the sentence when it decodes as another
/// (`" in this profile and header form"`); `silent` lets a frame the decoder gives nothing
/// back for pass (an AOK ack, which only the PC that sent a command expects).
pub(crate) fn check_decodes(
    name: &str,
    frame: &[u8],
    mut decoder: Core,
    form: &str,
    silent: bool,
) -> PyResult<()> {
    let mut events = decoder.events(frame, 0, false);
    decoder.finish(|p| events.push(p.to_event()));
    match events.first().map(|e| &e.body) {
        Some(Body::Message { name: got, .. }) if got == name => Ok(()),
        Some(Body::Message { name: got, .. }) => {
            Err(invalid(name, format!("it decodes as {got}{form}")))
        }
        Some(Body::Error { error, .. }) => Err(invalid(name, error)),
        None if silent => Ok(()),
        None => Err(invalid(name, "the decoder gives nothing back")),
    }
}
