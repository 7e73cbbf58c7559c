//! A message's fields into a table row, through serde: each number, flag and text into the
//! column of its path (a nested field as `outer.inner`, an element of a fixed-size array as
//! `array.0`, `array.1`, ..., the value of an enum variant that carries one as
//! `field.Variant`); a list (of any length) of a typed message as Arrow lists: a list of values
//! as one List column of their type, a list of structs as parallel List columns, one per field
//! of the struct (`satellites.id`, `satellites.snr`, ...), each row's lists of one length.
//!
//! The protocol crates' typed messages serialize with their own widths (`f32`, `u16`, ...), so
//! their columns have those types, and a top-level field's column takes the name (and type)
//! the message type's entry of [`super::names`] gives it. A rendered field
//! (`serde_json::Value`) has only integers and reals, which become `Int64` and `Float64`
//! columns; its lists, whose items may be of any type, are their JSON text.

use serde::Serialize;
use serde::ser::{self, Impossible};

use super::column::Scalar;
use super::table::Table;

/// Why a value is not written as columns: it is written as its JSON text instead.
#[derive(Debug)]
pub(crate) struct NotColumns;

impl std::fmt::Display for NotColumns {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("not a value of columns")
    }
}

impl std::error::Error for NotColumns {}

impl ser::Error for NotColumns {
    fn custom<T: std::fmt::Display>(_: T) -> Self {
        NotColumns
    }
}

/// Writes `fields` (a struct or a map) into the row of `table`, each field in the column of its
/// name; a top-level name that `clashes` (when given) in the column `field.NAME`.
pub(crate) fn write_fields<T: Serialize + ?Sized>(
    table: &mut Table,
    fields: &T,
    integers: Ints,
    clashes: Option<&dyn Fn(&str) -> bool>,
) {
    let mut path = String::new();
    let value = Value {
        table,
        path: &mut path,
        ints: integers,
        clashes,
        name: None,
        list: false,
    };
    if fields.serialize(value).is_err() {
        // A top level that is no struct nor map: one column, `value`.
        let text = serde_json::to_string(fields).unwrap_or_default();
        table.set("value", Scalar::Str(&text));
    }
}

/// How integers are kept: at their own width (typed messages), or all as `i64` (rendered
/// JSON values, whose integers carry no width).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Ints {
    /// `u8` as `UInt8`, `i32` as `Int32`, ...
    Own,
    /// Every integer as `Int64` (an unsigned one beyond it as `UInt64`).
    Wide,
}

/// The value of the column (or columns) at `path`.
struct Value<'a> {
    table: &'a mut Table,
    path: &'a mut String,
    ints: Ints,
    /// At the top level: which names are a metadata column's.
    clashes: Option<&'a dyn Fn(&str) -> bool>,
    /// A top-level field's name, held by the program: the column's name (`path` is empty and
    /// takes it only when the value nests).
    name: Option<&'static str>,
    /// The value is an item of a list: appended to this row's list in the column.
    list: bool,
}

impl Value<'_> {
    /// The value nests: its columns are under the path, which takes the top-level name.
    fn nest(mut self) -> Self {
        if let Some(name) = self.name.take() {
            self.path.push_str(name);
        }
        self
    }

    fn set(self, v: Scalar<'_>) -> Result<(), NotColumns> {
        if let Some(field) = self.name {
            // A typed message's field, in the column its type gives it.
            self.table.set_field(field, v);
            return Ok(());
        }
        if self.path.is_empty() {
            // A top level that is one value (a number, an enum without data): one column, as
            // `decode` renders it.
            self.table.set_static("value", v);
            return Ok(());
        }
        if self.list {
            self.table.push_item(self.path, v);
            return Ok(());
        }
        if self.ints == Ints::Own {
            self.table.set(self.path, v);
            return Ok(());
        }
        let v = match (self.ints, v) {
            (Ints::Wide, Scalar::U64(x)) => i64::try_from(x).map_or(v, Scalar::I64),
            (Ints::Wide, other) => match other {
                Scalar::I8(x) => Scalar::I64(x.into()),
                Scalar::I16(x) => Scalar::I64(x.into()),
                Scalar::I32(x) => Scalar::I64(x.into()),
                Scalar::U8(x) => Scalar::I64(x.into()),
                Scalar::U16(x) => Scalar::I64(x.into()),
                Scalar::U32(x) => Scalar::I64(x.into()),
                other => other,
            },
            (Ints::Own, other) => other,
        };
        self.table.set(self.path, v);
        Ok(())
    }
}

