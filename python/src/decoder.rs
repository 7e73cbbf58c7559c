//! The `Decoder` class the four protocols' classes extend: feeding a buffer in bounded steps
//! with the GIL released, the lazy `feed_iter`, the end of the input (`finish`), and the
//! counters as a dict, written once.
//!
//! A step feeds the decoder 64 KiB pieces (`PIECE`), without the GIL, until it has taken
//! 20 ms (`STEP_TIME`) or completed 4 096 events (`STEP_EVENTS`), or the input ends; its
//! events then become Python objects and `py.check_signals()` runs, so Ctrl-C (or any signal
//! handler that raises) ends a call of any length after at most one step of its work. An
//! interrupted `feed` leaves the decoder as if it had been fed the input up to a piece
//! boundary (`bytes_fed` says where), and keeps the messages of those bytes for the next
//! `feed`, `feed_iter` or `finish`: nothing is lost or decoded twice.

use std::collections::VecDeque;
use std::time::{Duration, Instant};

use protolink::proto::{ProfileArg, Side};
use pyo3::exceptions::{PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict, PyList};
use serde_json::Value;

use crate::input::{Input, to_bytes};
use crate::message::to_object;
use crate::stream::{Pending, Stream};
use crate::value;

/// The most bytes the decoder is fed at once: 64 KiB, at least a UDP datagram (whose end is
/// marked after its last piece).
pub(crate) const PIECE: usize = 64 * 1024;

/// A step ends after the piece that takes it past this long: the longest the decoder keeps a
/// signal waiting, but for one piece (and the Python objects of the step's events).
pub(crate) const STEP_TIME: Duration = Duration::from_millis(20);

/// A step ends after the piece that brings its events to this many, so that the events waiting
/// to become Python objects stay few: at most this many and one piece's (`feed_iter` holds at
/// most one step's).
pub(crate) const STEP_EVENTS: usize = 4096;

/// One step: feeds `stream` pieces of `bytes` until [`STEP_TIME`] or [`STEP_EVENTS`] is
/// reached or `bytes` ends; returns how many bytes it fed and its events. `datagram`: `bytes`
/// ends a datagram, marked when its last piece is fed (an empty `bytes` is one empty piece).
fn step(stream: &mut Stream, bytes: &[u8], datagram: bool) -> (usize, Vec<Pending>) {
    let started = Instant::now();
    let mut out = Vec::new();
    let mut at = 0;
    loop {
        let end = bytes.len().min(at + PIECE);
        stream.feed(
            bytes.get(at..end).unwrap_or(&[]),
            datagram && end == bytes.len(),
            &mut out,
        );
        at = end;
        if at == bytes.len() || out.len() >= STEP_EVENTS || started.elapsed() >= STEP_TIME {
            return (at, out);
        }
    }
}

/// The class every protocol's `Decoder` extends (`protolink.aeolus.Decoder`, ...): the
/// decoding methods, written once. A protocol's class ([`protocol_decoder!`]) adds only its
/// constructor (and the getter of its setting, AYDP's `profile` or AOK's `side`).
///
/// The one loop: `d.feed(data)` for every piece of the input, `d.finish()` at its end.
#[pyclass(module = "protolink._native", name = "Decoder", subclass)]
#[derive(Debug)]
pub(crate) struct Decoder {
    stream: Stream,
    /// The messages an interrupted `feed` completed, kept for the next call.
    held: Option<Py<PyList>>,
    /// The class's Python name, for `repr`: `protolink.aydp.Decoder`.
    class: &'static str,
    /// The constructor's setting, for `repr`: `("profile", "spec")`.
    setting: Option<(&'static str, &'static str)>,
}

impl Decoder {
    /// The base of `class` (its Python name) around `stream`, holding nothing; `setting` is
    /// the constructor argument its `repr` shows. A protocol's `#[new]` adds its class with
    /// `add_subclass`.
    pub(crate) fn new(
        class: &'static str,
        stream: Stream,
        setting: Option<(&'static str, &'static str)>,
    ) -> PyClassInitializer<Self> {
        PyClassInitializer::from(Decoder {
            stream,
            held: None,
            class,
            setting,
        })
    }

