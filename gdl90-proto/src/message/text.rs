//! Fixed-width text fields: the report call sign (space padded) and the ForeFlight device
//! names (NUL padded). Both keep the bytes as received; the string views are checked.

/// An 8-character call sign (ICD 3.5.1.11): ASCII, padded with spaces, as received.
///
/// ```
/// use gdl90_proto::message::CallSign;
/// let cs = CallSign::new("N825V").unwrap();
/// assert_eq!(cs.as_bytes(), b"N825V   ");
/// assert_eq!(cs.as_str(), Some("N825V"));
/// assert!(CallSign::new("TOOLONG99").is_none());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct CallSign([u8; 8]);

impl Default for CallSign {
    /// All spaces: no call sign.
    fn default() -> Self {
        CallSign([b' '; 8])
    }
}

impl CallSign {
    /// The call sign `s`, space padded; `None` if it is longer than 8 bytes or not printable
    /// ASCII (the ICD allows `0-9`, `A-Z` and space; other printable ASCII is let through).
    ///
    /// ```
    /// use gdl90_proto::message::CallSign;
    /// assert_eq!(CallSign::new("N825V").unwrap().as_bytes(), b"N825V   ");
    /// assert!(CallSign::new("N825É").is_none());
    /// ```
    pub fn new(s: &str) -> Option<Self> {
        let bytes = s.as_bytes();
        if bytes.len() > 8 || !bytes.iter().all(|b| (0x20..0x7F).contains(b)) {
            return None;
        }
        let mut out = [b' '; 8];
        out.get_mut(..bytes.len())?.copy_from_slice(bytes);
        Some(CallSign(out))
    }

    /// Wraps eight bytes as received.
    ///
    /// ```
    /// use gdl90_proto::message::CallSign;
    /// assert_eq!(CallSign::from_bytes(*b"N825V   ").as_str(), Some("N825V"));
    /// ```
    pub const fn from_bytes(bytes: [u8; 8]) -> Self {
        CallSign(bytes)
    }

    /// The eight bytes, padding included.
    ///
    /// ```
    /// use gdl90_proto::message::CallSign;
    /// assert_eq!(CallSign::default().as_bytes(), b"        ");
    /// ```
    pub const fn as_bytes(&self) -> &[u8; 8] {
        &self.0
    }

    /// The call sign without its trailing spaces; `None` if the bytes are not UTF-8.
    ///
    /// ```
    /// use gdl90_proto::message::CallSign;
    /// assert_eq!(CallSign::new("AB").unwrap().as_str(), Some("AB"));
    /// assert_eq!(CallSign::from_bytes([0xFF, b' ', b' ', b' ', b' ', b' ', b' ', b' ']).as_str(), None);
    /// ```
    pub fn as_str(&self) -> Option<&str> {
        let end = self.0.iter().rposition(|&b| b != b' ').map_or(0, |i| i + 1);
        core::str::from_utf8(self.0.get(..end)?).ok()
    }
}

/// A NUL-padded UTF-8 name of `N` bytes (the ForeFlight device name and long name).
///
/// ```
/// use gdl90_proto::message::Name;
/// let name = Name::<8>::new("SkyEcho").unwrap();
/// assert_eq!(name.as_bytes(), b"SkyEcho\0");
/// assert_eq!(name.as_str(), Some("SkyEcho"));
/// assert!(Name::<8>::new("far too long").is_none());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Name<const N: usize>([u8; N]);

impl<const N: usize> Default for Name<N> {
    /// All NULs: an empty name.
    fn default() -> Self {
        Name([0; N])
    }
}

impl<const N: usize> Name<N> {
    /// The name `s`, NUL padded; `None` if it is longer than `N` bytes or holds a NUL.
    ///
    /// ```
    /// use gdl90_proto::message::Name;
    /// assert_eq!(Name::<4>::new("ab").unwrap().as_bytes(), b"ab\0\0");
    /// assert!(Name::<4>::new("a\0b").is_none());
    /// ```
    pub fn new(s: &str) -> Option<Self> {
        let bytes = s.as_bytes();
        if bytes.len() > N || bytes.contains(&0) {
            return None;
        }
        let mut out = [0; N];
        out.get_mut(..bytes.len())?.copy_from_slice(bytes);
        Some(Name(out))
    }

    /// Wraps `N` bytes as received.
    ///
    /// ```
    /// use gdl90_proto::message::Name;
    /// assert_eq!(Name::from_bytes(*b"abc\0").as_str(), Some("abc"));
    /// ```
    pub const fn from_bytes(bytes: [u8; N]) -> Self {
        Name(bytes)
    }

    /// The `N` bytes, padding included.
    ///
    /// ```
    /// use gdl90_proto::message::Name;
    /// assert_eq!(Name::<4>::default().as_bytes(), &[0; 4]);
    /// ```
    pub const fn as_bytes(&self) -> &[u8; N] {
        &self.0
    }

    /// The name up to its first NUL; `None` if those bytes are not UTF-8.
    ///
    /// ```
    /// use gdl90_proto::message::Name;
    /// assert_eq!(Name::from_bytes([b'a', 0, b'b', 0]).as_str(), Some("a"));
    /// assert_eq!(Name::from_bytes([0xFF, 0, 0, 0]).as_str(), None);
    /// ```
    pub fn as_str(&self) -> Option<&str> {
        let end = self.0.iter().position(|&b| b == 0).unwrap_or(N);
        core::str::from_utf8(self.0.get(..end)?).ok()
    }
}

/// Text as a string when it is UTF-8, otherwise the raw bytes, so JSON stays readable.
#[cfg(feature = "serde")]
fn serialize_text<S: serde::Serializer>(
    text: Option<&str>,
    raw: &[u8],
    s: S,
) -> Result<S::Ok, S::Error> {
    match text {
        Some(t) => s.serialize_str(t),
        None => s.serialize_bytes(raw),
    }
}

#[cfg(feature = "serde")]
impl serde::Serialize for CallSign {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        serialize_text(self.as_str(), &self.0, s)
    }
}

#[cfg(feature = "serde")]
impl<const N: usize> serde::Serialize for Name<N> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        serialize_text(self.as_str(), &self.0, s)
    }
}