/// A field under `path` (of a list's item when `list`): written as columns, or as its JSON
/// text when it cannot be.
fn field<T: Serialize + ?Sized>(
    table: &mut Table,
    path: &mut String,
    name: &str,
    value: &T,
    (ints, list): (Ints, bool),
    clashes: Option<&dyn Fn(&str) -> bool>,
) {
    let len = path.len();
    if !path.is_empty() {
        path.push('.');
    }
    if clashes.is_some_and(|c| c(name)) {
        path.push_str("field.");
    }
    path.push_str(name);
    let ok = value
        .serialize(Value {
            table: &mut *table,
            path: &mut *path,
            ints,
            clashes: None,
            name: None,
            list,
        })
        .is_ok();
    if !ok {
        json_text(table, path, value, list);
    }
    path.truncate(len);
}

/// A value that is no columns (bytes, a list in a list, a rendered list) as its JSON text, in
/// the column `path` (appended to its list when `list`).
fn json_text<T: Serialize + ?Sized>(table: &mut Table, path: &str, value: &T, list: bool) {
    let text = serde_json::to_string(value).unwrap_or_default();
    if list {
        table.push_item(path, Scalar::Str(&text));
    } else {
        table.set(path, Scalar::Str(&text));
    }
}

/// The fields of a struct or map under the path.
struct Fields<'a> {
    table: &'a mut Table,
    path: &'a mut String,
    ints: Ints,
    clashes: Option<&'a dyn Fn(&str) -> bool>,
    /// The fields are a list item's.
    list: bool,
    /// A map's key, kept until its value comes.
    key: String,
}

impl ser::SerializeStruct for Fields<'_> {
    type Ok = ();
    type Error = NotColumns;

    fn serialize_field<T: Serialize + ?Sized>(
        &mut self,
        key: &'static str,
        value: &T,
    ) -> Result<(), NotColumns> {
        if self.path.is_empty() && self.clashes.is_none() {
            // A top-level field of a typed message: its column (of the name its message type
            // gives it, `names`) found by the field's address.
            let direct = Value {
                table: &mut *self.table,
                path: &mut *self.path,
                ints: self.ints,
                clashes: None,
                name: Some(key),
                list: false,
            };
            if value.serialize(direct).is_err() {
                let text = serde_json::to_string(value).unwrap_or_default();
                self.table.set_field(key, Scalar::Str(&text));
            }
            self.path.clear();
            return Ok(());
        }
        let how = (self.ints, self.list);
        field(self.table, self.path, key, value, how, self.clashes);
        Ok(())
    }

    fn end(self) -> Result<(), NotColumns> {
        Ok(())
    }
}

impl ser::SerializeMap for Fields<'_> {
    type Ok = ();
    type Error = NotColumns;

    fn serialize_key<T: Serialize + ?Sized>(&mut self, key: &T) -> Result<(), NotColumns> {
        // The key as `decode --json` writes it: a JSON object's keys are text.
        self.key = match serde_json::to_value(key).map_err(|_| NotColumns)? {
            serde_json::Value::String(text) => text,
            other => other.to_string(),
        };
        Ok(())
    }

    fn serialize_value<T: Serialize + ?Sized>(&mut self, value: &T) -> Result<(), NotColumns> {
        let how = (self.ints, self.list);
        field(self.table, self.path, &self.key, value, how, self.clashes);
        Ok(())
    }

    fn end(self) -> Result<(), NotColumns> {
        Ok(())
    }
}

