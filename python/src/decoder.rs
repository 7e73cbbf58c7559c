//! What the four `Decoder` classes share: feeding a buffer with the GIL released, the end of
//! the input, and the counters as a dict.

use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use serde_json::Value;

use crate::input::Input;
use crate::message::to_list;
use crate::stream::Stream;
use crate::value;

/// Decodes `data` (bytes read in place, another buffer copied once) with the GIL released,
/// and returns the messages and error events it completed.
pub(crate) fn feed<'py>(
    py: Python<'py>,
    stream: &mut Stream,
    data: &Bound<'py, PyAny>,
    datagram: bool,
) -> PyResult<Bound<'py, PyList>> {
    let input = Input::extract(data)?;
    let bytes = input.as_slice();
    let proto = stream.proto();
    let pending = py.detach(|| {
        let mut out = Vec::new();
        stream.feed(bytes, datagram, &mut out);
        out
    });
    to_list(py, pending, proto, None)
}

/// The end of the input: what the decoder still holds, reported.
pub(crate) fn flush<'py>(py: Python<'py>, stream: &mut Stream) -> PyResult<Bound<'py, PyList>> {
    let proto = stream.proto();
    let mut out = Vec::new();
    stream.finish(&mut out);
    to_list(py, out, proto, None)
}

/// The counters as a dict, exactly the `"counters"` of `protolink decode --json`'s summary.
pub(crate) fn stats<'py>(py: Python<'py>, stream: &Stream) -> PyResult<Bound<'py, PyDict>> {
    match stream.counters() {
        Value::Object(m) => value::dict(py, &m),
        _ => Ok(PyDict::new(py)),
    }
}

/// `arg` as one of `choices` (by name), or an exception naming them: `ValueError` for another
/// string, `TypeError` for anything else.
pub(crate) fn choose<T: Copy>(
    what: &str,
    arg: &Bound<'_, PyAny>,
    choices: &[(&str, T)],
) -> PyResult<T> {
    let names: Vec<String> = choices.iter().map(|(n, _)| format!("'{n}'")).collect();
    let names = names.join(" or ");
    let Ok(text) = arg.extract::<String>() else {
        return Err(PyTypeError::new_err(format!(
            "{what} is {names}, not {}",
            arg.repr()
                .map_or_else(|_| "that".to_owned(), |r| r.to_string())
        )));
    };
    choices
        .iter()
        .find(|(name, _)| *name == text)
        .map(|(_, v)| *v)
        .ok_or_else(|| PyValueError::new_err(format!("{what} is {names}, not '{text}'")))
}
