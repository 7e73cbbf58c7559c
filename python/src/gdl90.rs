//! `protolink.gdl90`: the GDL90 `Decoder` (GDL90 and the ForeFlight and Stratux extensions, as
//! EFB apps receive them on UDP port 4000).

use protolink::proto::{ProfileArg, Proto, Side};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::decoder::{Core, FeedIter, Owner};
use crate::stream::Stream;

/// The GDL90 stream decoder, as `protolink decode --proto gdl90` runs it.
#[pyclass(module = "protolink.gdl90", name = "Decoder")]
#[derive(Debug)]
pub(crate) struct Gdl90PyDecoder {
    pub(crate) core: Core,
}

#[pymethods]
impl Gdl90PyDecoder {
    #[new]
    fn new() -> Self {
        Gdl90PyDecoder {
            core: Core::new(Stream::new(Proto::Gdl90, ProfileArg::Spec, Side::Device)),
        }
    }

    /// Decodes `data` (bytes, bytearray, memoryview); returns the messages and error events it
    /// completed. `datagram=True`: the bytes are one whole UDP datagram.
    ///
    /// The list holds every message of `data` (a Python object each): over a big input,
    /// `feed_iter` keeps memory bounded. The bytes are decoded in steps (64 KiB pieces until
    /// 20 ms or 4 096 events) and Ctrl-C raises `KeyboardInterrupt` between two: the decoder
    /// has then been fed `data` up to a 64 KiB boundary (`bytes_fed` says where) and keeps
    /// the messages of those bytes for the next `feed`, `feed_iter` or `flush`.
    #[pyo3(signature = (data, /, datagram = false))]
    fn feed<'py>(
        &mut self,
        py: Python<'py>,
        data: &Bound<'py, PyAny>,
        datagram: bool,
    ) -> PyResult<Bound<'py, PyList>> {
        self.core.feed(py, data, datagram)
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
        FeedIter::new(Owner::Gdl90(slf.unbind()), data, datagram)
    }

    /// The end of the input: a frame still open is reported as a `truncated` error.
    /// Messages an interrupted `feed` kept come first.
    fn flush<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        self.core.flush(py)
    }

    /// The counters: the crate's `Stats` plus `truncated`.
    #[getter]
    fn stats<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        self.core.stats(py)
    }

    /// Bytes fed so far.
    #[getter]
    fn bytes_fed(&self) -> u64 {
        self.core.bytes_fed()
    }

    fn __repr__(&self) -> String {
        format!(
            "protolink.gdl90.Decoder(bytes_fed={})",
            self.core.bytes_fed()
        )
    }
}
