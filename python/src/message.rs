//! What a decoder hands Python: `Message` (a decoded message: name, ID, offset, one
//! attribute per field) and `ErrorEvent` (bad bytes in the stream: kind, sentence, offset).
//!
//! A message keeps the decoder's typed item (`protolink::decoders::Kept`: its frame's bytes, or
//! the owned message), decoded without the GIL, and builds its Python fields the first time one
//! is read, once: an AEOLUS message of a fixed layout straight from its typed value, the others
//! as the host tool renders them. Either way the fields are exactly the `"fields"` of
//! `protolink decode --json`; a row of `to_arrow` is the typed item's, as in `protolink export`.
//!
//! A field wins over the attribute of its name: `m.x` is `m["x"]` whenever the message has a
//! field `x`. Three attributes have a field of their name in some message type (`name`: GDL90
//! FOREFLIGHT_ID; `id`: GDL90 UNKNOWN; `len`: the AEOLUS raw messages); each reads that field
//! there, and what the attribute stands for has a name no field has (`get_type()`,
//! `wire_len`; the ID is the same number). `python/tests/test_field_names.py` checks every
//! message type for it.

use std::sync::OnceLock;

use protolink::columns::Tables;
use protolink::commands::decode::capture::proto_name;
use protolink::decoders::{Body as EventBody, Item, Kept};
use protolink::proto::Proto;
use pyo3::IntoPyObjectExt;
use pyo3::exceptions::{PyAttributeError, PyDeprecationWarning, PyKeyError};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyDict, PyList, PyString};
use serde_json::{Map, Value};

use crate::stream::Pending;
use crate::to_python::to_python;
use crate::value;

/// Where and when a message was captured: the capture file's record (its time, flow and
/// number), or the host's clock when the bytes arrived on a live link.
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct Origin {
    /// Seconds since the Unix epoch.
    pub(crate) capture_time: Option<f64>,
    /// The capture's flow, e.g. `udp 127.0.0.1:40000 > 127.0.0.1:5001`.
    pub(crate) flow: Option<String>,
    /// The capture record's number, from 1.
    pub(crate) frame: Option<u64>,
}

/// A decoded message: `name`, `id`, `offset`, and one attribute per field in the protocol
/// crate's units (also `msg["field"]` and `to_dict()`); a field wins over the attribute of
/// its name.
#[pyclass(frozen, module = "protolink", name = "Message")]
pub(crate) struct Message {
    proto: Proto,
    offset: u64,
    body: Kept,
    origin: Option<Box<Origin>>,
    /// The metadata, rendered once.
    meta: OnceLock<Map<String, Value>>,
    fields: PyOnceLock<Py<PyDict>>,
}

/// Bad bytes in a stream: `kind` (the protocol crate's error, e.g. `checksum_mismatch`),
/// `error` (one sentence, as `protolink decode` prints it) and `offset`. Its `name` is `ERROR`.
#[pyclass(frozen, module = "protolink", name = "ErrorEvent")]
#[derive(Debug)]
pub(crate) struct ErrorEvent {
    proto: Proto,
    offset: u64,
    wire_len: u64,
    kind: String,
    error: String,
    origin: Option<Box<Origin>>,
}

/// A pending event of a `proto` decoder as a Python object.
pub(crate) fn to_object<'py>(
    py: Python<'py>,
    pending: Pending,
    proto: Proto,
    origin: Option<&Origin>,
) -> PyResult<Bound<'py, PyAny>> {
    let origin = origin.map(|o| Box::new(o.clone()));
    if let Some((kind, error)) = pending.error() {
        let e = ErrorEvent {
            proto,
            offset: pending.offset,
            wire_len: pending.len,
            kind: kind.to_owned(),
            error: error.to_owned(),
            origin,
        };
        return Ok(Bound::new(py, e)?.into_any());
    }
    let (offset, body) = (pending.offset, pending);
    let m = Message {
        proto,
        offset,
        body,
        origin,
        meta: OnceLock::new(),
        fields: PyOnceLock::new(),
    };
    Ok(Bound::new(py, m)?.into_any())
}

/// Adds a `Message` or `ErrorEvent` to `tables` as a row (its type's table, or `ERROR`).
///
/// # Errors
/// `TypeError` for any other object.
pub(crate) fn add_row(obj: &Bound<'_, PyAny>, tables: &mut Tables) -> PyResult<()> {
    if let Ok(m) = obj.cast::<Message>() {
        let m = m.get();
        let origin = columns_origin(m.origin.as_deref(), m.proto);
        m.body.with(|p| tables.add(&origin, p));
        return Ok(());
    }
    if let Ok(e) = obj.cast::<ErrorEvent>() {
        let e = e.get();
        let origin = columns_origin(e.origin.as_deref(), e.proto);
        tables.add_error(&origin, e.offset, &e.kind, &e.error);
        return Ok(());
    }
    Err(pyo3::exceptions::PyTypeError::new_err(format!(
        "to_frames and to_arrow take messages (Message, ErrorEvent), not {}",
        value::type_name(obj)
    )))
}

