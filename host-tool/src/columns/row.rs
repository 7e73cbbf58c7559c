//! A message's fields into a table row, through serde: each number, flag and text into the
//! column of its path (a nested field as `outer.inner`, an element of a fixed-size array as
//! `array.0`, `array.1`, ..., the value of an enum variant that carries one as
//! `field.Variant`); a list (of any length, of anything) as its JSON text, so that its column
//! has one type whatever the lists hold.
//!
//! The protocol crates' typed messages serialize with their own widths (`f32`, `u16`, ...), so
//! their columns have those types; a rendered field (`serde_json::Value`) has only integers and
//! reals, which become `Int64` and `Float64` columns.

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
        if let Some(name) = self.name {
            self.table.set_static(name, v);
            return Ok(());
        }
        if self.path.is_empty() {
            // A top level that is one value (a number, an enum without data): one column, as
            // `decode` renders it.
            self.table.set_static("value", v);
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

/// A field under `path`: written as columns, or as its JSON text when it cannot be.
fn field<T: Serialize + ?Sized>(
    table: &mut Table,
    path: &mut String,
    name: &str,
    value: &T,
    ints: Ints,
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
        })
        .is_ok();
    if !ok {
        let text = serde_json::to_string(value).unwrap_or_default();
        table.set(path, Scalar::Str(&text));
    }
    path.truncate(len);
}

/// The fields of a struct or map under the path.
struct Fields<'a> {
    table: &'a mut Table,
    path: &'a mut String,
    ints: Ints,
    clashes: Option<&'a dyn Fn(&str) -> bool>,
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
            // A top-level field of a typed message: its column found by the name's address.
            let direct = Value {
                table: &mut *self.table,
                path: &mut *self.path,
                ints: self.ints,
                clashes: None,
                name: Some(key),
            };
            if value.serialize(direct).is_err() {
                let text = serde_json::to_string(value).unwrap_or_default();
                self.table.set_static(key, Scalar::Str(&text));
            }
            self.path.clear();
            return Ok(());
        }
        field(self.table, self.path, key, value, self.ints, self.clashes);
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
        field(
            self.table,
            self.path,
            &self.key,
            value,
            self.ints,
            self.clashes,
        );
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
        match INDEX.get(i) {
            Some(name) => field(self.table, self.path, name, value, self.ints, None),
            None => field(
                self.table,
                self.path,
                &i.to_string(),
                value,
                self.ints,
                None,
            ),
        }
        Ok(())
    }

    fn end(self) -> Result<(), NotColumns> {
        Ok(())
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
    type SerializeSeq = Impossible<(), NotColumns>;
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
        field(v.table, v.path, variant, value, v.ints, None);
        Ok(())
    }

    /// A list of any length: its JSON text (the field's fallback), one column of one type
    /// whatever the list holds.
    fn serialize_seq(self, _: Option<usize>) -> Result<Self::SerializeSeq, NotColumns> {
        Err(NotColumns)
    }

    fn serialize_tuple(self, _: usize) -> Result<Elements<'a>, NotColumns> {
        let v = self.nest();
        Ok(Elements {
            table: v.table,
            path: v.path,
            ints: v.ints,
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
