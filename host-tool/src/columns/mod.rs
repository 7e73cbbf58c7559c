//! Decoded messages as typed columns, one table per protocol and message type, cut into Arrow
//! record batches of at most a row group each: what `protolink export` writes as Parquet or
//! Arrow IPC files and what the Python package hands pyarrow (`protolink.to_arrow`,
//! `to_frames`).
//!
//! A row is one message: first its metadata, then its fields.
//!
//! | column | type | what |
//! |---|---|---|
//! | `source` | Utf8 | the file it was read from (`export`; only when given) |
//! | `file`, `capture_id` | Utf8, Utf8 | that file's name and content identity ([`SourceId`]; with `source`) |
//! | `capture_time` | Float64 | the capture record's time, seconds since the Unix epoch (null from a byte file) |
//! | `time` | Timestamp(µs, UTC) | the row's time: the capture record's, else an AYDP message's header time (`meta.time`); null when it has neither |
//! | `offset` | Int64 | its first byte in the input (in its flow, for a capture) |
//! | `flow`, `frame`, `proto` | Utf8, Int64, Utf8 | the capture's flow, record number (from 1) and protocol (only from a capture; an export's files leave `proto` out, their path holds it) |
//! | `meta.KEY` | Int64, Boolean, Utf8 | what `decode --json` prints about the frame beside `fields`: AEOLUS `id`, `len`, `crc`; AYDP `type`, `expedited`, `len`, `time` (the header's time as a Timestamp(µs, UTC)), `time.profile` (`spec` or `reference`: the unit of `time.subsec`, ms or µs), `time.seconds`, `time.subsec`; AOK `len`; GDL90 `id`, `len` |
//! | each field | its own | the `"fields"` of `decode --json`, a nested one as `outer.inner` |
//!
//! The fields' types are the message types' own, in all four protocols: the wire's widths
//! (`f32` as Float32, `u16` as UInt16, a fixed-size array as a column per element), flags as
//! Boolean, an enum without data by its variant's name (Utf8); what `decode` shows by name or
//! as hex is that text (AOK slots and actions, an AYDP system control's `command`, raw
//! `data`); a list of structs (AYDP output `entries`, `satellites`) is a List column per field
//! of its items (`satellites.id`, `satellites.snr`, ...: one list a row each, of one length),
//! of one schema whether the lists are empty or full. Some fields take the export's own name
//! and type, one entry per message type in `names.rs`: AEOLUS `timestamp_ms` is `box_time`, a
//! Duration(µs) since the box started; GYRO, ACCEL and MAGNET `x`, `y`, `z` name their units
//! (`x_radps`, `x_mps2`, `x_gauss`). A rendered message's list ([`Tables::add_rendered`],
//! whose items may be of any type) is its JSON text. Error events make the table `ERROR`
//! (`kind`, `error`). A field named like a metadata column is written as
//! `field.NAME` (no field of the four protocols is). [`Tables::keep`] keeps only some rows
//! ([`Keep`]: `export --types`, `--since`, `--until`).
//!
//! ```
//! use protolink::columns::{Origin, Tables};
//! use protolink::decoders::AeolusDecoder;
//!
//! let mut tables = Tables::new(1024);
//! let mut d = AeolusDecoder::new();
//! let origin = Origin::default();
//! d.feed(&[0x7E, 0x52, b'h', b'i', 0, 0x73, 0xEC, 0x7E], 0, |p| tables.add(&origin, &p));
//! let batches = tables.finish();
//! let (name, batch) = &batches[0];
//! assert_eq!((name.as_str(), batch.num_rows()), ("TOAST", 1));
//! let names: Vec<_> = batch.schema().fields().iter().map(|f| f.name().clone()).collect();
//! assert_eq!(names, ["capture_time", "time", "offset", "meta.id", "meta.len", "meta.crc", "text", "hex"]);
//! ```

mod air;
mod column;
mod fnv;
mod keep;
mod names;
mod row;
mod source;
mod table;
mod typed;
mod unit;
#[cfg(feature = "parquet")]
pub mod write;

use arrow_array::RecordBatch;
use serde::Serialize;
use serde_json::{Map, Value};

pub use self::keep::{Keep, TYPES, parse_time};
pub use self::source::{ID_PREFIX, SourceId};

