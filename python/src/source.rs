//! `protolink.open`: messages from a file (raw bytes, or a pcap / pcapng capture found by its
//! magic number, decoded per flow as `protolink decode` does), from `udp:PORT`,
//! `tcp:HOST:PORT` or `serial:DEVICE@BAUD`, as an iterator, in the manner of pymavlink's
//! `mavutil.mavlink_connection`. Reading and decoding run with the GIL released, a little at a
//! time (one read of at most 64 KiB, or up to 256 capture records), with a look for Ctrl-C
//! between two.
//!
//! A capture that ends inside a block (`protolink record` killed mid-write) gives every whole
//! record's messages, then, as the iteration ends, a `protolink.TruncatedCaptureWarning` that
//! names the byte offset where the cut block starts; `strict=True` raises `OSError` instead,
//! when the cut block is reached.

use std::collections::VecDeque;
use std::ffi::CString;
use std::path::PathBuf;
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use protolink::commands::decode::capture::{CaptureEvents, CaptureItem, proto_name};
use protolink::commands::decode::tables::{Report, Select};
use protolink::endpoint::{Endpoint, Input, Link};
use protolink::proto::{Proto, Side};
use pyo3::exceptions::{
    PyConnectionRefusedError, PyFileNotFoundError, PyOSError, PyPermissionError, PyRuntimeError,
    PyTypeError, PyValueError,
};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyString, PyTuple};
use serde_json::Value;

use crate::decoder::{PROFILES, SIDES, choose};
use crate::message::{Origin, to_object};
use crate::stream::{Pending, Stream};
use crate::value;

/// The protocols by name.
const PROTOS: [(&str, Proto); 4] = [
    ("aeolus", Proto::Aeolus),
    ("aydp", Proto::Aydp),
    ("aok", Proto::Aok),
    ("gdl90", Proto::Gdl90),
];

/// How long one read waits before the reader looks for Ctrl-C and its deadline.
const TICK: Duration = Duration::from_millis(100);

/// At most this many capture records are read between two looks for Ctrl-C.
const RECORDS_PER_STEP: usize = 256;

/// A host tool error as the Python exception that fits it, with its sentence.
pub(crate) fn error(e: protolink::Error) -> PyErr {
    let text = e.to_string();
    match &e {
        protolink::Error::CaptureCut { .. }
        | protolink::Error::CaptureDamaged { .. }
        | protolink::Error::Incomplete(_) => PyOSError::new_err(text),
        protolink::Error::Open { source, .. } | protolink::Error::Io { source, .. } => {
            match source.kind() {
                std::io::ErrorKind::NotFound => PyFileNotFoundError::new_err(text),
                std::io::ErrorKind::PermissionDenied => PyPermissionError::new_err(text),
                std::io::ErrorKind::ConnectionRefused => PyConnectionRefusedError::new_err(text),
                _ => PyOSError::new_err(text),
            }
        }
        protolink::Error::Endpoint { .. }
        | protolink::Error::Usage(_)
        | protolink::Error::Unsupported(_) => PyValueError::new_err(text),
        _ => PyRuntimeError::new_err(text),
    }
}

/// Where a capture is cut: the file ends inside the block at `offset`, after `frames` whole
/// records.
#[derive(Debug, Clone)]
pub(crate) struct Cut {
    /// The capture's path, as shown.
    pub(crate) path: String,
    /// Where the cut block starts.
    pub(crate) offset: u64,
    /// The whole records before it.
    pub(crate) frames: u64,
}

impl Cut {
    /// The warning's sentence.
    fn message(&self) -> String {
        format!(
            "the capture {} is cut inside the block at byte {}, after frame {}: every whole frame was read, that block was not (the first {} bytes are a whole capture)",
            self.path, self.offset, self.frames, self.offset
        )
    }
}

/// What a reader reads.
enum Source {
    /// A pcapng or pcap file, decoded per flow.
    Capture {
        /// The capture, decoded record by record.
        capture: Box<CaptureEvents>,
        /// A cut capture raises (`strict=True`) instead of ending with a warning.
        strict: bool,
        /// Where the capture was found cut, once it was.
        cut: Option<Cut>,
    },
    /// A byte stream or datagrams: a file, stdin, TCP, UDP, a serial port.
    Link {
        link: Link,
        stream: Stream,
        /// Each read is one whole datagram (UDP).
        datagrams: bool,
        /// Stamp each read with the host's clock (a live link, not a file).
        live: bool,
        buf: Vec<u8>,
    },
}

/// One step's events, each with its protocol and origin.
type Batch = Vec<(Pending, Proto, Option<Origin>)>;

