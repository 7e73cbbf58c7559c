//! One message type's table: its columns, filled a row at a time, and cut into Arrow record
//! batches (row groups).

use std::sync::Arc;

use arrow_array::RecordBatch;
use arrow_schema::{Schema, SchemaRef};

use super::PROTO_KEY;
use super::column::{Column, Scalar};
use super::fnv::FnvMap;
use super::names::{self, Convert, Named};
use super::unit;
use crate::proto::{Proto, proto_name};

/// The columns of one message type. A column appears with the first row that has a value in it
/// (the rows before hold nulls in it), or is declared before from samples of the type, and
/// stays: every batch cut from the table has all columns seen so far, in the order they first
/// appeared. No column is of Arrow's Null type: an absent value makes none.
pub(crate) struct Table {
    /// The message type: it tells some columns' units.
    kind: Box<str>,
    /// The protocol of its messages, when known: every batch's schema names it
    /// ([`PROTO_KEY`]).
    pub(crate) proto: Option<Proto>,
    columns: Vec<Column>,
    index: FnvMap<Box<str>, usize>,
    /// Rows ended since the last batch.
    rows: usize,
    /// Where the next value of this row is looked for first: rows of one type name their
    /// columns in the same order, so the lookup is one comparison.
    cursor: usize,
    /// Values that did not fit their column's type (a null was stored instead).
    pub(crate) mismatches: u64,
    /// Values make columns without filling them ([`Table::declare_like`] is running).
    declaring: bool,
    /// The message type's columns were declared from samples.
    declared: bool,
    /// The fields the export names its own way ([`names`]).
    names: &'static [Named],
}

impl Table {
    /// The empty table of message type `kind` of protocol `proto`.
    pub(crate) fn new(kind: &str, proto: Option<Proto>) -> Table {
        Table {
            kind: kind.into(),
            proto,
            columns: Vec::new(),
            index: FnvMap::default(),
            rows: 0,
            cursor: 0,
            mismatches: 0,
            declaring: false,
            declared: false,
            names: names::of(proto, kind),
        }
    }

    /// Rows ended since the last batch.
    pub(crate) fn rows(&self) -> usize {
        self.rows
    }

    /// The index of the column `name`, if it exists.
    fn find(&mut self, name: &str) -> Option<usize> {
        let i = match self.columns.get(self.cursor) {
            Some(c) if *c.name == *name => self.cursor,
            _ => *self.index.get(name)?,
        };
        self.cursor = i + 1;
        Some(i)
    }

    /// The index of the column `name`, if it exists: a name the program holds (a field's,
    /// a metadata column's) is found by its address when it was looked up before.
    fn find_static(&mut self, name: &'static str) -> Option<usize> {
        let key = key_of(name);
        if let Some(c) = self.columns.get(self.cursor)
            && c.key == key
        {
            self.cursor += 1;
            return Some(self.cursor - 1);
        }
        let i = self.find(name)?;
        if let Some(c) = self.columns.get_mut(i) {
            c.key = key;
        }
        Some(i)
    }

    /// [`Table::set`] of a name the program holds (found by its address).
    pub(crate) fn set_static(&mut self, name: &'static str, v: Scalar<'_>) {
        match self.find_static(name) {
            Some(i) => self.put(i, v),
            // An absent value makes no column: a column has the type of a value.
            None if matches!(v, Scalar::Null) => {}
            None => {
                let mut c = Column::new(name, v, self.rows);
                c.key = key_of(name);
                if !self.declaring {
                    c.push(v);
                }
                self.add(c);
            }
        }
    }

    /// Sets the value of typed field `field` (a top-level field of a message type) in this row,
    /// in the column the message type's entry of [`names`] gives it (its own name otherwise),
    /// written as that entry says: found by the field's address, the name looked up only once.
    pub(crate) fn set_field(&mut self, field: &'static str, v: Scalar<'_>) {
        let key = key_of(field);
        if let Some(c) = self.columns.get(self.cursor)
            && c.key == key
        {
            let i = self.cursor;
            self.cursor += 1;
            self.put(i, v);
            return;
        }
        let (column, convert) = names::column(self.names, field);
        let i = match self.find(column) {
            Some(i) => i,
            None => {
                // An absent value makes no column, unless its column's type is known.
                let like = match (convert.like(), convert.apply(v)) {
                    (Some(like), _) => like,
                    (None, Scalar::Null) => return,
                    (None, v) => v,
                };
                let mut c = Column::new(column, like, self.rows);
                c.convert = convert;
                self.add(c);
                self.columns.len() - 1
            }
        };
        if let Some(c) = self.columns.get_mut(i) {
            c.key = key;
        }
        self.put(i, v);
    }

    /// Sets the value of the column `name` in this row (a column it creates when new). A value
    /// for a column already set in this row is dropped (a field named like a nested one's path).
    pub(crate) fn set(&mut self, name: &str, v: Scalar<'_>) {
        match self.find(name) {
            Some(i) => self.put(i, v),
            // An absent value makes no column: a column has the type of a value.
            None if matches!(v, Scalar::Null) => {}
            None => {
                let mut c = Column::new(name, v, self.rows);
                if !self.declaring {
                    c.push(v);
                }
                self.add(c);
            }
        }
    }

