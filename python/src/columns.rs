//! Columns for pyarrow: a file's messages (or messages already decoded) as one table per message
//! type, built by the host tool's `columns` module with the GIL released, and handed to pyarrow
//! through the Arrow C stream interface (`__arrow_c_stream__`): no Python object per message,
//! no copy of the columns. `export` writes the tables as `protolink export` does.

use std::ops::ControlFlow;
use std::path::PathBuf;

use arrow_array::ffi_stream::FFI_ArrowArrayStream;
use arrow_array::{RecordBatch, RecordBatchIterator};
use arrow_schema::{ArrowError, SchemaRef};
use protolink::columns::write::{Export, Format};
use protolink::columns::{Keep, ROW_GROUP, Tables, proto_of, unify};
use protolink::commands::decode::tables::{Report, Select, read_file};
use protolink::endpoint::Endpoint;
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyCapsule, PyDict, PyList, PyTuple};

use crate::message::add_row;
use crate::source::{Cut, damage_sentence, endpoint, error, select, warn_cut, warn_damaged};

/// One message type's rows: record batches of one schema, read by pyarrow through
/// `__arrow_c_stream__` (`pyarrow.table(t)`, `pyarrow.RecordBatchReader.from_stream(t)`).
#[pyclass(frozen, module = "protolink", name = "ArrowTable")]
pub(crate) struct ArrowTable {
    schema: SchemaRef,
    batches: Vec<RecordBatch>,
}

#[pymethods]
impl ArrowTable {
    /// The rows as an Arrow C stream, in a capsule named `arrow_array_stream` (the Arrow
    /// PyCapsule interface). A requested schema is not honoured: the stream has its own.
    #[pyo3(signature = (requested_schema = None))]
    fn __arrow_c_stream__<'py>(
        &self,
        py: Python<'py>,
        requested_schema: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyCapsule>> {
        let _ = requested_schema;
        let batches: Vec<Result<RecordBatch, ArrowError>> =
            self.batches.iter().cloned().map(Ok).collect();
        let reader = RecordBatchIterator::new(batches, self.schema.clone());
        let stream = FFI_ArrowArrayStream::new(Box::new(reader));
        PyCapsule::new_with_value(py, stream, c"arrow_array_stream")
    }

    /// Rows.
    fn __len__(&self) -> usize {
        self.batches.iter().map(RecordBatch::num_rows).sum()
    }

    /// The column names, in order.
    #[getter]
    fn column_names(&self) -> Vec<String> {
        self.schema
            .fields()
            .iter()
            .map(|f| f.name().clone())
            .collect()
    }

    fn __repr__(&self) -> String {
        format!(
            "ArrowTable({} rows, {} columns)",
            self.__len__(),
            self.schema.fields().len()
        )
    }
}

/// The tables of `tables`' batches, by message type (in the order the types first came),
/// without `ERROR` unless `errors`. A name that two protocols' tables share (AYDP's and
/// GDL90's `HEARTBEAT`) is the key of neither: each is `PROTO.NAME`.
fn to_dict<'py>(
    py: Python<'py>,
    batches: Vec<(String, RecordBatch)>,
    errors: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let mut by_type: Vec<(Option<String>, String, Vec<RecordBatch>)> = Vec::new();
    for (name, batch) in batches {
        let proto = proto_of(&batch).map(str::to_owned);
        match by_type
            .iter_mut()
            .find(|(p, n, _)| *n == name && *p == proto)
        {
            Some((_, _, list)) => list.push(batch),
            None => by_type.push((proto, name, vec![batch])),
        }
    }
    let shared = |name: &str| by_type.iter().filter(|(_, n, _)| n == name).count() > 1;
    let keys: Vec<String> = by_type
        .iter()
        .map(|(proto, name, _)| match proto {
            Some(p) if shared(name) => format!("{p}.{name}"),
            _ => name.clone(),
        })
        .collect();
    let d = PyDict::new(py);
    for (key, (_, name, list)) in keys.into_iter().zip(by_type) {
        if name == "ERROR" && !errors {
            continue;
        }
        let (schema, batches) = unify(list);
        d.set_item(key, ArrowTable { schema, batches })?;
    }
    Ok(d)
}

/// The tables of a file (a capture, or raw bytes of `proto`): a dict of `ArrowTable`s by
/// message type, or None when `source` names no file (an endpoint such as `udp:5001`, which
/// the package reads through `open` instead).
#[pyfunction]
#[pyo3(signature = (source, proto = None, *, profile = None, side = None, errors = true, strict = false, row_group = ROW_GROUP))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn file_tables<'py>(
    py: Python<'py>,
    source: &Bound<'py, PyAny>,
    proto: Option<&Bound<'py, PyAny>>,
    profile: Option<&Bound<'py, PyAny>>,
    side: Option<&Bound<'py, PyAny>>,
    errors: bool,
    strict: bool,
    row_group: usize,
) -> PyResult<Option<Bound<'py, PyDict>>> {
    let Endpoint::File(path) = endpoint(source)? else {
        return Ok(None);
    };
    let choice = select(proto, profile, side)?;
    let mut tables = Tables::new(row_group);
    let mut batches = Vec::new();
    let report = read(py, &path, &choice, None, &mut tables, |full| {
        batches.extend(full);
        Ok(())
    })?;
    batches.extend(tables.finish());
    if let Some(offset) = report.cut_at {
        let cut = Cut {
            path: path.display().to_string(),
            offset,
            frames: report.records_before_cut,
        };
        if strict {
            return Err(PyOSError::new_err(
                protolink::Error::CaptureCut {
                    path: cut.path,
                    offset,
                    frames: cut.frames,
                }
                .to_string(),
            ));
        }
        warn_cut(py, &cut)?;
    }
    let shown = path.display().to_string();
    if strict && let Some(sentence) = damage_sentence(&shown, &report) {
        return Err(PyOSError::new_err(sentence));
    }
    warn_damaged(py, &shown, &report)?;
    Ok(Some(to_dict(py, batches, errors)?))
}