use self::column::Scalar;
use self::fnv::FnvMap;
use self::row::{Ints, write_fields};
use self::table::Table;
use crate::decoders::{Item, Placed, aok_command_name, aok_message_name, aydp_name};
use crate::proto::{Proto, proto_name};

/// Rows per row group (record batch) unless asked otherwise: 64 Ki rows of one type, a few
/// megabytes of columns.
pub const ROW_GROUP: usize = 65_536;

/// The key of a batch's schema metadata that names its message type's protocol (`aeolus`,
/// `aydp`, `aok`, `gdl90`), when it is known: two protocols' types of one name (AYDP's and
/// GDL90's `HEARTBEAT`) are two tables.
pub const PROTO_KEY: &str = "proto";

/// The protocol a batch's schema names ([`PROTO_KEY`]), if any.
///
/// ```
/// use protolink::columns::{Origin, Tables, proto_of};
/// use protolink::decoders::AeolusDecoder;
/// let mut tables = Tables::new(8);
/// let mut d = AeolusDecoder::new();
/// d.feed(&[0x7E, 0x52, b'h', b'i', 0, 0x73, 0xEC, 0x7E], 0, |p| tables.add(&Origin::default(), &p));
/// assert_eq!(proto_of(&tables.finish()[0].1), Some("aeolus"));
/// ```
pub fn proto_of(batch: &RecordBatch) -> Option<&str> {
    batch
        .schema_ref()
        .metadata()
        .get(PROTO_KEY)
        .map(String::as_str)
}

/// The metadata columns a field's name must not take.
const METADATA: [&str; 9] = [
    "source",
    "file",
    "capture_id",
    "capture_time",
    "time",
    "offset",
    "flow",
    "frame",
    "proto",
];

/// Where a message came from: its source file, and for a capture its record.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Origin {
    /// The file it was read from (`export` names every row's).
    pub source: Option<String>,
    /// The capture record's time, seconds since the Unix epoch (or the host's clock on a live
    /// link).
    pub capture_time: Option<f64>,
    /// The capture's flow, e.g. `udp 127.0.0.1:40000 > 127.0.0.1:5001`.
    pub flow: Option<String>,
    /// The capture record's number, from 1.
    pub frame: Option<u64>,
    /// The flow's protocol (from a capture).
    pub proto: Option<Proto>,
}

/// The tables being filled, one per protocol and message type (in the order the types first
/// came; a table's batches name its protocol, [`proto_of`]), and
/// the batches cut from them.
pub struct Tables {
    tables: Vec<(String, Table)>,
    /// The first table of each name (another protocol's table of the same name is found
    /// past it, in `tables`).
    index: FnvMap<String, usize>,
    /// The tables of names the program holds, by the name's address and protocol: found
    /// without hashing the text.
    by_address: Vec<(usize, Option<Proto>, usize)>,
    row_group: usize,
    full: Vec<(String, RecordBatch)>,
    rows: u64,
    /// The rows kept.
    keep: Keep,
    /// Rows left out by `keep`.
    left_out: u64,
    /// The name and identity of the file being read (`export`).
    source_id: Option<SourceId>,
    /// The flows' state for the `AIR` table, when it is derived.
    air: Option<self::air::AirState>,
}

impl std::fmt::Debug for Tables {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Tables")
            .field("types", &self.tables.len())
            .field("rows", &self.rows)
            .finish_non_exhaustive()
    }
}

impl Tables {
    /// No tables yet; each is cut into a batch whenever it holds `row_group` rows (at least 1).
    ///
    /// ```
    /// let tables = protolink::columns::Tables::new(protolink::columns::ROW_GROUP);
    /// assert_eq!(tables.rows(), 0);
    /// ```
    pub fn new(row_group: usize) -> Tables {
        Tables {
            tables: Vec::new(),
            index: FnvMap::default(),
            by_address: Vec::new(),
            row_group: row_group.max(1),
            full: Vec::new(),
            rows: 0,
            keep: Keep::default(),
            left_out: 0,
            source_id: None,
            air: None,
        }
    }

