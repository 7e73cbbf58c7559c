//! A crate value straight to Python objects through serde, rendered exactly as the host tool's
//! `protolink::render::to_json` renders it (and so as `protolink decode --json` prints it), but
//! without the JSON value in between: structs become dicts in field order, enums serde's
//! external tags (`"Ok"`, `{"Other": -5}`), byte strings lists of ints, a non-finite float
//! `None`, and every float that is exactly an `f32` the `f32`'s shortest decimal (`0.1f32`
//! reads 0.1). The AEOLUS messages read this way are the hot path of `Message.to_dict()`; the
//! tests compare its output with `decode --json` on every message they decode.

use std::fmt;

use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyList, PyString};
use serde::ser::{self, Serialize};

/// A Python error carried through serde.
#[derive(Debug)]
pub(crate) struct Error(PyErr);

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Display::fmt(&self.0, f)
    }
}

impl std::error::Error for Error {}

impl ser::Error for Error {
    fn custom<T: fmt::Display>(msg: T) -> Self {
        Error(pyo3::exceptions::PyValueError::new_err(msg.to_string()))
    }
}

impl From<PyErr> for Error {
    fn from(e: PyErr) -> Self {
        Error(e)
    }
}

/// `value` as Python objects.
pub(crate) fn to_python<'py, T: Serialize + ?Sized>(
    py: Python<'py>,
    value: &T,
) -> PyResult<Bound<'py, PyAny>> {
    value.serialize(Serializer { py }).map_err(|e| e.0)
}

/// The float `to_json` writes for `x`: `None` when not finite; the `f32`'s shortest decimal
/// when `x` is exactly an `f32`; `x` otherwise.
fn float(py: Python<'_>, x: f64) -> Bound<'_, PyAny> {
    if !x.is_finite() {
        return py.None().into_bound(py);
    }
    let short = x as f32;
    if f64::from(short) == x {
        // The text and the parse of `to_json`: Rust's shortest decimal of the f32 (never an
        // exponent: tiny values are long), kept a float, read by serde_json's own parser, whose
        // result for a long decimal can differ from Rust's by an ulp (2.1120881e-29 reads
        // 2.1120880999999998e-29), so the same parser is used here.
        let mut text = short.to_string();
        if !text.contains(['.', 'e', 'E']) {
            text.push_str(".0");
        }
        if let Some(v) = text
            .parse::<serde_json::Number>()
            .ok()
            .and_then(|n| n.as_f64())
        {
            return PyFloat::new(py, v).into_any();
        }
    }
    PyFloat::new(py, x).into_any()
}

#[derive(Clone, Copy)]
struct Serializer<'py> {
    py: Python<'py>,
}

type Out<'py> = Result<Bound<'py, PyAny>, Error>;

/// `{variant: value}`, serde's external tag.
fn tagged<'py>(py: Python<'py>, variant: &str, value: Bound<'py, PyAny>) -> Out<'py> {
    let d = PyDict::new(py);
    d.set_item(variant, value)?;
    Ok(d.into_any())
}

/// `Serializer` methods that widen a small integer to the 64-bit one of its sign.
macro_rules! widen {
    ($($method:ident($t:ty) => $wide:ident($w:ty)),* $(,)?) => {$(
        fn $method(self, v: $t) -> Out<'py> {
            self.$wide(<$w>::from(v))
        }
    )*};
}

/// The `Serializer` methods that start a named `$builder` (a tuple struct's list, a struct's
/// dict) as `$start` does, and one tagged by its variant (a tuple or struct variant).
macro_rules! starts {
    ($builder:ident: $start:ident => $named:ident, $variant:ident) => {
        fn $named(self, _name: &'static str, len: usize) -> Result<$builder<'py>, Error> {
            self.$start(Some(len))
        }
        fn $variant(
            self,
            _name: &'static str,
            _i: u32,
            variant: &'static str,
            len: usize,
        ) -> Result<$builder<'py>, Error> {
            let mut b = self.$start(Some(len))?;
            b.variant = Some(variant);
            Ok(b)
        }
    };
}

impl<'py> ser::Serializer for Serializer<'py> {
    type Ok = Bound<'py, PyAny>;
    type Error = Error;
    type SerializeSeq = Seq<'py>;
    type SerializeTuple = Seq<'py>;
    type SerializeTupleStruct = Seq<'py>;
    type SerializeTupleVariant = Seq<'py>;
    type SerializeMap = Map<'py>;
    type SerializeStruct = Map<'py>;
    type SerializeStructVariant = Map<'py>;

