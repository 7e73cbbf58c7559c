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
    #[inline]
    pub const fn as_bytes(&self) -> &'a [u8] {
        self.bytes
    }

    /// The profile the frame was checked in.
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
    #[inline]
    pub fn type_byte(&self) -> u8 {
        self.header().type_byte()
    }

    /// The type without the expedited bit.
    #[inline]
    pub fn base_type(&self) -> u8 {
        self.header().base_type()
    }

    /// Whether the message is expedited (6-byte header, no time).
    #[inline]
    pub fn is_expedited(&self) -> bool {
        self.header().is_expedited()
    }

    /// Header time of a normal message.
    #[inline]
    pub fn timestamp(&self) -> Option<Timestamp> {
        self.header().timestamp()
    }

    /// The data between header and checksum.
    pub fn data(&self) -> &'a [u8] {
        let start = self.header().header_len();
        let end = self.bytes.len().saturating_sub(1);
        self.bytes.get(start..end).unwrap_or(&[])
    }

    /// The checksum byte.
    pub fn checksum(&self) -> u8 {
        self.bytes.last().copied().unwrap_or(0)
    }

    /// Parse the data as a typed message (profile-aware).
    pub fn message(&self) -> Result<Message<'a>> {
        Message::parse(
            self.base_type(),
            self.is_expedited(),
            self.data(),
            self.profile,
        )
    }
}
