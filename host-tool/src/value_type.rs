//! AYDP system-value types as written on the command line (`--as f32[3]`): parsing them, turning
//! command-line text into little-endian value bytes, and value bytes back into values.

use std::fmt;
use std::str::FromStr;

use serde_json::{Value, json};

/// One element type.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Scalar {
    /// `u8`.
    U8,
    /// `u16`.
    U16,
    /// `u32`.
    U32,
    /// `i32`.
    I32,
    /// `f32`.
    F32,
    /// `f64`.
    F64,
}

impl Scalar {
    /// Bytes per element.
    pub(crate) const fn size(self) -> usize {
        match self {
            Scalar::U8 => 1,
            Scalar::U16 => 2,
            Scalar::U32 | Scalar::I32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }

    const fn name(self) -> &'static str {
        match self {
            Scalar::U8 => "u8",
            Scalar::U16 => "u16",
            Scalar::U32 => "u32",
            Scalar::I32 => "i32",
            Scalar::F32 => "f32",
            Scalar::F64 => "f64",
        }
    }

    /// Little-endian bytes of one value written as text (integers also as `0x..`).
    ///
    /// # Errors
    /// A sentence saying why the text is not a value of this type.
    pub(crate) fn encode(self, text: &str) -> Result<Vec<u8>, String> {
        let t = text.trim();
        let int = || -> Option<i128> {
            match t.strip_prefix("0x").or_else(|| t.strip_prefix("0X")) {
                Some(hex) => i128::from_str_radix(hex, 16).ok(),
                None => t.parse::<i128>().ok(),
            }
        };
        let bad = || format!("'{t}' is not a {} value", self.name());
        Ok(match self {
            Scalar::U8 => u8::try_from(int().ok_or_else(bad)?)
                .map_err(|_| bad())?
                .to_le_bytes()
                .to_vec(),
            Scalar::U16 => u16::try_from(int().ok_or_else(bad)?)
                .map_err(|_| bad())?
                .to_le_bytes()
                .to_vec(),
            Scalar::U32 => u32::try_from(int().ok_or_else(bad)?)
                .map_err(|_| bad())?
                .to_le_bytes()
                .to_vec(),
            Scalar::I32 => i32::try_from(int().ok_or_else(bad)?)
                .map_err(|_| bad())?
                .to_le_bytes()
                .to_vec(),
            Scalar::F32 => t.parse::<f32>().map_err(|_| bad())?.to_le_bytes().to_vec(),
            Scalar::F64 => t.parse::<f64>().map_err(|_| bad())?.to_le_bytes().to_vec(),
        })
    }

    /// One element from exactly [`Scalar::size`] bytes.
    fn decode(self, b: &[u8]) -> Value {
        let a = |n: usize| {
            let mut x = [0u8; 8];
            x[..n].copy_from_slice(&b[..n]);
            x
        };
        match self {
            Scalar::U8 => json!(b[0]),
            Scalar::U16 => json!(u16::from_le_bytes([b[0], b[1]])),
            Scalar::U32 => json!(u32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::I32 => json!(i32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::F32 => crate::render::to_json(&f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::F64 => json!(f64::from_le_bytes(a(8))),
        }
    }
}

/// A system value's type: a scalar, a fixed-length array, or a `char[N]` text.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum ValueType {
    /// One value.
    Scalar(Scalar),
    /// `N` values.
    Array(Scalar, usize),
    /// Text of at most `N` bytes, NUL-padded on the device.
    Chars(usize),
}

impl FromStr for ValueType {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let (base, count) = match s.strip_suffix(']').and_then(|r| r.split_once('[')) {
            Some((base, n)) => {
                let n = n
                    .parse::<usize>()
                    .ok()
                    .filter(|&n| n > 0)
                    .ok_or_else(|| format!("'{n}' in '{s}' is not an element count"))?;
                (base, Some(n))
            }
            None => (s, None),
        };
        let scalar = match base {
            "u8" => Scalar::U8,
            "u16" => Scalar::U16,
            "u32" => Scalar::U32,
            "i32" => Scalar::I32,
            "f32" => Scalar::F32,
            "f64" => Scalar::F64,
            "char" => {
                return count
                    .map(ValueType::Chars)
                    .ok_or_else(|| "a text type needs its length, e.g. char[40]".to_string());
            }
            other => {
                return Err(format!(
                    "unknown type '{other}': expected u8, u16, u32, i32, f32, f64 or char[N], \
                     optionally with [N] for an array"
                ));
            }
        };
        Ok(match count {
            Some(n) => ValueType::Array(scalar, n),
            None => ValueType::Scalar(scalar),
        })
    }
}

impl fmt::Display for ValueType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ValueType::Scalar(s) => f.write_str(s.name()),
            ValueType::Array(s, n) => write!(f, "{}[{n}]", s.name()),
            ValueType::Chars(n) => write!(f, "char[{n}]"),
        }
    }
}