    /// From now on, each AEOLUS PRESSURE also makes a row of the table `AIR`: the air data
    /// derived from it (indicated and true airspeed, pressure altitude, vertical speed; see
    /// `columns/air.rs`), as `export` writes it.
    ///
    /// ```
    /// use aeolus_proto::message::{Message, Pressure};
    /// use protolink::columns::{Origin, Tables};
    /// let mut tables = Tables::new(8);
    /// tables.derive_air();
    /// let p = Pressure { valid: true, timestamp_ms: 0.0, static_mbar: 1013.25, pitot_mbar: 0.0, airspeed_mps: 0.0 };
    /// tables.add_aeolus_message(&Origin::default(), 0, 60, true, 25, &Message::Pressure(p));
    /// let names: Vec<String> = tables.finish().into_iter().map(|(n, _)| n).collect();
    /// assert_eq!(names, ["AIR", "PRESSURE"]);
    /// ```
    pub fn derive_air(&mut self) {
        self.air.get_or_insert_with(Default::default);
    }

    /// From now on, only the rows `keep` keeps are added (the others are counted,
    /// [`Tables::left_out`]).
    ///
    /// ```
    /// use protolink::columns::{Keep, Origin, Tables};
    /// let mut tables = Tables::new(8);
    /// tables.keep(Keep::new(&["TOAST".into()], None, None)?);
    /// tables.add_error(&Origin::default(), 0, "truncated", "input ends inside a frame");
    /// assert_eq!((tables.rows(), tables.left_out()), (0, 1));
    /// # Ok::<(), String>(())
    /// ```
    pub fn keep(&mut self, keep: Keep) {
        self.keep = keep;
    }

    /// Rows left out by [`Tables::keep`]: of a type not asked for, or outside the times.
    pub fn left_out(&self) -> u64 {
        self.left_out
    }

    /// The file the next rows come from, named in their `file` and `capture_id` columns when
    /// their origin names a `source` ([`SourceId::of`]).
    pub fn reading(&mut self, id: Option<SourceId>) {
        self.source_id = id;
        if let Some(air) = &mut self.air {
            air.clear();
        }
    }

    /// Whether a row of table `name` of `proto` at `time` (the capture's, else `own_time`) is
    /// kept; counts it when it is not.
    fn kept(
        &mut self,
        name: &str,
        proto: Option<Proto>,
        origin: &Origin,
        own: Option<i64>,
    ) -> bool {
        if self.keep.keeps_everything() {
            return true;
        }
        let time = origin.capture_time.map(micros).or(own);
        let kept = self.keep.keeps_type(name, proto) && self.keep.keeps_time(time);
        if !kept {
            self.left_out += 1;
        }
        kept
    }

    /// Rows added so far.
    ///
    /// ```
    /// let tables = protolink::columns::Tables::new(8);
    /// assert_eq!(tables.rows(), 0);
    /// ```
    pub fn rows(&self) -> u64 {
        self.rows
    }

    /// Values stored as null because they did not fit the type their column had from its first
    /// value (none in the four protocols' messages: each field keeps one type).
    ///
    /// ```
    /// assert_eq!(protolink::columns::Tables::new(8).mismatches(), 0);
    /// ```
    pub fn mismatches(&self) -> u64 {
        self.tables.iter().map(|(_, t)| t.mismatches).sum()
    }

    /// The table of `name` of the origin's protocol (its index), its row begun with the
    /// metadata of `origin` and `offset`.
    fn begin(&mut self, name: &str, origin: &Origin, offset: u64) -> (usize, &mut Table) {
        let i = self.index_of(name, origin.proto);
        self.begin_at(i, origin, offset, None)
    }

    /// The index of the table `name` of protocol `proto`, a table it creates when new.
    fn index_of(&mut self, name: &str, proto: Option<Proto>) -> usize {
        match self.index.get(name) {
            Some(&i) if self.tables.get(i).is_some_and(|(_, t)| t.proto == proto) => i,
            Some(&first) => {
                let found = self
                    .tables
                    .iter()
                    .skip(first)
                    .position(|(n, t)| n == name && t.proto == proto);
                match found {
                    Some(k) => first + k,
                    None => self.push(name, proto),
                }
            }
            None => {
                self.index.insert(name.to_owned(), self.tables.len());
                self.push(name, proto)
            }
        }
    }

    /// A new table, and its index.
    fn push(&mut self, name: &str, proto: Option<Proto>) -> usize {
        self.tables.push((name.to_owned(), Table::new(name, proto)));
        self.tables.len() - 1
    }