/// The items of a fixed-size array (a tuple to serde), each its own column `path.0`, `path.1`, ...
struct Elements<'a> {
    table: &'a mut Table,
    path: &'a mut String,
    ints: Ints,
    list: bool,
    next: usize,
}

/// The names of the first elements' columns.
const INDEX: [&str; 16] = [
    "0", "1", "2", "3", "4", "5", "6", "7", "8", "9", "10", "11", "12", "13", "14", "15",
];

impl ser::SerializeTuple for Elements<'_> {
    type Ok = ();
    type Error = NotColumns;

    fn serialize_element<T: Serialize + ?Sized>(&mut self, value: &T) -> Result<(), NotColumns> {
        let i = self.next;
        self.next += 1;
        let how = (self.ints, self.list);
        match INDEX.get(i) {
            Some(name) => field(self.table, self.path, name, value, how, None),
            None => field(self.table, self.path, &i.to_string(), value, how, None),
        }
        Ok(())
    }

    fn end(self) -> Result<(), NotColumns> {
        Ok(())
    }
}

/// The items of a list, each appended to this row's list in the column of its path (a
/// struct's field `path.FIELD`).
pub(crate) struct Items<'a> {
    table: &'a mut Table,
    path: &'a mut String,
    ints: Ints,
}

impl ser::SerializeSeq for Items<'_> {
    type Ok = ();
    type Error = NotColumns;

    fn serialize_element<T: Serialize + ?Sized>(&mut self, value: &T) -> Result<(), NotColumns> {
        let item = Value {
            table: &mut *self.table,
            path: &mut *self.path,
            ints: self.ints,
            clashes: None,
            name: None,
            list: true,
        };
        if value.serialize(item).is_err() {
            json_text(self.table, self.path, value, true);
        }
        Ok(())
    }

    fn end(self) -> Result<(), NotColumns> {
        Ok(())
    }
}

/// Writes the list `items` into the row of `table`, as a typed message's list field `name`
/// (each item's columns under `name`), its columns declared from `sample` (one item, every
/// optional field present) when the table is new: a list of any length, empty too, gives the
/// same columns.
pub(crate) fn write_list<T: Serialize>(
    table: &mut Table,
    name: &'static str,
    items: impl Iterator<Item = T>,
    sample: &T,
) {
    if !table.declared() {
        table.declare_like(|t| {
            let mut path = String::from(name);
            let mut items = Items {
                table: t,
                path: &mut path,
                ints: Ints::Own,
            };
            let _ = ser::SerializeSeq::serialize_element(&mut items, sample);
        });
    }
    let mut path = String::from(name);
    table.open_lists(name);
    let mut list = Items {
        table,
        path: &mut path,
        ints: Ints::Own,
    };
    for item in items {
        let _ = ser::SerializeSeq::serialize_element(&mut list, &item);
    }
}

macro_rules! scalar_methods {
    ($( $method:ident($t:ty) => $variant:ident ),* $(,)?) => {
        $( fn $method(self, v: $t) -> Result<Self::Ok, NotColumns> { self.set(Scalar::$variant(v)) } )*
    };
}

impl<'a> ser::Serializer for Value<'a> {
    type Ok = ();
    type Error = NotColumns;
    type SerializeSeq = Items<'a>;
    type SerializeTuple = Elements<'a>;
    type SerializeTupleStruct = Impossible<(), NotColumns>;
    type SerializeTupleVariant = Impossible<(), NotColumns>;
    type SerializeMap = Fields<'a>;
    type SerializeStruct = Fields<'a>;
    type SerializeStructVariant = Impossible<(), NotColumns>;

    scalar_methods!(
        serialize_bool(bool) => Bool,
        serialize_i8(i8) => I8,
        serialize_i16(i16) => I16,
        serialize_i32(i32) => I32,
        serialize_i64(i64) => I64,
        serialize_u8(u8) => U8,
        serialize_u16(u16) => U16,
        serialize_u32(u32) => U32,
        serialize_u64(u64) => U64,
        serialize_f32(f32) => F32,
        serialize_f64(f64) => F64,
    );

