//! One column of a table: its values of one type, appended a row at a time, with nulls where a
//! row has none, turned into an Arrow array when a row group is full. A list column holds a
//! list of values of one type a row ([`Data::List`]).

use std::sync::Arc;

use arrow_array::builder::{
    BooleanBuilder, DurationMicrosecondBuilder, Float32Builder, Float64Builder, Int8Builder,
    Int16Builder, Int32Builder, Int64Builder, StringBuilder, TimestampMicrosecondBuilder,
    UInt8Builder, UInt16Builder, UInt32Builder, UInt64Builder,
};
use arrow_array::{ArrayRef, ListArray, NullArray};
use arrow_buffer::{NullBufferBuilder, OffsetBuffer, ScalarBuffer};
use arrow_schema::{DataType, Field, TimeUnit};

use super::names::Convert;

/// The time zone of every timestamp column: the times are UTC.
const UTC: &str = "UTC";

/// One value as the decoders give it: a number of its own width, a flag, a text, or none.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Scalar<'a> {
    /// No value (an absent option).
    Null,
    /// A flag.
    Bool(bool),
    /// Signed integers.
    I8(i8),
    /// Signed integers.
    I16(i16),
    /// Signed integers.
    I32(i32),
    /// Signed integers.
    I64(i64),
    /// Unsigned integers.
    U8(u8),
    /// Unsigned integers.
    U16(u16),
    /// Unsigned integers.
    U32(u32),
    /// Unsigned integers.
    U64(u64),
    /// A single-precision real, as the wire carries it.
    F32(f32),
    /// A double-precision real.
    F64(f64),
    /// A text.
    Str(&'a str),
    /// A text that mostly repeats the row before's (a source's name, a protocol's): a column
    /// whose first value is one keeps each run of equal texts once, and writes it out as a plain
    /// text column ([`Data::Runs`]).
    Run(&'a str),
    /// A point in time: microseconds since the Unix epoch, UTC.
    Time(i64),
    /// A length of time, in microseconds (an AEOLUS message's time since the box started).
    Duration(i64),
}

impl Scalar<'_> {
    /// The value as an integer, when it is one.
    fn integer(self) -> Option<i128> {
        Some(match self {
            Scalar::I8(v) => v.into(),
            Scalar::I16(v) => v.into(),
            Scalar::I32(v) => v.into(),
            Scalar::I64(v) => v.into(),
            Scalar::U8(v) => v.into(),
            Scalar::U16(v) => v.into(),
            Scalar::U32(v) => v.into(),
            Scalar::U64(v) => v.into(),
            _ => return None,
        })
    }

    /// The value as a real, when it is a number.
    #[allow(clippy::cast_precision_loss)]
    fn real(self) -> Option<f64> {
        match self {
            Scalar::F32(v) => Some(v.into()),
            Scalar::F64(v) => Some(v),
            other => other.integer().map(|i| i as f64),
        }
    }
}

/// The values of a column so far, in the Arrow type of its first value.
pub(crate) enum Data {
    /// Only nulls so far (the type is not known yet).
    Null(usize),
    /// Flags.
    Bool(BooleanBuilder),
    /// `i8`.
    I8(Int8Builder),
    /// `i16`.
    I16(Int16Builder),
    /// `i32`.
    I32(Int32Builder),
    /// `i64`.
    I64(Int64Builder),
    /// `u8`.
    U8(UInt8Builder),
    /// `u16`.
    U16(UInt16Builder),
    /// `u32`.
    U32(UInt32Builder),
    /// `u64`.
    U64(UInt64Builder),
    /// `f32`.
    F32(Float32Builder),
    /// `f64`.
    F64(Float64Builder),
    /// UTF-8 texts.
    Str(StringBuilder),
    /// UTF-8 texts kept as runs of equal ones, turned into a plain text array at the end.
    Runs(Runs),
    /// Points in time, microseconds since the Unix epoch, UTC.
    Time(TimestampMicrosecondBuilder),
    /// Lengths of time, microseconds.
    Duration(DurationMicrosecondBuilder),
    /// A list of values of one type a row (or a null).
    List(Box<List>),
}

macro_rules! each_primitive {
    ($data:expr, $b:ident => $body:expr, $other:pat => $otherwise:expr) => {
        match $data {
            Data::Bool($b) => $body,
            Data::I8($b) => $body,
            Data::I16($b) => $body,
            Data::I32($b) => $body,
            Data::I64($b) => $body,
            Data::U8($b) => $body,
            Data::U16($b) => $body,
            Data::U32($b) => $body,
            Data::U64($b) => $body,
            Data::F32($b) => $body,
            Data::F64($b) => $body,
            Data::Str($b) => $body,
            Data::Time($b) => $body,
            Data::Duration($b) => $body,
            $other => $otherwise,
        }
    };
}