impl ValueType {
    /// The element type (`u8` for text).
    pub(crate) const fn element(self) -> Scalar {
        match self {
            ValueType::Scalar(s) | ValueType::Array(s, _) => s,
            ValueType::Chars(_) => Scalar::U8,
        }
    }

    /// The value bytes for a whole value written as text: one value, a comma-separated list of
    /// exactly `N` values for an array, or the text itself for `char[N]`.
    ///
    /// # Errors
    /// A sentence saying why the text does not fit the type.
    pub(crate) fn encode(self, text: &str) -> Result<Vec<u8>, String> {
        match self {
            ValueType::Scalar(s) => s.encode(text),
            ValueType::Array(s, n) => {
                let items: Vec<&str> = text.split(',').collect();
                if items.len() != n {
                    return Err(format!(
                        "{self} needs exactly {n} comma-separated values, got {}",
                        items.len()
                    ));
                }
                let mut out = Vec::with_capacity(n * s.size());
                for item in items {
                    out.extend(s.encode(item)?);
                }
                Ok(out)
            }
            ValueType::Chars(n) => {
                if text.len() > n {
                    return Err(format!(
                        "'{text}' is {} bytes long, more than {self} holds",
                        text.len()
                    ));
                }
                Ok(text.as_bytes().to_vec())
            }
        }
    }

    /// The value in `data` (the bytes of a system value update): a number, a list, or a string
    /// cut at the first NUL.
    ///
    /// # Errors
    /// A sentence when the length does not fit the type.
    pub(crate) fn decode(self, data: &[u8]) -> Result<Value, String> {
        let size = self.element().size();
        match self {
            ValueType::Chars(n) if data.len() == n => {
                let end = data.iter().position(|&b| b == 0).unwrap_or(data.len());
                Ok(json!(crate::render::escape_text(&data[..end])))
            }
            ValueType::Scalar(s) if data.len() == size => Ok(s.decode(data)),
            ValueType::Array(s, n) if data.len() == n.saturating_mul(size) => Ok(Value::Array(
                data.chunks_exact(size).map(|c| s.decode(c)).collect(),
            )),
            _ => Err(format!(
                "{} value bytes do not fit {self} ({size} bytes per element)",
                data.len()
            )),
        }
    }
}

/// The examples of this module's items, as tests (the items are crate-private, so rustdoc
/// does not run them).
#[cfg(test)]
#[allow(unused_imports, clippy::unnecessary_wraps)]
mod examples {
    use super::*;

    #[test]
    fn encode_example() -> Result<(), Box<dyn std::error::Error>> {
        assert_eq!(Scalar::U16.encode("0x1234").unwrap(), [0x34, 0x12]);
        assert_eq!(Scalar::F32.encode("10").unwrap(), 10f32.to_le_bytes());
        assert!(Scalar::U8.encode("256").is_err());
        Ok(())
    }

    #[test]
    fn valuetype_example() -> Result<(), Box<dyn std::error::Error>> {
        assert_eq!(
            "f32[3]".parse::<ValueType>(),
            Ok(ValueType::Array(Scalar::F32, 3))
        );
        assert_eq!("char[40]".parse::<ValueType>(), Ok(ValueType::Chars(40)));
        assert_eq!(
            "u16".parse::<ValueType>(),
            Ok(ValueType::Scalar(Scalar::U16))
        );
        assert!("float".parse::<ValueType>().is_err());
        Ok(())
    }

    #[test]
    fn encode_2_example() -> Result<(), Box<dyn std::error::Error>> {
        let t: ValueType = "u16[3]".parse().unwrap();
        assert_eq!(t.encode("10,20,100").unwrap(), [10, 0, 20, 0, 100, 0]);
        assert!(t.encode("10,20").is_err());
        let c: ValueType = "char[4]".parse().unwrap();
        assert_eq!(c.encode("boat").unwrap(), b"boat");
        assert!(c.encode("yacht").is_err());
        Ok(())
    }

    #[test]
    fn decode_example() -> Result<(), Box<dyn std::error::Error>> {
        let t: ValueType = "f32[2]".parse().unwrap();
        let mut data = 1.5f32.to_le_bytes().to_vec();
        data.extend(0.1f32.to_le_bytes());
        assert_eq!(t.decode(&data).unwrap().to_string(), "[1.5,0.1]");
        assert!(t.decode(&data[..4]).is_err()); // one element short of f32[2]
        let c: ValueType = "char[8]".parse().unwrap();
        assert_eq!(c.decode(b"boat\0\0\0\0").unwrap(), "boat");
        Ok(())
    }
}
