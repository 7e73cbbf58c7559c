//! The message header (DECISIONS.md Y3): a checked zero-copy view and a plain representation.
//!
//! ```text
//! normal     FF | type | length u32 LE | seconds i64 LE | sub-seconds i64 LE     (22 bytes)
//! expedited  FF | type|0x80 | length u32 LE                                     ( 6 bytes)
//! ```

use crate::error::{EncodeError, Error, Result};
use crate::layout::header as layout;
use crate::profile::{EXPEDITED, MAX_BASE_TYPE, NORMAL_HEADER_LEN, Profile, START, Timestamp};

/// Read `K` bytes at a constant offset; zeros if the buffer is short (never panics).
#[inline]
pub(crate) fn array_at<const K: usize>(buf: &[u8], at: usize) -> [u8; K] {
    let src = buf.get(at..).unwrap_or(&[]);
    // The whole field as one array when it is there (the case of every caller that has
    // checked the length: a few loads once inlined); a byte loop only for a short buffer.
    if let Some(field) = src.first_chunk::<K>() {
        return *field;
    }
    let mut out = [0u8; K];
    for (d, s) in out.iter_mut().zip(src) {
        *d = *s;
    }
    out
}

/// Copy `src` into `buf` from offset `at`, as far as it fits (never panics).
#[inline]
pub(crate) fn put(buf: &mut [u8], at: usize, src: &[u8]) {
    if let Some(dst) = buf.get_mut(at..) {
        for (d, s) in dst.iter_mut().zip(src) {
            *d = *s;
        }
    }
}

/// A read-only view of a header at the start of a buffer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub(crate) struct Header<T: AsRef<[u8]>> {
    buffer: T,
}

impl<T: AsRef<[u8]>> Header<T> {
    /// Wrap a buffer without checks. Accessors never panic; on a short buffer they read zeros.
    pub(crate) const fn new_unchecked(buffer: T) -> Self {
        Self { buffer }
    }

    /// Wrap a buffer after checking the start byte, that the type is not 0xFF, and that the
    /// buffer holds the whole header (6 or 22 bytes).
    pub(crate) fn new_checked(buffer: T) -> Result<Self> {
        let h = Self::new_unchecked(buffer);
        h.check()?;
        Ok(h)
    }

    /// The checks [`Header::new_checked`] performs.
    pub(crate) fn check(&self) -> Result<()> {
        let b = self.buffer.as_ref();
        match b {
            [] | [_] => Err(Error::Truncated),
            [s, ..] if *s != START => Err(Error::BadStart),
            [_, t, ..] if *t == START => Err(Error::ReservedType),
            _ if b.len() < self.header_len() => Err(Error::Truncated),
            _ => Ok(()),
        }
    }

    /// The type byte as sent (with the expedited bit).
    #[inline]
    pub(crate) fn type_byte(&self) -> u8 {
        self.buffer.as_ref().get(1).copied().unwrap_or(0)
    }

    /// Whether the expedited bit (0x80) is set.
    #[inline]
    pub(crate) fn is_expedited(&self) -> bool {
        self.type_byte() & EXPEDITED != 0
    }

    /// The type without the expedited bit.
    #[inline]
    pub(crate) fn base_type(&self) -> u8 {
        self.type_byte() & !EXPEDITED
    }

    /// Header length: 6 if expedited, else 22.
    #[inline]
    pub(crate) fn header_len(&self) -> usize {
        Profile::header_len(self.is_expedited())
    }

    /// The raw u32 length field (its meaning depends on the profile).
    #[inline]
    pub(crate) fn length_field(&self) -> u32 {
        u32::from_le_bytes(array_at(self.buffer.as_ref(), layout::LENGTH))
    }