    fn serialize_bool(self, v: bool) -> Out<'py> {
        Ok(PyBool::new(self.py, v).to_owned().into_any())
    }
    widen!(
        serialize_i8(i8) => serialize_i64(i64),
        serialize_i16(i16) => serialize_i64(i64),
        serialize_i32(i32) => serialize_i64(i64),
        serialize_u8(u8) => serialize_u64(u64),
        serialize_u16(u16) => serialize_u64(u64),
        serialize_u32(u32) => serialize_u64(u64),
    );
    fn serialize_i64(self, v: i64) -> Out<'py> {
        let Ok(n) = v.into_pyobject(self.py);
        Ok(n.into_any())
    }
    fn serialize_u64(self, v: u64) -> Out<'py> {
        let Ok(n) = v.into_pyobject(self.py);
        Ok(n.into_any())
    }
    fn serialize_f32(self, v: f32) -> Out<'py> {
        Ok(float(self.py, f64::from(v)))
    }
    fn serialize_f64(self, v: f64) -> Out<'py> {
        Ok(float(self.py, v))
    }
    fn serialize_char(self, v: char) -> Out<'py> {
        let mut buf = [0u8; 4];
        self.serialize_str(v.encode_utf8(&mut buf))
    }
    fn serialize_str(self, v: &str) -> Out<'py> {
        Ok(PyString::new(self.py, v).into_any())
    }
    fn serialize_bytes(self, v: &[u8]) -> Out<'py> {
        Ok(PyList::new(self.py, v)?.into_any())
    }
    fn serialize_none(self) -> Out<'py> {
        Ok(self.py.None().into_bound(self.py))
    }
    fn serialize_some<T: Serialize + ?Sized>(self, value: &T) -> Out<'py> {
        value.serialize(self)
    }
    fn serialize_unit(self) -> Out<'py> {
        self.serialize_none()
    }
    fn serialize_unit_struct(self, _name: &'static str) -> Out<'py> {
        self.serialize_none()
    }
    fn serialize_unit_variant(
        self,
        _name: &'static str,
        _i: u32,
        variant: &'static str,
    ) -> Out<'py> {
        self.serialize_str(variant)
    }
    fn serialize_newtype_struct<T: Serialize + ?Sized>(
        self,
        _name: &'static str,
        value: &T,
    ) -> Out<'py> {
        value.serialize(self)
    }
    fn serialize_newtype_variant<T: Serialize + ?Sized>(
        self,
        _name: &'static str,
        _i: u32,
        variant: &'static str,
        value: &T,
    ) -> Out<'py> {
        tagged(self.py, variant, value.serialize(self)?)
    }
    fn serialize_seq(self, _len: Option<usize>) -> Result<Seq<'py>, Error> {
        Ok(Seq {
            py: self.py,
            items: PyList::empty(self.py),
            variant: None,
        })
    }
    fn serialize_tuple(self, len: usize) -> Result<Seq<'py>, Error> {
        self.serialize_seq(Some(len))
    }
    starts!(Seq: serialize_seq => serialize_tuple_struct, serialize_tuple_variant);
    fn serialize_map(self, _len: Option<usize>) -> Result<Map<'py>, Error> {
        Ok(Map {
            py: self.py,
            dict: PyDict::new(self.py),
            key: None,
            variant: None,
        })
    }
    starts!(Map: serialize_map => serialize_struct, serialize_struct_variant);
}

/// A list being built (a sequence, tuple or tuple variant).
pub(crate) struct Seq<'py> {
    py: Python<'py>,
    items: Bound<'py, PyList>,
    variant: Option<&'static str>,
}

impl<'py> Seq<'py> {
    fn push<T: Serialize + ?Sized>(&mut self, value: &T) -> Result<(), Error> {
        self.items
            .append(value.serialize(Serializer { py: self.py })?)?;
        Ok(())
    }

    fn done(self) -> Out<'py> {
        match self.variant {
            Some(v) => tagged(self.py, v, self.items.into_any()),
            None => Ok(self.items.into_any()),
        }
    }
}

/// The serde trait `$trait` for a list or dict being built: `$method` hands each value (and,
/// for a struct, its field name) to the builder's `$add`, and `end` finishes it.
macro_rules! serialize_into {
    ($builder:ident: $trait:ident::$method:ident($($key:ident: $k:ty)?) => $add:ident) => {
        impl<'py> ser::$trait for $builder<'py> {
            type Ok = Bound<'py, PyAny>;
            type Error = Error;
            fn $method<T: Serialize + ?Sized>(
                &mut self,
                $($key: $k,)?
                value: &T,
            ) -> Result<(), Error> {
                self.$add($($key,)? value)
            }
            fn end(self) -> Out<'py> {
                self.done()
            }
        }
    };
}

serialize_into!(Seq: SerializeSeq::serialize_element() => push);
serialize_into!(Seq: SerializeTuple::serialize_element() => push);
serialize_into!(Seq: SerializeTupleStruct::serialize_field() => push);
serialize_into!(Seq: SerializeTupleVariant::serialize_field() => push);

/// A dict being built (a map, struct or struct variant).
pub(crate) struct Map<'py> {
    py: Python<'py>,
    dict: Bound<'py, PyDict>,
    key: Option<Bound<'py, PyAny>>,
    variant: Option<&'static str>,
}

impl<'py> Map<'py> {
    /// A struct's field.
    fn field<T: Serialize + ?Sized>(&mut self, key: &'static str, value: &T) -> Result<(), Error> {
        // Field names are few and fixed: interned, their hash is computed once.
        self.dict.set_item(
            PyString::intern(self.py, key),
            value.serialize(Serializer { py: self.py })?,
        )?;
        Ok(())
    }

    fn done(self) -> Out<'py> {
        match self.variant {
            Some(v) => tagged(self.py, v, self.dict.into_any()),
            None => Ok(self.dict.into_any()),
        }
    }
}

impl<'py> ser::SerializeMap for Map<'py> {
    type Ok = Bound<'py, PyAny>;
    type Error = Error;
    fn serialize_key<T: Serialize + ?Sized>(&mut self, key: &T) -> Result<(), Error> {
        // JSON keys are strings: a number key is written as its digits, as serde_json does.
        let k = key.serialize(Serializer { py: self.py })?;
        self.key = Some(if k.is_instance_of::<PyString>() {
            k
        } else {
            k.str()?.into_any()
        });
        Ok(())
    }
    fn serialize_value<T: Serialize + ?Sized>(&mut self, value: &T) -> Result<(), Error> {
        let Some(key) = self.key.take() else {
            return Err(ser::Error::custom("a map value came without its key"));
        };
        self.dict
            .set_item(key, value.serialize(Serializer { py: self.py })?)?;
        Ok(())
    }
    fn end(self) -> Out<'py> {
        self.done()
    }
}

serialize_into!(Map: SerializeStruct::serialize_field(key: &'static str) => field);
serialize_into!(Map: SerializeStructVariant::serialize_field(key: &'static str) => field);
