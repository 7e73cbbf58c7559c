//! `protolink.gdl90`: the GDL90 `Decoder` (GDL90 and the ForeFlight and Stratux extensions, as
//! EFB apps receive them on UDP port 4000).

use protolink::proto::{ProfileArg, Proto, Side};
use pyo3::prelude::*;

use crate::decoder::Decoder;
use crate::stream::Stream;

/// The GDL90 stream decoder, as `protolink decode --proto gdl90` runs it. `finish()`: a frame
/// still open is a `truncated` error.
#[pyclass(extends = Decoder, module = "protolink.gdl90", name = "Decoder")]
#[derive(Debug)]
pub(crate) struct Gdl90PyDecoder;

#[pymethods]
impl Gdl90PyDecoder {
    #[new]
    fn new() -> PyClassInitializer<Self> {
        let stream = Stream::new(Proto::Gdl90, ProfileArg::Spec, Side::Device);
        Decoder::new("protolink.gdl90.Decoder", stream, None).add_subclass(Gdl90PyDecoder)
    }
}
