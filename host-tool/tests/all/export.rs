//! `protolink export` over several captures: a damaged capture among them is read around its
//! damage and the others whole, the summary says per source what was read and what was lost,
//! and an export never writes into a directory that holds anything.

use std::path::{Path, PathBuf};
use std::time::Duration;

use crate::common::*;
use protolink::capture::CaptureWriter;

/// The AEOLUS sample of the QEMU box.
const SAMPLE: &[u8] = include_bytes!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../testdata/qemu-uart0-aeolus.bin"
));

/// A fresh directory for one test's files.
fn temp_dir(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("protolink-export-{}-{tag}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A pcapng of the AEOLUS sample repeated `copies` times, as `protolink record` writes a UART:
/// chunks of 1000 bytes on a stream interface, a millisecond apart.
fn capture(path: &Path, copies: usize) {
    let bytes = SAMPLE.repeat(copies);
    let mut w = CaptureWriter::create(path, 147, "uart").unwrap();
    for (i, chunk) in bytes.chunks(1000).enumerate() {
        let time = Duration::from_secs(1_700_000_000) + Duration::from_millis(i as u64);
        w.chunk(time, chunk).unwrap();
    }
    w.flush().unwrap();
}

/// The byte where the pcapng block holding byte `at` ends (each block ends with its length).
fn block_end_after(file: &[u8], at: usize) -> usize {
    // The section header's length, then block after block.
    let len = |p: usize| u32::from_le_bytes(file[p + 4..p + 8].try_into().unwrap()) as usize;
    let mut p = 0;
    while p + len(p) <= at {
        p += len(p);
    }
    p + len(p)
}

/// The line of `source` in an export's summary.
fn line_of<'a>(out: &'a str, source: &Path) -> &'a str {
    let name = format!("{}:", source.display());
    out.lines()
        .find(|l| l.starts_with(&name))
        .unwrap_or_else(|| panic!("no line for {name} in:\n{out}"))
}

/// The rows a source's summary line names (`..., N rows`).
fn rows_of(line: &str) -> u64 {
    let words: Vec<&str> = line.split([' ', ',', ';']).collect();
    let at = words
        .iter()
        .position(|w| *w == "rows")
        .unwrap_or_else(|| panic!("no rows in {line}"));
    words[at - 1].parse().unwrap()
}

