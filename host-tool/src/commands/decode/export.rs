//! `protolink export`: captures and byte files as tables an analyst's engine reads as they are,
//! one directory per message type under `--out`, in Parquet or Arrow IPC files (see
//! [`crate::columns`] for the columns and [`crate::columns::write`] for the files).
//!
//! Many sources go into one set of tables, each row naming its file in `source`. The files are
//! read one after another, a little at a time, and a table's rows are written whenever a row
//! group is full: memory holds at most a row group per message type, whatever the size of the
//! sources. Ctrl-C ends the reading; what was read is written and the parts are completed.

use std::ops::ControlFlow;
use std::path::PathBuf;

use clap::Args;

use super::tables::{Select, read_file};
use crate::columns::write::{Export, Format};
use crate::columns::{ROW_GROUP, Tables};
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
    /// The directory the tables go to (created when missing): OUT/TYPE/part-00000.parquet.
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
/// # Errors
/// A source cannot be read, or a file cannot be written. The tables read before the error are
/// written and completed first, and listed.
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
    crate::stop::install_ctrl_c();
    let select = Select {
        proto: args.proto,
        profile: args.profile,
        side: args.side,
    };
    let mut export = Export::new(&args.out, args.format)?;
    let mut tables = Tables::new(args.row_group);
    let mut out = Out::new();
    let mut failed = None;
    let (mut bytes, mut stopped) = (0u64, false);
    for path in &args.sources {
        let source = path.display().to_string();
        let read = read_file(path, &select, Some(&source), &mut tables, |t| {
            for (name, batch) in t.take_full() {
                export.write(&name, &batch)?;
            }
            Ok(if crate::stop::requested() {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            })
        });
        match read {
            Ok(report) if report.stopped => {
                stopped = true;
                break;
            }
            Ok(report) => {
                bytes += report.bytes;
                if let Some(at) = report.cut_at {
                    eprintln!(
                        "warning: the capture {source} is cut inside the block at byte {at}: every whole record before it was exported"
                    );
                }
                out.line(&format!(
                    "{source}: {} bytes, {} rows",
                    report.bytes, report.rows
                ))?;
            }
            Err(e) => {
                failed = Some(e);
                break;
            }
        }
    }
    for (name, batch) in tables.finish() {
        if let Err(e) = export.write(&name, &batch) {
            failed.get_or_insert(e);
        }
    }
    let written = export.finish()?;
    let rows: u64 = written.iter().map(|w| w.rows).sum();
    for w in &written {
        let parts: Vec<String> = w.parts.iter().map(|p| p.display().to_string()).collect();
        out.line(&format!("{} {} rows: {}", w.name, w.rows, parts.join(" ")))?;
    }
    let mismatches = tables.mismatches();
    out.line(&format!(
        "export: {} sources, {bytes} bytes, {rows} rows in {} tables{}{}",
        args.sources.len(),
        written.len(),
        if mismatches > 0 {
            format!(", {mismatches} values of another type stored as null")
        } else {
            String::new()
        },
        if stopped { " (interrupted)" } else { "" }
    ))?;
    match failed {
        Some(e) => Err(e),
        None => Ok(()),
    }
}