impl Data {
    /// A column for values like `v`, with `nulls` nulls before them.
    fn for_value(v: Scalar<'_>, nulls: usize) -> Data {
        let mut d = match v {
            Scalar::Null => return Data::Null(nulls),
            Scalar::Bool(_) => Data::Bool(BooleanBuilder::new()),
            Scalar::I8(_) => Data::I8(Int8Builder::new()),
            Scalar::I16(_) => Data::I16(Int16Builder::new()),
            Scalar::I32(_) => Data::I32(Int32Builder::new()),
            Scalar::I64(_) => Data::I64(Int64Builder::new()),
            Scalar::U8(_) => Data::U8(UInt8Builder::new()),
            Scalar::U16(_) => Data::U16(UInt16Builder::new()),
            Scalar::U32(_) => Data::U32(UInt32Builder::new()),
            Scalar::U64(_) => Data::U64(UInt64Builder::new()),
            Scalar::F32(_) => Data::F32(Float32Builder::new()),
            Scalar::F64(_) => Data::F64(Float64Builder::new()),
            Scalar::Str(_) => Data::Str(StringBuilder::new()),
            Scalar::Run(_) => Data::Runs(Runs::default()),
            Scalar::Time(_) => Data::Time(TimestampMicrosecondBuilder::new().with_timezone(UTC)),
            Scalar::Duration(_) => Data::Duration(DurationMicrosecondBuilder::new()),
        };
        d.nulls(nulls);
        d
    }

    /// Appends `n` nulls.
    fn nulls(&mut self, n: usize) {
        match self {
            Data::Null(count) => *count += n,
            Data::Runs(r) => r.push(None, n),
            Data::List(l) => (0..n).for_each(|_| l.close(false)),
            other => each_primitive!(other, b => b.append_nulls(n), _ => {}),
        }
    }

    /// Appends `v`, converted to the column's type when that loses nothing (an integer into a
    /// column of another integer width or of reals). `false` (and a null appended) when it
    /// cannot be: a text into a column of numbers, a real into one of integers, a value out of
    /// the column's range.
    fn push(&mut self, v: Scalar<'_>) -> bool {
        if v == Scalar::Null {
            self.nulls(1);
            return true;
        }
        let fits = match self {
            Data::Null(_) | Data::List(_) => false,
            Data::Bool(b) => match v {
                Scalar::Bool(x) => {
                    b.append_value(x);
                    true
                }
                _ => false,
            },
            Data::Str(b) => match v {
                Scalar::Str(x) | Scalar::Run(x) => {
                    b.append_value(x);
                    true
                }
                _ => false,
            },
            Data::Runs(r) => match v {
                Scalar::Str(x) | Scalar::Run(x) => {
                    r.push(Some(x), 1);
                    true
                }
                _ => false,
            },
            Data::Time(b) => match v {
                Scalar::Time(x) => {
                    b.append_value(x);
                    true
                }
                _ => false,
            },
            Data::Duration(b) => match v {
                Scalar::Duration(x) => {
                    b.append_value(x);
                    true
                }
                _ => false,
            },
            #[allow(clippy::cast_possible_truncation)]
            Data::F32(b) => match v {
                Scalar::F32(x) => {
                    b.append_value(x);
                    true
                }
                // An f64 or an integer only when the f32 holds it exactly.
                other => match other.real() {
                    Some(x) if f64::from(x as f32) == x || x.is_nan() => {
                        b.append_value(x as f32);
                        true
                    }
                    _ => false,
                },
            },
            Data::F64(b) => match v.real() {
                Some(x) => {
                    b.append_value(x);
                    true
                }
                None => false,
            },
            Data::I8(b) => int(b, v),
            Data::I16(b) => int(b, v),
            Data::I32(b) => int(b, v),
            Data::I64(b) => int(b, v),
            Data::U8(b) => int(b, v),
            Data::U16(b) => int(b, v),
            Data::U32(b) => int(b, v),
            Data::U64(b) => int(b, v),
        };
        if !fits {
            self.nulls(1);
        }
        fits
    }