impl Source {
    /// Reads a little (one read of at most [`TICK`], or up to [`RECORDS_PER_STEP`] capture
    /// records) and decodes it. `Ok(false)` once the source has ended and been flushed. A cut
    /// capture ends there (its flows are flushed), unless it is strict: then the cut is the
    /// error.
    fn step(&mut self, out: &mut Batch) -> protolink::Result<bool> {
        match self {
            Source::Capture {
                capture,
                strict,
                cut,
            } => {
                let mut items = Vec::new();
                for _ in 0..RECORDS_PER_STEP {
                    match capture.next_items(&mut items) {
                        Ok(true) => {}
                        Ok(false) => return Ok(false),
                        Err(protolink::Error::CaptureCut {
                            path,
                            offset,
                            frames,
                        }) if !*strict => {
                            *cut = Some(Cut {
                                path,
                                offset,
                                frames,
                            });
                            capture.stop();
                            continue;
                        }
                        Err(e) => return Err(e),
                    }
                    for item in items.drain(..) {
                        if let CaptureItem::Event {
                            frame,
                            time,
                            flow,
                            proto,
                            item,
                        } = item
                        {
                            let origin = Origin {
                                capture_time: Some(time),
                                flow: Some(flow),
                                frame: Some(frame),
                            };
                            out.push((item, proto, Some(origin)));
                        }
                    }
                    if !out.is_empty() {
                        break;
                    }
                }
                Ok(true)
            }
            Source::Link {
                link,
                stream,
                datagrams,
                live,
                buf,
            } => {
                let proto = stream.proto();
                let mut pending = Vec::new();
                let more = match link.read(buf, TICK)? {
                    Input::Data(n) => {
                        stream.feed(buf.get(..n).unwrap_or(&[]), *datagrams, &mut pending);
                        true
                    }
                    Input::Idle => true,
                    Input::End => {
                        stream.finish(&mut pending);
                        false
                    }
                };
                let origin = live.then(|| Origin {
                    capture_time: Some(now()),
                    ..Origin::default()
                });
                out.extend(pending.into_iter().map(|p| (p, proto, origin.clone())));
                Ok(more)
            }
        }
    }
}

fn now() -> f64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .unwrap_or(Duration::ZERO)
        .as_secs_f64()
}

/// Messages (and, unless `errors=False`, error events) from a file, capture or live link:
/// iterate it, or call `recv_match`. Close it (or use `with`) to release a socket or port.
#[pyclass(module = "protolink", name = "Reader")]
pub(crate) struct Reader {
    /// `None` once closed. In a mutex only to make the class `Sync` (stdin's reader thread
    /// hands over its chunks through a channel, which is not): every method that reads takes
    /// `&mut self`, so the lock is never contended (`get_mut`).
    source: std::sync::Mutex<Option<Source>>,
    /// The source has ended and been flushed.
    ended: bool,
    /// The cut of a capture has been warned about.
    warned: bool,
    ready: VecDeque<Py<PyAny>>,
    errors: bool,
    name: String,
}

impl Reader {
    fn source_mut(&mut self) -> Option<&mut Source> {
        self.source
            .get_mut()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .as_mut()
    }

    /// The next message or error event, waiting at most until `deadline`.
    fn next_item(
        &mut self,
        py: Python<'_>,
        deadline: Option<Instant>,
    ) -> PyResult<Option<Py<PyAny>>> {
        loop {
            if let Some(item) = self.ready.pop_front() {
                return Ok(Some(item));
            }
            let name = self.name.clone();
            let (ended, warned) = (self.ended, self.warned);
            let Some(source) = self.source_mut() else {
                return Err(PyValueError::new_err(format!(
                    "the reader of {name} is closed"
                )));
            };
            if ended {
                let cut = match source {
                    Source::Capture { cut, .. } if !warned => cut.clone(),
                    _ => None,
                };
                if let Some(cut) = cut {
                    self.warned = true;
                    warn_cut(py, &cut)?;
                }
                return Ok(None);
            }
            if deadline.is_some_and(|d| Instant::now() >= d) {
                return Ok(None);
            }
            let mut batch = Vec::new();
            let more = py.detach(|| source.step(&mut batch)).map_err(error)?;
            self.ended = !more;
            for (pending, proto, origin) in batch {
                if pending.is_error() && !self.errors {
                    continue;
                }
                self.ready
                    .push_back(to_object(py, pending, proto, origin.as_ref())?.unbind());
            }
            py.check_signals()?;
        }
    }
}

/// Issues a `protolink.TruncatedCaptureWarning` about `cut` (an exception if warnings are
/// errors).
pub(crate) fn warn_cut(py: Python<'_>, cut: &Cut) -> PyResult<()> {
    let category = py
        .import("protolink._warnings")?
        .getattr("TruncatedCaptureWarning")?;
    let text = CString::new(cut.message())
        .map_err(|_| PyValueError::new_err("the capture's path holds a NUL byte"))?;
    PyErr::warn(py, &category, &text, 1)
}

