//! Turning decoded values into output: JSON values, readable `key=value` text, hex, and a
//! buffered stdout that reports a closed pipe instead of panicking.

use std::io::{self, BufWriter, Stdout, Write};

use serde::Serialize;
use serde_json::{Map, Number, Value};

use crate::error::{Error, Result};

/// Lower-case hex of `bytes`, no separators.
///
/// ```
/// assert_eq!(protolink::render::hex(&[0x7e, 0x00, 0xff]), "7e00ff");
/// ```
pub fn hex(bytes: &[u8]) -> String {
    use std::fmt::Write as _;
    bytes
        .iter()
        .fold(String::with_capacity(bytes.len() * 2), |mut s, b| {
            let _ = write!(s, "{b:02x}");
            s
        })
}

/// `CamelCase` to `UPPER_SNAKE` (`SystemValueUpdate` -> `SYSTEM_VALUE_UPDATE`).
///
/// ```
/// assert_eq!(protolink::render::upper_snake("SystemValueUpdate"), "SYSTEM_VALUE_UPDATE");
/// assert_eq!(protolink::render::upper_snake("Debug"), "DEBUG");
/// ```
pub fn upper_snake(name: &str) -> String {
    let mut out = String::with_capacity(name.len() + 4);
    for (i, c) in name.chars().enumerate() {
        if c.is_uppercase() && i > 0 {
            out.push('_');
        }
        out.extend(c.to_uppercase());
    }
    out
}

/// Serialises `value` to JSON and shortens every float that is exactly an `f32` to the `f32`'s
/// shortest decimal form, so `0.1f32` reads `0.1`, not `0.10000000149011612`.
///
/// ```
/// let v = protolink::render::to_json(&(0.1f32, 123456.5f64, 10f32));
/// assert_eq!(v.to_string(), "[0.1,123456.5,10.0]");
/// ```
pub fn to_json<T: Serialize + ?Sized>(value: &T) -> Value {
    let mut v = serde_json::to_value(value).unwrap_or(Value::Null);
    tidy_floats(&mut v);
    v
}

fn tidy_floats(v: &mut Value) {
    match v {
        Value::Number(n) if n.is_f64() => {
            if let Some(x) = n.as_f64() {
                let short = x as f32;
                let mut text = short.to_string();
                if !text.contains(['.', 'e', 'E']) {
                    // Keep it a float: "10" would read back as an integer.
                    text.push_str(".0");
                }
                if f64::from(short) == x
                    && let Ok(parsed) = text.parse::<Number>()
                {
                    *n = parsed;
                }
            }
        }
        Value::Array(items) => items.iter_mut().for_each(tidy_floats),
        Value::Object(map) => map.values_mut().for_each(tidy_floats),
        _ => {}
    }
}

/// Splits an externally tagged enum value (`{"Gyro": {...}}` or `"Heartbeat"`) into its
/// variant name and its fields (always an object; a bare inner value becomes `{"value": ...}`).
///
/// ```
/// use serde_json::json;
/// let (name, fields) = protolink::render::variant(json!({"WindSpeed": 3.5}));
/// assert_eq!((name.as_str(), fields), ("WindSpeed", json!({"value": 3.5})));
/// ```
pub fn variant(value: Value) -> (String, Value) {
    match value {
        Value::String(name) => (name, Value::Object(Map::new())),
        Value::Object(map) if map.len() == 1 => {
            let Some((name, inner)) = map.into_iter().next() else {
                return (String::new(), Value::Object(Map::new()));
            };
            let fields = match inner {
                Value::Object(m) => Value::Object(m),
                Value::Null => Value::Object(Map::new()),
                other => {
                    let mut m = Map::new();
                    m.insert("value".into(), other);
                    Value::Object(m)
                }
            };
            (name, fields)
        }
        other => {
            let mut m = Map::new();
            m.insert("value".into(), other);
            (String::new(), Value::Object(m))
        }
    }
}

/// Replaces every `"data"` array of bytes in an object tree by its hex string.
pub fn data_as_hex(v: &mut Value) {
    match v {
        Value::Object(map) => {
            for (key, item) in map.iter_mut() {
                if key == "data"
                    && let Some(bytes) = as_bytes(item)
                {
                    *item = Value::String(hex(&bytes));
                } else {
                    data_as_hex(item);
                }
            }
        }
        Value::Array(items) => items.iter_mut().for_each(data_as_hex),
        _ => {}
    }
}

fn as_bytes(v: &Value) -> Option<Vec<u8>> {
    v.as_array()?
        .iter()
        .map(|b| b.as_u64().and_then(|b| u8::try_from(b).ok()))
        .collect()
}

/// Renders a JSON value the way a person reads it: objects as `key=value` pairs separated by
/// spaces, nested objects in braces, arrays in brackets, plain strings unquoted.
///
/// ```
/// use serde_json::json;
/// let v = json!({"valid": true, "x": 0.5, "mode": {"Array": {"count": 3}}, "mac": [1, 2]});
/// assert_eq!(protolink::render::text(&v), "valid=true x=0.5 mode={Array={count=3}} mac=[1,2]");
/// ```
pub fn text(v: &Value) -> String {
    match v {
        Value::Object(map) => map
            .iter()
            .map(|(k, v)| format!("{k}={}", inner_text(v)))
            .collect::<Vec<_>>()
            .join(" "),
        other => inner_text(other),
    }
}

fn inner_text(v: &Value) -> String {
    match v {
        Value::String(s)
            if !s.is_empty() && !s.contains(char::is_whitespace) && !s.contains('"') =>
        {
            s.clone()
        }
        Value::String(s) => format!("{s:?}"),
        Value::Array(items) => format!(
            "[{}]",
            items.iter().map(inner_text).collect::<Vec<_>>().join(",")
        ),
        Value::Object(_) => format!("{{{}}}", text(v)),
        other => other.to_string(),
    }
}

/// Buffered standard output. A closed pipe (`protolink decode ... | head`) becomes an
/// [`Error::Output`] instead of a panic.
#[derive(Debug)]
pub struct Out {
    inner: BufWriter<Stdout>,
}

impl Default for Out {
    fn default() -> Self {
        Self::new()
    }
}

impl Out {
    /// Standard output, buffered.
    pub fn new() -> Self {
        Out {
            inner: BufWriter::with_capacity(64 * 1024, io::stdout()),
        }
    }

    /// Writes one line.
    ///
    /// # Errors
    /// [`Error::Output`] when stdout is closed or fails.
    pub fn line(&mut self, line: &str) -> Result<()> {
        self.inner
            .write_all(line.as_bytes())
            .and_then(|()| self.inner.write_all(b"\n"))
            .map_err(Error::Output)
    }

    /// Writes raw text (no newline added).
    ///
    /// # Errors
    /// [`Error::Output`] when stdout is closed or fails.
    pub fn raw(&mut self, text: &str) -> Result<()> {
        self.inner.write_all(text.as_bytes()).map_err(Error::Output)
    }

    /// Pushes buffered lines out.
    ///
    /// # Errors
    /// [`Error::Output`] when stdout is closed or fails.
    pub fn flush(&mut self) -> Result<()> {
        self.inner.flush().map_err(Error::Output)
    }
}
