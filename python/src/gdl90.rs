//! `protolink.gdl90`: the GDL90 `Decoder` (GDL90 and the ForeFlight and Stratux extensions, as
//! EFB apps receive them on UDP port 4000).

use protolink::proto::{ProfileArg, Proto, Side};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::stream::Stream;

/// The GDL90 stream decoder, as `protolink decode --proto gdl90` runs it.
#[pyclass(module = "protolink.gdl90", name = "Decoder")]
#[derive(Debug)]
pub(crate) struct Gdl90PyDecoder {
    stream: Stream,
}

#[pymethods]
impl Gdl90PyDecoder {
    #[new]
    fn new() -> Self {
        Gdl90PyDecoder {
            stream: Stream::new(Proto::Gdl90, ProfileArg::Spec, Side::Device),
        }
    }

    /// Decodes `data` (bytes, bytearray, memoryview); returns the messages and error events it
    /// completed. `datagram=True`: the bytes are one whole UDP datagram.
    #[pyo3(signature = (data, /, datagram = false))]
    fn feed<'py>(
        &mut self,
        py: Python<'py>,
        data: &Bound<'py, PyAny>,
        datagram: bool,
    ) -> PyResult<Bound<'py, PyList>> {
        crate::decoder::feed(py, &mut self.stream, data, datagram)
    }

    /// The end of the input: a frame still open is reported as a `truncated` error.
    fn flush<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        crate::decoder::flush(py, &mut self.stream)
    }

    /// The counters: the crate's `Stats` plus `truncated`.
    #[getter]
    fn stats<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        crate::decoder::stats(py, &self.stream)
    }

    /// Bytes fed so far.
    #[getter]
    fn bytes_fed(&self) -> u64 {
        self.stream.bytes_fed()
    }

    fn __repr__(&self) -> String {
        format!(
            "protolink.gdl90.Decoder(bytes_fed={})",
            self.stream.bytes_fed()
        )
    }
}
