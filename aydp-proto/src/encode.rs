//! Encoding: into a caller's buffer, or as a byte iterator that needs no buffer at all.

use crate::checksum::xor;
use crate::error::EncodeError;
use crate::header::HeaderRepr;
use crate::profile::{NORMAL_HEADER_LEN, Profile, Timestamp};

/// Anything that can be sent as the data of an AYDP message.
///
/// Implemented by every typed message, by [`Message`](crate::Message) and by [`Raw`]. Its
/// `emit` and `buffer_len` are the encode vocabulary of every protocol crate here: the data
/// bytes into a caller's buffer, and how many there are. [`Encoder::encode`] frames them as a
/// whole message (header, data, checksum). The fixed-size messages also have `emit` and
/// `buffer_len` of their own, callable without this trait in scope.
///
/// ```
/// use aydp_proto::{Payload, Position, SystemControl};
/// let p = Position { latitude: 50.5, longitude: -1.25, altitude: 12.5 };
/// assert_eq!(p.base_type(), 3);
/// assert_eq!(p.buffer_len(), 20);
/// assert_eq!(p.data_byte(19), 0x41);
/// let request = SystemControl::RequestData { address: 8 };
/// let mut data = [0u8; 3];
/// assert_eq!(Payload::emit(&request, &mut data), Ok(3));
/// assert_eq!(data, [1, 8, 0]);
/// ```
pub trait Payload {
    /// Base type, 0..=126.
    fn base_type(&self) -> u8;
    /// Number of data bytes: what [`Payload::emit`] writes.
    fn buffer_len(&self) -> usize;
    /// Data byte at `index` (0 beyond the end). Used by the buffer-free iterator.
    fn data_byte(&self, index: usize) -> u8;
    /// Write the data into `out`, which is exactly [`Payload::buffer_len`] bytes long.
    fn write_data(&self, out: &mut [u8]) {
        for (i, b) in out.iter_mut().enumerate() {
            *b = self.data_byte(i);
        }
    }
    /// Write the data (no header, no checksum) into `out`; returns [`Payload::buffer_len`].
    ///
    /// ```
    /// use aydp_proto::{EncodeError, Payload, Raw};
    /// let raw = Raw { msg_type: 100, data: &[1, 2, 3] };
    /// let mut out = [0u8; 3];
    /// assert_eq!(raw.emit(&mut out), Ok(3));
    /// assert_eq!(out, [1, 2, 3]);
    /// assert_eq!(raw.emit(&mut out[..2]), Err(EncodeError::BufferTooSmall { needed: 3 }));
    /// ```
    ///
    /// # Errors
    /// [`EncodeError::BufferTooSmall`] if `out` is shorter than [`Payload::buffer_len`]; `out`
    /// is then untouched.
    fn emit(&self, out: &mut [u8]) -> Result<usize, EncodeError> {
        let needed = self.buffer_len();
        let dst = out
            .get_mut(..needed)
            .ok_or(EncodeError::BufferTooSmall { needed })?;
        self.write_data(dst);
        Ok(needed)
    }
}

/// A message given as a type and its raw data bytes.
///
/// ```
/// use aydp_proto::{Encoder, Profile, Raw};
/// let mut buf = [0u8; 16];
/// let n = Encoder::new(Profile::Spec).encode(&Raw { msg_type: 9, data: &[2] }, None, &mut buf).unwrap();
/// assert_eq!(&buf[..n], &[0xFF, 0x89, 0x08, 0, 0, 0, 0x02, 0x7C]);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Raw<'a> {
    /// Base type, 0..=126.
    pub msg_type: u8,
    /// Data bytes.
    pub data: &'a [u8],
}

impl Payload for Raw<'_> {
    fn base_type(&self) -> u8 {
        self.msg_type
    }
    fn buffer_len(&self) -> usize {
        self.data.len()
    }
    fn data_byte(&self, index: usize) -> u8 {
        self.data.get(index).copied().unwrap_or(0)
    }
    fn write_data(&self, out: &mut [u8]) {
        for (d, s) in out.iter_mut().zip(self.data) {
            *d = *s;
        }
    }
}