    /// [`Tables::begin`] for a name the program holds, of protocol `proto`; `own_time` is
    /// the message's own time (µs since the Unix epoch), the row's `time` when the origin has
    /// none.
    fn begin_static(
        &mut self,
        name: &'static str,
        proto: Proto,
        origin: &Origin,
        offset: u64,
        own_time: Option<i64>,
    ) -> (usize, &mut Table) {
        let (key, proto) = (name.as_ptr() as usize, Some(proto));
        let i = match self
            .by_address
            .iter()
            .find(|(k, p, _)| *k == key && *p == proto)
        {
            Some(&(_, _, i)) => i,
            None => {
                let i = self.index_of(name, proto);
                self.by_address.push((key, proto, i));
                i
            }
        };
        self.begin_at(i, origin, offset, own_time)
    }

    /// Table `i`, its row begun with the metadata; `time` is the capture's, else `own_time`.
    fn begin_at(
        &mut self,
        i: usize,
        origin: &Origin,
        offset: u64,
        own_time: Option<i64>,
    ) -> (usize, &mut Table) {
        let table = &mut self.tables[i].1;
        if let Some(s) = &origin.source {
            table.set_static("source", Scalar::Run(s));
            let id = self.source_id.as_ref();
            table.set_typed("file", id.map(|id| Scalar::Run(&id.file)), Scalar::Run(""));
            table.set_typed(
                "capture_id",
                id.map(|id| Scalar::Run(&id.capture_id)),
                Scalar::Run(""),
            );
        }
        table.set_typed(
            "capture_time",
            origin.capture_time.map(Scalar::F64),
            Scalar::F64(0.0),
        );
        let time = origin.capture_time.map(micros).or(own_time);
        table.set_typed("time", time.map(Scalar::Time), Scalar::Time(0));
        table.set_static(
            "offset",
            Scalar::I64(i64::try_from(offset).unwrap_or(i64::MAX)),
        );
        if origin.source.is_some() {
            // An export's tables have every metadata column from the first row, so that byte
            // files and captures give the same columns.
            table.declare("flow", Scalar::Run(""));
            table.declare("frame", Scalar::I64(0));
            table.declare("proto", Scalar::Run(""));
        }
        if let Some(flow) = &origin.flow {
            table.set_static("flow", Scalar::Run(flow));
            let frame = origin.frame.and_then(|f| i64::try_from(f).ok());
            table.set_typed("frame", frame.map(Scalar::I64), Scalar::I64(0));
            let proto = origin.proto.map(|p| Scalar::Run(proto_name(p)));
            table.set_typed("proto", proto, Scalar::Run(""));
        }
        (i, table)
    }

    /// Ends the row of table `i`, and cuts a batch when it is full.
    fn end(&mut self, i: usize) {
        let Some((name, table)) = self.tables.get_mut(i) else {
            return;
        };
        table.end_row();
        self.rows += 1;
        if table.rows() >= self.row_group
            && let Some(batch) = table.take_batch()
        {
            self.full.push((name.clone(), batch));
        }
    }