    /// Seconds from the epoch, or `None` for an expedited header.
    pub(crate) fn timestamp(&self) -> Option<Timestamp> {
        if self.is_expedited() {
            return None;
        }
        let b = self.buffer.as_ref();
        Some(Timestamp {
            seconds: i64::from_le_bytes(array_at(b, layout::SECONDS)),
            subsec: i64::from_le_bytes(array_at(b, layout::SUBSEC)),
        })
    }
}

/// A header as plain values. Expedited iff `timestamp` is `None`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct HeaderRepr {
    /// Base type, 0..=126 (the expedited bit is derived from `timestamp`).
    pub base_type: u8,
    /// Header time for a normal message; `None` makes the message expedited.
    pub timestamp: Option<Timestamp>,
    /// Number of data bytes between header and checksum.
    pub data_len: usize,
}

impl HeaderRepr {
    /// Whether this header is expedited (no time fields).
    #[inline]
    pub(crate) const fn is_expedited(&self) -> bool {
        self.timestamp.is_none()
    }

    /// The type byte on the wire, or `None` for a base type over 126, which has no type byte
    /// (Y3; `HeaderRepr::bytes` refuses it with [`Error::BadType`]).
    #[inline]
    pub(crate) const fn type_byte(&self) -> Option<u8> {
        if self.base_type > MAX_BASE_TYPE {
            None
        } else if self.is_expedited() {
            Some(self.base_type | EXPEDITED)
        } else {
            Some(self.base_type)
        }
    }

    /// Header length: 6 (expedited) or 22 (normal).
    #[inline]
    pub(crate) const fn buffer_len(&self) -> usize {
        Profile::header_len(self.is_expedited())
    }

    /// Whole message length: header, data and checksum (saturating).
    #[inline]
    pub(crate) const fn frame_len(&self) -> usize {
        self.data_len
            .saturating_add(Profile::overhead(self.is_expedited()))
    }

    /// The header bytes; only the first [`HeaderRepr::buffer_len`] are meaningful.
    ///
    /// # Errors
    /// [`EncodeError::BadType`] for a base type over 126, [`EncodeError::TooLong`] when the length does
    /// not fit its field, and [`EncodeError::ExpeditedInReference`] for an expedited header in a
    /// profile without one ([`Profile::has_expedited`]).
    pub(crate) fn bytes(
        self,
        profile: Profile,
    ) -> core::result::Result<[u8; NORMAL_HEADER_LEN], EncodeError> {
        if self.is_expedited() && !profile.has_expedited() {
            return Err(EncodeError::ExpeditedInReference);
        }
        let type_byte = self
            .type_byte()
            .ok_or(EncodeError::BadType(self.base_type))?;
        let length = profile
            .length_field(self.data_len, self.is_expedited())
            .ok_or(EncodeError::TooLong)?;
        let mut out = [0u8; NORMAL_HEADER_LEN];
        out[layout::START] = START;
        out[layout::TYPE] = type_byte;
        put(&mut out, layout::LENGTH, &length.to_le_bytes());
        if let Some(t) = self.timestamp {
            put(&mut out, layout::SECONDS, &t.seconds.to_le_bytes());
            put(&mut out, layout::SUBSEC, &t.subsec.to_le_bytes());
        }
        Ok(out)
    }