#[test]
fn a_damaged_capture_among_four_is_read_around_its_damage() {
    let dir = temp_dir("damaged");
    let names = ["a.pcapng", "b.pcapng", "c.pcapng", "d.pcapng"];
    let paths: Vec<PathBuf> = names.iter().map(|n| dir.join(n)).collect();
    for (path, copies) in paths.iter().zip([2, 13, 13, 1]) {
        capture(path, copies);
    }
    // 200 bytes of 0xFF at byte ~700,000 of c: over the end of one block and the start of
    // the next, so that neither can be read.
    let mut c = std::fs::read(&paths[2]).unwrap();
    let end = block_end_after(&c, 700_000);
    c[end - 100..end + 100].fill(0xFF);
    std::fs::write(&paths[2], &c).unwrap();
    let out = dir.join("tables");
    let mut args = vec!["export", "--out", out.to_str().unwrap()];
    args.extend(paths.iter().map(|p| p.to_str().unwrap()));
    let o = run(&args);
    // The exit status says that something was lost, after everything else was exported.
    let err = failed(&o);
    assert!(
        err.contains("1 of 4 sources was not exported whole"),
        "{err}"
    );
    let text = stdout(&o);
    let (b, c_line, d) = (
        line_of(&text, &paths[1]),
        line_of(&text, &paths[2]),
        line_of(&text, &paths[3]),
    );
    // The damaged capture: its rows before and after the damage, and what was lost.
    let lost = c_line
        .split("; ")
        .nth(1)
        .unwrap_or_else(|| panic!("no loss in {c_line}"));
    assert!(lost.contains("bytes lost in 1 damaged region"), "{c_line}");
    assert!(rows_of(c_line) > rows_of(b) * 99 / 100, "{c_line} vs {b}");
    assert!(rows_of(c_line) < rows_of(b), "{c_line} vs {b}");
    // The capture after it was read whole.
    assert!(!d.contains("lost"), "{d}");
    assert!(rows_of(d) > 0, "{d}");
    let last = text.lines().last().unwrap();
    assert!(last.starts_with("export: 4 sources, "), "{last}");
    assert!(last.contains("bytes lost in 1 source"), "{last}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_source_that_cannot_be_read_is_named_and_the_others_are_exported() {
    let dir = temp_dir("unreadable");
    let (a, bad, c) = (
        dir.join("a.pcapng"),
        dir.join("bad.pcapng"),
        dir.join("c.pcapng"),
    );
    capture(&a, 1);
    capture(&c, 1);
    // A pcapng magic number, then nothing a section header could be.
    let mut bytes = vec![0x0A, 0x0D, 0x0D, 0x0A];
    bytes.extend([0x55; 60]);
    std::fs::write(&bad, &bytes).unwrap();
    let out = dir.join("tables");
    let o = run(&[
        "export",
        "--out",
        out.to_str().unwrap(),
        a.to_str().unwrap(),
        bad.to_str().unwrap(),
        c.to_str().unwrap(),
    ]);
    let err = failed(&o);
    assert!(
        err.contains("1 of 3 sources was not exported whole"),
        "{err}"
    );
    let text = stdout(&o);
    let line = line_of(&text, &bad);
    assert!(
        line.contains("not read whole, 0 rows before the error: "),
        "{line}"
    );
    assert_eq!(rows_of(line_of(&text, &a)), rows_of(line_of(&text, &c)));
    let last = text.lines().last().unwrap();
    assert!(last.ends_with(", 1 source not read whole"), "{last}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn an_export_into_a_directory_that_holds_anything_is_refused_before_writing() {
    let dir = temp_dir("again");
    let a = dir.join("a.pcapng");
    capture(&a, 1);
    let out = dir.join("tables");
    ok(&run(&[
        "export",
        "--out",
        out.to_str().unwrap(),
        a.to_str().unwrap(),
    ]));
    let listing = |dir: &Path| {
        let mut files: Vec<(PathBuf, Vec<u8>)> = Vec::new();
        let mut todo = vec![dir.to_owned()];
        while let Some(d) = todo.pop() {
            for e in std::fs::read_dir(&d).unwrap() {
                let p = e.unwrap().path();
                if p.is_dir() {
                    todo.push(p);
                } else {
                    let bytes = std::fs::read(&p).unwrap();
                    files.push((p, bytes));
                }
            }
        }
        files.sort();
        files
    };
    let before = listing(&out);
    let err = usage_failed(&run(&[
        "export",
        "--out",
        out.to_str().unwrap(),
        a.to_str().unwrap(),
    ]));
    assert!(
        err.contains(&format!(
            "{} is not empty: an export goes to a new or empty directory",
            out.display()
        )),
        "{err}"
    );
    assert_eq!(listing(&out), before);
    // A directory with any file in it, even one no export wrote.
    let other = dir.join("other");
    std::fs::create_dir_all(&other).unwrap();
    std::fs::write(other.join("notes.txt"), b"x").unwrap();
    usage_failed(&run(&[
        "export",
        "--out",
        other.to_str().unwrap(),
        a.to_str().unwrap(),
    ]));
    assert_eq!(std::fs::read_dir(&other).unwrap().count(), 1);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A pcapng of two copies of the AEOLUS sample 100 s apart, each in chunks of 1000 bytes a
/// millisecond apart: the first from 1,700,000,000 s (2023-11-14T22:13:20Z), the second from
/// 1,700,000,100 s.
fn two_flights(path: &Path) {
    let mut w = CaptureWriter::create(path, 147, "uart").unwrap();
    for start in [1_700_000_000, 1_700_000_100] {
        for (i, chunk) in SAMPLE.chunks(1000).enumerate() {
            let time = Duration::from_secs(start) + Duration::from_millis(i as u64);
            w.chunk(time, chunk).unwrap();
        }
    }
    w.flush().unwrap();
}

/// The tables an export's output lists: (`proto=P/type=T`, rows).
fn tables_of(out: &str) -> Vec<(String, u64)> {
    out.lines()
        .filter(|l| l.starts_with("proto="))
        .map(|l| {
            let (dir, rest) = l.split_once(' ').unwrap();
            (
                dir.to_owned(),
                rest.split(' ').next().unwrap().parse().unwrap(),
            )
        })
        .collect()
}

#[test]
fn types_since_and_until_choose_the_rows() {
    let dir = temp_dir("choose");
    let a = dir.join("a.pcapng");
    two_flights(&a);
    let export = |tag: &str, options: &[&str]| {
        let out = dir.join(tag);
        let mut args = vec!["export", "--out", out.to_str().unwrap()];
        args.extend(options);
        args.push(a.to_str().unwrap());
        (ok(&run(&args)), out)
    };
    let (all, _) = export("all", &[]);
    let all = tables_of(&all);
    let rows = |tables: &[(String, u64)], dir: &str| {
        tables.iter().find(|(d, _)| d == dir).map_or(0, |&(_, n)| n)
    };
    let (gyro, pressure) = (
        rows(&all, "proto=aeolus/type=GYRO"),
        rows(&all, "proto=aeolus/type=PRESSURE"),
    );
    assert!(gyro > 100 && pressure > 10 && all.len() > 5, "{all:?}");
    let total: u64 = all.iter().map(|(_, n)| n).sum();
    // --types: those tables only, whole; the line and the summary count the rows left out.
    let (text, out) = export("types", &["--types", "gyro,aeolus.PRESSURE"]);
    assert_eq!(
        tables_of(&text),
        [
            ("proto=aeolus/type=GYRO".to_owned(), gyro),
            ("proto=aeolus/type=PRESSURE".to_owned(), pressure)
        ]
    );
    let left = total - gyro - pressure;
    assert!(
        line_of(&text, &a).ends_with(&format!("{} rows ({left} left out)", gyro + pressure)),
        "{text}"
    );
    assert!(
        text.contains(&format!(", {left} rows left out by --types")),
        "{text}"
    );
    assert_eq!(
        std::fs::read_dir(out.join("proto=aeolus")).unwrap().count(),
        2
    );
    // AIR, when asked for: a row per PRESSURE, derived from the PRESSURE rows even when they
    // are left out.
    let (text, _) = export("air", &["--types", "AIR"]);
    assert_eq!(
        tables_of(&text),
        [("proto=aeolus/type=AIR".to_owned(), pressure)]
    );
    assert_eq!(rows(&all, "proto=aeolus/type=AIR"), 0);
    let (text, _) = export("with-air", &["--air"]);
    let with_air = tables_of(&text);
    assert_eq!(rows(&with_air, "proto=aeolus/type=AIR"), pressure);
    assert_eq!(with_air.len(), all.len() + 1);
    // --since and --until: the second flight, then the first; every row of either is one.
    let (second, _) = export("since", &["--since", "2023-11-14T22:14:00Z"]);
    let (first, _) = export(
        "until",
        &["--until", "2023-11-14T23:14:00+01:00", "--types", "GYRO"],
    );
    let second = tables_of(&second);
    assert_eq!(second.iter().map(|(_, n)| n).sum::<u64>() * 2, total);
    assert_eq!(rows(&second, "proto=aeolus/type=GYRO") * 2, gyro);
    assert_eq!(
        tables_of(&first),
        [("proto=aeolus/type=GYRO".to_owned(), gyro / 2)]
    );
    // 10 ms of the first flight (10 of its 79 records): some of its rows, none of the
    // second's.
    let (window, _) = export(
        "window",
        &[
            "--since",
            "2023-11-14T22:13:20.010Z",
            "--until",
            "2023-11-14T22:13:20.020Z",
        ],
    );
    let got: u64 = tables_of(&window).iter().map(|(_, n)| n).sum();
    assert!(got > 0 && got < total / 8, "{got} of {total}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_types_and_times_are_refused_in_one_sentence_before_writing() {
    let dir = temp_dir("refused");
    let a = dir.join("a.pcapng");
    capture(&a, 1);
    let out = dir.join("tables");
    for (options, sentence) in [
        (
            &["--types", "GYRO,GYROS"][..],
            "error: 'GYROS' is no message type of aeolus, aydp, aok or gdl90 (docs/columns.md lists them, ERROR is the errors)",
        ),
        (
            &["--types", "aok.GYRO"],
            "error: 'aok.GYRO' is no message type of aok (docs/columns.md lists them, ERROR is the errors)",
        ),
        (
            &["--since", "yesterday"],
            "error: 'yesterday' is not a time: give one as 2024-05-01T12:00:00Z or 2024-05-01T14:00:00.5+02:00 (RFC 3339), or a day as 2024-05-01",
        ),
        (
            &["--until", "2024-02-30"],
            "error: '2024-02-30' is not a time",
        ),
        (
            &[
                "--since",
                "2024-05-01T12:00:00Z",
                "--until",
                "2024-05-01T13:00:00+01:00",
            ],
            "error: --since (2024-05-01T12:00:00Z) is not before --until (2024-05-01T12:00:00Z): no row would be kept",
        ),
    ] {
        let mut args = vec!["export", "--out", out.to_str().unwrap()];
        args.extend(options);
        args.push(a.to_str().unwrap());
        let err = usage_failed(&run(&args));
        assert!(err.starts_with(sentence), "{options:?}: {err}");
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(!out.exists(), "{options:?}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The Arrow schema of an export's first part of table `dir` (`proto=P/type=T`), as the
/// Parquet file keeps it.
fn parquet_schema(out: &Path, dir: &str) -> arrow_schema::SchemaRef {
    let file = std::fs::File::open(out.join(dir).join("part-00000.parquet")).unwrap();
    parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder::try_new(file)
        .unwrap()
        .schema()
        .clone()
}

#[test]
fn parquet_files_keep_box_time_as_a_duration_and_lists_as_lists() {
    use arrow_schema::{DataType, Field, TimeUnit};
    let dir = temp_dir("types");
    let a = dir.join("a.pcapng");
    capture(&a, 1);
    let (full, empty) = (dir.join("full.bin"), dir.join("empty.bin"));
    std::fs::write(
        &full,
        crate::columns::aydp_lists(&[(7, 180.0, 45.0, 38.0)], &[(1, 2, 10.0)]),
    )
    .unwrap();
    std::fs::write(&empty, crate::columns::aydp_lists(&[], &[])).unwrap();
    let out = dir.join("tables");
    ok(&run(&[
        "export",
        "--air",
        "--out",
        out.to_str().unwrap(),
        a.to_str().unwrap(),
    ]));
    let gyro = parquet_schema(&out, "proto=aeolus/type=GYRO");
    let names: Vec<&str> = gyro.fields().iter().map(|f| f.name().as_str()).collect();
    assert!(
        names.ends_with(&["valid", "box_time", "x_radps", "y_radps", "z_radps"]),
        "{names:?}"
    );
    for table in ["GYRO", "ACCEL", "MAGNET", "PRESSURE", "AIR"] {
        let schema = parquet_schema(&out, &format!("proto=aeolus/type={table}"));
        let field = schema.field_with_name("box_time").unwrap();
        assert_eq!(
            field.data_type(),
            &DataType::Duration(TimeUnit::Microsecond),
            "{table}"
        );
        assert_eq!(
            field.metadata().get("unit").map(String::as_str),
            Some("µs since the box started")
        );
        assert!(schema.field_with_name("timestamp_ms").is_err(), "{table}");
    }
    let unit = |t: &str, c: &str| {
        let schema = parquet_schema(&out, &format!("proto=aeolus/type={t}"));
        schema
            .field_with_name(c)
            .unwrap()
            .metadata()
            .get("unit")
            .cloned()
    };
    assert_eq!(unit("ACCEL", "z_mps2").as_deref(), Some("m/s²"));
    assert_eq!(unit("MAGNET", "y_gauss").as_deref(), Some("gauss"));
    // AYDP lists: a list column per field of the items, the same whether the lists have items
    // or none.
    let mut schemas = Vec::new();
    for (tag, file) in [("full", &full), ("empty", &empty)] {
        let out = dir.join(tag);
        let args = ["export", "--proto", "aydp", "--profile", "spec", "--out"];
        let mut args = args.to_vec();
        args.extend([out.to_str().unwrap(), file.to_str().unwrap()]);
        ok(&run(&args));
        schemas.push((
            parquet_schema(&out, "proto=aydp/type=FIX_DETAIL"),
            parquet_schema(&out, "proto=aydp/type=DIRECT_OUTPUT"),
        ));
    }
    assert_eq!(schemas[0], schemas[1]);
    let list = |t: DataType| DataType::List(std::sync::Arc::new(Field::new_list_field(t, true)));
    let (fix, output) = &schemas[0];
    assert_eq!(
        fix.field_with_name("satellites.id").unwrap().data_type(),
        &list(DataType::UInt8)
    );
    assert_eq!(
        fix.field_with_name("satellites.snr").unwrap().data_type(),
        &list(DataType::Float32)
    );
    assert_eq!(
        output.field_with_name("entries.value").unwrap().data_type(),
        &list(DataType::Float32)
    );
    assert!(fix.field_with_name("satellites").is_err());
    let _ = std::fs::remove_dir_all(&dir);
}
