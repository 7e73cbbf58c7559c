//! `protolink export`: captures and byte files as tables an analyst's engine reads as they are,
//! one directory per protocol and message type under `--out`
//! (`proto=PROTO/type=TYPE/part-00000.parquet`), in Parquet or Arrow IPC files (see
//! [`crate::columns`] for the columns and [`crate::columns::write`] for the files).
//!
//! Many sources go into one set of tables, each row naming its file in `source`. The files are
//! read one after another, a little at a time, and a table's rows are written whenever a row
//! group is full: memory holds at most a row group per message type, whatever the size of the
//! sources. Ctrl-C ends the reading; what was read is written and the parts are completed.

use std::ops::ControlFlow;
use std::path::PathBuf;

use clap::Args;

use super::tables::{Report, Select, read_file};
use crate::columns::write::{Export, Format};
use crate::columns::{Keep, ROW_GROUP, Tables};
use crate::error::{Error, Result};
use crate::proto::{ProfileArg, Proto, Side};
use crate::render::Out;

/// The largest row group `--row-group` takes.
const MAX_ROW_GROUP: usize = 1 << 20;

/// Arguments of `protolink export`.
#[derive(Debug, Clone, Args)]
pub(crate) struct ExportArgs {
    /// The file format: parquet (snappy) or arrow (Arrow IPC, LZ4).
    #[arg(long, value_enum, default_value_t = Format::Parquet)]
    pub(crate) format: Format,
    /// The directory the tables go to, new or empty (created when missing): OUT/proto=PROTO/type=TYPE/part-00000.parquet.
    #[arg(long, value_name = "DIR")]
    pub(crate) out: PathBuf,
    /// The protocol of the byte files (a capture names its own; --proto keeps only its flows of this protocol).
    #[arg(long, value_enum)]
    pub(crate) proto: Option<Proto>,
    /// AYDP profile (default: spec; in a capture, AYDP on TCP/UDP 6321 is read as reference).
    #[arg(long, value_enum)]
    pub(crate) profile: Option<ProfileArg>,
    /// AOK: who sent the bytes (pc: commands; device: debug values, acks, replies).
    #[arg(long, value_enum, default_value_t = Side::Device)]
    pub(crate) side: Side,
    /// Only these message types, comma-separated, as their tables are named (GYRO,PRESSURE;
    /// aydp.HEARTBEAT for one protocol's; ERROR for the error events).
    #[arg(long, value_name = "TYPES", value_delimiter = ',')]
    pub(crate) types: Vec<String>,
    /// Only rows whose time is at or after this one (RFC 3339, e.g. 2024-05-01T12:00:00Z, or a
    /// day, 2024-05-01); a row without a time is left out.
    #[arg(long, value_name = "TIME")]
    pub(crate) since: Option<String>,
    /// Only rows whose time is before this one (as --since).
    #[arg(long, value_name = "TIME")]
    pub(crate) until: Option<String>,
    /// Also write the table AIR: the air data derived from each AEOLUS PRESSURE (indicated and
    /// true airspeed, pressure altitude, vertical speed); --types AIR writes it too.
    #[arg(long)]
    pub(crate) air: bool,
    /// Rows per row group (1 to 1048576): the most rows of one type held in memory.
    #[arg(long, value_name = "ROWS", default_value_t = ROW_GROUP, value_parser = row_group)]
    pub(crate) row_group: usize,
    /// The captures (pcapng, pcap) and byte files to read.
    #[arg(value_name = "SOURCE", required = true)]
    pub(crate) sources: Vec<PathBuf>,
}

fn row_group(text: &str) -> std::result::Result<usize, String> {
    match text.parse::<usize>() {
        Ok(n) if (1..=MAX_ROW_GROUP).contains(&n) => Ok(n),
        _ => Err(format!(
            "'{text}' is not a row count from 1 to {MAX_ROW_GROUP}"
        )),
    }
}