    /// The list the next call returns: the held messages, or a new list.
    fn take_held<'py>(&mut self, py: Python<'py>) -> Bound<'py, PyList> {
        self.held
            .take()
            .map_or_else(|| PyList::empty(py), |l| l.into_bound(py))
    }
}

#[pymethods]
impl Decoder {
    /// Decodes `data` (bytes, bytearray, memoryview); returns the messages and error events it
    /// completed. `datagram=True`: the bytes are one whole UDP datagram (a frame never spans
    /// two).
    ///
    /// The list holds every message of `data` (a Python object each): over a big input,
    /// `feed_iter` keeps memory bounded. The bytes are decoded in steps (64 KiB pieces until
    /// 20 ms or 4 096 events) with the GIL released, and Ctrl-C raises `KeyboardInterrupt`
    /// between two: the decoder has then been fed `data` up to a 64 KiB boundary (`bytes_fed`
    /// says where) and keeps the messages of those bytes for the next `feed`, `feed_iter` or
    /// `finish`.
    #[pyo3(signature = (data, /, datagram = false))]
    fn feed<'py>(
        &mut self,
        py: Python<'py>,
        data: &Bound<'py, PyAny>,
        datagram: bool,
    ) -> PyResult<Bound<'py, PyList>> {
        let input = Input::extract(data, "feed")?;
        let bytes = input.as_slice();
        let proto = self.stream.proto();
        let list = self.take_held(py);
        let mut at = 0;
        loop {
            let rest = bytes.get(at..).unwrap_or(&[]);
            let stream = &mut self.stream;
            let (n, pending) = py.detach(|| step(stream, rest, datagram));
            at += n;
            for p in pending {
                list.append(to_object(py, p, proto, None)?)?;
            }
            if at >= bytes.len() {
                return Ok(list);
            }
            if let Err(e) = py.check_signals() {
                self.held = Some(list.unbind());
                return Err(e);
            }
        }
    }

    /// Decodes `data` lazily: an iterator of the messages and error events `feed` would
    /// return, decoded one step (64 KiB pieces until 20 ms or 4 096 events) at a time as it is
    /// read, so that memory stays bounded whatever the length of `data`; Ctrl-C lands between
    /// two steps, and iterating again goes on where it stopped. Feed the decoder nothing else
    /// until it ends (a `RuntimeError` says so).
    #[pyo3(signature = (data, /, datagram = false))]
    fn feed_iter(
        slf: Bound<'_, Self>,
        data: &Bound<'_, PyAny>,
        datagram: bool,
    ) -> PyResult<FeedIter> {
        FeedIter::new(slf.unbind(), data, datagram)
    }

    /// The end of the input: what the decoder still holds is reported (a frame still open is
    /// a `truncated` error; AYDP and AOK then rescan what followed its first byte). Messages
    /// an interrupted `feed` kept come first.
    fn finish<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let proto = self.stream.proto();
        let list = self.take_held(py);
        let mut out = Vec::new();
        self.stream.finish(&mut out);
        for p in out {
            list.append(to_object(py, p, proto, None)?)?;
        }
        Ok(list)
    }

    /// The counters as a dict, exactly the `"counters"` of `protolink decode --json`'s
    /// summary: the crate's `Stats` plus the host tool's `malformed` and `truncated` where
    /// the protocol has them.
    #[getter]
    fn stats<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        match self.stream.counters() {
            Value::Object(m) => value::dict(py, &m),
            _ => Ok(PyDict::new(py)),
        }
    }

    /// Bytes fed so far.
    #[getter]
    fn bytes_fed(&self) -> u64 {
        self.stream.bytes_fed()
    }

    fn __repr__(&self) -> String {
        let setting = self
            .setting
            .map_or_else(String::new, |(key, value)| format!("{key}={value:?}, "));
        format!(
            "{}({setting}bytes_fed={})",
            self.class,
            self.stream.bytes_fed()
        )
    }
}