/// Builds messages in one profile.
///
/// ```
/// use aydp_proto::{Encoder, Profile, Timestamp, WindSpeed};
/// let enc = Encoder::new(Profile::Reference);
/// let mut buf = [0u8; 64];
/// let n = enc.encode(&WindSpeed(3.5), Some(Timestamp::new(42, 500_000)), &mut buf).unwrap();
/// assert_eq!(n, 27);
/// // The same message without any buffer:
/// let it = enc.iter(&WindSpeed(3.5), Some(Timestamp::new(42, 500_000))).unwrap();
/// assert!(it.eq(buf[..n].iter().copied()));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Encoder {
    profile: Profile,
}

impl Encoder {
    /// An encoder for `profile`.
    ///
    /// ```
    /// use aydp_proto::{Encoder, Profile};
    /// assert_eq!(Encoder::new(Profile::Reference).profile(), Profile::Reference);
    /// ```
    pub const fn new(profile: Profile) -> Self {
        Self { profile }
    }

    /// The profile this encoder follows.
    ///
    /// ```
    /// use aydp_proto::{Encoder, Profile};
    /// assert_eq!(Encoder::default().profile(), Profile::Spec);
    /// ```
    pub const fn profile(&self) -> Profile {
        self.profile
    }

    /// Whole message length for `payload`, normal or expedited.
    ///
    /// ```
    /// use aydp_proto::{Encoder, Profile, Raw};
    /// let two = Raw { msg_type: 9, data: &[1, 2] };
    /// // 6-byte header or 22-byte header, the data, the checksum.
    /// assert_eq!(Encoder::new(Profile::Spec).frame_len(&two, true), 9);
    /// assert_eq!(Encoder::new(Profile::Spec).frame_len(&two, false), 25);
    /// ```
    pub fn frame_len<P: Payload + ?Sized>(&self, payload: &P, expedited: bool) -> usize {
        payload
            .buffer_len()
            .saturating_add(Profile::overhead(expedited))
    }

    /// Encode the whole message (header, data, checksum) into `buf`; returns its length,
    /// [`Encoder::frame_len`]. The header is chosen by `timestamp`: a normal message (22-byte
    /// header) with `Some(timestamp)`, an expedited one (6-byte header, type | 0x80) with
    /// `None`. The one AYDP framing encoder: the payload's own bytes are its
    /// [`Payload::emit`].
    ///
    /// # Errors
    /// [`EncodeError::ExpeditedInReference`] for `None` in the `Reference` profile (checked
    /// first), [`EncodeError::BufferTooSmall`], [`EncodeError::BadType`] and [`EncodeError::TooLong`].
    ///
    /// ```
    /// use aydp_proto::{EncodeError, Encoder, Profile, Raw, Timestamp};
    /// let enc = Encoder::new(Profile::Spec);
    /// let mut buf = [0u8; 32];
    /// // Normal: the start byte, the type without the 0x80 bit, ...
    /// let n = enc.encode(&Raw { msg_type: 9, data: &[2] }, Some(Timestamp::new(1, 0)), &mut buf);
    /// assert_eq!(n, Ok(24));
    /// assert_eq!(&buf[..2], &[0xFF, 0x09]);
    /// // Expedited: type 9 with the expedited bit.
    /// let mut buf = [0u8; 8];
    /// assert_eq!(enc.encode(&Raw { msg_type: 9, data: &[2] }, None, &mut buf), Ok(8));
    /// assert_eq!(buf, [0xFF, 0x89, 0x08, 0, 0, 0, 0x02, 0x7C]);
    /// assert_eq!(
    ///     Encoder::new(Profile::Reference).encode(&Raw { msg_type: 9, data: &[2] }, None, &mut buf),
    ///     Err(EncodeError::ExpeditedInReference)
    /// );
    /// assert_eq!(
    ///     enc.encode(&Raw { msg_type: 9, data: &[2, 3] }, None, &mut buf),
    ///     Err(EncodeError::BufferTooSmall { needed: 9 })
    /// );
    /// assert_eq!(
    ///     enc.encode(&Raw { msg_type: 127, data: &[] }, None, &mut buf),
    ///     Err(EncodeError::BadType(127))
    /// );
    /// ```
    pub fn encode<P: Payload + ?Sized>(
        &self,
        payload: &P,
        timestamp: Option<Timestamp>,
        buf: &mut [u8],
    ) -> Result<usize, EncodeError> {
        if timestamp.is_none() && !self.profile.has_expedited() {
            return Err(EncodeError::ExpeditedInReference);
        }
        let repr = HeaderRepr {
            base_type: payload.base_type(),
            timestamp,
            data_len: payload.buffer_len(),
        };
        let total = repr.frame_len();
        let Some(frame) = buf.get_mut(..total) else {
            return Err(EncodeError::BufferTooSmall { needed: total });
        };
        let hlen = repr.emit(frame, self.profile)?;
        let Some((last, body)) = frame.split_last_mut() else {
            return Err(EncodeError::BufferTooSmall { needed: total });
        };
        if let Some(data) = body.get_mut(hlen..) {
            payload.write_data(data);
        }
        *last = xor(body);
        Ok(total)
    }

