//! A complete, checked message: header, data and checksum.

use crate::checksum::xor;
use crate::error::{Error, Result};
use crate::header::Header;
use crate::message::Message;
use crate::profile::{Profile, Timestamp};

/// A zero-copy view of one whole message whose length and checksum have been verified.
///
/// Decoders hand these out; [`Frame::new_checked`] builds one from a slice.
///
/// ```
/// use aydp_proto::{Frame, Message, Profile, SystemControl};
/// let f = Frame::new_checked(&[0xFF, 0x89, 0x08, 0, 0, 0, 0x02, 0x7C], Profile::Spec).unwrap();
/// assert_eq!(f.base_type(), 9);
/// assert_eq!(f.data(), &[0x02]);
/// assert_eq!(f.message(), Ok(Message::SystemControl(SystemControl::StoreConfiguration)));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Frame<'a> {
    bytes: &'a [u8],
    profile: Profile,
}

impl<'a> Frame<'a> {
    /// The header's layout: `(field, wire type, offset from the start byte)` per field, for
    /// tools that describe the wire format (the Wireshark dissector `protolink wireshark`
    /// writes). An expedited header ([`EXPEDITED_HEADER_LEN`](crate::profile::EXPEDITED_HEADER_LEN)
    /// bytes) ends before `seconds`; a normal one is
    /// [`NORMAL_HEADER_LEN`](crate::profile::NORMAL_HEADER_LEN) bytes. Little-endian.
    ///
    /// ```
    /// use aydp_proto::Frame;
    /// assert_eq!(Frame::HEADER_FIELDS[2], ("length", "u32", 2));
    /// ```
    pub const HEADER_FIELDS: &'static [(&'static str, &'static str, usize)] =
        crate::layout::header::FIELDS;

    /// Check that `bytes` is exactly one message in `profile`: start byte, type not 0xFF,
    /// length field agreeing with `bytes.len()`, and the XOR checksum.
    ///
    /// ```
    /// use aydp_proto::{Error, Frame, Profile};
    /// let good = [0xFF, 0x89, 0x08, 0, 0, 0, 0x02, 0x7C];
    /// assert!(Frame::new_checked(&good, Profile::Spec).is_ok());
    /// assert_eq!(Frame::new_checked(&good[..7], Profile::Spec), Err(Error::BadLength(8)));
    /// let bad = [0xFF, 0x89, 0x08, 0, 0, 0, 0x02, 0x7D];
    /// let mismatch = Error::ChecksumMismatch { id: 0x89, computed: 0x7C, received: 0x7D };
    /// assert_eq!(Frame::new_checked(&bad, Profile::Spec), Err(mismatch));
    /// // In `Reference` the length field counts data bytes only: 8 is wrong there.
    /// assert_eq!(Frame::new_checked(&good, Profile::Reference), Err(Error::BadLength(8)));
    /// ```
    pub fn new_checked(bytes: &'a [u8], profile: Profile) -> Result<Self> {
        let header = Header::new_checked(bytes)?;
        let field = header.length_field();
        let total = profile
            .frame_len(field, header.is_expedited())
            .ok_or(Error::BadLength(field))?;
        if total != bytes.len() {
            return Err(Error::BadLength(field));
        }
        if xor(bytes) != 0 {
            return Err(Error::mismatch(bytes));
        }
        Ok(Self { bytes, profile })
    }

    /// Wrap bytes the decoder has already checked.
    #[inline]
    pub(crate) const fn new_unchecked(bytes: &'a [u8], profile: Profile) -> Self {
        Self { bytes, profile }
    }

