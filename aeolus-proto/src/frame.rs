//! A checked, zero-copy view of one unescaped frame.

use crate::{Error, crc, message::Message};

/// One received frame: the message ID, the data and the CRC, unescaped, flags removed.
///
/// A `Frame` only exists once its CRC checked out (or, outside strict mode, once it was found
/// to carry no CRC, section 4.1). It borrows the decoder's buffer.
///
/// ```
/// use aeolus_proto::Frame;
/// // ID 82 (TOAST), "hi\0", CRC 0xEC73 sent LSB first.
/// let frame = Frame::new_checked(&[0x52, b'h', b'i', 0, 0x73, 0xEC], true).unwrap();
/// assert_eq!(frame.id(), 82);
/// assert_eq!(frame.data(), b"hi\0");
/// assert!(frame.has_crc());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Frame<'a> {
    raw: &'a [u8],
    has_crc: bool,
}

impl<'a> Frame<'a> {
    /// Checks the unescaped bytes between two flags (ID, data, CRC) and wraps them: the
    /// checked constructor, named as in every protocol crate (`aydp_proto::Frame::new_checked`).
    ///
    /// A received CRC of `00 00` means "no CRC" (DECISIONS.md A3): the frame is accepted
    /// unchecked, unless `strict` is set. A frame whose real CRC happens to be `0x0000` is
    /// recognised as checked in both modes.
    ///
    /// ```
    /// use aeolus_proto::{Error, Frame};
    /// // TOAST "hi": ID 82, the data, the CRC 0xEC73 LSB first.
    /// assert!(Frame::new_checked(&[0x52, b'h', b'i', 0, 0x73, 0xEC], true).is_ok());
    /// let bad = Frame::new_checked(&[0x52, b'h', b'i', 0, 0x74, 0xEC], true);
    /// assert_eq!(bad, Err(Error::ChecksumMismatch { id: 82, computed: 0xEC73, received: 0xEC74 }));
    /// let no_crc = [0x52, b'h', b'i', 0, 0, 0];
    /// assert_eq!(Frame::new_checked(&no_crc, true), Err(Error::MissingCrc { id: 82 }));
    /// assert!(!Frame::new_checked(&no_crc, false).unwrap().has_crc());
    /// assert_eq!(Frame::new_checked(&[0x52, 0], false), Err(Error::TooShort));
    /// ```
    ///
    /// # Errors
    /// [`Error::TooShort`], [`Error::ChecksumMismatch`], or [`Error::MissingCrc`] in strict mode.
    pub const fn new_checked(raw: &'a [u8], strict: bool) -> Result<Self, Error> {
        Self::checked_running(raw, strict, crc::checksum(raw))
    }

    /// [`Frame::new_checked`], given the CRC run over all of `raw` (its two CRC bytes included), as
    /// a decoder keeps it while it stores the bytes: the frame is good when that comes to
    /// [`crc::residue`] of the received CRC. The body's own CRC is only computed again for
    /// the error it reports.
    pub(crate) const fn checked_running(
        raw: &'a [u8],
        strict: bool,
        all: u16,
    ) -> Result<Self, Error> {
        let [body @ .., lo, hi] = raw else {
            return Err(Error::TooShort);
        };
        let [id, ..] = body else {
            return Err(Error::TooShort);
        };
        let received = u16::from_le_bytes([*lo, *hi]);
        if all == crc::residue(received) {
            Ok(Frame { raw, has_crc: true })
        } else if received != 0 {
            Err(Error::ChecksumMismatch {
                id: *id,
                computed: crc::checksum(body),
                received,
            })
        } else if strict {
            Err(Error::MissingCrc { id: *id })
        } else {
            Ok(Frame {
                raw,
                has_crc: false,
            })
        }
    }

    /// Wraps bytes the decoder has already checked, without checking them again.
    pub(crate) const fn checked(raw: &'a [u8], has_crc: bool) -> Self {
        Frame { raw, has_crc }
    }

    /// The message ID.
    ///
    /// ```
    /// # use aeolus_proto::Frame;
    /// let frame = Frame::new_checked(&[0x52, b'h', b'i', 0, 0x73, 0xEC], true).unwrap();
    /// assert_eq!(frame.id(), 82);
    /// ```
    pub const fn id(&self) -> u8 {
        match self.raw {
            [id, ..] => *id,
            [] => 0,
        }
    }

    /// The message data (between the ID and the CRC).
    ///
    /// ```
    /// # use aeolus_proto::Frame;
    /// let frame = Frame::new_checked(&[0x52, b'h', b'i', 0, 0x73, 0xEC], true).unwrap();
    /// assert_eq!(frame.data(), b"hi\0");
    /// ```
    pub const fn data(&self) -> &'a [u8] {
        match self.raw {
            [_, data @ .., _, _] => data,
            _ => &[],
        }
    }

    /// The CRC as received (`0` for a frame sent without CRC).
    ///
    /// ```
    /// # use aeolus_proto::Frame;
    /// let frame = Frame::new_checked(&[0x52, b'h', b'i', 0, 0x73, 0xEC], true).unwrap();
    /// assert_eq!(frame.crc(), 0xEC73);
    /// ```
    pub const fn crc(&self) -> u16 {
        match self.raw {
            [.., lo, hi] => u16::from_le_bytes([*lo, *hi]),
            _ => 0,
        }
    }

    /// Whether the frame carried a CRC that was checked (`false`: sent as `00 00`, unchecked).
    ///
    /// ```
    /// # use aeolus_proto::Frame;
    /// assert!(Frame::new_checked(&[0x52, b'h', b'i', 0, 0x73, 0xEC], false).unwrap().has_crc());
    /// assert!(!Frame::new_checked(&[0x52, b'h', b'i', 0, 0, 0], false).unwrap().has_crc());
    /// ```
    pub const fn has_crc(&self) -> bool {
        self.has_crc
    }

    /// The whole unescaped frame: ID, data and CRC. Kept for callers that want the bytes even
    /// when the typed parse fails.
    ///
    /// ```
    /// # use aeolus_proto::Frame;
    /// let frame = Frame::new_checked(&[0x52, b'h', b'i', 0, 0x73, 0xEC], true).unwrap();
    /// assert_eq!(frame.raw(), &[0x52, b'h', b'i', 0, 0x73, 0xEC]);
    /// ```
    pub const fn raw(&self) -> &'a [u8] {
        self.raw
    }

    /// Parses the data into a typed [`Message`].
    ///
    /// ```
    /// use aeolus_proto::{Frame, message::Message};
    /// let frame = Frame::new_checked(&[0x52, b'h', b'i', 0, 0x73, 0xEC], true).unwrap();
    /// let Message::Toast(text) = frame.message().unwrap() else { panic!() };
    /// assert_eq!(text.as_str(), Some("hi"));
    /// ```
    ///
    /// # Errors
    /// [`Error::WrongLength`] for a known fixed-size ID with the wrong data length, and
    /// [`Error::TextTooLong`]; the frame itself stays available.
    pub fn message(&self) -> Result<Message<'a>, Error> {
        Message::parse(self.id(), self.data())
    }
}
