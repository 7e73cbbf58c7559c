//! The bytes a decoder is fed: a `bytes` object is read in place (no copy, no Python object
//! per byte); a `bytearray`, a `memoryview` or any other object with the buffer protocol
//! (`array('B')`, a NumPy `uint8` array) is copied once, since its owner may change it while
//! the decoder runs without the GIL. (The stable ABI of Python 3.9 has no buffer protocol for
//! extensions: the copy is `memoryview(obj).tobytes()`.)

use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyByteArray, PyBytes, PyString};

use crate::value::type_name;

/// Bytes borrowed from a `bytes` object, or a copy of another buffer.
pub(crate) enum Input<'a, 'py> {
    /// The contents of an immutable `bytes` object.
    Borrowed(&'a [u8]),
    /// A copy of a `bytearray`.
    Owned(Vec<u8>),
    /// A copy of another buffer, as a new `bytes` object.
    Copied(Bound<'py, PyBytes>),
}

impl<'a, 'py> Input<'a, 'py> {
    /// The bytes of `obj`, for the method `what` (named in the exception).
    ///
    /// # Errors
    /// `TypeError` for a `str`, an `int` or an object without the buffer protocol.
    pub(crate) fn extract(obj: &'a Bound<'py, PyAny>, what: &str) -> PyResult<Self> {
        if let Ok(b) = obj.cast::<PyBytes>() {
            return Ok(Input::Borrowed(b.as_bytes()));
        }
        if let Ok(b) = obj.cast::<PyByteArray>() {
            return Ok(Input::Owned(b.to_vec()));
        }
        copy(obj, what).map(Input::Copied)
    }

    /// The bytes.
    pub(crate) fn as_slice(&self) -> &[u8] {
        match self {
            Input::Borrowed(b) => b,
            Input::Owned(v) => v,
            Input::Copied(b) => b.as_bytes(),
        }
    }
}

/// `obj` as a `bytes` object: itself, or a copy of another buffer (made once, as `feed`
/// makes it), for the method `what`.
///
/// # Errors
/// As [`Input::extract`].
pub(crate) fn to_bytes<'py>(obj: &Bound<'py, PyAny>, what: &str) -> PyResult<Bound<'py, PyBytes>> {
    match obj.cast::<PyBytes>() {
        Ok(b) => Ok(b.clone()),
        Err(_) => copy(obj, what),
    }
}

/// A copy of a buffer that is not `bytes`, as `memoryview(obj).tobytes()`.
fn copy<'py>(obj: &Bound<'py, PyAny>, what: &str) -> PyResult<Bound<'py, PyBytes>> {
    if obj.is_instance_of::<PyString>() {
        return Err(PyTypeError::new_err(format!(
            "{what} takes bytes, not str: encode the text first (data.encode('latin-1') keeps every byte)"
        )));
    }
    let py = obj.py();
    let copied = py
        .import("builtins")
        .and_then(|b| b.getattr("memoryview"))
        .and_then(|mv| mv.call1((obj,)))
        .and_then(|view| view.call_method0("tobytes"))
        .and_then(|bytes| bytes.cast_into::<PyBytes>().map_err(PyErr::from));
    copied.map_err(|_| {
        PyTypeError::new_err(format!(
            "{what} takes bytes, bytearray, memoryview or another buffer of bytes, not {}",
            type_name(obj)
        ))
    })
}
