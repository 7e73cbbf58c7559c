//! The tables of `protolink export` and `to_arrow`, built from decoded messages: column names and
//! types, the rule for a field named like a metadata column, values of another type, row
//! groups, and the parts of an export when a table's columns change.

use arrow_array::cast::AsArray;
use arrow_array::types::{DurationMicrosecondType, Float32Type, Int64Type, UInt8Type};
use arrow_array::{Array, RecordBatch};
use arrow_schema::{DataType, Field, TimeUnit};
use protolink::columns::write::{Export, Format};
use protolink::columns::{Origin, Tables, unify};
use protolink::decoders::AeolusDecoder;
use serde_json::{Map, Value, json};

fn names(batch: &RecordBatch) -> Vec<String> {
    batch
        .schema()
        .fields()
        .iter()
        .map(|f| f.name().clone())
        .collect()
}

fn meta(v: Value) -> Map<String, Value> {
    v.as_object().cloned().unwrap_or_default()
}

/// The bytes of the AEOLUS sample.
fn sample_bytes() -> Vec<u8> {
    let bytes = std::fs::read(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../testdata/qemu-uart0-aeolus.bin"
    ))
    .unwrap_or_default();
    assert!(!bytes.is_empty());
    bytes
}

/// The AEOLUS sample: the frames of the firmware's telemetry.
fn sample() -> Vec<(String, RecordBatch)> {
    let bytes = sample_bytes();
    let mut tables = Tables::new(100);
    let origin = Origin::default();
    let mut d = AeolusDecoder::new();
    d.feed(&bytes, 0, |p| tables.add(&origin, &p));
    d.finish(|p| tables.add(&origin, &p));
    assert_eq!(tables.mismatches(), 0);
    tables.finish()
}

#[test]
fn typed_aeolus_columns_keep_the_wire_types() {
    let batches = sample();
    let (_, compass) = batches
        .iter()
        .find(|(n, _)| n == "COMPASS")
        .expect("a COMPASS table");
    let names = names(compass);
    assert_eq!(
        names[..9],
        [
            "capture_time",
            "time",
            "offset",
            "meta.id",
            "meta.len",
            "meta.crc",
            "valid",
            "calibration",
            "has_value"
        ]
    );
    // A fixed-size array is a column per element.
    assert!(names.iter().any(|n| n == "hard_iron.8") && !names.iter().any(|n| n == "hard_iron"));
    let schema = compass.schema();
    let kind = |n: &str| {
        schema
            .field_with_name(n)
            .map(|f| f.data_type().clone())
            .ok()
    };
    assert_eq!(kind("heading_deg"), Some(DataType::Float32));
    assert_eq!(kind("calibration_percent"), Some(DataType::UInt8));
    assert_eq!(kind("calibration"), Some(DataType::Utf8));
    assert_eq!(kind("capture_time"), Some(DataType::Float64));
    // Units ride in the fields' metadata: by suffix, by name, none for a flag.
    let unit = |n: &str| {
        schema
            .field_with_name(n)
            .ok()
            .and_then(|f| f.metadata().get("unit").cloned())
    };
    assert_eq!(unit("heading_deg").as_deref(), Some("deg"));
    assert_eq!(unit("calibration_percent").as_deref(), Some("%"));
    assert_eq!(unit("capture_time").as_deref(), Some("s since 1970"));
    assert_eq!(unit("valid"), None);
    let gyro = batches
        .iter()
        .find(|(n, _)| n == "GYRO")
        .map(|(_, b)| b.schema())
        .expect("GYRO");
    let x = gyro
        .field_with_name("x_radps")
        .map(|f| f.metadata().get("unit").cloned());
    assert_eq!(x.ok().flatten().as_deref(), Some("rad/s"));
    // 248 COMPASS rows in batches of at most 100 rows.
    let rows: Vec<usize> = batches
        .iter()
        .filter(|(n, _)| n == "COMPASS")
        .map(|(_, b)| b.num_rows())
        .collect();
    assert_eq!(rows, [100, 100, 48]);
    let first = compass.column_by_name("heading_deg").expect("heading");
    assert_eq!(first.as_primitive::<Float32Type>().value(0), 357.290_04);
    let info = batches
        .iter()
        .find(|(n, _)| n == "AEOLUSINFO")
        .map(|(_, b)| b.clone())
        .expect("AEOLUSINFO");
    let mac: Vec<u8> = (0..6)
        .map(|i| {
            info.column_by_name(&format!("mac.{i}"))
                .expect("mac")
                .as_primitive::<UInt8Type>()
                .value(0)
        })
        .collect();
    assert_eq!(mac, [2, 174, 1, 5, 0, 1]);
}

