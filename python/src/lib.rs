//! # protolink-python
//!
//! The `protolink` Python package's native module, `protolink._native`: the host tool's
//! decoders (`protolink::decoders`), capture reading and command line behind a thin pyo3
//! face, so that a flight decoded in Python is decoded by the very code `protolink decode` and
//! the firmware run. The Python side (`python/protolink/`) re-exports it under the names of
//! the package (`protolink.aeolus.Decoder`, `protolink.open`, ...).
//!
//! | module | holds |
//! | --- | --- |
//! | [`stream`] | the host tool's four stream decoders without Python: bytes in, pending events out |
//! | [`message`] | `Message` and `ErrorEvent`, the Python objects of those events |
//! | [`decoder`] | the `Decoder` class the four protocols' classes extend, its methods written once: `feed` and `feed_iter` (in bounded steps, GIL released, Ctrl-C between two), `finish`, `stats`, `bytes_fed`; `protocol_decoder!`, a protocol's class and constructor |
//! | [`aeolus`], [`aydp`], [`aok`], [`gdl90`] | each protocol's `Decoder` (one `protocol_decoder!`) and encoder |
//! | [`encode`] | what the encoders share: fields through serde, one sentence per refusal |
//! | [`source`] | `open`: files, captures (a cut one warned about) and live links as an iterator |
//! | [`columns`] | `to_arrow`'s tables and `export`: the host tool's typed columns handed to pyarrow through the Arrow C stream interface |
//! | [`input`] | the bytes `feed` takes: `bytes` in place, other buffers copied once |
//! | [`value`] | JSON values and Python objects |
//! | [`to_python`] | crate values straight to Python objects, rendered as `decode --json` renders them |
//! | [`cli`] | `python -m protolink decode` |
//!
//! No input makes it panic: bad bytes are error events and counters; a misuse of the API is a
//! `TypeError` or `ValueError` of one sentence. No call runs long without a look for Ctrl-C:
//! a long input is decoded in bounded steps with `py.check_signals()` between two.
#![forbid(unsafe_code)]
#![deny(missing_docs)]

use pyo3::prelude::*;

pub mod aeolus;
pub mod aok;
pub mod aydp;
pub mod cli;
pub mod columns;
pub mod decoder;
pub mod encode;
pub mod gdl90;
pub mod input;
pub mod message;
pub mod source;
pub mod stream;
pub mod to_python;
pub mod value;

/// The native module: the classes and functions the Python package re-exports.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add_class::<decoder::Decoder>()?;
    m.add("AeolusDecoder", py.get_type::<aeolus::AeolusPyDecoder>())?;
    m.add("AydpDecoder", py.get_type::<aydp::AydpPyDecoder>())?;
    m.add("AokDecoder", py.get_type::<aok::AokPyDecoder>())?;
    m.add("Gdl90Decoder", py.get_type::<gdl90::Gdl90PyDecoder>())?;
    m.add_class::<message::Message>()?;
    m.add_class::<message::ErrorEvent>()?;
    m.add_class::<source::Reader>()?;
    m.add_class::<decoder::FeedIter>()?;
    m.add_function(wrap_pyfunction!(aeolus::encode_aeolus, m)?)?;
    m.add_function(wrap_pyfunction!(aydp::encode_aydp, m)?)?;
    m.add_function(wrap_pyfunction!(aok::encode_aok, m)?)?;
    m.add_function(wrap_pyfunction!(source::open, m)?)?;
    m.add_class::<columns::ArrowTable>()?;
    m.add_function(wrap_pyfunction!(columns::file_tables, m)?)?;
    m.add_function(wrap_pyfunction!(columns::message_tables, m)?)?;
    m.add_function(wrap_pyfunction!(columns::export, m)?)?;
    m.add_function(wrap_pyfunction!(cli::run_cli, m)?)?;
    Ok(())
}
