//! Turning decoded values into output: JSON values, readable `key=value` text, hex, and a
//! buffered stdout that reports a closed pipe instead of panicking.

use std::io::{self, BufWriter, Write};

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

/// Text from the wire made safe and lossless for a terminal: printable characters stay,
/// a backslash becomes `\\`, control characters and bytes that are not UTF-8 become `\xNN`
/// (C1 controls `\u{NN}`). Different byte strings always give different text.
pub(crate) fn escape_text(bytes: &[u8]) -> String {
    use std::fmt::Write as _;
    let mut out = String::with_capacity(bytes.len());
    for chunk in bytes.utf8_chunks() {
        for c in chunk.valid().chars() {
            match c {
                '\\' => out.push_str("\\\\"),
                c if (c as u32) < 0x20 || c as u32 == 0x7f => {
                    let _ = write!(out, "\\x{:02x}", c as u32);
                }
                c if c.is_control() => {
                    let _ = write!(out, "\\u{{{:x}}}", c as u32);
                }
                c => out.push(c),
            }
        }
        for b in chunk.invalid() {
            let _ = write!(out, "\\x{b:02x}");
        }
    }
    out
}

/// Whether `bytes` is text that [`escape_text`] leaves unchanged (UTF-8 without controls or
/// backslashes); when it is not, JSON output carries the raw bytes in hex beside the text.
pub(crate) fn is_clean_text(bytes: &[u8]) -> bool {
    std::str::from_utf8(bytes).is_ok_and(|s| !s.chars().any(|c| c.is_control() || c == '\\'))
}

/// Any control character left in `s` as `\xNN` or `\u{NN}`, so nothing reaches a terminal raw.
fn no_controls(s: &str) -> String {
    use std::fmt::Write as _;
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        if c.is_control() {
            let _ = write!(out, "\\u{{{:x}}}", c as u32);
        } else {
            out.push(c);
        }
    }
    out
}

/// `CamelCase` to `UPPER_SNAKE` (`SystemValueUpdate` -> `SYSTEM_VALUE_UPDATE`).
pub(crate) fn upper_snake(name: &str) -> String {
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
pub(crate) fn variant(value: Value) -> (String, Value) {
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
pub(crate) fn data_as_hex(v: &mut Value) {
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
pub(crate) fn text(v: &Value) -> String {
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
            no_controls(s)
        }
        Value::String(s) => format!("\"{}\"", no_controls(s).replace('"', "\\\"")),
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
pub(crate) struct Out {
    inner: BufWriter<Box<dyn Write>>,
}

impl std::fmt::Debug for Out {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Out")
    }
}

impl Default for Out {
    fn default() -> Self {
        Self::new()
    }
}

impl Out {
    /// Standard output, buffered.
    pub(crate) fn new() -> Self {
        Out {
            inner: BufWriter::with_capacity(64 * 1024, Box::new(io::stdout())),
        }
    }

    /// The output for result lines of a command whose frames go to `to`: standard error when
    /// the frames take standard output (`--to -`), so text never mixes with binary frames.
    pub(crate) fn beside(to: &crate::endpoint::Endpoint) -> Self {
        if *to == crate::endpoint::Endpoint::Stdio {
            Out {
                inner: BufWriter::new(Box::new(io::stderr())),
            }
        } else {
            Self::new()
        }
    }

    /// Writes one line.
    ///
    /// # Errors
    /// [`Error::Output`] when stdout is closed or fails.
    pub(crate) fn line(&mut self, line: &str) -> Result<()> {
        self.inner
            .write_all(line.as_bytes())
            .and_then(|()| self.inner.write_all(b"\n"))
            .map_err(Error::Output)
    }

    /// Writes raw text (no newline added).
    ///
    /// # Errors
    /// [`Error::Output`] when stdout is closed or fails.
    pub(crate) fn raw(&mut self, text: &str) -> Result<()> {
        self.inner.write_all(text.as_bytes()).map_err(Error::Output)
    }

    /// Pushes buffered lines out.
    ///
    /// # Errors
    /// [`Error::Output`] when stdout is closed or fails.
    pub(crate) fn flush(&mut self) -> Result<()> {
        self.inner.flush().map_err(Error::Output)
    }
}

/// The examples of this module's items, as tests (the items are crate-private, so rustdoc
/// does not run them).
#[cfg(test)]
#[allow(unused_imports, clippy::unnecessary_wraps)]
mod examples {
    use super::*;

    #[test]
    fn escape_text_example() -> Result<(), Box<dyn std::error::Error>> {
        assert_eq!(escape_text(b"AEOLUS on"), "AEOLUS on");
        assert_eq!(escape_text(b"\x1b[2Jhi\xff"), "\\x1b[2Jhi\\xff");
        assert_eq!(escape_text("a\\b".as_bytes()), "a\\\\b");
        assert_eq!(escape_text("Grüße".as_bytes()), "Grüße");
        Ok(())
    }

    #[test]
    fn is_clean_text_example() -> Result<(), Box<dyn std::error::Error>> {
        assert!(is_clean_text(b"a pause"));
        assert!(!is_clean_text(b"\xff"));
        Ok(())
    }

    #[test]
    fn upper_snake_example() -> Result<(), Box<dyn std::error::Error>> {
        assert_eq!(upper_snake("SystemValueUpdate"), "SYSTEM_VALUE_UPDATE");
        assert_eq!(upper_snake("Debug"), "DEBUG");
        Ok(())
    }

    #[test]
    fn variant_example() -> Result<(), Box<dyn std::error::Error>> {
        use serde_json::json;
        let (name, fields) = variant(json!({"WindSpeed": 3.5}));
        assert_eq!(
            (name.as_str(), fields),
            ("WindSpeed", json!({"value": 3.5}))
        );
        Ok(())
    }

    #[test]
    fn text_example() -> Result<(), Box<dyn std::error::Error>> {
        use serde_json::json;
        let v = json!({"valid": true, "x": 0.5, "mode": {"Array": {"count": 3}}, "mac": [1, 2]});
        assert_eq!(
            text(&v),
            "valid=true x=0.5 mode={Array={count=3}} mac=[1,2]"
        );
        Ok(())
    }
}