/// Reads a file into `tables` with the GIL released, looking for Ctrl-C after each step and
/// handing each step's full batches to `full`.
fn read(
    py: Python<'_>,
    path: &std::path::Path,
    choice: &Select,
    source: Option<&str>,
    tables: &mut Tables,
    mut full: impl FnMut(Vec<(String, RecordBatch)>) -> protolink::Result<()> + Send,
) -> PyResult<Report> {
    // Ctrl-C's exception, kept while the reading unwinds.
    let mut interrupt = None;
    let result = py.detach(|| {
        read_file(path, choice, source, tables, |t| {
            full(t.take_full())?;
            Ok(match Python::attach(|py| py.check_signals()) {
                Err(e) => {
                    interrupt = Some(e);
                    ControlFlow::Break(())
                }
                Ok(()) => ControlFlow::Continue(()),
            })
        })
    });
    match (result, interrupt) {
        (_, Some(e)) => Err(e),
        (Err(e), None) => Err(error(e)),
        (Ok(report), None) => Ok(report),
    }
}

/// The tables of messages already decoded (`Message` and `ErrorEvent` objects, e.g. a
/// `Reader` or the list `Decoder.feed` returns), by message type.
#[pyfunction]
#[pyo3(signature = (messages, *, errors = true))]
pub(crate) fn message_tables<'py>(
    py: Python<'py>,
    messages: &Bound<'py, PyAny>,
    errors: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let mut tables = Tables::new(ROW_GROUP);
    let mut batches = Vec::new();
    for (i, m) in messages.try_iter()?.enumerate() {
        add_row(&m?, &mut tables)?;
        if i % 4096 == 4095 {
            batches.extend(tables.take_full());
            py.check_signals()?;
        }
    }
    batches.extend(tables.finish());
    to_dict(py, batches, errors)
}

/// Writes files (captures, raw bytes of `proto`) as tables under `out`, one directory per
/// message type, as `protolink export` does; returns `[(type, rows, [part paths])]`. A
/// capture's damage is skipped with a `DamagedCaptureWarning`; a source that cannot be read
/// is raised once the other sources are exported.
#[pyfunction]
#[pyo3(signature = (sources, out, format = "parquet", proto = None, *, profile = None, side = None, row_group = ROW_GROUP, types = Vec::new(), since = None, until = None, air = false))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn export<'py>(
    py: Python<'py>,
    sources: Vec<PathBuf>,
    out: PathBuf,
    format: &str,
    proto: Option<&Bound<'py, PyAny>>,
    profile: Option<&Bound<'py, PyAny>>,
    side: Option<&Bound<'py, PyAny>>,
    row_group: usize,
    types: Vec<String>,
    since: Option<&str>,
    until: Option<&str>,
    air: bool,
) -> PyResult<Bound<'py, PyList>> {
    let format = match format {
        "parquet" => Format::Parquet,
        "arrow" => Format::Arrow,
        other => {
            return Err(PyValueError::new_err(format!(
                "format is 'parquet' or 'arrow', not '{other}'"
            )));
        }
    };
    if !(1..=1 << 20).contains(&row_group) {
        return Err(PyValueError::new_err(format!(
            "row_group is a row count from 1 to 1048576, not {row_group}"
        )));
    }
    let choice = select(proto, profile, side)?;
    let keep = Keep::new(&types, since, until).map_err(PyValueError::new_err)?;
    let mut exported = Export::new(&out, format).map_err(error)?;
    let mut tables = Tables::new(row_group);
    if air || keep.names("AIR") {
        tables.derive_air();
    }
    tables.keep(keep);
    // A file that cannot be written ends the export; a source that cannot be read is
    // raised after the others are exported.
    let mut failed = None;
    let mut unread = None;
    for path in &sources {
        let name = path.display().to_string();
        let mut writing = false;
        let report = read(py, path, &choice, Some(&name), &mut tables, |full| {
            for (n, b) in full {
                if let Err(e) = exported.write(&n, &b) {
                    writing = true;
                    return Err(e);
                }
            }
            Ok(())
        });
        match report {
            Ok(report) => warn_damaged(py, &name, &report)?,
            Err(e) if writing || e.is_instance_of::<pyo3::exceptions::PyKeyboardInterrupt>(py) => {
                failed = Some(e);
                break;
            }
            Err(e) => {
                unread.get_or_insert(e);
            }
        }
    }
    let mut last = Ok(());
    for (n, b) in tables.finish() {
        if let Err(e) = exported.write(&n, &b) {
            last = Err(error(e));
            break;
        }
    }
    let written = py.detach(|| exported.finish()).map_err(error)?;
    if let Some(e) = failed.or(unread) {
        return Err(e);
    }
    last?;
    let list = PyList::empty(py);
    for w in written {
        let parts: Vec<String> = w.parts.iter().map(|p| p.display().to_string()).collect();
        list.append(PyTuple::new(
            py,
            [
                w.name.into_pyobject(py)?.into_any(),
                w.rows.into_pyobject(py)?.into_any(),
                PyList::new(py, parts)?.into_any(),
            ],
        )?)?;
    }
    Ok(list)
}
