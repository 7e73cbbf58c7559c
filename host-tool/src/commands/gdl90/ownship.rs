//! The ownship's identity for `protolink gdl90`: `--icao` and `--callsign`, checked, and kept
//! per box in a small JSON file so the next run sends the same identity without them.
//!
//! The file is `$XDG_STATE_HOME/protolink/ownship.json` (`~/.local/state/protolink/` when
//! `XDG_STATE_HOME` is not set), a map from the box's `--from` endpoint (`udp:127.0.0.1:5001`,
//! `tcp:127.0.0.1:7000`, ...) to its ICAO address and call sign. It is bounded: at most
//! [`MAX_BOXES`] boxes and [`MAX_FILE_BYTES`] bytes; a file that is not this map is an error,
//! never silently replaced.

use std::collections::BTreeMap;
use std::io::Read as _;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};

/// Boxes the file remembers at most.
pub(crate) const MAX_BOXES: usize = 256;
/// The largest file read.
pub(crate) const MAX_FILE_BYTES: u64 = 64 * 1024;

/// Parses a 24-bit ICAO address: 1 to 6 hex digits, with or without `0x`; 000000 and FFFFFF
/// are refused (no aircraft has them).
///
/// # Errors
/// One sentence naming what is wrong.
pub(crate) fn parse_icao(text: &str) -> std::result::Result<u32, String> {
    let t = text.trim();
    let digits = t
        .strip_prefix("0x")
        .or_else(|| t.strip_prefix("0X"))
        .unwrap_or(t);
    let ok = (1..=6).contains(&digits.len()) && digits.bytes().all(|b| b.is_ascii_hexdigit());
    let value = u32::from_str_radix(digits, 16)
        .ok()
        .filter(|_| ok)
        .ok_or_else(|| {
            format!("'{text}' is not a 24-bit ICAO address (1 to 6 hex digits, such as A1B2C3)")
        })?;
    if value == 0 || value == 0xFF_FFFF {
        return Err(format!(
            "'{text}' is not an aircraft's ICAO address (000000 and FFFFFF are not assigned)"
        ));
    }
    Ok(value)
}

/// Parses a GDL90 call sign: 1 to 8 characters of `0-9`, `A-Z` (lower case is taken as upper
/// case), no spaces inside.
///
/// # Errors
/// One sentence naming what is wrong.
pub(crate) fn parse_callsign(text: &str) -> std::result::Result<String, String> {
    let upper = text.trim().to_ascii_uppercase();
    if upper.is_empty() || upper.len() > 8 {
        return Err(format!("'{text}' is not a call sign of 1 to 8 characters"));
    }
    if let Some(c) = upper.chars().find(|c| !c.is_ascii_alphanumeric()) {
        return Err(format!(
            "'{text}' has '{c}', but a GDL90 call sign holds only 0-9 and A-Z (D-EKAB is DEKAB)"
        ));
    }
    Ok(upper)
}

/// What is kept for one box.
#[derive(Debug, Clone, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub(crate) struct Identity {
    /// The 24-bit ICAO address, when given.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) icao: Option<u32>,
    /// The call sign, when given.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) callsign: Option<String>,
}

/// The file the identities are kept in: `$XDG_STATE_HOME/protolink/ownship.json`, or
/// `$HOME/.local/state/protolink/ownship.json`; `None` when neither variable is set.
pub(crate) fn state_file() -> Option<PathBuf> {
    let base = std::env::var_os("XDG_STATE_HOME")
        .filter(|v| !v.is_empty())
        .map(PathBuf::from)
        .or_else(|| {
            std::env::var_os("HOME")
                .filter(|v| !v.is_empty())
                .map(|h| PathBuf::from(h).join(".local").join("state"))
        })?;
    Some(base.join("protolink").join("ownship.json"))
}

fn io_error(what: String) -> impl FnOnce(std::io::Error) -> Error {
    move |source| Error::Io { what, source }
}

