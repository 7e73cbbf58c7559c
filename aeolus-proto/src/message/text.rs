//! TOAST and COMMAND texts (sections 7.14, 7.15, DECISIONS.md A6).

use crate::{EncodeError, Error, TEXT_CAPACITY};

/// A bounded text: TOAST (82) and COMMAND (11) carry a NUL-terminated string.
///
/// The bytes are kept as received (text that is not UTF-8 keeps its raw bytes, A6);
/// [`Text::as_str`] gives the string when it is UTF-8. The NUL terminator is not stored.
///
/// ```
/// use aeolus_proto::message::Text;
/// let t = Text::new("a pause").unwrap();
/// assert_eq!(t.as_bytes(), b"a pause");
/// assert_eq!(t.buffer_len(), 8); // the text and its NUL
/// ```
#[derive(Clone, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Text(heapless::Vec<u8, TEXT_CAPACITY>);

impl Text {
    /// A text from a string.
    ///
    /// ```
    /// use aeolus_proto::{EncodeError, message::Text};
    /// assert_eq!(Text::new("a reboot").unwrap().as_str(), Some("a reboot"));
    /// let long = "x".repeat(121);
    /// assert_eq!(Text::new(&long), Err(EncodeError::TextTooLong { len: 121 }));
    /// ```
    ///
    /// # Errors
    /// [`EncodeError::TextTooLong`] if it is longer than [`TEXT_CAPACITY`].
    pub fn new(text: &str) -> Result<Self, EncodeError> {
        Self::from_bytes(text.as_bytes()).map_err(|_| EncodeError::TextTooLong { len: text.len() })
    }

    /// A text from raw bytes (not necessarily UTF-8), up to a NUL if one is present.
    ///
    /// ```
    /// use aeolus_proto::message::Text;
    /// assert_eq!(Text::from_bytes(b"ok\0junk").unwrap().as_bytes(), b"ok");
    /// assert_eq!(Text::from_bytes(&[0xFF, b'a']).unwrap().as_bytes(), &[0xFF, b'a']);
    /// ```
    ///
    /// # Errors
    /// [`EncodeError::TextTooLong`] if the bytes before the NUL exceed [`TEXT_CAPACITY`].
    pub fn from_bytes(bytes: &[u8]) -> Result<Self, EncodeError> {
        let end = bytes.iter().position(|&b| b == 0).unwrap_or(bytes.len());
        let text = bytes.get(..end).unwrap_or(&[]);
        heapless::Vec::from_slice(text)
            .map(Text)
            .map_err(|_| EncodeError::TextTooLong { len: end })
    }

    /// Parses message data: the string runs to the first NUL, or over all the data if there is
    /// none (A6). Bytes after the NUL are ignored (they stay in the raw frame).
    ///
    /// ```
    /// use aeolus_proto::{Error, message::Text};
    /// assert_eq!(Text::parse(82, b"hi\0").unwrap().as_str(), Some("hi"));
    /// assert_eq!(Text::parse(82, b"no nul").unwrap().as_str(), Some("no nul"));
    /// assert_eq!(Text::parse(82, &[b'x'; 130]), Err(Error::TextTooLong { id: 82, len: 130 }));
    /// ```
    ///
    /// # Errors
    /// [`Error::TextTooLong`] carrying `id`.
    pub fn parse(id: u8, data: &[u8]) -> Result<Self, Error> {
        Self::from_bytes(data).map_err(|e| match e {
            EncodeError::TextTooLong { len } | EncodeError::BufferTooSmall { needed: len } => {
                Error::TextTooLong {
                    id,
                    len: len.min(u16::MAX as usize) as u16,
                }
            }
        })
    }

    /// The text bytes, without the NUL.
    ///
    /// ```
    /// use aeolus_proto::message::Text;
    /// assert_eq!(Text::parse(82, b"hi\0").unwrap().as_bytes(), b"hi");
    /// ```
    pub fn as_bytes(&self) -> &[u8] {
        &self.0
    }

    /// The text, if it is UTF-8.
    ///
    /// ```
    /// use aeolus_proto::message::Text;
    /// assert_eq!(Text::new("hi").unwrap().as_str(), Some("hi"));
    /// assert_eq!(Text::from_bytes(&[0xFF]).unwrap().as_str(), None);
    /// ```
    pub fn as_str(&self) -> Option<&str> {
        core::str::from_utf8(&self.0).ok()
    }

    /// The data length on the wire: the text and its NUL terminator.
    ///
    /// ```
    /// use aeolus_proto::message::Text;
    /// assert_eq!(Text::new("hi").unwrap().buffer_len(), 3);
    /// ```
    pub fn buffer_len(&self) -> usize {
        self.0.len() + 1
    }

    /// Writes the text and its NUL into `out`; returns [`Text::buffer_len`].
    ///
    /// ```
    /// use aeolus_proto::{EncodeError, message::Text};
    /// let text = Text::new("hi").unwrap();
    /// let mut out = [0xAA; 4];
    /// assert_eq!(text.emit(&mut out), Ok(3));
    /// assert_eq!(out, [b'h', b'i', 0, 0xAA]);
    /// assert_eq!(text.emit(&mut out[..2]), Err(EncodeError::BufferTooSmall { needed: 3 }));
    /// ```
    ///
    /// # Errors
    /// [`EncodeError::BufferTooSmall`].
    pub fn emit(&self, out: &mut [u8]) -> Result<usize, EncodeError> {
        let n = self.0.len();
        let out = out
            .get_mut(..=n)
            .ok_or(EncodeError::BufferTooSmall { needed: n + 1 })?;
        let (text, nul) = out.split_at_mut(n);
        text.copy_from_slice(&self.0);
        nul.fill(0);
        Ok(n + 1)
    }
}

/// Shows the text as a string when it is UTF-8, as bytes otherwise.
impl core::fmt::Debug for Text {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self.as_str() {
            Some(s) => f.debug_tuple("Text").field(&s).finish(),
            None => f.debug_tuple("Text").field(&self.as_bytes()).finish(),
        }
    }
}
