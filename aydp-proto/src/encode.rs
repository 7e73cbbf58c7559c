//! Encoding: into a caller's buffer, or as a byte iterator that needs no buffer at all.

use crate::checksum::xor;
use crate::error::EncodeError;
use crate::header::HeaderRepr;
use crate::profile::{NORMAL_HEADER_LEN, Profile, Timestamp};

/// Anything that can be sent as the data of an AYDP message.
///
/// Implemented by every typed message, by [`Message`](crate::Message) and by [`Raw`].
///
/// ```
/// use aydp_proto::{Payload, Position};
/// let p = Position { latitude: 50.5, longitude: -1.25, altitude: 12.5 };
/// assert_eq!(p.base_type(), 3);
/// assert_eq!(p.data_len(), 20);
/// assert_eq!(p.data_byte(19), 0x41);
/// ```
pub trait Payload {
    /// Base type, 0..=126.
    fn base_type(&self) -> u8;
    /// Number of data bytes.
    fn data_len(&self) -> usize;
    /// Data byte at `index` (0 beyond the end). Used by the buffer-free iterator.
    fn data_byte(&self, index: usize) -> u8;
    /// Write the data into `out`, which is exactly [`Payload::data_len`] bytes long.
    fn write_data(&self, out: &mut [u8]) {
        for (i, b) in out.iter_mut().enumerate() {
            *b = self.data_byte(i);
        }
    }
}

/// A message given as a type and its raw data bytes.
///
/// ```
/// use aydp_proto::{Encoder, Profile, Raw};
/// let mut buf = [0u8; 16];
/// let n = Encoder::new(Profile::Spec).encode_expedited(&Raw { msg_type: 9, data: &[2] }, &mut buf).unwrap();
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
    fn data_len(&self) -> usize {
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
/// let n = enc.encode_normal(&WindSpeed(3.5), Timestamp::new(42, 500_000), &mut buf).unwrap();
/// assert_eq!(n, 27);
/// // The same message without any buffer:
/// let it = enc.iter_normal(&WindSpeed(3.5), Timestamp::new(42, 500_000)).unwrap();
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
            .data_len()
            .saturating_add(Profile::overhead(expedited))
    }

    /// Encode a normal message (22-byte header with `timestamp`) into `buf`; returns its length.
    ///
    /// # Errors
    /// As [`Encoder::encode`].
    ///
    /// ```
    /// use aydp_proto::{Encoder, Profile, Raw, Timestamp};
    /// let mut buf = [0u8; 32];
    /// let n = Encoder::new(Profile::Spec)
    ///     .encode_normal(&Raw { msg_type: 9, data: &[2] }, Timestamp::new(1, 0), &mut buf)
    ///     .unwrap();
    /// assert_eq!(n, 24);
    /// assert_eq!(&buf[..2], &[0xFF, 0x09]); // the start byte, the type without the 0x80 bit
    /// ```
    pub fn encode_normal<P: Payload + ?Sized>(
        &self,
        payload: &P,
        timestamp: Timestamp,
        buf: &mut [u8],
    ) -> Result<usize, EncodeError> {
        self.encode(payload, Some(timestamp), buf)
    }

    /// Encode an expedited message (6-byte header, type | 0x80) into `buf`; returns its length.
    ///
    /// # Errors
    /// [`EncodeError::ExpeditedInReference`] in the `Reference` profile, which has no expedited
    /// header; otherwise as [`Encoder::encode`].
    ///
    /// ```
    /// use aydp_proto::{EncodeError, Encoder, Profile, Raw};
    /// let mut buf = [0u8; 16];
    /// let raw = Raw { msg_type: 9, data: &[2] };
    /// assert_eq!(Encoder::new(Profile::Spec).encode_expedited(&raw, &mut buf), Ok(8));
    /// assert_eq!(buf[1], 0x89); // type 9 with the expedited bit
    /// assert_eq!(
    ///     Encoder::new(Profile::Reference).encode_expedited(&raw, &mut buf),
    ///     Err(EncodeError::ExpeditedInReference)
    /// );
    /// ```
    pub fn encode_expedited<P: Payload + ?Sized>(
        &self,
        payload: &P,
        buf: &mut [u8],
    ) -> Result<usize, EncodeError> {
        self.encode(payload, None, buf)
    }

    /// Encode into `buf`: normal with `Some(timestamp)`, expedited with `None`.
    ///
    /// # Errors
    /// [`EncodeError::ExpeditedInReference`] for `None` in the `Reference` profile (checked
    /// first), [`EncodeError::BufferTooSmall`], [`EncodeError::BadType`] and [`EncodeError::TooLong`].
    ///
    /// ```
    /// use aydp_proto::{EncodeError, Encoder, Profile, Raw};
    /// let enc = Encoder::new(Profile::Spec);
    /// let mut buf = [0u8; 8];
    /// assert_eq!(enc.encode(&Raw { msg_type: 9, data: &[2] }, None, &mut buf), Ok(8));
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
            data_len: payload.data_len(),
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

    /// The message as a byte iterator, normal, without any output buffer.
    ///
    /// # Errors
    /// As [`Encoder::iter`].
    ///
    /// ```
    /// use aydp_proto::{Encoder, Profile, Raw, Timestamp};
    /// let raw = Raw { msg_type: 9, data: &[2] };
    /// let it = Encoder::new(Profile::Spec).iter_normal(&raw, Timestamp::new(1, 0)).unwrap();
    /// assert_eq!(it.len(), 24);
    /// ```
    pub fn iter_normal<'p, P: Payload + ?Sized>(
        &self,
        payload: &'p P,
        timestamp: Timestamp,
    ) -> Result<Bytes<'p, P>, EncodeError> {
        self.iter(payload, Some(timestamp))
    }

    /// The message as a byte iterator, expedited, without any output buffer.
    ///
    /// # Errors
    /// [`EncodeError::ExpeditedInReference`] in the `Reference` profile; otherwise as
    /// [`Encoder::iter`].
    ///
    /// ```
    /// use aydp_proto::{Encoder, Profile, Raw};
    /// let raw = Raw { msg_type: 9, data: &[2] };
    /// let bytes: Vec<u8> = Encoder::new(Profile::Spec).iter_expedited(&raw).unwrap().collect();
    /// assert_eq!(bytes, [0xFF, 0x89, 0x08, 0, 0, 0, 0x02, 0x7C]);
    /// ```
    pub fn iter_expedited<'p, P: Payload + ?Sized>(
        &self,
        payload: &'p P,
    ) -> Result<Bytes<'p, P>, EncodeError> {
        self.iter(payload, None)
    }

    /// The message as a byte iterator: normal with `Some(timestamp)`, expedited with `None`.
    ///
    /// # Errors
    /// [`EncodeError::ExpeditedInReference`] for `None` in the `Reference` profile,
    /// [`EncodeError::BadType`] and [`EncodeError::TooLong`].
    ///
    /// ```
    /// use aydp_proto::{EncodeError, Encoder, Profile, Raw};
    /// let enc = Encoder::new(Profile::Reference);
    /// assert!(enc.iter(&Raw { msg_type: 9, data: &[2] }, None).is_err()); // no expedited form
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
            data_len: payload.data_len(),
        };
        let header = repr.to_bytes(self.profile)?;
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
/// let mut it = Encoder::new(Profile::Spec).iter_expedited(&raw).unwrap();
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