    /// The message as a byte iterator: normal with `Some(timestamp)`, expedited with `None`.
    ///
    /// # Errors
    /// [`EncodeError::ExpeditedInReference`] for `None` in the `Reference` profile,
    /// [`EncodeError::BadType`] and [`EncodeError::TooLong`].
    ///
    /// ```
    /// use aydp_proto::{EncodeError, Encoder, Profile, Raw, Timestamp};
    /// let raw = Raw { msg_type: 9, data: &[2] };
    /// let spec = Encoder::new(Profile::Spec);
    /// let bytes: Vec<u8> = spec.iter(&raw, None).unwrap().collect();
    /// assert_eq!(bytes, [0xFF, 0x89, 0x08, 0, 0, 0, 0x02, 0x7C]);
    /// assert_eq!(spec.iter(&raw, Some(Timestamp::new(1, 0))).unwrap().len(), 24);
    /// let enc = Encoder::new(Profile::Reference);
    /// assert!(enc.iter(&raw, None).is_err()); // no expedited form
    /// assert_eq!(
    ///     enc.iter(&Raw { msg_type: 200, data: &[] }, None).err(),
    ///     Some(EncodeError::ExpeditedInReference)
    /// );
    /// ```
    pub fn iter<'p, P: Payload + ?Sized>(
        &self,
        payload: &'p P,
        timestamp: Option<Timestamp>,
    ) -> Result<Bytes<'p, P>, EncodeError> {
        let repr = HeaderRepr {
            base_type: payload.base_type(),
            timestamp,
            data_len: payload.buffer_len(),
        };
        let header = repr.bytes(self.profile)?;
        Ok(Bytes {
            payload,
            header,
            header_len: repr.buffer_len(),
            total: repr.frame_len(),
            pos: 0,
            xor: 0,
        })
    }
}

/// Iterator over the bytes of one message, computing the checksum on the fly.
///
/// Made by [`Encoder::iter`]; it holds the 22 header bytes and a reference to the payload.
///
/// ```
/// use aydp_proto::{Encoder, Profile, Raw};
/// let raw = Raw { msg_type: 9, data: &[2] };
/// let mut it = Encoder::new(Profile::Spec).iter(&raw, None).unwrap();
/// assert_eq!(it.len(), 8);
/// assert_eq!(it.next(), Some(0xFF));
/// assert_eq!(it.last(), Some(0x7C)); // the XOR checksum, computed on the way
/// ```
#[derive(Debug, Clone)]
pub struct Bytes<'p, P: ?Sized> {
    payload: &'p P,
    header: [u8; NORMAL_HEADER_LEN],
    header_len: usize,
    total: usize,
    pos: usize,
    xor: u8,
}

impl<P: Payload + ?Sized> Iterator for Bytes<'_, P> {
    type Item = u8;

    #[inline]
    fn next(&mut self) -> Option<u8> {
        let pos = self.pos;
        let last = self.total.wrapping_sub(1);
        let b = if pos < self.header_len {
            self.header.get(pos).copied().unwrap_or(0)
        } else if pos < last {
            self.payload.data_byte(pos.wrapping_sub(self.header_len))
        } else if pos == last {
            self.pos = pos.wrapping_add(1);
            return Some(self.xor);
        } else {
            return None;
        };
        self.xor ^= b;
        self.pos = pos.wrapping_add(1);
        Some(b)
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        let left = self.total.saturating_sub(self.pos);
        (left, Some(left))
    }
}

impl<P: Payload + ?Sized> ExactSizeIterator for Bytes<'_, P> {}
impl<P: Payload + ?Sized> core::iter::FusedIterator for Bytes<'_, P> {}
