//! What an export's rows say of their file besides `source` (the path as it was given): its
//! name (`file`) and an identity of its content (`capture_id`), which stay the same whatever the
//! directory the export ran in or the name the file was copied under.

use std::io::Read;
use std::path::Path;

use super::fnv::Fnv;
use crate::error::{Error, Result};

/// The bytes of a file's start that its identity covers.
pub const ID_PREFIX: usize = 64 * 1024;

/// A source file's name and content identity.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SourceId {
    /// The file's name, without its directory.
    pub file: String,
    /// 16 hex digits: the FNV-1a hash (64 bits) of the file's first [`ID_PREFIX`] bytes
    /// followed by its length (8 bytes, little-endian).
    pub capture_id: String,
}

impl SourceId {
    /// The name and identity of the file at `path`.
    ///
    /// # Errors
    /// The file cannot be opened or read.
    ///
    /// ```
    /// use protolink::columns::SourceId;
    /// let dir = std::env::temp_dir().join(format!("protolink-doc-id-{}", std::process::id()));
    /// std::fs::create_dir_all(&dir)?;
    /// std::fs::write(dir.join("a.bin"), b"flight")?;
    /// std::fs::write(dir.join("b.bin"), b"flight")?;
    /// let (a, b) = (SourceId::of(&dir.join("a.bin"))?, SourceId::of(&dir.join("b.bin"))?);
    /// assert_eq!((a.file.as_str(), a.capture_id.len()), ("a.bin", 16));
    /// assert_eq!(a.capture_id, b.capture_id);
    /// # std::fs::remove_dir_all(&dir)?;
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn of(path: &Path) -> Result<SourceId> {
        let failed = |source| Error::Io {
            what: format!("reading {}", path.display()),
            source,
        };
        let file = std::fs::File::open(path).map_err(|e| Error::Open {
            endpoint: path.display().to_string(),
            source: e,
        })?;
        let len = file.metadata().map_err(failed)?.len();
        let mut start = Vec::with_capacity(ID_PREFIX);
        file.take(ID_PREFIX as u64)
            .read_to_end(&mut start)
            .map_err(failed)?;
        Ok(SourceId {
            file: path
                .file_name()
                .map_or_else(String::new, |n| n.to_string_lossy().into_owned()),
            capture_id: content_id(&start, len),
        })
    }
}

/// The identity of a file of length `len` that starts with `start` (its first
/// [`ID_PREFIX`] bytes, or all of it).
fn content_id(start: &[u8], len: u64) -> String {
    use std::hash::Hasher;
    let mut h = Fnv::default();
    h.write(start.get(..ID_PREFIX).unwrap_or(start));
    h.write(&len.to_le_bytes());
    format!("{:016x}", h.finish())
}

#[cfg(test)]
mod tests {
    use super::content_id;

    #[test]
    fn the_id_follows_the_start_and_the_length() {
        let a = vec![7u8; 100_000];
        let id = content_id(&a, 100_000);
        // Pinned: an id must not change between versions.
        assert_eq!(id, content_id(&a[..super::ID_PREFIX], 100_000));
        assert_eq!(content_id(b"", 0), "a8c7f832281a39c5");
        let mut b = a.clone();
        b[10] = 8;
        assert_ne!(content_id(&b, 100_000), id);
        assert_ne!(content_id(&a, 100_001), id);
    }
}