/// A message's origin as the tables' metadata (the protocol only from a capture).
fn columns_origin(origin: Option<&Origin>, proto: Proto) -> protolink::columns::Origin {
    let Some(o) = origin else {
        return protolink::columns::Origin::default();
    };
    protolink::columns::Origin {
        source: None,
        capture_time: o.capture_time,
        flow: o.flow.clone(),
        frame: o.frame,
        proto: o.flow.as_ref().map(|_| proto),
    }
}

/// The fields of an AEOLUS message of a fixed layout, straight from its typed value to Python
/// (as `aeolus_fields` renders them, without the JSON value in between); `None` for the texts
/// and raw messages and the other protocols, which the host tool renders its own way.
fn aeolus_typed<'py>(py: Python<'py>, kept: &Kept) -> Option<PyResult<Bound<'py, PyDict>>> {
    use aeolus_proto::message::Message as M;
    let fields = kept.with(|p| {
        let Item::Aeolus { message, .. } = &p.item else {
            return None;
        };
        Some(match message {
            M::AeolusInfo(v) => to_python(py, v),
            M::Pressure(v) => to_python(py, v),
            M::Gyro(v) => to_python(py, v),
            M::Accel(v) => to_python(py, v),
            M::Magnet(v) => to_python(py, v),
            M::Temp(v) => to_python(py, v),
            M::Gps(v) => to_python(py, v),
            M::Attitude(v) => to_python(py, v),
            M::Compass(v) => to_python(py, v),
            M::Wind(v) => to_python(py, v),
            M::SetTime(v) => to_python(py, v),
            M::CalibInfo(_)
            | M::DebugInfo(_)
            | M::Log(_)
            | M::Toast(_)
            | M::Command(_)
            | M::Unknown { .. } => return None,
        })
    })?;
    Some(fields.and_then(|d| d.cast_into::<PyDict>().map_err(PyErr::from)))
}

/// The attributes every message has, beside its fields (for `dir()`; not the deprecated
/// `len`, which is listed only where it is a field).
const MESSAGE_ATTRIBUTES: [&str; 12] = [
    "name",
    "id",
    "offset",
    "wire_len",
    "proto",
    "meta",
    "capture_time",
    "flow",
    "frame",
    "to_dict",
    "get_type",
    "is_error",
];

/// What `Message.len` and `ErrorEvent.len` warn where they are not a field.
const LEN_DEPRECATED: &std::ffi::CStr = c"Message.len is deprecated: use wire_len, the length on the wire (on a message with a field named len, m.len is that field, as m[\"len\"])";

/// Warns that `len` is deprecated (an exception if warnings are errors).
fn warn_len(py: Python<'_>) -> PyResult<()> {
    PyErr::warn(
        py,
        py.get_type::<PyDeprecationWarning>().as_any(),
        LEN_DEPRECATED,
        1,
    )
}

/// The `#[pymethods]` of a class of what a decoder reports (`Message`, `ErrorEvent`) and the
/// getters both have, written once: `proto`, `capture_time`, `flow`, `frame` (from the class's
/// `proto` and `origin`) and `is_error`.
macro_rules! event_methods {
    (impl $class:ident { is_error: $is_error:literal; $($methods:tt)* }) => {
        #[pymethods]
        impl $class {
            /// The protocol: `aeolus`, `aydp`, `aok` or `gdl90`.
            #[getter]
            fn proto(&self) -> &'static str {
                proto_name(self.proto)
            }

            /// When it was captured, seconds since the Unix epoch: the record's time in a
            /// capture file, the host's clock when the bytes arrived on a live link; None
            /// otherwise.
            #[getter]
            fn capture_time(&self) -> Option<f64> {
                self.origin.as_ref().and_then(|o| o.capture_time)
            }

            /// The capture's flow it came in (`udp 127.0.0.1:40000 > 127.0.0.1:5001`); None
            /// outside a capture.
            #[getter]
            fn flow(&self) -> Option<&str> {
                self.origin.as_ref().and_then(|o| o.flow.as_deref())
            }

            /// The number of the capture record it came in, from 1; None outside a capture.
            #[getter]
            fn frame(&self) -> Option<u64> {
                self.origin.as_ref().and_then(|o| o.frame)
            }

            /// Whether this is an `ErrorEvent` (bad bytes) rather than a `Message`.
            #[getter]
            fn is_error(&self) -> bool {
                $is_error
            }

            $($methods)*
        }
    };
}