    /// Write the header into the start of `buf`; returns the bytes written.
    ///
    /// # Errors
    /// [`EncodeError::BufferTooSmall`], or any error of `HeaderRepr::bytes`.
    pub(crate) fn emit(
        &self,
        buf: &mut [u8],
        profile: Profile,
    ) -> core::result::Result<usize, EncodeError> {
        let n = self.buffer_len();
        if buf.len() < n {
            return Err(EncodeError::BufferTooSmall { needed: n });
        }
        let bytes = self.bytes(profile)?;
        put(buf, 0, bytes.get(..n).unwrap_or(&[]));
        Ok(n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_view_reads_and_checks_a_header() {
        let h = Header::new_checked(&[0xFF, 0x80, 0x07, 0, 0, 0, 0x78][..]).unwrap();
        assert!(h.is_expedited());
        assert_eq!(h.base_type(), 0);
        assert_eq!(h.length_field(), 7);
        assert_eq!(
            Header::new_checked(&[0xFF, 0xFF, 0, 0, 0, 0][..]),
            Err(Error::ReservedType)
        );
        assert_eq!(
            Header::new_checked(&[0xFE, 0x80, 0, 0, 0, 0][..]),
            Err(Error::BadStart)
        );
        assert_eq!(
            Header::new_checked(&[0xFF, 0x00, 0, 0, 0, 0][..]),
            Err(Error::Truncated)
        );
        // Fewer than two bytes are too short to judge, whatever the first one is.
        assert_eq!(Header::new_checked(&[][..]), Err(Error::Truncated));
        assert_eq!(Header::new_checked(&[0xFE][..]), Err(Error::Truncated));
        assert_eq!(Header::new_checked(&[0xFF][..]), Err(Error::Truncated));
    }

    #[test]
    fn the_repr_writes_a_header() {
        let repr = HeaderRepr {
            base_type: 1,
            timestamp: Some(Timestamp::new(42, 500_000)),
            data_len: 4,
        };
        let mut buf = [0u8; 22];
        repr.emit(&mut buf, Profile::Reference).unwrap();
        assert_eq!(&buf[..6], &[0xFF, 0x01, 0x04, 0, 0, 0]);
        assert_eq!(repr.buffer_len(), 22);
        assert_eq!(repr.frame_len(), 27);
        let expedited = HeaderRepr {
            base_type: 9,
            timestamp: None,
            data_len: 1,
        };
        assert_eq!(expedited.type_byte(), Some(0x89));
        let normal = HeaderRepr {
            timestamp: Some(Timestamp::new(0, 0)),
            ..expedited
        };
        assert_eq!(normal.type_byte(), Some(0x09));
        assert_eq!(
            HeaderRepr {
                base_type: 0x85,
                ..expedited
            }
            .type_byte(),
            None
        );
        // The Reference profile has no expedited header.
        let none = HeaderRepr {
            base_type: 0,
            timestamp: None,
            data_len: 0,
        };
        assert_eq!(
            none.bytes(Profile::Reference),
            Err(EncodeError::ExpeditedInReference)
        );
        assert_eq!(
            none.emit(&mut buf, Profile::Reference),
            Err(EncodeError::ExpeditedInReference)
        );
    }

    /// `emit` writes 6 (expedited) or 22 (normal) bytes into a buffer of at least that size
    /// and refuses a shorter one, naming the size it needs, with nothing written.
    #[test]
    fn emit_needs_exactly_the_header_length() {
        let expedited = HeaderRepr {
            base_type: 9,
            timestamp: None,
            data_len: 1,
        };
        let normal = HeaderRepr {
            timestamp: Some(Timestamp::new(1, 2)),
            ..expedited
        };
        for (h, n) in [(expedited, 6), (normal, 22)] {
            let mut short = [0xAA; 22];
            let short = &mut short[..n - 1];
            assert_eq!(
                h.emit(short, Profile::Spec),
                Err(EncodeError::BufferTooSmall { needed: n })
            );
            assert!(short.iter().all(|&b| b == 0xAA));
            let mut exact = [0xAA; 22];
            assert_eq!(h.emit(&mut exact[..n], Profile::Spec), Ok(n));
            let mut long = [0xAA; 25];
            assert_eq!(h.emit(&mut long[..n + 3], Profile::Spec), Ok(n));
            assert_eq!(long[..n], exact[..n]);
            assert_eq!(long[n..n + 3], [0xAA; 3]);
        }
        let mut exact = [0u8; 6];
        expedited.emit(&mut exact, Profile::Spec).unwrap();
        // FF, type 9 with the expedited bit, length 8 (whole message, Spec) little-endian.
        assert_eq!(exact, [0xFF, 0x89, 0x08, 0, 0, 0]);
    }
}
