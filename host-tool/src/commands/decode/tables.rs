//! A file's messages into tables ([`crate::columns`]): a pcapng or pcap capture decoded per
//! flow, or a file of raw bytes of one protocol, read a little at a time so that the caller can
//! write out the full batches (and look for Ctrl-C) between two steps. What `export` and the
//! Python package's `to_arrow` read files with.

use std::io::Read;
use std::ops::ControlFlow;
use std::path::Path;

use super::capture::CaptureEvents;
use crate::columns::{Origin, SourceId, Tables};
use crate::decoders::Decoder;
use crate::error::{Error, Result};
use crate::proto::{ProfileArg, Proto, Side};

/// Bytes read from a byte file per step.
const CHUNK: usize = 256 * 1024;

/// Capture records read per step.
const RECORDS_PER_STEP: usize = 1024;

/// Which decoder reads a file: a capture names its protocols (`proto` picks one), a byte file
/// needs `proto`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Select {
    /// The protocol (of a byte file; in a capture, only its flows of this protocol).
    pub proto: Option<Proto>,
    /// The AYDP profile.
    pub profile: Option<ProfileArg>,
    /// The AOK side.
    pub side: Side,
}

/// What was read of a file.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Report {
    /// Bytes of the file read (the whole file, or up to a capture's cut), without the bytes
    /// lost to damage.
    pub bytes: u64,
    /// Rows it gave (messages and errors).
    pub rows: u64,
    /// A capture's damaged regions: blocks or records that could not be read, skipped to the
    /// next whole one (or to the end).
    pub damaged: u64,
    /// The bytes of those regions.
    pub lost: u64,
    /// Where the first of them starts.
    pub first_damage: Option<u64>,
    /// A capture cut inside a block (`protolink record` killed mid-write): the byte where the
    /// cut block starts. Every whole record before it was read.
    pub cut_at: Option<u64>,
    /// The whole records before the cut.
    pub records_before_cut: u64,
    /// The caller's `step` asked to stop (`ControlFlow::Break`): `bytes` and `rows` are those
    /// read up to there.
    pub stopped: bool,
}

/// Reads the file at `path` into `tables`, every row's `source` set to `source` when given
/// (and `file` and `capture_id` to the file's name and identity, [`SourceId`]);
/// `step` runs after each step with the tables (to take their full batches): its
/// `ControlFlow::Break` ends the reading there ([`Report::stopped`]), its error ends it with
/// that error.
///
/// A capture's damaged blocks or records are skipped, and counted in the report
/// ([`Report::damaged`], [`Report::lost`]); the reading goes on after them.
///
/// # Errors
/// The file cannot be opened or read, a byte file without `proto`, or `step`'s error.
///
/// ```
/// use std::ops::ControlFlow;
/// use protolink::columns::Tables;
/// use protolink::commands::decode::tables::{Select, read_file};
/// use protolink::proto::Proto;
/// let path = std::env::temp_dir().join(format!("protolink-doc-read-{}", std::process::id()));
/// std::fs::write(&path, [0x7E, 0x52, b'h', b'i', 0, 0x73, 0xEC, 0x7E])?;
/// let mut tables = Tables::new(1024);
/// let select = Select { proto: Some(Proto::Aeolus), ..Select::default() };
/// let report = read_file(&path, &select, None, &mut tables, |_| Ok(ControlFlow::Continue(())))?;
/// assert_eq!((report.bytes, report.rows, report.stopped), (8, 1, false));
/// // A step that stops at once: the first step's bytes and rows.
/// let report = read_file(&path, &select, None, &mut tables, |_| Ok(ControlFlow::Break(())))?;
/// assert_eq!((report.bytes, report.rows, report.stopped), (8, 1, true));
/// # std::fs::remove_file(&path)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn read_file(
    path: &Path,
    select: &Select,
    source: Option<&str>,
    tables: &mut Tables,
    mut step: impl FnMut(&mut Tables) -> Result<ControlFlow<()>>,
) -> Result<Report> {
    let rows_before = tables.rows();
    let mut report = Report::default();
    // An export's rows name the file and its content's identity beside `source`.
    tables.reading(match source {
        Some(_) => Some(SourceId::of(path)?),
        None => None,
    });
    // The report of a reading `step` stopped after `bytes`.
    let stopped = |mut report: Report, tables: &Tables, bytes: u64| {
        report.bytes = bytes;
        report.rows = tables.rows() - rows_before;
        report.stopped = true;
        report
    };
    if crate::capture::file_is_capture(path) {
        let mut capture = CaptureEvents::open(path, select)?;
        'records: loop {
            for _ in 0..RECORDS_PER_STEP {
                match capture.next_columns(tables, source) {
                    Ok(true) => {}
                    Ok(false) => break 'records,
                    Err(Error::CaptureCut { offset, frames, .. }) => {
                        report.cut_at = Some(offset);
                        report.records_before_cut = frames;
                        capture.stop();
                    }
                    // The reader reads on past the damage (or ends): the loss is counted.
                    Err(Error::CaptureDamaged {
                        offset, skipped, ..
                    }) => {
                        report.damaged += 1;
                        report.lost += skipped;
                        report.first_damage.get_or_insert(offset);
                    }
                    Err(e) => return Err(e),
                }
            }
            if step(tables)?.is_break() {
                let bytes = capture.offset().saturating_sub(report.lost);
                return Ok(stopped(report, tables, bytes));
            }
        }
        report.bytes = report
            .cut_at
            .unwrap_or_else(|| file_len(path))
            .saturating_sub(report.lost);
    } else {
        let Some(proto) = select.proto else {
            return Err(Error::Usage(format!(
                "{} is no pcapng or pcap capture, and no protocol was chosen for its bytes",
                path.display()
            )));
        };
        let mut file = std::fs::File::open(path).map_err(|e| Error::Open {
            endpoint: path.display().to_string(),
            source: e,
        })?;
        let mut decoder = Decoder::new(proto, select.profile.unwrap_or_default(), select.side);
        // The protocol names the tables of the errors too (no `proto` column: that is a
        // capture's).
        let origin = Origin {
            source: source.map(str::to_owned),
            proto: Some(proto),
            ..Origin::default()
        };
        let mut buf = vec![0u8; CHUNK];
        loop {
            let n = match file.read(&mut buf) {
                Ok(0) => break,
                Ok(n) => n,
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
                Err(e) => {
                    return Err(Error::Io {
                        what: format!("reading {}", path.display()),
                        source: e,
                    });
                }
            };
            let bytes = buf.get(..n).unwrap_or_default();
            decoder.feed(bytes, report.bytes, |p| tables.add(&origin, &p));
            report.bytes += n as u64;
            if step(tables)?.is_break() {
                let bytes = report.bytes;
                return Ok(stopped(report, tables, bytes));
            }
        }
        decoder.finish(|p| tables.add(&origin, &p));
    }
    report.rows = tables.rows() - rows_before;
    report.stopped = step(tables)?.is_break();
    Ok(report)
}

/// The file's length (0 when it cannot be read).
fn file_len(path: &Path) -> u64 {
    std::fs::metadata(path).map_or(0, |m| m.len())
}