impl Message {
    /// The field `key` when the message has one: a field wins over the attribute of its name.
    /// Looks without building the Python fields where it can: of the AEOLUS messages, only the
    /// texts and raw data (rendered by the host tool) have a field named like an attribute;
    /// the typed ones have none (`python/tests/test_field_names.py` checks every type). The
    /// others look in their fields, built once.
    fn field_named<'py>(&self, py: Python<'py>, key: &str) -> PyResult<Option<Bound<'py, PyAny>>> {
        // The typed AEOLUS messages have no field named like an attribute: no fields built.
        let typed = self.proto == Proto::Aeolus
            && self.body.with(|p| {
                use aeolus_proto::message::Message as M;
                !matches!(
                    &p.item,
                    Item::Aeolus {
                        message: M::CalibInfo(_)
                            | M::DebugInfo(_)
                            | M::Log(_)
                            | M::Toast(_)
                            | M::Command(_)
                            | M::Unknown { .. },
                        ..
                    }
                )
            });
        if typed {
            return Ok(None);
        }
        self.fields(py)?.get_item(key)
    }

    /// The message's length on the wire.
    fn wire_len_value(&self) -> Option<u64> {
        Some(self.body.len)
    }

    /// The message as `protolink decode --json` renders it: its metadata and fields.
    fn event(&self) -> (Map<String, Value>, Value) {
        match self.body.with(|p| p.to_event()).body {
            EventBody::Message { meta, fields, .. } => (meta, fields),
            EventBody::Error { .. } => (Map::new(), Value::Null),
        }
    }

    /// The metadata, rendered once (here, or with the fields).
    fn meta_map(&self) -> &Map<String, Value> {
        self.meta.get_or_init(|| self.event().0)
    }

    /// The fields as a Python dict, built once (and the metadata kept, when they are rendered
    /// together).
    fn fields<'py>(&self, py: Python<'py>) -> PyResult<&Bound<'py, PyDict>> {
        let d = self
            .fields
            .get_or_try_init(py, || -> PyResult<Py<PyDict>> {
                if let Some(d) = aeolus_typed(py, &self.body) {
                    return Ok(d?.unbind());
                }
                let (meta, fields) = self.event();
                let _ = self.meta.set(meta);
                let map = match fields {
                    Value::Object(m) => m,
                    other => {
                        let mut m = Map::new();
                        m.insert("value".into(), other);
                        m
                    }
                };
                Ok(value::dict(py, &map)?.unbind())
            })?;
        Ok(d.bind(py))
    }

    /// The field `key`, or the error `missing` makes of the sentence that says there is none.
    fn field_or<'py>(
        &self,
        py: Python<'py>,
        key: &str,
        missing: fn(String) -> PyErr,
    ) -> PyResult<Bound<'py, PyAny>> {
        self.fields(py)?
            .get_item(key)?
            .ok_or_else(|| missing(format!("{} has no field '{key}'", self.name_str())))
    }

    fn name_str(&self) -> &'static str {
        self.body.name()
    }
}