    /// Makes sure the column `name` exists, of the type of `like` (all nulls so far when it is
    /// new); sets nothing in this row.
    pub(crate) fn declare(&mut self, name: &'static str, like: Scalar<'_>) {
        if self.find_static(name).is_none() {
            let mut c = Column::new(name, like, self.rows);
            c.key = key_of(name);
            self.add(c);
        }
    }

    /// Makes the columns `write` would set, each of the type of the value it gives, without
    /// setting anything in this row; then the table counts as declared.
    pub(crate) fn declare_like(&mut self, write: impl FnOnce(&mut Table)) {
        self.declaring = true;
        write(self);
        self.declaring = false;
        self.declared = true;
    }

    /// Whether [`Table::declare_like`] has run.
    pub(crate) fn declared(&self) -> bool {
        self.declared
    }

    /// Sets the value of the column `name` in this row, or a null: a column it creates is of the
    /// type of `like`.
    pub(crate) fn set_typed(
        &mut self,
        name: &'static str,
        v: Option<Scalar<'_>>,
        like: Scalar<'_>,
    ) {
        let i = match self.find_static(name) {
            Some(i) => i,
            None => {
                let mut c = Column::new(name, like, self.rows);
                c.key = key_of(name);
                self.add(c);
                self.columns.len() - 1
            }
        };
        self.put(i, v.unwrap_or(Scalar::Null));
    }

    /// Appends an item to this row's list in the list column `name` (a column it creates when
    /// new, of items of the type of `v`; while declaring, it only creates it).
    pub(crate) fn push_item(&mut self, name: &str, v: Scalar<'_>) {
        let i = match self.find(name) {
            Some(i) => i,
            None => {
                self.add(Column::new_list(name, v, self.rows));
                self.columns.len() - 1
            }
        };
        if self.declaring {
            return;
        }
        let rows = self.rows;
        if let Some(c) = self.columns.get_mut(i)
            && !c.push_item(v, rows)
        {
            self.mismatches += 1;
        }
    }

    /// Opens this row's lists under `root` (the list column `root`, or the parallel lists
    /// `root.FIELD` of a list of structs): each is this row's list, empty until an item comes,
    /// instead of a null.
    pub(crate) fn open_lists(&mut self, root: &str) {
        if self.declaring {
            return;
        }
        let rows = self.rows;
        for c in &mut self.columns {
            let under = c
                .name
                .strip_prefix(root)
                .is_some_and(|rest| rest.is_empty() || rest.starts_with('.'));
            if under {
                c.open(rows);
            }
        }
    }

    /// Sets this row's value of column `i`, unless it has one.
    fn put(&mut self, i: usize, v: Scalar<'_>) {
        if self.declaring {
            return;
        }
        let rows = self.rows;
        if let Some(c) = self.columns.get_mut(i)
            && c.filled == rows
            && !c.push(match c.convert {
                Convert::Same => v,
                other => other.apply(v),
            })
        {
            self.mismatches += 1;
        }
    }

    /// Adds a column (its unit from its name).
    fn add(&mut self, mut c: Column) {
        c.unit = unit::unit(&self.kind, &c.name);
        self.index.insert(c.name.clone(), self.columns.len());
        self.columns.push(c);
        self.cursor = self.columns.len();
    }

    /// Ends this row: every column it did not set holds a null.
    pub(crate) fn end_row(&mut self) {
        let rows = self.rows;
        for c in &mut self.columns {
            c.end_row(rows);
        }
        self.rows += 1;
        self.cursor = 0;
    }

    /// The schema of the next batch: its columns, and the protocol in the metadata.
    pub(crate) fn schema(&self) -> SchemaRef {
        let fields = self.columns.iter().map(Column::field).collect::<Vec<_>>();
        let metadata: std::collections::HashMap<String, String> = self
            .proto
            .map(|p| (PROTO_KEY.to_owned(), proto_name(p).to_owned()))
            .into_iter()
            .collect();
        Arc::new(Schema::new_with_metadata(fields, metadata))
    }

    /// The rows since the last batch as a record batch; the table starts again empty, with the
    /// same columns.
    pub(crate) fn take_batch(&mut self) -> Option<RecordBatch> {
        if self.rows == 0 {
            return None;
        }
        let schema = self.schema();
        let arrays = self.columns.iter_mut().map(Column::finish).collect();
        let rows = std::mem::take(&mut self.rows);
        let options = arrow_array::RecordBatchOptions::new().with_row_count(Some(rows));
        RecordBatch::try_new_with_options(schema, arrays, &options).ok()
    }
}

/// The lookup key of a name the program holds: its address and length.
fn key_of(name: &'static str) -> (usize, usize) {
    (name.as_ptr() as usize, name.len())
}