#[test]
fn a_field_named_like_metadata_is_field_and_its_name() {
    let mut tables = Tables::new(8);
    let fields =
        json!({"offset": 99, "meta.len": 98, "field.x": 97, "source": "s", "x": 1, "t": {"a": 2}});
    tables.add_rendered(
        &Origin::default(),
        5,
        "ODD",
        &meta(json!({"len": 3})),
        &fields,
    );
    let (name, batch) = tables.finish().remove(0);
    assert_eq!(name, "ODD");
    assert_eq!(
        names(&batch),
        [
            "capture_time",
            "time",
            "offset",
            "meta.len",
            "field.offset",
            "field.meta.len",
            "field.field.x",
            "field.source",
            "x",
            "t.a"
        ]
    );
    let int = |n: &str| {
        batch
            .column_by_name(n)
            .map(|c| c.as_primitive::<Int64Type>().value(0))
    };
    assert_eq!(
        (int("offset"), int("field.offset"), int("t.a")),
        (Some(5), Some(99), Some(2))
    );
}

#[test]
fn a_value_of_another_type_is_a_counted_null() {
    let mut tables = Tables::new(8);
    let origin = Origin::default();
    for v in [json!(1), json!("one"), json!(2.5), json!(3)] {
        tables.add_rendered(&origin, 0, "T", &Map::new(), &json!({ "v": v }));
    }
    // The text is no integer; 2.5 is none either.
    assert_eq!(tables.mismatches(), 2);
    let (_, batch) = tables.finish().remove(0);
    let v = batch.column_by_name("v").expect("v");
    assert_eq!(v.data_type(), &DataType::Int64);
    let got: Vec<Option<i64>> = v.as_primitive::<Int64Type>().iter().collect();
    assert_eq!(got, [Some(1), None, None, Some(3)]);
}