/// Runs `protolink export`.
///
/// Every source is read, whatever happened to the ones before it: a capture's damaged blocks
/// are skipped and counted, a source that cannot be read is named with its error, and the
/// rows read from it before the error are kept. Each source's line says what was read of it
/// and what was lost; a cut capture (what `record` leaves when it is killed) is read up to
/// its cut and counts as read whole.
///
/// # Errors
/// A source had damage or could not be read ([`Error::Incomplete`], after all the others
/// were exported), a file cannot be written, or `--out` holds anything (refused before
/// anything is read or written). The tables read before a write error are completed first,
/// and listed.
pub(crate) fn run(args: &ExportArgs) -> Result<()> {
    for s in &args.sources {
        if !s.is_file() {
            return Err(Error::Usage(format!(
                "{} is no file to export",
                s.display()
            )));
        }
        // A command-line mistake, refused before anything is written (`read_file` would
        // refuse the file too, in the library's words).
        if args.proto.is_none() && !crate::capture::file_is_capture(s) {
            return Err(Error::Usage(format!(
                "{} is no pcapng or pcap capture: say which protocol its bytes are (--proto)",
                s.display()
            )));
        }
    }
    let keep = Keep::new(&args.types, args.since.as_deref(), args.until.as_deref())
        .map_err(Error::Usage)?;
    crate::stop::install_ctrl_c();
    let select = Select {
        proto: args.proto,
        profile: args.profile,
        side: args.side,
    };
    let mut export = Export::new(&args.out, args.format)?;
    let mut tables = Tables::new(args.row_group);
    if args.air || keep.names("AIR") {
        tables.derive_air();
    }
    tables.keep(keep);
    let mut out = Out::new();
    // A file that could not be written ends the export; a source that could not be read
    // does not.
    let mut write_failed = None;
    let mut stopped = false;
    let mut total = Totals::default();
    for path in &args.sources {
        let source = path.display().to_string();
        let rows_before = tables.rows();
        let left_out_before = tables.left_out();
        let mut writing = None;
        let read = read_file(path, &select, Some(&source), &mut tables, |t| {
            for (name, batch) in t.take_full() {
                if let Err(e) = export.write(&name, &batch) {
                    writing = Some(());
                    return Err(e);
                }
            }
            Ok(if crate::stop::requested() {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            })
        });
        match read {
            Ok(report) => {
                total.bytes += report.bytes;
                if report.damaged > 0 {
                    total.lost += report.lost;
                    total.damaged += 1;
                }
                let left_out = tables.left_out() - left_out_before;
                out.line(&source_line(&source, &report, left_out))?;
                if report.stopped {
                    stopped = true;
                    break;
                }
            }
            Err(e) if writing.is_some() => {
                write_failed = Some(e);
                break;
            }
            Err(e) => {
                total.failed += 1;
                out.line(&format!(
                    "{source}: not read whole, {} rows before the error: {e}",
                    tables.rows() - rows_before
                ))?;
            }
        }
    }
    for (name, batch) in tables.finish() {
        if let Err(e) = export.write(&name, &batch) {
            write_failed.get_or_insert(e);
        }
    }
    let written = export.finish()?;
    let rows: u64 = written.iter().map(|w| w.rows).sum();
    for w in &written {
        let parts: Vec<String> = w.parts.iter().map(|p| p.display().to_string()).collect();
        out.line(&format!("{} {} rows: {}", w.dir, w.rows, parts.join(" ")))?;
    }
    let mismatches = tables.mismatches();
    let mut summary = format!(
        "export: {} sources, {} bytes, {rows} rows in {} tables",
        args.sources.len(),
        total.bytes,
        written.len(),
    );
    if total.damaged > 0 {
        summary += &format!(
            ", {} bytes lost in {}",
            total.lost,
            count(total.damaged, "source")
        );
    }
    if total.failed > 0 {
        summary += &format!(", {} not read whole", count(total.failed, "source"));
    }
    if tables.left_out() > 0 {
        summary += &format!(
            ", {} rows left out by --types, --since or --until",
            tables.left_out()
        );
    }
    if mismatches > 0 {
        summary += &format!(", {mismatches} values of another type stored as null");
    }
    if stopped {
        summary += " (interrupted)";
    }
    out.line(&summary)?;
    if let Some(e) = write_failed {
        return Err(e);
    }
    let incomplete = total.damaged + total.failed;
    if incomplete > 0 {
        return Err(Error::Incomplete(format!(
            "{incomplete} of {} sources {} not exported whole: the lines above say what {} lost",
            args.sources.len(),
            if incomplete == 1 { "was" } else { "were" },
            if incomplete == 1 { "it" } else { "each" },
        )));
    }
    Ok(())
}

/// What an export read of all its sources.
#[derive(Debug, Default)]
struct Totals {
    /// Bytes read.
    bytes: u64,
    /// Bytes lost to damage.
    lost: u64,
    /// Sources with damage.
    damaged: u64,
    /// Sources that could not be read to their end.
    failed: u64,
}

/// `n` things, `thing` in the plural unless `n` is 1.
fn count(n: u64, thing: &str) -> String {
    if n == 1 {
        format!("1 {thing}")
    } else {
        format!("{n} {thing}s")
    }
}

/// A source's line: what was read of it, and what was lost.
fn source_line(source: &str, report: &Report, left_out: u64) -> String {
    let mut line = format!("{source}: {} bytes, {} rows", report.bytes, report.rows);
    if left_out > 0 {
        line += &format!(" ({left_out} left out)");
    }
    if report.damaged > 0 {
        line += &format!(
            "; {} bytes lost in {}, the first at byte {}",
            report.lost,
            count(report.damaged, "damaged region"),
            report.first_damage.unwrap_or_default()
        );
    }
    if let Some(at) = report.cut_at {
        line += &format!(
            "; the capture is cut inside the block at byte {at}: every whole record before it was read"
        );
    }
    if report.stopped {
        line += "; interrupted";
    }
    line
}
