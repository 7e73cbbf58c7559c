//! The tables as files: one directory per protocol and message type under the output
//! directory, its rows in Parquet (snappy-compressed, a row group per batch) or Arrow IPC files
//! (LZ4 frames).
//!
//! A table's rows go to `OUT/proto=PROTO/type=TYPE/part-00000.parquet` (or `.arrow`), the
//! Hive layout: the protocol (`aeolus`, `aydp`, `aok`, `gdl90`; `none` for a batch that names
//! none, [`super::proto_of`]) and the type are columns that DuckDB (`hive_partitioning =
//! true`), Polars (`hive_partitioning=True`) and Spark read from the path, so AYDP's and GDL90's
//! `HEARTBEAT` are two tables, and the files leave out the `proto` column of a capture's rows.
//! A new part begins only when the table's columns change (a column first seen after the part
//! began, or a column of nulls so far that gets its type), so the parts of one type differ only
//! by columns added: DuckDB reads them with `union_by_name = true`, Spark with `mergeSchema`,
//! Polars with `how="diagonal"`. A part is written as `part-NNNNN.parquet.partial` and renamed
//! when it is complete, so a reader never sees half a file. An export goes to a new or empty
//! directory ([`Export::new`] refuses any other), and a part that exists already is never
//! overwritten. A Parquet file's key-value metadata holds its columns' units as one JSON object
//! under the key `units` ([`UNITS_KEY`]), beside each Arrow field's own `unit`.

use std::collections::HashMap;
use std::fs::{File, OpenOptions};
use std::path::{Path, PathBuf};

use arrow_array::RecordBatch;
use arrow_ipc::writer::{FileWriter, IpcWriteOptions};
use arrow_schema::SchemaRef;
use parquet::arrow::ArrowWriter;
use parquet::basic::Compression;
use parquet::file::properties::WriterProperties;

use crate::error::{Error, Result};

/// The file format of an export.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
pub enum Format {
    /// Apache Parquet, snappy-compressed: DuckDB, Polars, Spark, pandas and pyarrow read it.
    Parquet,
    /// Arrow IPC files (Feather v2), LZ4-compressed: pyarrow and Polars map them.
    Arrow,
}

impl Format {
    /// The file name extension.
    fn extension(self) -> &'static str {
        match self {
            Format::Parquet => "parquet",
            Format::Arrow => "arrow",
        }
    }
}

/// What was written of one message type.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Written {
    /// The message type.
    pub name: String,
    /// Its protocol (`none` when its batches named none).
    pub proto: String,
    /// The table's directory under the export's: `proto=PROTO/type=NAME`.
    pub dir: String,
    /// Its parts, in order.
    pub parts: Vec<PathBuf>,
    /// Its rows.
    pub rows: u64,
}

enum Writer {
    Parquet(ArrowWriter<File>),
    Ipc(FileWriter<File>),
}

/// The part being written of one type.
struct Part {
    schema: SchemaRef,
    writer: Writer,
    partial: PathBuf,
    path: PathBuf,
}

impl Part {
    fn close(self) -> Result<PathBuf> {
        let failed = |e: &dyn std::fmt::Display| Error::Io {
            what: format!("writing {}", self.partial.display()),
            source: std::io::Error::other(e.to_string()),
        };
        match self.writer {
            Writer::Parquet(w) => {
                w.close().map_err(|e| failed(&e))?;
            }
            Writer::Ipc(mut w) => w.finish().map_err(|e| failed(&e))?,
        }
        std::fs::rename(&self.partial, &self.path).map_err(|source| Error::Io {
            what: format!(
                "renaming {} to {}",
                self.partial.display(),
                self.path.display()
            ),
            source,
        })?;
        Ok(self.path)
    }
}

/// Batches of many message types written as files under one directory.
pub struct Export {
    dir: PathBuf,
    format: Format,
    open: HashMap<String, Part>,
    written: Vec<Written>,
}

impl std::fmt::Debug for Export {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Export")
            .field("dir", &self.dir)
            .field("format", &self.format)
            .field("open", &self.open.len())
            .finish_non_exhaustive()
    }
}