    /// The Arrow type of the values.
    fn data_type(&self) -> DataType {
        match self {
            Data::Null(_) => DataType::Null,
            Data::Bool(_) => DataType::Boolean,
            Data::I8(_) => DataType::Int8,
            Data::I16(_) => DataType::Int16,
            Data::I32(_) => DataType::Int32,
            Data::I64(_) => DataType::Int64,
            Data::U8(_) => DataType::UInt8,
            Data::U16(_) => DataType::UInt16,
            Data::U32(_) => DataType::UInt32,
            Data::U64(_) => DataType::UInt64,
            Data::F32(_) => DataType::Float32,
            Data::F64(_) => DataType::Float64,
            Data::Str(_) | Data::Runs(_) => DataType::Utf8,
            Data::Time(_) => DataType::Timestamp(TimeUnit::Microsecond, Some(UTC.into())),
            Data::Duration(_) => DataType::Duration(TimeUnit::Microsecond),
            Data::List(l) => DataType::List(l.item_field()),
        }
    }

    /// The values so far as an array; the column starts again, empty, of the same type.
    fn finish(&mut self) -> ArrayRef {
        match self {
            Data::Null(n) => Arc::new(NullArray::new(std::mem::take(n))),
            Data::Runs(r) => Arc::new(r.finish()),
            Data::List(l) => l.finish(),
            other => {
                each_primitive!(other, b => Arc::new(b.finish()), _ => Arc::new(NullArray::new(0)))
            }
        }
    }
}

/// Appends `v` to `data`, which takes the type of `v` when it holds only nulls so far; `false`
/// when it had to be a null ([`Data::push`]).
#[inline]
fn push_typing(data: &mut Data, v: Scalar<'_>) -> bool {
    if let Data::Null(n) = data
        && v != Scalar::Null
    {
        let nulls = *n;
        *data = Data::for_value(v, nulls);
    }
    data.push(v)
}

/// The lists of a list column: every row's items, one after the other, in one column of their
/// type, and where each row's list ends. A row's list is open from its first item (or
/// [`Column::open`]) until [`List::close`].
pub(crate) struct List {
    /// The items of all rows so far.
    items: Data,
    /// Items so far (the end of the open list).
    count: i32,
    /// Where each closed row's list ends, after a leading 0.
    offsets: Vec<i32>,
    /// Which closed rows have a list (the others are null).
    valid: NullBufferBuilder,
}

impl List {
    /// No rows yet; the items have the type of `like` (none yet: a null).
    fn new(like: Scalar<'_>) -> List {
        List {
            items: Data::for_value(like, 0),
            count: 0,
            offsets: vec![0],
            valid: NullBufferBuilder::new(0),
        }
    }

    /// Appends an item to the open list; `false` when it does not fit the items' type (a null
    /// item is appended instead, so that parallel lists keep one item per element), or when
    /// the row group holds `i32::MAX` items already (nothing is appended).
    fn push(&mut self, v: Scalar<'_>) -> bool {
        let Some(count) = self.count.checked_add(1) else {
            return false;
        };
        self.count = count;
        push_typing(&mut self.items, v)
    }

    /// Ends a row: its list is the items since the last row's (`valid`), or a null.
    fn close(&mut self, valid: bool) {
        self.offsets.push(self.count);
        self.valid.append(valid);
    }

    /// The field of an item.
    fn item_field(&self) -> Arc<Field> {
        Arc::new(Field::new_list_field(self.items.data_type(), true))
    }

    /// The rows so far as a list array; empty again after.
    fn finish(&mut self) -> ArrayRef {
        let field = self.item_field();
        let offsets = std::mem::replace(&mut self.offsets, vec![0]);
        let rows = offsets.len() - 1;
        self.count = 0;
        let items = self.items.finish();
        let nulls = self.valid.finish();
        let offsets = OffsetBuffer::new(ScalarBuffer::from(offsets));
        // The offsets grow with the items and the validity with the offsets: always valid.
        match ListArray::try_new(field.clone(), offsets, items, nulls) {
            Ok(a) => Arc::new(a),
            Err(_) => Arc::new(ListArray::new_null(field, rows)),
        }
    }
}

/// Texts as runs of equal ones: a text that repeats from row to row is kept once a run, not
/// once a row, until the row group is written.
#[derive(Default)]
pub(crate) struct Runs {
    /// Each run's text (none: nulls) and its length in rows, in order.
    runs: Vec<(Option<Box<str>>, usize)>,
}

impl Runs {
    /// Appends `n` rows of `v`.
    fn push(&mut self, v: Option<&str>, n: usize) {
        match self.runs.last_mut() {
            Some((last, count)) if last.as_deref() == v => *count += n,
            _ => self.runs.push((v.map(Box::from), n)),
        }
    }