event_methods! {
impl Message {
    is_error: false;

    /// The message's name, e.g. `GYRO`, `POSITION`, `SET_PARAMETER`, `HEARTBEAT`; the field
    /// `name` where the message has one (GDL90 FOREFLIGHT_ID: the device's name), as
    /// `m["name"]`.
    #[getter]
    fn name<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        if let Some(field) = self.field_named(py, "name")? {
            return Ok(field);
        }
        Ok(self.get_type(py).into_any())
    }

    /// The message's name, as pymavlink's `get_type()` gives it: always the message's, even
    /// where a field is named `name`.
    fn get_type<'py>(&self, py: Python<'py>) -> Bound<'py, PyString> {
        PyString::intern(py, self.body.name())
    }

    /// The message's identifier on the wire: the AEOLUS and GDL90 message ID, the AYDP base
    /// type, the first byte of an AOK frame (its command letter, or the reply's start byte).
    /// The field `id` where the message has one (GDL90 UNKNOWN: the same ID), as `m["id"]`.
    #[getter]
    fn id<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        if let Some(field) = self.field_named(py, "id")? {
            return Ok(Some(field));
        }
        // From the typed item: the same number as `meta["id"]` (AYDP: `meta["type"]`), nothing
        // rendered.
        let id = self.body.with(|p| match &p.item {
            Item::Aeolus { frame, .. } => Some(frame.id()),
            Item::Aydp { frame, .. } => Some(frame.base_type()),
            Item::Gdl90(m) => Some(m.id()),
            item @ (Item::AokCommand(_) | Item::AokMessage(_)) => crate::aok::first_byte(item),
            Item::Error(_) => None,
        });
        id.map(|id| id.into_bound_py_any(py)).transpose()
    }

    /// Offset of the message's first byte in the input (within its flow, for a capture).
    #[getter]
    fn offset(&self) -> u64 {
        self.offset
    }

    /// The message's length on the wire, in bytes (AEOLUS and GDL90: both flags and the
    /// escapes included): `meta["len"]`.
    #[getter]
    fn wire_len(&self) -> Option<u64> {
        self.wire_len_value()
    }

    /// The field `len` where the message has one (the AEOLUS raw messages CALIBINFO,
    /// DEBUGINFO, LOG and UNKNOWN: their data's length), as `m["len"]`; elsewhere the
    /// deprecated name of `wire_len` (with a `DeprecationWarning`).
    #[getter]
    fn len<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        if let Some(field) = self.field_named(py, "len")? {
            return Ok(Some(field));
        }
        warn_len(py)?;
        self.wire_len_value()
            .map(|n| n.into_bound_py_any(py))
            .transpose()
    }

    /// What `protolink decode` prints about the frame before the fields: AEOLUS `id`, `len`,
    /// `crc`; AYDP `type`, `expedited`, `len`, `time`; AOK `len`; GDL90 `id`, `len`.
    #[getter]
    fn meta<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        value::dict(py, self.meta_map())
    }

    /// The fields as a new dict, exactly the `"fields"` of `protolink decode --json`.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        self.fields(py)?.copy()
    }

    /// A field as an attribute (Python asks here only when an attribute is not found, so the
    /// class's own attributes, `name` among them, come first).
    fn __getattr__<'py>(&self, py: Python<'py>, attr: &str) -> PyResult<Bound<'py, PyAny>> {
        self.field_or(py, attr, PyAttributeError::new_err)
    }

    fn __getitem__<'py>(&self, py: Python<'py>, key: &str) -> PyResult<Bound<'py, PyAny>> {
        self.field_or(py, key, PyKeyError::new_err)
    }

    fn __contains__(&self, py: Python<'_>, key: &str) -> PyResult<bool> {
        self.fields(py)?.contains(key)
    }

    fn __dir__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let list = PyList::new(py, MESSAGE_ATTRIBUTES)?;
        for k in self.fields(py)?.keys() {
            list.append(k)?;
        }
        Ok(list)
    }

    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        let mut parts = Vec::new();
        for (k, v) in self.fields(py)?.iter() {
            parts.push(format!("{}={}", k.str()?, v.repr()?));
        }
        Ok(format!("{}({})", self.name_str(), parts.join(", ")))
    }
}
}

event_methods! {
impl ErrorEvent {
    is_error: true;

    /// `ERROR`, so that `m.name` tells messages and errors apart.
    #[getter]
    fn name(&self) -> &'static str {
        "ERROR"
    }

    /// `ERROR`, as pymavlink's `get_type()`.
    fn get_type(&self) -> &'static str {
        "ERROR"
    }

    /// What went wrong: the protocol crate's error in snake case (`checksum_mismatch`,
    /// `invalid_escape`, `overflow`, `wrong_length`, `truncated`, ...).
    #[getter]
    fn kind(&self) -> &str {
        &self.kind
    }

    /// One sentence, as `protolink decode` prints it.
    #[getter]
    fn error(&self) -> &str {
        &self.error
    }

    /// Offset in the input of the first byte the error condemns (the failed frame's first
    /// byte, or its opening flag).
    #[getter]
    fn offset(&self) -> u64 {
        self.offset
    }

    /// None: an error has no message ID.
    #[getter]
    fn id(&self) -> Option<u64> {
        None
    }

    /// The length on the wire of the bytes the error condemns, from `offset`.
    #[getter]
    fn wire_len(&self) -> u64 {
        self.wire_len
    }

    /// The deprecated name of `wire_len` (with a `DeprecationWarning`).
    #[getter]
    fn len(&self, py: Python<'_>) -> PyResult<u64> {
        warn_len(py)?;
        Ok(self.wire_len)
    }

    /// `{"kind": ..., "error": ...}`.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        d.set_item("kind", &self.kind)?;
        d.set_item("error", &self.error)?;
        Ok(d)
    }

    fn __repr__(&self) -> String {
        format!(
            "ERROR(kind={:?}, offset={}, error={:?})",
            self.kind, self.offset, self.error
        )
    }
}
}