    /// The whole message, start byte to checksum.
    ///
    /// ```
    /// # use aydp_proto::{Frame, Profile};
    /// // Expedited system control (type 9 | 0x80) "store configuration", `Spec`.
    /// let frame = Frame::new_checked(&[0xFF, 0x89, 0x08, 0, 0, 0, 0x02, 0x7C], Profile::Spec).unwrap();
    /// assert_eq!(frame.as_bytes(), &[0xFF, 0x89, 0x08, 0, 0, 0, 0x02, 0x7C]);
    /// ```
    #[inline]
    pub const fn as_bytes(&self) -> &'a [u8] {
        self.bytes
    }

    /// The profile the frame was checked in.
    ///
    /// ```
    /// # use aydp_proto::{Frame, Profile};
    /// // Expedited system control (type 9 | 0x80) "store configuration", `Spec`.
    /// let frame = Frame::new_checked(&[0xFF, 0x89, 0x08, 0, 0, 0, 0x02, 0x7C], Profile::Spec).unwrap();
    /// assert_eq!(frame.profile(), Profile::Spec);
    /// ```
    #[inline]
    pub const fn profile(&self) -> Profile {
        self.profile
    }

    /// The header view.
    #[inline]
    pub(crate) const fn header(&self) -> Header<&'a [u8]> {
        Header::new_unchecked(self.bytes)
    }

    /// The type byte as sent.
    ///
    /// ```
    /// # use aydp_proto::{Frame, Profile};
    /// // Expedited system control (type 9 | 0x80) "store configuration", `Spec`.
    /// let frame = Frame::new_checked(&[0xFF, 0x89, 0x08, 0, 0, 0, 0x02, 0x7C], Profile::Spec).unwrap();
    /// assert_eq!(frame.type_byte(), 0x89);
    /// ```
    #[inline]
    pub fn type_byte(&self) -> u8 {
        self.header().type_byte()
    }

    /// The type without the expedited bit.
    ///
    /// ```
    /// # use aydp_proto::{Frame, Profile};
    /// // Expedited system control (type 9 | 0x80) "store configuration", `Spec`.
    /// let frame = Frame::new_checked(&[0xFF, 0x89, 0x08, 0, 0, 0, 0x02, 0x7C], Profile::Spec).unwrap();
    /// assert_eq!(frame.base_type(), 9);
    /// ```
    #[inline]
    pub fn base_type(&self) -> u8 {
        self.header().base_type()
    }

    /// Whether the message is expedited (6-byte header, no time).
    ///
    /// ```
    /// # use aydp_proto::{Frame, Profile};
    /// // Expedited system control (type 9 | 0x80) "store configuration", `Spec`.
    /// let frame = Frame::new_checked(&[0xFF, 0x89, 0x08, 0, 0, 0, 0x02, 0x7C], Profile::Spec).unwrap();
    /// assert!(frame.is_expedited());
    /// ```
    #[inline]
    pub fn is_expedited(&self) -> bool {
        self.header().is_expedited()
    }

    /// Header time of a normal message.
    ///
    /// ```
    /// use aydp_proto::{Frame, Profile, Timestamp};
    /// // A normal time sync (type 0) at 7 s and 500 ms.
    /// let bytes = [
    ///     0xFF, 0x00, 0x17, 0, 0, 0, 0x07, 0, 0, 0, 0, 0, 0, 0, 0xF4, 0x01, 0, 0, 0, 0, 0, 0, 0x1A,
    /// ];
    /// let frame = Frame::new_checked(&bytes, Profile::Spec).unwrap();
    /// assert_eq!(frame.timestamp(), Some(Timestamp::new(7, 500)));
    /// let expedited = [0xFF, 0x89, 0x08, 0, 0, 0, 0x02, 0x7C];
    /// assert_eq!(Frame::new_checked(&expedited, Profile::Spec).unwrap().timestamp(), None);
    /// ```
    #[inline]
    pub fn timestamp(&self) -> Option<Timestamp> {
        self.header().timestamp()
    }

    /// The data between header and checksum.
    ///
    /// ```
    /// # use aydp_proto::{Frame, Profile};
    /// // Expedited system control (type 9 | 0x80) "store configuration", `Spec`.
    /// let frame = Frame::new_checked(&[0xFF, 0x89, 0x08, 0, 0, 0, 0x02, 0x7C], Profile::Spec).unwrap();
    /// assert_eq!(frame.data(), &[0x02]);
    /// ```
    pub fn data(&self) -> &'a [u8] {
        let start = self.header().header_len();
        let end = self.bytes.len().saturating_sub(1);
        self.bytes.get(start..end).unwrap_or(&[])
    }

    /// The checksum byte.
    ///
    /// ```
    /// # use aydp_proto::{Frame, Profile};
    /// // Expedited system control (type 9 | 0x80) "store configuration", `Spec`.
    /// let frame = Frame::new_checked(&[0xFF, 0x89, 0x08, 0, 0, 0, 0x02, 0x7C], Profile::Spec).unwrap();
    /// assert_eq!(frame.checksum(), 0x7C);
    /// ```
    pub fn checksum(&self) -> u8 {
        self.bytes.last().copied().unwrap_or(0)
    }

    /// Parse the data as a typed message (profile-aware).
    ///
    /// ```
    /// # use aydp_proto::{Frame, Message, Profile, SystemControl};
    /// let frame = Frame::new_checked(&[0xFF, 0x89, 0x08, 0, 0, 0, 0x02, 0x7C], Profile::Spec).unwrap();
    /// assert_eq!(frame.message(), Ok(Message::SystemControl(SystemControl::StoreConfiguration)));
    /// // The same frame with an unknown command byte (3) and its checksum.
    /// let frame = Frame::new_checked(&[0xFF, 0x89, 0x08, 0, 0, 0, 0x03, 0x7D], Profile::Spec).unwrap();
    /// assert_eq!(frame.message(), Err(aydp_proto::Error::UnknownCommand(3)));
    /// ```
    pub fn message(&self) -> Result<Message<'a>> {
        Message::parse(
            self.base_type(),
            self.is_expedited(),
            self.data(),
            self.profile,
        )
    }
}