impl Export {
    /// An export into `dir`, created when missing: a new or empty directory, so that an
    /// export's tables hold its sources' rows only (many exports are read as one through a
    /// glob over their directories).
    ///
    /// # Errors
    /// `dir` holds anything ([`Error::Usage`], nothing written), or it cannot be created.
    ///
    /// ```
    /// use protolink::columns::write::{Export, Format};
    /// let dir = std::env::temp_dir().join(format!("protolink-doc-export-{}", std::process::id()));
    /// let export = Export::new(&dir, Format::Parquet)?;
    /// assert!(export.finish()?.is_empty());
    /// # std::fs::remove_dir_all(&dir)?;
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn new(dir: &Path, format: Format) -> Result<Export> {
        if std::fs::read_dir(dir).is_ok_and(|mut entries| entries.next().is_some()) {
            return Err(Error::Usage(format!(
                "{} is not empty: an export goes to a new or empty directory",
                dir.display()
            )));
        }
        std::fs::create_dir_all(dir).map_err(|source| Error::Io {
            what: format!("creating the directory {}", dir.display()),
            source,
        })?;
        Ok(Export {
            dir: dir.to_owned(),
            format,
            open: HashMap::new(),
            written: Vec::new(),
        })
    }

    /// Writes a batch of the type `name`: into its open part when the columns are the same,
    /// else into a new part.
    ///
    /// # Errors
    /// A file cannot be created or written, or the part exists already.
    ///
    /// ```
    /// use protolink::columns::{Origin, Tables};
    /// use protolink::columns::write::{Export, Format};
    /// let dir = std::env::temp_dir().join(format!("protolink-doc-write-{}", std::process::id()));
    /// let mut tables = Tables::new(8);
    /// tables.add_error(&Origin::default(), 0, "truncated", "input ends inside a frame");
    /// let mut export = Export::new(&dir, Format::Arrow)?;
    /// for (name, batch) in tables.finish() {
    ///     export.write(&name, &batch)?;
    /// }
    /// let written = export.finish()?;
    /// assert_eq!((written[0].name.as_str(), written[0].rows), ("ERROR", 1));
    /// assert!(dir.join("proto=none/type=ERROR/part-00000.arrow").exists());
    /// # std::fs::remove_dir_all(&dir)?;
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn write(&mut self, name: &str, batch: &RecordBatch) -> Result<()> {
        let proto = super::proto_of(batch).unwrap_or("none").to_owned();
        let dir = format!("proto={}/type={}", safe_name(&proto), safe_name(name));
        // The path names the protocol: the files leave out the `proto` column, which a reader
        // of the layout takes from the path.
        let batch = &without_proto(batch);
        let same = self
            .open
            .get(&dir)
            .is_some_and(|p| p.schema == batch.schema());
        if !same {
            if let Some(part) = self.open.remove(&dir) {
                let path = part.close()?;
                self.entry(name, &proto, &dir).parts.push(path);
            }
            let number = self.entry(name, &proto, &dir).parts.len();
            let part = self.begin(&dir, number, batch.schema())?;
            self.open.insert(dir.clone(), part);
        }
        let Some(part) = self.open.get_mut(&dir) else {
            return Ok(());
        };
        let failed = |e: &dyn std::fmt::Display| Error::Io {
            what: format!("writing {}", part.partial.display()),
            source: std::io::Error::other(e.to_string()),
        };
        match &mut part.writer {
            // One row group per batch: the writer holds at most one batch's pages.
            Writer::Parquet(w) => {
                w.write(batch).map_err(|e| failed(&e))?;
                w.flush().map_err(|e| failed(&e))?;
            }
            Writer::Ipc(w) => w.write(batch).map_err(|e| failed(&e))?,
        }
        self.entry(name, &proto, &dir).rows += batch.num_rows() as u64;
        Ok(())
    }

    /// Closes every part, and says what was written (in the order the types first came).
    ///
    /// # Errors
    /// A part cannot be completed or renamed.
    ///
    /// ```
    /// use protolink::columns::write::{Export, Format};
    /// let dir = std::env::temp_dir().join(format!("protolink-doc-finish-{}", std::process::id()));
    /// assert!(Export::new(&dir, Format::Parquet)?.finish()?.is_empty());
    /// # std::fs::remove_dir_all(&dir)?;
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn finish(mut self) -> Result<Vec<Written>> {
        let mut first_error = None;
        for w in &mut self.written {
            if let Some(part) = self.open.remove(&w.dir) {
                match part.close() {
                    Ok(path) => w.parts.push(path),
                    Err(e) => {
                        first_error.get_or_insert(e);
                    }
                }
            }
        }
        match first_error {
            Some(e) => Err(e),
            None => Ok(self.written),
        }
    }