    /// Adds a decoder's item: a message to its type's table, each field in a column of its
    /// own type; an error to `ERROR`.
    ///
    /// ```
    /// use protolink::columns::{Origin, Tables};
    /// use protolink::decoders::AydpDecoder;
    /// let mut tables = Tables::new(8);
    /// let mut d = AydpDecoder::new(aydp_proto::Profile::Spec);
    /// d.feed(&[0xFF, 0x80, 0x07, 0x00, 0x00, 0x00, 0x78], 0, |p| tables.add(&Origin::default(), &p));
    /// let batches = tables.finish();
    /// assert_eq!(batches[0].0, "HEARTBEAT");
    /// ```
    pub fn add(&mut self, origin: &Origin, placed: &Placed<'_>) {
        let (offset, len) = (placed.offset, placed.len);
        // An AEOLUS message is checked by `add_aeolus_message`, after the AIR table has seen
        // it.
        if !self.keep.keeps_everything()
            && !matches!(placed.item, Item::Aeolus { .. })
            && !self.kept_item(origin, placed)
        {
            return;
        }
        match &placed.item {
            Item::Aeolus { frame, message } => {
                self.add_aeolus_message(origin, offset, frame.id(), frame.has_crc(), len, message);
            }
            Item::Aydp { frame, message } => {
                // The header's time (normal messages), in the unit of the frame's profile.
                let time = frame.timestamp();
                let profile = frame.profile();
                let own = aydp_time(frame);
                let (i, table) =
                    self.begin_static(aydp_name(message), Proto::Aydp, origin, offset, own);
                table.set_static("meta.type", Scalar::I64(frame.base_type().into()));
                table.set_static("meta.expedited", Scalar::Bool(frame.is_expedited()));
                table.set_static("meta.len", Scalar::I64(wide(len)));
                table.set_typed("meta.time", own.map(Scalar::Time), Scalar::Time(0));
                // The unit of the header's sub-seconds: null where there is no header time.
                let unit = own.map(|_| Scalar::Str(profile_name(profile)));
                table.set_typed("meta.time.profile", unit, Scalar::Str(""));
                table.set_typed(
                    "meta.time.seconds",
                    time.map(|t| Scalar::I64(t.seconds)),
                    Scalar::I64(0),
                );
                table.set_typed(
                    "meta.time.subsec",
                    time.map(|t| Scalar::I64(t.subsec)),
                    Scalar::I64(0),
                );
                typed::aydp(table, message);
                self.end(i);
            }
            Item::AokMessage(m) => {
                let (i, table) =
                    self.begin_static(aok_message_name(m), Proto::Aok, origin, offset, None);
                table.set_static("meta.len", Scalar::I64(wide(len)));
                typed::aok_message(table, m);
                self.end(i);
            }
            Item::AokCommand(c) => {
                let (i, table) =
                    self.begin_static(aok_command_name(c), Proto::Aok, origin, offset, None);
                table.set_static("meta.len", Scalar::I64(wide(len)));
                typed::aok_command(table, c);
                self.end(i);
            }
            Item::Gdl90(m) => {
                let (i, table) = self.begin_static(m.name(), Proto::Gdl90, origin, offset, None);
                table.set_static("meta.id", Scalar::I64(m.id().into()));
                table.set_static("meta.len", Scalar::I64(wide(len)));
                typed::gdl90(table, m);
                self.end(i);
            }
            Item::Error(fault) => self.add_error(origin, offset, &fault.kind(), &fault.sentence()),
        }
    }

    /// Whether `placed` is kept (counted when it is not).
    fn kept_item(&mut self, origin: &Origin, placed: &Placed<'_>) -> bool {
        let (name, proto, own) = match &placed.item {
            Item::Aeolus { .. } => return true,
            Item::Aydp { frame, message } => (aydp_name(message), Proto::Aydp, aydp_time(frame)),
            Item::AokMessage(m) => (aok_message_name(m), Proto::Aok, None),
            Item::AokCommand(c) => (aok_command_name(c), Proto::Aok, None),
            Item::Gdl90(m) => (m.name(), Proto::Gdl90, None),
            Item::Error(_) => return self.kept("ERROR", origin.proto, origin, None),
        };
        self.kept(name, Some(proto), origin, own)
    }

    /// Adds a message as the host tool renders it (`decode --json`'s `name`, metadata and
    /// `fields`).
    ///
    /// ```
    /// use protolink::columns::{Origin, Tables};
    /// let meta = serde_json::json!({"len": 7});
    /// let meta = meta.as_object().cloned().unwrap_or_default();
    /// let mut tables = Tables::new(8);
    /// tables.add_rendered(&Origin::default(), 0, "DEBUG", &meta, &serde_json::json!({"number": 1, "value": 2000}));
    /// let batches = tables.finish();
    /// assert_eq!(batches[0].1.num_columns(), 6);
    /// ```
    pub fn add_rendered(
        &mut self,
        origin: &Origin,
        offset: u64,
        name: &str,
        meta: &Map<String, Value>,
        fields: &Value,
    ) {
        if !self.kept(name, origin.proto, origin, None) {
            return;
        }
        let (i, table) = self.begin(name, origin, offset);
        for (key, value) in meta {
            match value {
                Value::Object(inner) => {
                    for (sub, v) in inner {
                        write_meta(table, &format!("meta.{key}.{sub}"), v);
                    }
                }
                v => write_meta(table, &format!("meta.{key}"), v),
            }
        }
        write_checked(table, fields);
        self.end(i);
    }