/// Issues a `protolink.DamagedCaptureWarning` (an exception if warnings are errors) about the
/// damage `report` counts in the capture at `path`; nothing when it has none.
pub(crate) fn warn_damaged(py: Python<'_>, path: &str, report: &Report) -> PyResult<()> {
    let Some(text) = damage_sentence(path, report) else {
        return Ok(());
    };
    let category = py
        .import("protolink._warnings")?
        .getattr("DamagedCaptureWarning")?;
    let text = CString::new(text)
        .map_err(|_| PyValueError::new_err("the capture's path holds a NUL byte"))?;
    PyErr::warn(py, &category, &text, 1)
}

/// What `report` says of the damage in the capture at `path`, if it holds any.
pub(crate) fn damage_sentence(path: &str, report: &Report) -> Option<String> {
    let one = report.damaged == 1;
    (report.damaged > 0).then(|| {
        format!(
            "the capture {path} holds {} damaged {} of {} bytes, the first at byte {}: {} skipped, every whole record around {} was read",
            report.damaged,
            if one { "region" } else { "regions" },
            report.lost,
            report.first_damage.unwrap_or_default(),
            if one { "it was" } else { "they were" },
            if one { "it" } else { "them" },
        )
    })
}

/// The names `recv_match(type=...)` accepts: one name or a list of names.
fn wanted(types: Option<&Bound<'_, PyAny>>) -> PyResult<Option<Vec<String>>> {
    let Some(t) = types.filter(|t| !t.is_none()) else {
        return Ok(None);
    };
    if let Ok(s) = t.cast::<PyString>() {
        return Ok(Some(vec![s.to_cow()?.into_owned()]));
    }
    if t.is_instance_of::<PyList>() || t.is_instance_of::<PyTuple>() {
        return t.extract::<Vec<String>>().map(Some).map_err(|_| {
            PyTypeError::new_err("recv_match(type=...) takes a message name or a list of names")
        });
    }
    Err(PyTypeError::new_err(
        "recv_match(type=...) takes a message name or a list of names",
    ))
}