#[test]
fn a_rendered_list_is_its_json_text() {
    // A rendered message's lists (of items of any type: numbers, objects, nothing) are strings;
    // a typed message's are Arrow lists (aydp_lists_are_arrow_lists_of_one_schema_...).
    let mut tables = Tables::new(8);
    let origin = Origin::default();
    let fields = json!({"n": [1, 2.5, 3], "o": [{"a": 1}], "e": []});
    tables.add_rendered(&origin, 0, "L", &Map::new(), &fields);
    let (_, batch) = tables.finish().remove(0);
    let text = |n: &str| {
        batch
            .column_by_name(n)
            .map(|c| c.as_string::<i32>().value(0).to_owned())
    };
    assert_eq!(text("n").as_deref(), Some("[1,2.5,3]"));
    assert_eq!(text("o").as_deref(), Some(r#"[{"a":1}]"#));
    assert_eq!(text("e").as_deref(), Some("[]"));
    assert_eq!(tables.mismatches(), 0);
}

#[test]
fn a_column_seen_later_is_null_before_and_unify_pads_earlier_batches() {
    let mut tables = Tables::new(2);
    let origin = Origin::default();
    for (i, f) in [json!({"a": 1}), json!({"a": 2}), json!({"a": 3, "b": true})]
        .iter()
        .enumerate()
    {
        tables.add_rendered(&origin, i as u64, "T", &Map::new(), f);
    }
    let batches: Vec<RecordBatch> = tables.finish().into_iter().map(|(_, b)| b).collect();
    assert_eq!(batches.len(), 2);
    assert!(batches[0].column_by_name("b").is_none());
    let (schema, batches) = unify(batches);
    // capture_time, time, offset, a, b.
    assert_eq!(schema.fields().len(), 5);
    assert_eq!(
        batches[0].column_by_name("b").map(|c| c.null_count()),
        Some(2)
    );
}

#[test]
fn export_starts_a_new_part_when_the_columns_change() -> Result<(), Box<dyn std::error::Error>> {
    let dir = std::env::temp_dir().join(format!("protolink-columns-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let mut tables = Tables::new(1);
    let origin = Origin::default();
    let mut export = Export::new(&dir, Format::Parquet)?;
    for f in [json!({"a": 1}), json!({"a": 2}), json!({"a": 3, "b": true})] {
        tables.add_rendered(&origin, 0, "T", &Map::new(), &f);
        for (name, batch) in tables.take_full() {
            export.write(&name, &batch)?;
        }
    }
    let written = export.finish()?;
    assert_eq!(written.len(), 1);
    assert_eq!(written[0].rows, 3);
    let parts: Vec<_> = written[0]
        .parts
        .iter()
        .map(|p| p.file_name().map(|n| n.to_string_lossy().into_owned()))
        .collect();
    assert_eq!(
        parts,
        [
            Some("part-00000.parquet".to_string()),
            Some("part-00001.parquet".to_string())
        ]
    );
    // Nothing half-written is left.
    let left: Vec<_> = std::fs::read_dir(dir.join("proto=none/type=T"))?
        .filter_map(Result::ok)
        .filter(|e| e.file_name().to_string_lossy().ends_with(".partial"))
        .collect();
    assert!(left.is_empty());
    // The next export into the same place is refused before it writes anything.
    let e = Export::new(&dir, Format::Parquet).expect_err("refused");
    assert_eq!(
        e.to_string(),
        format!(
            "{} is not empty: an export goes to a new or empty directory",
            dir.display()
        )
    );
    std::fs::remove_dir_all(&dir)?;
    Ok(())
}

/// `read_file` ends where its step says (`ControlFlow::Break`), in a byte file and in a
/// capture: the report counts the bytes and rows read up to there and says it stopped; a step
/// that never stops reads the whole file.
#[test]
fn read_file_stops_where_the_step_says() -> Result<(), Box<dyn std::error::Error>> {
    use protolink::capture::CaptureWriter;
    use protolink::columns::ROW_GROUP;
    use protolink::commands::decode::tables::{Select, read_file};
    use protolink::proto::Proto;
    use std::net::SocketAddrV4;
    use std::ops::ControlFlow;
    use std::time::Duration;

    let dir = std::env::temp_dir().join(format!("protolink-read-stop-{}", std::process::id()));
    std::fs::create_dir_all(&dir)?;
    let aeolus = include_bytes!("../../../testdata/qemu-uart0-aeolus.bin");
    let select = Select {
        proto: Some(Proto::Aeolus),
        ..Select::default()
    };
    // Stops at the `at`-th step (0: never); the report and the steps taken.
    let read = |path: &std::path::Path, at: u32| {
        let mut steps = 0;
        let report = read_file(path, &select, None, &mut Tables::new(ROW_GROUP), |_| {
            steps += 1;
            Ok(if steps == at {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            })
        });
        (report, steps)
    };

    // A byte file of eight copies, about 630 KB: three steps of 256 KiB and the last one.
    let bytes = dir.join("aeolus.bin");
    std::fs::write(&bytes, aeolus.repeat(8))?;
    let (whole, steps) = read(&bytes, 0);
    let whole = whole?;
    assert_eq!(
        (whole.bytes, whole.stopped, steps),
        (8 * aeolus.len() as u64, false, 4)
    );
    let (cut, steps) = read(&bytes, 2);
    let cut = cut?;
    assert_eq!((cut.bytes, cut.stopped, steps), (2 * 256 * 1024, true, 2));
    assert!(
        cut.rows > 0 && cut.rows < whole.rows,
        "{cut:?} of {whole:?}"
    );

    // A capture of 3000 datagrams of one frame each: a step per 1024 records.
    let capture = dir.join("aeolus.pcapng");
    let mut w = CaptureWriter::create(&capture, 1, "stop")?;
    let frame = &aeolus[..15]; // the TOAST "AEOLUS on"
    let (src, dst) = (
        SocketAddrV4::new([127, 0, 0, 1].into(), 40000),
        SocketAddrV4::new([127, 0, 0, 1].into(), 5001),
    );
    for i in 0..3000u64 {
        w.udp(Duration::from_millis(i), src, dst, frame)?;
    }
    w.flush()?;
    drop(w);
    let (whole, _) = read(&capture, 0);
    let whole = whole?;
    assert_eq!((whole.rows, whole.stopped), (3000, false));
    assert_eq!(whole.bytes, std::fs::metadata(&capture)?.len());
    let (cut, steps) = read(&capture, 1);
    let cut = cut?;
    assert_eq!((cut.stopped, steps), (true, 1));
    assert!(
        cut.bytes > 0 && cut.bytes < whole.bytes && cut.rows >= 1000 && cut.rows < 3000,
        "{cut:?} of {whole:?}"
    );
    std::fs::remove_dir_all(&dir)?;
    Ok(())
}

/// The tables of a byte file of `proto` (`side`: AOK's), through the one decoder.
fn tables_of(
    bytes: &[u8],
    proto: protolink::proto::Proto,
    side: protolink::proto::Side,
) -> Vec<(String, RecordBatch)> {
    let mut tables = Tables::new(1000);
    let origin = Origin::default();
    let mut d = protolink::decoders::Decoder::new(proto, Default::default(), side);
    d.feed(bytes, 0, |p| tables.add(&origin, &p));
    d.finish(|p| tables.add(&origin, &p));
    assert_eq!(tables.mismatches(), 0);
    tables.finish()
}

/// The type of column `column` of table `table`.
fn column_type(batches: &[(String, RecordBatch)], table: &str, column: &str) -> Option<DataType> {
    let (_, batch) = batches.iter().find(|(n, _)| n == table)?;
    let schema = batch.schema();
    schema
        .field_with_name(column)
        .ok()
        .map(|f| f.data_type().clone())
}

#[test]
fn aydp_aok_and_gdl90_columns_have_the_wire_types() {
    use protolink::proto::{Proto, Side};
    let testdata = concat!(env!("CARGO_MANIFEST_DIR"), "/../testdata/");
    let aydp = std::fs::read(format!("{testdata}qemu-uart1-aydp.bin")).unwrap_or_default();
    let aydp = tables_of(&aydp, Proto::Aydp, Side::default());
    assert_eq!(
        column_type(&aydp, "FIX_QUALITY", "fix_type"),
        Some(DataType::UInt8)
    );
    assert_eq!(
        column_type(&aydp, "FIX_QUALITY", "hdop"),
        Some(DataType::Float32)
    );
    assert_eq!(
        column_type(&aydp, "POSITION", "altitude"),
        Some(DataType::Float32)
    );
    assert_eq!(
        column_type(&aydp, "POSITION", "latitude"),
        Some(DataType::Float64)
    );
    let aok = std::fs::read(format!("{testdata}qemu-uart2-aok.bin")).unwrap_or_default();
    let aok = tables_of(&aok, Proto::Aok, Side::Device);
    assert_eq!(column_type(&aok, "DEBUG", "number"), Some(DataType::UInt8));
    assert_eq!(column_type(&aok, "DEBUG", "value"), Some(DataType::Int32));
    let mut gdl90 = vec![0u8; 64];
    let n = gdl90_proto::encode_frame(0x0B, &[0x01, 0x02, 0x00, 0x0A], &mut gdl90).unwrap_or(0);
    gdl90.truncate(n);
    let gdl90 = tables_of(&gdl90, Proto::Gdl90, Side::default());
    assert_eq!(
        column_type(&gdl90, "GEO_ALTITUDE", "altitude_ft"),
        Some(DataType::Int32)
    );
}

#[test]
fn a_message_type_has_one_schema_whatever_its_messages_hold() {
    use protolink::proto::{Proto, Side};
    // A clean TOAST and one with a byte that is not text: the second has `hex`, the first a
    // null there; the same columns either way, in either order.
    let clean = [0x7E, 0x52, b'h', b'i', 0, 0x73, 0xEC, 0x7E];
    let mut raw = vec![0u8; 32];
    let message = aeolus_proto::message::Message::Toast(
        aeolus_proto::message::Text::new("h\u{1b}").unwrap_or_else(|_| unreachable!()),
    );
    let n = message
        .encode(&mut raw, aeolus_proto::CrcMode::Compute)
        .unwrap_or(0);
    raw.truncate(n);
    let schema = |bytes: &[u8]| {
        let batches = tables_of(bytes, Proto::Aeolus, Side::default());
        batches[0].1.schema()
    };
    assert_eq!(schema(&clean), schema(&raw));
    assert_eq!(schema(&[&clean[..], &raw].concat()), schema(&raw));
    // A GDL90 OWNSHIP without a position, track or speeds, and one with them all: one schema,
    // with no column of Arrow's Null type.
    use gdl90_proto::message::{LatLon, Message as G, Report, Track};
    let frame = |r: Report| {
        let mut out = vec![0u8; 128];
        let n = G::Ownship(r).encode(&mut out).unwrap_or(0);
        out.truncate(n);
        out
    };
    let bare = frame(Report::default());
    let full = frame(Report {
        position: Some(LatLon {
            lat_deg: 47.0,
            lon_deg: 8.0,
        }),
        pressure_altitude_ft: Some(1500),
        track: Some(Track::MagneticHeading(90.0)),
        ground_speed_kt: Some(80),
        vertical_rate_fpm: Some(-64),
        ..Report::default()
    });
    let ownship = |bytes: &[u8]| {
        let batches = tables_of(bytes, Proto::Gdl90, Side::default());
        batches[0].1.schema()
    };
    assert_eq!(ownship(&bare), ownship(&full));
    assert_eq!(ownship(&[&bare[..], &full].concat()), ownship(&full));
    let bare_schema = ownship(&bare);
    assert!(
        bare_schema
            .fields()
            .iter()
            .all(|f| f.data_type() != &DataType::Null)
    );
    assert_eq!(
        bare_schema
            .field_with_name("track.TrueHeading")
            .map(|f| f.data_type().clone())
            .ok(),
        Some(DataType::Float32)
    );
    // An expedited AYDP HEARTBEAT has no header time: its time columns are there, null.
    let heartbeat = [0xFF, 0x80, 0x07, 0x00, 0x00, 0x00, 0x78];
    let batches = tables_of(&heartbeat, Proto::Aydp, Side::default());
    let (_, batch) = &batches[0];
    let seconds = batch.column_by_name("meta.time.seconds");
    assert_eq!(seconds.map(|c| c.null_count()), Some(1));
}

/// The table `name` of `batches`.
fn table(batches: &[(String, RecordBatch)], name: &str) -> RecordBatch {
    batches
        .iter()
        .find(|(n, _)| n == name)
        .map(|(_, b)| b.clone())
        .unwrap_or_else(|| panic!("no {name}"))
}

/// The names and types of a batch's columns.
fn types(batch: &RecordBatch) -> Vec<(String, DataType)> {
    batch
        .schema()
        .fields()
        .iter()
        .map(|f| (f.name().clone(), f.data_type().clone()))
        .collect()
}

#[test]
fn aeolus_box_time_is_a_duration_and_motion_columns_name_their_units() {
    let batches = sample();
    let gyro = table(&batches, "GYRO");
    let micros = DataType::Duration(TimeUnit::Microsecond);
    assert_eq!(
        types(&gyro)[3..],
        [
            ("meta.id".to_owned(), DataType::Int64),
            ("meta.len".to_owned(), DataType::Int64),
            ("meta.crc".to_owned(), DataType::Utf8),
            ("valid".to_owned(), DataType::Boolean),
            ("box_time".to_owned(), micros.clone()),
            ("x_radps".to_owned(), DataType::Float32),
            ("y_radps".to_owned(), DataType::Float32),
            ("z_radps".to_owned(), DataType::Float32),
        ]
    );
    let names_of = |t: &str| names(&table(&batches, t));
    assert!(
        names_of("ACCEL").ends_with(&["box_time", "x_mps2", "y_mps2", "z_mps2"].map(String::from))
    );
    assert!(
        names_of("MAGNET")
            .ends_with(&["box_time", "x_gauss", "y_gauss", "z_gauss"].map(String::from))
    );
    // Every AEOLUS table of a message with a time has it as `box_time`, none as `timestamp_ms`.
    for (name, batch) in &batches {
        assert!(batch.column_by_name("timestamp_ms").is_none(), "{name}");
        if let Some(c) = batch.column_by_name("box_time") {
            assert_eq!(c.data_type(), &micros, "{name}");
        }
    }
    // The box's milliseconds, to the microsecond.
    let mut d = AeolusDecoder::new();
    let mut ms = Vec::new();
    d.feed(&sample_bytes(), 0, |p| {
        if let protolink::decoders::Item::Aeolus {
            message: aeolus_proto::message::Message::Gyro(g),
            ..
        } = &p.item
        {
            ms.push(g.timestamp_ms);
        }
    });
    let got: Vec<i64> = gyro
        .column_by_name("box_time")
        .expect("box_time")
        .as_primitive::<DurationMicrosecondType>()
        .values()
        .iter()
        .copied()
        .collect();
    let want: Vec<i64> = ms
        .iter()
        .take(got.len())
        .map(|m| (m * 1000.0).round() as i64)
        .collect();
    assert_eq!(got, want);
    assert!(got.iter().any(|&us| us % 1000 == 0 && us > 0));
}

/// An AYDP FIX_DETAIL of `satellites` (id, azimuth, elevation, snr) and a DIRECT_OUTPUT of
/// `entries` (device, channel, value), as a stream of normal frames.
pub(crate) fn aydp_lists(satellites: &[(u8, f32, f32, f32)], entries: &[(u8, u8, f32)]) -> Vec<u8> {
    let enc = aydp_proto::Encoder::new(aydp_proto::Profile::Spec);
    let mut fix = vec![u8::try_from(satellites.len()).unwrap()];
    for &(id, azimuth, elevation, snr) in satellites {
        let s = aydp_proto::Satellite {
            id,
            azimuth,
            elevation,
            snr,
        };
        let mut b = [0u8; aydp_proto::Satellite::LEN];
        s.emit(&mut b).unwrap();
        fix.extend_from_slice(&b);
    }
    let mut out = u16::try_from(entries.len()).unwrap().to_le_bytes().to_vec();
    for &(device, channel, value) in entries {
        let e = aydp_proto::OutputEntry {
            device,
            channel,
            value,
        };
        let mut b = [0u8; aydp_proto::OutputEntry::LEN];
        e.emit(&mut b).unwrap();
        out.extend_from_slice(&b);
    }
    let mut stream = Vec::new();
    let types = [aydp_proto::FixDetail::TYPE, aydp_proto::DirectOutput::TYPE];
    for (msg_type, data) in types.into_iter().zip([&fix, &out]) {
        let raw = aydp_proto::Raw { msg_type, data };
        let mut buf = vec![0u8; enc.frame_len(&raw, false)];
        let ts = Some(aydp_proto::Timestamp::new(1_700_000_000, 5));
        let n = enc.encode(&raw, ts, &mut buf).unwrap();
        stream.extend_from_slice(&buf[..n]);
    }
    stream
}

/// The tables of an AYDP stream.
fn aydp_tables(stream: &[u8]) -> Vec<(String, RecordBatch)> {
    let mut tables = Tables::new(8);
    let mut d = protolink::decoders::AydpDecoder::new(aydp_proto::Profile::Spec);
    d.feed(stream, 0, |p| tables.add(&Origin::default(), &p));
    tables.finish()
}

#[test]
fn aydp_lists_are_arrow_lists_of_one_schema_whether_empty_or_full() {
    let full = aydp_tables(&aydp_lists(
        &[(7, 180.0, 45.0, 38.0), (9, 90.0, 10.0, 20.5)],
        &[(1, 2, 10.0)],
    ));
    let empty = aydp_tables(&aydp_lists(&[], &[]));
    let list = |t: DataType| DataType::List(std::sync::Arc::new(Field::new_list_field(t, true)));
    let fix = table(&full, "FIX_DETAIL");
    assert_eq!(
        types(&fix)[10..],
        [
            ("satellites.id".to_owned(), list(DataType::UInt8)),
            ("satellites.azimuth".to_owned(), list(DataType::Float32)),
            ("satellites.elevation".to_owned(), list(DataType::Float32)),
            ("satellites.snr".to_owned(), list(DataType::Float32)),
        ]
    );
    let output = table(&full, "DIRECT_OUTPUT");
    assert_eq!(
        types(&output)[10..],
        [
            ("entries.device".to_owned(), list(DataType::UInt8)),
            ("entries.channel".to_owned(), list(DataType::UInt8)),
            ("entries.value".to_owned(), list(DataType::Float32)),
        ]
    );
    // Empty lists: the same schema, and an empty list (not a null) in the row.
    for name in ["FIX_DETAIL", "DIRECT_OUTPUT"] {
        let (e, f) = (table(&empty, name), table(&full, name));
        assert_eq!(e.schema(), f.schema(), "{name}");
        let first = e.column(10).as_list::<i32>();
        assert_eq!(
            (first.null_count(), first.value_length(0)),
            (0, 0),
            "{name}"
        );
    }
    let snr = fix
        .column_by_name("satellites.snr")
        .expect("snr")
        .as_list::<i32>();
    let snr: Vec<f32> = snr.value(0).as_primitive::<Float32Type>().values().to_vec();
    assert_eq!(snr, [38.0, 20.5]);
    let ids = fix
        .column_by_name("satellites.id")
        .expect("id")
        .as_list::<i32>();
    assert_eq!(
        ids.value(0).as_primitive::<UInt8Type>().values().to_vec(),
        [7, 9]
    );
    // The units of the list's items are the fields' own (none here), and no value was lost.
    assert_eq!(
        aydp_tables(&aydp_lists(&[(1, 0.0, 0.0, 0.0)], &[])).len(),
        2
    );
}

#[test]
fn a_box_time_out_of_a_durations_range_is_a_null_of_its_type() {
    use aeolus_proto::message::{Gyro, Message};
    let mut tables = Tables::new(8);
    let origin = Origin::default();
    for ms in [1e300, f64::NAN, 2.5] {
        let g = Gyro {
            valid: true,
            timestamp_ms: ms,
            x: 0.0,
            y: 0.0,
            z: 0.0,
        };
        tables.add_aeolus_message(&origin, 0, Gyro::ID, true, 37, &Message::Gyro(g));
    }
    let (_, batch) = tables.finish().remove(0);
    let c = batch.column_by_name("box_time").expect("box_time");
    assert_eq!(c.data_type(), &DataType::Duration(TimeUnit::Microsecond));
    let got: Vec<Option<i64>> = c.as_primitive::<DurationMicrosecondType>().iter().collect();
    assert_eq!(got, [None, None, Some(2500)]);
}
