//! What the four `Decoder` classes share: feeding a buffer in bounded steps with the GIL
//! released, the lazy `feed_iter`, the end of the input, and the counters as a dict.
//!
//! A step feeds the decoder 64 KiB pieces (`PIECE`), without the GIL, until it has taken
//! 20 ms (`STEP_TIME`) or completed 4 096 events (`STEP_EVENTS`), or the input ends; its
//! events then become Python objects and `py.check_signals()` runs, so Ctrl-C (or any signal
//! handler that raises) ends a call of any length after at most one step of its work. An
//! interrupted `feed` leaves the decoder as if it had been fed the input up to a piece
//! boundary (`bytes_fed` says where), and keeps the messages of those bytes for the next
//! `feed`, `feed_iter` or `flush`: nothing is lost or decoded twice.

use std::collections::VecDeque;
use std::time::{Duration, Instant};

use pyo3::exceptions::{PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict, PyList};
use serde_json::Value;

use crate::aeolus::AeolusPyDecoder;
use crate::aok::AokPyDecoder;
use crate::aydp::AydpPyDecoder;
use crate::gdl90::Gdl90PyDecoder;
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

/// A decoder and the messages an interrupted `feed` completed, kept for the next call.
#[derive(Debug)]
pub(crate) struct Core {
    stream: Stream,
    held: Option<Py<PyList>>,
}

impl Core {
    /// A core around `stream`, holding nothing.
    pub(crate) fn new(stream: Stream) -> Self {
        Core { stream, held: None }
    }

    /// Bytes fed so far.
    pub(crate) fn bytes_fed(&self) -> u64 {
        self.stream.bytes_fed()
    }

    /// The list the next call returns: the held messages, or a new list.
    fn take_held<'py>(&mut self, py: Python<'py>) -> Bound<'py, PyList> {
        self.held
            .take()
            .map_or_else(|| PyList::empty(py), |l| l.into_bound(py))
    }

    /// Decodes `data` (bytes read in place, another buffer copied once) step by step with the
    /// GIL released, and returns the messages and error events it completed (after any an
    /// interrupted call kept). A signal handler's exception between two steps is raised with
    /// the decoder fed up to that step and its messages kept.
    pub(crate) fn feed<'py>(
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

    /// The end of the input: what the decoder still holds, reported (after any messages an
    /// interrupted `feed` kept).
    pub(crate) fn flush<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
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
    /// summary.
    pub(crate) fn stats<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        match self.stream.counters() {
            Value::Object(m) => value::dict(py, &m),
            _ => Ok(PyDict::new(py)),
        }
    }
}

/// The decoder a `FeedIter` feeds: one of the four classes.
pub(crate) enum Owner {
    /// `protolink.aeolus.Decoder`.
    Aeolus(Py<AeolusPyDecoder>),
    /// `protolink.aydp.Decoder`.
    Aydp(Py<AydpPyDecoder>),
    /// `protolink.aok.Decoder`.
    Aok(Py<AokPyDecoder>),
    /// `protolink.gdl90.Decoder`.
    Gdl90(Py<Gdl90PyDecoder>),
}

impl Owner {
    /// Runs `f` on the decoder's core, borrowed for the call (`RuntimeError` if another
    /// thread is using the decoder).
    fn with<R>(&self, py: Python<'_>, f: impl FnOnce(&mut Core) -> R) -> PyResult<R> {
        Ok(match self {
            Owner::Aeolus(d) => f(&mut d.bind(py).try_borrow_mut()?.core),
            Owner::Aydp(d) => f(&mut d.bind(py).try_borrow_mut()?.core),
            Owner::Aok(d) => f(&mut d.bind(py).try_borrow_mut()?.core),
            Owner::Gdl90(d) => f(&mut d.bind(py).try_borrow_mut()?.core),
        })
    }
}

/// The messages and error events of a buffer, decoded one step at a time as they are asked
/// for: what `Decoder.feed_iter(data)` returns. It holds at most one step's events (and,
/// before them, any an interrupted `feed` of the decoder kept).
#[pyclass(module = "protolink", name = "FeedIter")]
pub(crate) struct FeedIter {
    owner: Owner,
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
    pub(crate) fn new(owner: Owner, data: &Bound<'_, PyAny>, datagram: bool) -> PyResult<Self> {
        let py = data.py();
        let data = to_bytes(data, "feed_iter")?.unbind();
        let expected = owner.with(py, |core| core.bytes_fed())?;
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
            let (held, n, pending, proto, fed) = self.owner.with(py, |core| {
                if core.bytes_fed() != expected {
                    return Err(PyRuntimeError::new_err(format!(
                        "the decoder was fed elsewhere while feed_iter was feeding it ({} bytes fed, not {expected}): finish the iterator before feeding the decoder again",
                        core.bytes_fed()
                    )));
                }
                let held = core.held.take();
                let stream = &mut core.stream;
                let (n, pending) = py.detach(|| step(stream, rest, datagram));
                Ok((held, n, pending, core.stream.proto(), core.bytes_fed()))
            })??;
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