    /// What was written of `name` of `proto` (in `dir`) so far.
    fn entry(&mut self, name: &str, proto: &str, dir: &str) -> &mut Written {
        let i = match self.written.iter().position(|w| w.dir == dir) {
            Some(i) => i,
            None => {
                self.written.push(Written {
                    name: name.to_owned(),
                    proto: proto.to_owned(),
                    dir: dir.to_owned(),
                    parts: Vec::new(),
                    rows: 0,
                });
                self.written.len() - 1
            }
        };
        &mut self.written[i]
    }

    /// Opens part `number` in the table directory `table` (`proto=PROTO/type=NAME`).
    fn begin(&self, table: &str, number: usize, schema: SchemaRef) -> Result<Part> {
        let dir = self.dir.join(table);
        std::fs::create_dir_all(&dir).map_err(|source| Error::Io {
            what: format!("creating the directory {}", dir.display()),
            source,
        })?;
        let ext = self.format.extension();
        let path = dir.join(format!("part-{number:05}.{ext}"));
        if path.exists() {
            return Err(Error::Usage(format!(
                "{} exists already: export writes into a directory of its own",
                path.display()
            )));
        }
        let partial = dir.join(format!("part-{number:05}.{ext}.partial"));
        let file = OpenOptions::new()
            .write(true)
            .create(true)
            .truncate(true)
            .open(&partial)
            .map_err(|source| Error::Io {
                what: format!("creating {}", partial.display()),
                source,
            })?;
        let failed = |e: &dyn std::fmt::Display| Error::Io {
            what: format!("writing {}", partial.display()),
            source: std::io::Error::other(e.to_string()),
        };
        let writer = match self.format {
            Format::Parquet => {
                // Dictionary encoding for texts (source, flow, names of states), which repeat;
                // numbers are measurements, rarely repeated: plain, then snappy.
                let mut props = WriterProperties::builder()
                    .set_compression(Compression::SNAPPY)
                    .set_dictionary_enabled(false)
                    .set_created_by(format!("protolink {}", env!("CARGO_PKG_VERSION")));
                for f in schema.fields() {
                    if f.data_type() == &arrow_schema::DataType::Utf8 {
                        props = props.set_column_dictionary_enabled(
                            parquet::schema::types::ColumnPath::from(f.name().as_str()),
                            true,
                        );
                    }
                }
                // The units in the file's key-value metadata too, where DuckDB
                // (`parquet_kv_metadata`) and pyarrow (`metadata.metadata`) show them.
                let units = units_of(&schema);
                if !units.is_empty() {
                    props = props.set_key_value_metadata(Some(vec![
                        parquet::file::metadata::KeyValue::new(UNITS_KEY.to_owned(), units),
                    ]));
                }
                let props = props.build();
                Writer::Parquet(
                    ArrowWriter::try_new(file, schema.clone(), Some(props))
                        .map_err(|e| failed(&e))?,
                )
            }
            Format::Arrow => {
                let options = IpcWriteOptions::default()
                    .try_with_compression(Some(arrow_ipc::CompressionType::LZ4_FRAME))
                    .map_err(|e| failed(&e))?;
                Writer::Ipc(
                    FileWriter::try_new_with_options(file, &schema, options)
                        .map_err(|e| failed(&e))?,
                )
            }
        };
        Ok(Part {
            schema,
            writer,
            partial,
            path,
        })
    }
}

/// The key of a Parquet file's key-value metadata that holds its columns' units.
pub const UNITS_KEY: &str = "units";

/// The units of `schema`'s columns as a JSON object, column name to unit (`{}` when none has
/// one): what [`UNITS_KEY`] holds.
fn units_of(schema: &SchemaRef) -> String {
    let units: serde_json::Map<String, serde_json::Value> = schema
        .fields()
        .iter()
        .filter_map(|f| {
            let unit = f.metadata().get(super::unit::KEY)?;
            Some((f.name().clone(), serde_json::Value::String(unit.clone())))
        })
        .collect();
    if units.is_empty() {
        String::new()
    } else {
        serde_json::Value::Object(units).to_string()
    }
}

/// `batch` without its `proto` column (a capture's tables have one), the same batch when it
/// has none.
fn without_proto(batch: &RecordBatch) -> RecordBatch {
    match batch.schema_ref().index_of("proto") {
        Ok(i) => {
            let mut b = batch.clone();
            b.remove_column(i);
            b
        }
        Err(_) => batch.clone(),
    }
}

/// A message type's name as a directory name: letters, digits, `_` and `-` kept, anything
/// else `_` (the names are upper-case words, `ERROR` and `UNKNOWN_3`).
fn safe_name(name: &str) -> String {
    name.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect()
}