    /// Adds an error event to the table `ERROR`: its `kind` and `error` sentence.
    ///
    /// ```
    /// use protolink::columns::{Origin, Tables};
    /// let mut tables = Tables::new(8);
    /// tables.add_error(&Origin::default(), 3, "checksum_mismatch", "checksum mismatch");
    /// assert_eq!(tables.finish()[0].0, "ERROR");
    /// ```
    pub fn add_error(&mut self, origin: &Origin, offset: u64, kind: &str, error: &str) {
        if !self.kept("ERROR", origin.proto, origin, None) {
            return;
        }
        let (i, table) = self.begin("ERROR", origin, offset);
        table.set_static("kind", Scalar::Str(kind));
        table.set_static("error", Scalar::Str(error));
        self.end(i);
    }

    /// Adds an AEOLUS message of ID `id` (`has_crc`: it carried a CRC; `len`: its length on the
    /// wire) placed at `offset`.
    ///
    /// ```
    /// use aeolus_proto::message::{Message, Text};
    /// use protolink::columns::{Origin, Tables};
    /// let mut tables = Tables::new(8);
    /// let toast = Message::Toast(Text::new("hi").unwrap());
    /// tables.add_aeolus_message(&Origin::default(), 0, 82, true, 8, &toast);
    /// assert_eq!(tables.finish()[0].0, "TOAST");
    /// ```
    pub fn add_aeolus_message(
        &mut self,
        origin: &Origin,
        offset: u64,
        id: u8,
        has_crc: bool,
        len: u64,
        message: &aeolus_proto::message::Message<'_>,
    ) {
        if let Some(air) = &mut self.air {
            use aeolus_proto::message::Message as M;
            match message {
                M::Temp(t) => air.temp(origin.flow.as_deref(), t),
                M::Pressure(p) => {
                    let data = air.pressure(origin.flow.as_deref(), p);
                    self.add_air(origin, offset, p.timestamp_ms, &data);
                }
                _ => {}
            }
        }
        if !self.kept(message.name(), Some(Proto::Aeolus), origin, None) {
            return;
        }
        let (i, table) = self.begin_static(message.name(), Proto::Aeolus, origin, offset, None);
        table.set_static("meta.id", Scalar::I64(id.into()));
        table.set_static("meta.len", Scalar::I64(wide(len)));
        table.set_static("meta.crc", Scalar::Str(if has_crc { "ok" } else { "none" }));
        // The typed messages' field names are fixed, and none is a metadata column's
        // (python/tests/test_field_names.py): no check per row.
        typed::aeolus(table, message);
        self.end(i);
    }

    /// A row of `AIR`: the air data of the PRESSURE at `offset`, of box time `box_ms`.
    fn add_air(
        &mut self,
        origin: &Origin,
        offset: u64,
        box_ms: f64,
        air: &crate::air_data::AirData,
    ) {
        if !self.kept("AIR", Some(Proto::Aeolus), origin, None) {
            return;
        }
        let (i, table) = self.begin_static("AIR", Proto::Aeolus, origin, offset, None);
        let real = |v: Option<f64>| v.map(Scalar::F64);
        let box_time = self::names::millis_to_micros(box_ms).map(Scalar::Duration);
        table.set_typed("box_time", box_time, Scalar::Duration(0));
        table.set_typed("static_hpa", real(air.static_hpa), Scalar::F64(0.0));
        table.set_typed("dynamic_pa", real(air.dynamic_pa), Scalar::F64(0.0));
        table.set_typed("celsius", real(air.celsius), Scalar::F64(0.0));
        table.set_typed("ias_mps", real(air.ias_mps), Scalar::F64(0.0));
        table.set_typed("tas_mps", real(air.tas_mps), Scalar::F64(0.0));
        table.set_typed(
            "pressure_altitude_m",
            real(air.pressure_altitude_m),
            Scalar::F64(0.0),
        );
        table.set_typed(
            "vertical_speed_mps",
            real(air.vertical_speed_mps),
            Scalar::F64(0.0),
        );
        self.end(i);
    }

    /// The batches cut so far (full row groups), in the order they were cut.
    ///
    /// ```
    /// let mut tables = protolink::columns::Tables::new(1);
    /// tables.add_error(&Default::default(), 0, "truncated", "input ends inside a frame");
    /// assert_eq!(tables.take_full().len(), 1);
    /// ```
    pub fn take_full(&mut self) -> Vec<(String, RecordBatch)> {
        std::mem::take(&mut self.full)
    }