/// Reads the map from `file`; an absent file is an empty map.
fn load(file: &Path) -> Result<BTreeMap<String, Identity>> {
    let f = match std::fs::File::open(file) {
        Ok(f) => f,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(BTreeMap::new()),
        Err(e) => return Err(io_error(format!("reading {}", file.display()))(e)),
    };
    let mut text = String::new();
    f.take(MAX_FILE_BYTES + 1)
        .read_to_string(&mut text)
        .map_err(io_error(format!("reading {}", file.display())))?;
    if text.len() as u64 > MAX_FILE_BYTES {
        return Err(Error::Usage(format!(
            "{} is larger than {MAX_FILE_BYTES} bytes: it is not protolink's ownship file",
            file.display()
        )));
    }
    serde_json::from_str(&text).map_err(|e| {
        Error::Usage(format!(
            "{} is not protolink's ownship file ({e}); move it away to start afresh",
            file.display()
        ))
    })
}

/// Writes the map to `file` (through a temporary file beside it, then a rename).
fn save(file: &Path, map: &BTreeMap<String, Identity>) -> Result<()> {
    if let Some(dir) = file.parent() {
        std::fs::create_dir_all(dir).map_err(io_error(format!("creating {}", dir.display())))?;
    }
    let text = serde_json::to_string_pretty(map).unwrap_or_default();
    let tmp = file.with_extension("json.tmp");
    std::fs::write(&tmp, text).map_err(io_error(format!("writing {}", tmp.display())))?;
    std::fs::rename(&tmp, file).map_err(io_error(format!("writing {}", file.display())))
}

/// The identity for the box `key`: what was given now (kept in `file` for the next run), else
/// what `file` kept from an earlier run, else nothing. Without a file (no home directory)
/// only what was given now.
///
/// # Errors
/// The file cannot be read or written, is not this map, or already holds [`MAX_BOXES`] other
/// boxes.
pub(crate) fn resolve(key: &str, given: Identity, file: Option<&Path>) -> Result<Identity> {
    let Some(file) = file else {
        return Ok(given);
    };
    let mut map = load(file)?;
    let kept = map.get(key).cloned().unwrap_or_default();
    if given == Identity::default() {
        return Ok(kept);
    }
    let merged = Identity {
        icao: given.icao.or(kept.icao),
        callsign: given.callsign.or(kept.callsign),
    };
    if !map.contains_key(key) && map.len() >= MAX_BOXES {
        return Err(Error::Usage(format!(
            "{} already keeps {MAX_BOXES} boxes; remove some entries to add {key}",
            file.display()
        )));
    }
    map.insert(key.to_owned(), merged.clone());
    save(file, &map)?;
    Ok(merged)
}

/// The examples of this module's items, as tests (the items are crate-private, so rustdoc
/// does not run them).
#[cfg(test)]
#[allow(unused_imports, clippy::unnecessary_wraps)]
mod examples {
    use super::*;

    #[test]
    fn parse_icao_example() -> Result<(), Box<dyn std::error::Error>> {
        assert_eq!(parse_icao("A1B2C3"), Ok(0xA1B2C3));
        assert_eq!(parse_icao("0x3c6586"), Ok(0x3C6586));
        assert!(parse_icao("1234567").unwrap_err().contains("24-bit"));
        assert!(parse_icao("000000").is_err());
        assert!(parse_icao("G12345").is_err());
        Ok(())
    }

    #[test]
    fn parse_callsign_example() -> Result<(), Box<dyn std::error::Error>> {
        assert_eq!(parse_callsign("n123ab").unwrap(), "N123AB");
        assert!(
            parse_callsign("D-EKAB")
                .unwrap_err()
                .contains("only 0-9 and A-Z")
        );
        assert!(parse_callsign("TOOLONG99").is_err());
        Ok(())
    }

    #[test]
    fn resolve_example() -> Result<(), Box<dyn std::error::Error>> {
        let file = std::env::temp_dir().join(format!("ownship-doc-{}.json", std::process::id()));
        let given = Identity {
            icao: Some(0xA1B2C3),
            callsign: Some("N123AB".into()),
        };
        assert_eq!(
            resolve("udp:127.0.0.1:5001", given.clone(), Some(&file))?,
            given
        );
        // The next run, without the options, sends the same identity.
        assert_eq!(
            resolve("udp:127.0.0.1:5001", Identity::default(), Some(&file))?,
            given
        );
        assert_eq!(
            resolve("udp:127.0.0.1:6001", Identity::default(), Some(&file))?,
            Identity::default()
        );
        std::fs::remove_file(&file)?;
        Ok(())
    }
}