/// The messages and error events of a buffer, decoded one step at a time as they are asked
/// for: what `Decoder.feed_iter(data)` returns. It holds at most one step's events (and,
/// before them, any an interrupted `feed` of the decoder kept).
#[pyclass(module = "protolink", name = "FeedIter")]
pub(crate) struct FeedIter {
    owner: Py<Decoder>,
    data: Py<PyBytes>,
    datagram: bool,
    /// Bytes of `data` fed so far.
    at: usize,
    /// The decoder's `bytes_fed` when this iterator last fed it.
    expected: u64,
    /// Every byte of `data` has been fed (an empty `data` once, for its datagram end).
    done: bool,
    ready: VecDeque<Py<PyAny>>,
}

impl FeedIter {
    /// An iterator over what `owner` decodes of `data` (bytes kept as they are, another
    /// buffer copied once).
    fn new(owner: Py<Decoder>, data: &Bound<'_, PyAny>, datagram: bool) -> PyResult<Self> {
        let py = data.py();
        let data = to_bytes(data, "feed_iter")?.unbind();
        let expected = owner.bind(py).try_borrow()?.bytes_fed();
        Ok(FeedIter {
            owner,
            data,
            datagram,
            at: 0,
            expected,
            done: false,
            ready: VecDeque::new(),
        })
    }
}