    /// Every batch not taken yet: the full ones, then each table's last rows (in the order
    /// the types first came).
    ///
    /// ```
    /// let mut tables = protolink::columns::Tables::new(8);
    /// tables.add_error(&Default::default(), 0, "truncated", "input ends inside a frame");
    /// assert_eq!(tables.finish()[0].1.num_rows(), 1);
    /// ```
    pub fn finish(&mut self) -> Vec<(String, RecordBatch)> {
        let mut out = std::mem::take(&mut self.full);
        for (name, table) in &mut self.tables {
            if let Some(batch) = table.take_batch() {
                out.push((name.clone(), batch));
            }
        }
        out
    }
}

/// The batches of one table with one schema: the last batch's (a table's columns only grow),
/// each earlier batch given the columns it lacks as nulls.
///
/// ```
/// let mut tables = protolink::columns::Tables::new(1);
/// tables.add_error(&Default::default(), 0, "truncated", "input ends inside a frame");
/// tables.add_error(&Default::default(), 9, "truncated", "input ends inside a frame");
/// let batches: Vec<_> = tables.finish().into_iter().map(|(_, b)| b).collect();
/// let (schema, batches) = protolink::columns::unify(batches);
/// assert_eq!((schema.fields().len(), batches.len()), (5, 2));
/// ```
pub fn unify(batches: Vec<RecordBatch>) -> (arrow_schema::SchemaRef, Vec<RecordBatch>) {
    let Some(schema) = batches.last().map(RecordBatch::schema) else {
        return (std::sync::Arc::new(arrow_schema::Schema::empty()), batches);
    };
    let batches = batches
        .into_iter()
        .map(|b| {
            if b.schema() == schema {
                return b;
            }
            let columns = schema
                .fields()
                .iter()
                .map(|f| match b.column_by_name(f.name()) {
                    Some(c) if c.data_type() == f.data_type() => c.clone(),
                    _ => arrow_array::new_null_array(f.data_type(), b.num_rows()),
                })
                .collect();
            let options = arrow_array::RecordBatchOptions::new().with_row_count(Some(b.num_rows()));
            RecordBatch::try_new_with_options(schema.clone(), columns, &options).unwrap_or(b)
        })
        .collect();
    (schema, batches)
}

/// Seconds since the Unix epoch as microseconds (saturated; a NaN is 0).
#[allow(clippy::cast_possible_truncation)]
fn micros(seconds: f64) -> i64 {
    (seconds * 1e6).round() as i64
}

/// An AYDP frame's header time (normal messages), µs since the Unix epoch, its sub-seconds
/// read in the unit of the frame's profile.
fn aydp_time(frame: &aydp_proto::Frame<'_>) -> Option<i64> {
    let profile = frame.profile();
    frame.timestamp().map(|t| {
        t.seconds
            .saturating_mul(1_000_000)
            .saturating_add(t.subsec_micros(profile))
    })
}

/// An AYDP profile's name, as `--profile` takes it.
fn profile_name(profile: aydp_proto::Profile) -> &'static str {
    match profile {
        aydp_proto::Profile::Spec => "spec",
        aydp_proto::Profile::Reference => "reference",
    }
}

/// A count or length as an Int64 value (saturated).
fn wide(n: u64) -> i64 {
    i64::try_from(n).unwrap_or(i64::MAX)
}

/// A metadata value (a number, flag or text) into the column `name`.
fn write_meta(table: &mut Table, name: &str, v: &Value) {
    let s = match v {
        Value::Bool(b) => Scalar::Bool(*b),
        Value::Number(n) => match (n.as_i64(), n.as_u64(), n.as_f64()) {
            (Some(i), _, _) => Scalar::I64(i),
            (None, Some(u), _) => Scalar::U64(u),
            (_, _, Some(f)) => Scalar::F64(f),
            _ => Scalar::Null,
        },
        Value::String(s) => Scalar::Str(s),
        _ => Scalar::Null,
    };
    table.set(name, s);
}

/// Rendered fields into the row (integers as Int64), a field named like a metadata column
/// under `field.NAME`.
fn write_checked<T: Serialize + ?Sized>(table: &mut Table, fields: &T) {
    write_fields(table, fields, Ints::Wide, Some(&clashes));
}

/// Whether a field's name is a metadata column's (or looks like one).
fn clashes(name: &str) -> bool {
    METADATA.contains(&name) || name.starts_with("meta.") || name.starts_with("field.")
}