    /// The rows so far as a text array; empty again after.
    fn finish(&mut self) -> arrow_array::StringArray {
        let rows = self.runs.iter().map(|(_, n)| n).sum();
        let bytes = self
            .runs
            .iter()
            .map(|(v, n)| v.as_ref().map_or(0, |v| v.len().saturating_mul(*n)))
            .fold(0usize, usize::saturating_add);
        let mut b = StringBuilder::with_capacity(rows, bytes);
        for (v, n) in self.runs.drain(..) {
            match v {
                Some(v) => (0..n).for_each(|_| b.append_value(&v)),
                None => b.append_nulls(n),
            }
        }
        b.finish()
    }
}

/// Appends an integer to a column of integers when it is in the column's range.
fn int<T>(b: &mut arrow_array::builder::PrimitiveBuilder<T>, v: Scalar<'_>) -> bool
where
    T: arrow_array::ArrowPrimitiveType,
    T::Native: TryFrom<i128>,
{
    match v.integer().map(T::Native::try_from) {
        Some(Ok(x)) => {
            b.append_value(x);
            true
        }
        _ => false,
    }
}

/// A named column and the rows it has a value (or a null) for.
pub(crate) struct Column {
    /// Its name: a field's, a nested one's as `outer.inner`, or a metadata column's.
    pub(crate) name: Box<str>,
    pub(crate) data: Data,
    /// Rows filled so far (a row not yet ended may have filled it).
    pub(crate) filled: usize,
    /// The address and length of the `&'static str` it was last looked up with ((0, 0):
    /// none), its name or the field's it holds ([`super::names`]): the same address and length
    /// are the same name, found without comparing the text.
    pub(crate) key: (usize, usize),
    /// How a field's value is written into it ([`super::names`]).
    pub(crate) convert: Convert,
    /// Its unit, kept in its Arrow field's metadata.
    pub(crate) unit: Option<&'static str>,
}

impl Column {
    /// A column whose first value, in row `row`, is `v`.
    pub(crate) fn new(name: &str, v: Scalar<'_>, row: usize) -> Column {
        Column {
            name: name.into(),
            data: Data::for_value(v, row),
            filled: row,
            key: (0, 0),
            convert: Convert::Same,
            unit: None,
        }
    }

    /// A list column whose items are like `like`, created in row `row` (the rows before hold
    /// nulls); this row's list is not open.
    pub(crate) fn new_list(name: &str, like: Scalar<'_>, row: usize) -> Column {
        let mut data = Data::List(Box::new(List::new(like)));
        data.nulls(row);
        Column {
            name: name.into(),
            data,
            filled: row,
            key: (0, 0),
            convert: Convert::Same,
            unit: None,
        }
    }

    /// Whether it holds lists.
    pub(crate) fn is_list(&self) -> bool {
        matches!(self.data, Data::List(_))
    }

    /// Sets this row's value; `false` when it had to be a null (a value of another type).
    pub(crate) fn push(&mut self, v: Scalar<'_>) -> bool {
        self.filled += 1;
        if self.is_list() {
            // One value where a list is kept: this row's list is empty.
            return v == Scalar::Null;
        }
        push_typing(&mut self.data, v)
    }

    /// Opens this row's list (of row `rows`), empty so far, when it is not open; nothing for a
    /// column of values.
    pub(crate) fn open(&mut self, rows: usize) {
        if self.is_list() && self.filled == rows {
            self.filled += 1;
        }
    }

    /// Appends an item to this row's list (of row `rows`), opening it; `false` when the item
    /// is no value of the column's (or the column holds no lists).
    pub(crate) fn push_item(&mut self, v: Scalar<'_>, rows: usize) -> bool {
        self.open(rows);
        match &mut self.data {
            Data::List(l) => l.push(v),
            _ => false,
        }
    }

    /// Ends this row: a null when it has no value (a list column: no list open), else the
    /// list open.
    pub(crate) fn end_row(&mut self, rows: usize) {
        if self.filled == rows {
            // No value (a list column: no list open): a null.
            self.data.nulls(1);
            self.filled += 1;
        } else if let Data::List(l) = &mut self.data {
            l.close(true);
        }
    }

    /// The Arrow field of the column, its unit in its metadata (`unit`).
    pub(crate) fn field(&self) -> Field {
        let field = Field::new(self.name.as_ref(), self.data.data_type(), true);
        match self.unit {
            Some(unit) => field.with_metadata(std::collections::BTreeMap::from([(
                super::unit::KEY.to_owned(),
                unit.to_owned(),
            )])),
            None => field,
        }
    }

    /// The values so far as an array; the column starts again empty.
    pub(crate) fn finish(&mut self) -> ArrayRef {
        self.filled = 0;
        self.data.finish()
    }
}