#[pymethods]
impl FeedIter {
    fn __iter__(slf: PyRef<'_, Self>) -> PyRef<'_, Self> {
        slf
    }

    fn __next__(&mut self, py: Python<'_>) -> PyResult<Option<Py<PyAny>>> {
        loop {
            if let Some(item) = self.ready.pop_front() {
                return Ok(Some(item));
            }
            if self.done {
                return Ok(None);
            }
            let bytes = self.data.bind(py).as_bytes();
            let rest = bytes.get(self.at..).unwrap_or(&[]);
            let (expected, datagram) = (self.expected, self.datagram);
            let (held, n, pending, proto, fed) = {
                // `RuntimeError` if another thread is using the decoder.
                let mut core = self.owner.bind(py).try_borrow_mut()?;
                if core.bytes_fed() != expected {
                    return Err(PyRuntimeError::new_err(format!(
                        "the decoder was fed elsewhere while feed_iter was feeding it ({} bytes fed, not {expected}): finish the iterator before feeding the decoder again",
                        core.bytes_fed()
                    )));
                }
                let held = core.held.take();
                let stream = &mut core.stream;
                let (n, pending) = py.detach(|| step(stream, rest, datagram));
                (held, n, pending, core.stream.proto(), core.bytes_fed())
            };
            self.at += n;
            self.expected = fed;
            self.done = self.at >= bytes.len();
            if let Some(held) = held {
                self.ready.extend(held.bind(py).iter().map(Bound::unbind));
            }
            for p in pending {
                self.ready
                    .push_back(to_object(py, p, proto, None)?.unbind());
            }
            py.check_signals()?;
        }
    }

    /// Bytes of the buffer not yet fed to the decoder.
    #[getter]
    fn bytes_left(&self, py: Python<'_>) -> usize {
        self.data.bind(py).as_bytes().len().saturating_sub(self.at)
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        format!(
            "protolink.FeedIter(bytes_left={}, ready={})",
            self.bytes_left(py),
            self.ready.len()
        )
    }
}

/// The AYDP profiles by name, the default first.
pub(crate) const PROFILES: [(&str, ProfileArg); 2] = [
    ("spec", ProfileArg::Spec),
    ("reference", ProfileArg::Reference),
];

/// The AOK sides by name (who sent the bytes), the default first.
pub(crate) const SIDES: [(&str, Side); 2] = [("device", Side::Device), ("pc", Side::Pc)];

/// A protocol's `Decoder` class, written once: the class (extending [`Decoder`]), its
/// constructor and, for a decoder with a setting (AYDP's `profile`, AOK's `side`), the setting's
/// getter. Without a setting: `protocol_decoder!(docs Class, "protolink.x", proto)`. With one:
/// `..., proto, docs setting in CHOICES => |v| (profile, side), docs`: the constructor's
/// argument `setting` picks `v` from `CHOICES` (the first when it is None), and the decoder
/// is built for that profile and side.
macro_rules! protocol_decoder {
    ($(#[$doc:meta])* $class:ident, $module:tt, $proto:expr) => {
        $(#[$doc])*
        #[::pyo3::pyclass(extends = $crate::decoder::Decoder, module = $module, name = "Decoder")]
        #[derive(Debug)]
        pub(crate) struct $class;

        #[::pyo3::pymethods]
        impl $class {
            #[new]
            fn new() -> ::pyo3::PyClassInitializer<Self> {
                use ::protolink::proto::{ProfileArg, Side};
                let stream = $crate::stream::Stream::new($proto, ProfileArg::Spec, Side::Device);
                let base = $crate::decoder::Decoder::new(concat!($module, ".Decoder"), stream, None);
                base.add_subclass($class)
            }
        }
    };
    ($(#[$doc:meta])* $class:ident, $module:tt, $proto:expr,
     $(#[$new_doc:meta])* $key:ident in $choices:expr => |$v:ident| ($profile:expr, $side:expr),
     $(#[$get_doc:meta])*) => {
        $(#[$doc])*
        #[::pyo3::pyclass(extends = $crate::decoder::Decoder, module = $module, name = "Decoder")]
        #[derive(Debug)]
        pub(crate) struct $class {
            $key: &'static str,
        }

        #[::pyo3::pymethods]
        impl $class {
            $(#[$new_doc])*
            #[new]
            #[pyo3(signature = ($key = None))]
            fn new(
                $key: Option<&::pyo3::Bound<'_, ::pyo3::PyAny>>,
            ) -> ::pyo3::PyResult<::pyo3::PyClassInitializer<Self>> {
                let ($key, $v) = $crate::decoder::setting(stringify!($key), $key, &$choices)?;
                let stream = $crate::stream::Stream::new($proto, $profile, $side);
                let setting = Some((stringify!($key), $key));
                let base = $crate::decoder::Decoder::new(concat!($module, ".Decoder"), stream, setting);
                Ok(base.add_subclass($class { $key }))
            }

            $(#[$get_doc])*
            #[getter]
            fn $key(&self) -> &'static str {
                self.$key
            }
        }
    };
}
pub(crate) use protocol_decoder;

/// A decoder's setting: `arg` as one of `choices` ([`choice`]), the first when `arg` is None.
pub(crate) fn setting<T: Copy>(
    what: &str,
    arg: Option<&Bound<'_, PyAny>>,
    choices: &[(&'static str, T)],
) -> PyResult<(&'static str, T)> {
    match (arg, choices.first()) {
        (Some(a), _) => choice(what, a, choices),
        (None, Some(first)) => Ok(*first),
        (None, None) => Err(PyValueError::new_err(format!("{what} has no choices"))),
    }
}

/// `arg` as one of `choices` (by name), or an exception naming them: `ValueError` for another
/// string, `TypeError` for anything else.
pub(crate) fn choose<T: Copy>(
    what: &str,
    arg: &Bound<'_, PyAny>,
    choices: &[(&'static str, T)],
) -> PyResult<T> {
    choice(what, arg, choices).map(|(_, v)| v)
}

/// [`choose`], with the name chosen: a decoder's setting as its `repr` shows it.
fn choice<T: Copy>(
    what: &str,
    arg: &Bound<'_, PyAny>,
    choices: &[(&'static str, T)],
) -> PyResult<(&'static str, T)> {
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
        .copied()
        .ok_or_else(|| PyValueError::new_err(format!("{what} is {names}, not '{text}'")))
}