    fn serialize_char(self, v: char) -> Result<(), NotColumns> {
        self.set(Scalar::Str(v.encode_utf8(&mut [0; 4])))
    }

    fn serialize_str(self, v: &str) -> Result<(), NotColumns> {
        self.set(Scalar::Str(v))
    }

    fn serialize_bytes(self, _: &[u8]) -> Result<(), NotColumns> {
        Err(NotColumns)
    }

    fn serialize_none(self) -> Result<(), NotColumns> {
        self.set(Scalar::Null)
    }

    fn serialize_some<T: Serialize + ?Sized>(self, value: &T) -> Result<(), NotColumns> {
        value.serialize(self)
    }

    fn serialize_unit(self) -> Result<(), NotColumns> {
        self.set(Scalar::Null)
    }

    fn serialize_unit_struct(self, _: &'static str) -> Result<(), NotColumns> {
        self.set(Scalar::Null)
    }

    fn serialize_unit_variant(
        self,
        _: &'static str,
        _: u32,
        variant: &'static str,
    ) -> Result<(), NotColumns> {
        self.set(Scalar::Str(variant))
    }

    fn serialize_newtype_struct<T: Serialize + ?Sized>(
        self,
        _: &'static str,
        value: &T,
    ) -> Result<(), NotColumns> {
        value.serialize(self)
    }

    /// A variant carrying a value: the value under `path.Variant`, as the JSON object
    /// `{"Variant": value}` that `decode --json` renders flattens.
    fn serialize_newtype_variant<T: Serialize + ?Sized>(
        self,
        _: &'static str,
        _: u32,
        variant: &'static str,
        value: &T,
    ) -> Result<(), NotColumns> {
        let v = self.nest();
        field(v.table, v.path, variant, value, (v.ints, v.list), None);
        Ok(())
    }

    /// A list of any length of a typed message: this row's lists under the path, opened
    /// (empty, not null, when it has no item). A rendered list, or a list in a list's item, is
    /// its JSON text (the field's fallback).
    fn serialize_seq(self, _: Option<usize>) -> Result<Items<'a>, NotColumns> {
        if self.ints == Ints::Wide || self.list {
            return Err(NotColumns);
        }
        let v = self.nest();
        if v.path.is_empty() {
            // A top level that is a list: no column is named for it.
            return Err(NotColumns);
        }
        v.table.open_lists(v.path);
        Ok(Items {
            table: v.table,
            path: v.path,
            ints: v.ints,
        })
    }

    fn serialize_tuple(self, _: usize) -> Result<Elements<'a>, NotColumns> {
        let v = self.nest();
        Ok(Elements {
            table: v.table,
            path: v.path,
            ints: v.ints,
            list: v.list,
            next: 0,
        })
    }

    fn serialize_tuple_struct(
        self,
        _: &'static str,
        _: usize,
    ) -> Result<Self::SerializeTupleStruct, NotColumns> {
        Err(NotColumns)
    }

    fn serialize_tuple_variant(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: usize,
    ) -> Result<Self::SerializeTupleVariant, NotColumns> {
        Err(NotColumns)
    }

    fn serialize_map(self, _: Option<usize>) -> Result<Fields<'a>, NotColumns> {
        let v = self.nest();
        Ok(Fields {
            table: v.table,
            path: v.path,
            ints: v.ints,
            clashes: v.clashes,
            list: v.list,
            key: String::new(),
        })
    }

    fn serialize_struct(self, _: &'static str, _: usize) -> Result<Fields<'a>, NotColumns> {
        self.serialize_map(None)
    }

    fn serialize_struct_variant(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: usize,
    ) -> Result<Self::SerializeStructVariant, NotColumns> {
        Err(NotColumns)
    }
}