#[pymethods]
impl Reader {
    fn __iter__(slf: PyRef<'_, Self>) -> PyRef<'_, Self> {
        slf
    }

    fn __next__(&mut self, py: Python<'_>) -> PyResult<Option<Py<PyAny>>> {
        self.next_item(py, None)
    }

    /// The next message named `type` (a name or a list of names; any message when None),
    /// waiting at most `timeout` seconds (for ever when None); None when the time is up or
    /// the source has ended. Error events are never matched.
    #[pyo3(signature = (r#type = None, timeout = None))]
    fn recv_match(
        &mut self,
        py: Python<'_>,
        r#type: Option<&Bound<'_, PyAny>>,
        timeout: Option<f64>,
    ) -> PyResult<Option<Py<PyAny>>> {
        let names = wanted(r#type)?;
        let deadline = match timeout {
            None => None,
            Some(t) if t.is_finite() && t >= 0.0 => {
                Some(Instant::now() + Duration::from_secs_f64(t.min(1e9)))
            }
            Some(t) => {
                return Err(PyValueError::new_err(format!(
                    "timeout is a number of seconds, 0 or more, not {t}"
                )));
            }
        };
        while let Some(item) = self.next_item(py, deadline)? {
            let b = item.bind(py);
            if b.getattr("is_error")?.is_truthy()? {
                continue;
            }
            let matches = match &names {
                None => true,
                Some(names) => {
                    // The message's name, even where a field is named `name`.
                    let name: String = b.call_method0("get_type")?.extract()?;
                    names.contains(&name)
                }
            };
            if matches {
                return Ok(Some(item));
            }
        }
        Ok(None)
    }

    /// The counters: of the decoder, for a byte source; for a capture, a dict from each flow
    /// to its decoder's counters (`protolink decode`'s summary line of that flow).
    #[getter]
    fn stats<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        match self.source_mut() {
            Some(Source::Link { stream, .. }) => match stream.counters() {
                Value::Object(m) => value::dict(py, &m),
                _ => Ok(PyDict::new(py)),
            },
            Some(Source::Capture { capture, .. }) => {
                let d = PyDict::new(py);
                for (flow, proto, bytes, counters) in capture.flows() {
                    let entry = PyDict::new(py);
                    entry.set_item("proto", proto_name(proto))?;
                    entry.set_item("bytes", bytes)?;
                    entry.set_item("counters", value::to_py(py, &counters)?)?;
                    d.set_item(flow, entry)?;
                }
                Ok(d)
            }
            None => Ok(PyDict::new(py)),
        }
    }

    /// Where a capture was found cut: the byte offset of the block the file ends inside
    /// (its first `truncated_at` bytes are a whole capture); None for a whole capture (so
    /// far) and for other sources.
    #[getter]
    fn truncated_at(&mut self) -> Option<u64> {
        match self.source_mut() {
            Some(Source::Capture { cut: Some(cut), .. }) => Some(cut.offset),
            _ => None,
        }
    }

    /// What is read, as the endpoint syntax writes it (`file:flight.pcapng`, `udp:127.0.0.1:5001`).
    #[getter]
    fn source(&self) -> &str {
        &self.name
    }

    /// Releases the file, socket or port; the messages already read are dropped.
    fn close(&mut self) {
        *self
            .source
            .get_mut()
            .unwrap_or_else(std::sync::PoisonError::into_inner) = None;
        self.ready.clear();
    }

    fn __enter__(slf: PyRef<'_, Self>) -> PyRef<'_, Self> {
        slf
    }

    #[pyo3(signature = (*_args))]
    fn __exit__(&mut self, _args: &Bound<'_, PyTuple>) -> bool {
        self.close();
        false
    }

    fn __repr__(&self) -> String {
        format!("protolink.Reader({:?})", self.name)
    }
}

/// The endpoint `source` names: a path (str or os.PathLike) or `udp:`, `tcp:`, `serial:`,
/// `file:`, `-`.
pub(crate) fn endpoint(source: &Bound<'_, PyAny>) -> PyResult<Endpoint> {
    if let Ok(s) = source.cast::<PyString>() {
        return s.to_cow()?.parse::<Endpoint>().map_err(error);
    }
    match source.extract::<PathBuf>() {
        Ok(path) => Ok(Endpoint::File(path)),
        Err(_) => Err(PyTypeError::new_err(format!(
            "open takes a path or an endpoint such as 'udp:5001', not {}",
            value::type_name(source)
        ))),
    }
}

/// The decoder choice of `proto=`, `profile=` and `side=` (each a name, or None).
pub(crate) fn select(
    proto: Option<&Bound<'_, PyAny>>,
    profile: Option<&Bound<'_, PyAny>>,
    side: Option<&Bound<'_, PyAny>>,
) -> PyResult<Select> {
    let proto = proto.map(|p| choose("proto", p, &PROTOS)).transpose()?;
    let profile = profile
        .map(|p| choose("profile", p, &PROFILES))
        .transpose()?;
    let side = side.map_or(Ok(Side::Device), |s| choose("side", s, &SIDES))?;
    Ok(Select {
        proto,
        profile,
        side,
    })
}

/// Opens `source` for reading: see the module's documentation. `strict=True`: a cut capture
/// raises `OSError` instead of ending with a `TruncatedCaptureWarning`.
#[pyfunction(name = "open")]
#[pyo3(signature = (source, proto = None, *, profile = None, side = None, errors = true, strict = false))]
pub(crate) fn open(
    py: Python<'_>,
    source: &Bound<'_, PyAny>,
    proto: Option<&Bound<'_, PyAny>>,
    profile: Option<&Bound<'_, PyAny>>,
    side: Option<&Bound<'_, PyAny>>,
    errors: bool,
    strict: bool,
) -> PyResult<Reader> {
    let endpoint = endpoint(source)?;
    let Select {
        proto,
        profile,
        side,
    } = select(proto, profile, side)?;
    let name = endpoint.to_string();
    let source = match &endpoint {
        Endpoint::File(path) if protolink::capture::file_is_capture(path) => {
            let select = Select {
                proto,
                profile,
                side,
            };
            let capture = py
                .detach(|| CaptureEvents::open(path, &select))
                .map_err(error)?;
            Source::Capture {
                capture: Box::new(capture),
                strict,
                cut: None,
            }
        }
        _ => {
            let Some(proto) = proto else {
                return Err(PyValueError::new_err(format!(
                    "open needs proto= for {name}: only a pcapng or pcap capture names its protocols"
                )));
            };
            let link = py.detach(|| endpoint.open()).map_err(error)?;
            Source::Link {
                datagrams: link.is_datagram(),
                live: !matches!(endpoint, Endpoint::File(_) | Endpoint::Stdio),
                link,
                stream: Stream::new(proto, profile.unwrap_or_default(), side),
                buf: vec![0u8; 64 * 1024],
            }
        }
    };
    Ok(Reader {
        source: std::sync::Mutex::new(Some(source)),
        ended: false,
        warned: false,
        ready: VecDeque::new(),
        errors,
        name,
    })
}
