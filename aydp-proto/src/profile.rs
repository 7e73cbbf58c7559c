//! The two conventions AYDP is found in (DECISIONS.md Y1, Y2) and the header timestamp.

/// Start byte of every message.
pub const START: u8 = 0xFF;
/// Bit set in the type byte of an expedited message (no time fields).
pub const EXPEDITED: u8 = 0x80;
/// Length of a normal header: start, type, u32 length, i64 seconds, i64 sub-seconds (Y3).
pub const NORMAL_HEADER_LEN: usize = crate::layout::header::NORMAL_LEN;
/// Length of an expedited header: start, type, u32 length (Y3).
pub const EXPEDITED_HEADER_LEN: usize = crate::layout::header::EXPEDITED_LEN;
/// Highest base type (Y3).
pub(crate) const MAX_BASE_TYPE: u8 = 126;

/// Which AYDP convention an encoder or decoder follows.
///
/// ```
/// use aydp_proto::Profile;
/// // Spec: the length counts the whole message. A heartbeat is 7 bytes.
/// assert_eq!(Profile::Spec.length_field(0, true), Some(7));
/// // Reference: the length counts data bytes only.
/// assert_eq!(Profile::Reference.length_field(4, false), Some(4));
/// assert_eq!(Profile::Reference.frame_len(4, false), Some(27));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Profile {
    /// The 2016 document (Y1): the length counts the whole message, sub-seconds are milliseconds.
    #[default]
    Spec,
    /// The released AYDP software (Y2): the length counts data bytes only, sub-seconds are
    /// microseconds, and wind speed (1), wind direction (2) and vessel data (17) are typed.
    Reference,
}

impl Profile {
    /// Header length for a normal (`expedited == false`) or expedited message.
    ///
    /// ```
    /// use aydp_proto::Profile;
    /// assert_eq!(Profile::header_len(false), 22);
    /// assert_eq!(Profile::header_len(true), 6);
    /// ```
    #[inline]
    pub const fn header_len(expedited: bool) -> usize {
        if expedited {
            EXPEDITED_HEADER_LEN
        } else {
            NORMAL_HEADER_LEN
        }
    }

    /// Bytes a message adds around its data: header plus checksum byte.
    ///
    /// ```
    /// use aydp_proto::Profile;
    /// assert_eq!(Profile::overhead(false), 23);
    /// assert_eq!(Profile::overhead(true), 7);
    /// ```
    #[inline]
    pub const fn overhead(expedited: bool) -> usize {
        Self::header_len(expedited) + 1
    }

    /// The length field for `data_len` data bytes, or `None` if it does not fit in a u32.
    ///
    /// ```
    /// use aydp_proto::Profile;
    /// // A position report: 20 data bytes.
    /// assert_eq!(Profile::Spec.length_field(20, false), Some(43));
    /// assert_eq!(Profile::Reference.length_field(20, false), Some(20));
    /// assert_eq!(Profile::Spec.length_field(usize::MAX, false), None);
    /// ```
    #[inline]
    pub const fn length_field(self, data_len: usize, expedited: bool) -> Option<u32> {
        let n = match self {
            Profile::Spec => match data_len.checked_add(Self::overhead(expedited)) {
                Some(n) => n,
                None => return None,
            },
            Profile::Reference => data_len,
        };
        if n > u32::MAX as usize {
            None
        } else {
            Some(n as u32)
        }
    }

    /// Whole message length (start to checksum) announced by a length field, or `None` if the
    /// field is below this profile's minimum or the sum overflows `usize`.
    ///
    /// ```
    /// use aydp_proto::Profile;
    /// assert_eq!(Profile::Spec.frame_len(43, false), Some(43));
    /// assert_eq!(Profile::Reference.frame_len(20, false), Some(43));
    /// // Below `Spec`'s minimum for an expedited message (7: header and checksum).
    /// assert_eq!(Profile::Spec.frame_len(6, true), None);
    /// ```
    #[inline]
    pub const fn frame_len(self, length_field: u32, expedited: bool) -> Option<usize> {
        let field = length_field as usize;
        // u32 -> usize never truncates on the 32- and 64-bit targets this crate supports;
        // guard anyway so a 16-bit target cannot alias.
        if field as u32 != length_field {
            return None;
        }
        match self {
            Profile::Spec => {
                if field < Self::overhead(expedited) {
                    None
                } else {
                    Some(field)
                }
            }
            Profile::Reference => field.checked_add(Self::overhead(expedited)),
        }
    }

    /// Whether this profile has the expedited header (type | 0x80, no time fields). `Spec`
    /// does; `Reference` does not: the AYDP reference software never sends one, and a model of
    /// its receiver loses the frame that follows one. An encoder in `Reference` refuses an
    /// expedited message with [`EncodeError::ExpeditedInReference`](crate::EncodeError::ExpeditedInReference);
    /// decoders in either profile still read one.
    ///
    /// ```
    /// use aydp_proto::{EncodeError, Encoder, Profile, Raw};
    /// assert!(Profile::Spec.has_expedited());
    /// assert!(!Profile::Reference.has_expedited());
    /// let mut buf = [0u8; 16];
    /// let no_op = Raw { msg_type: 0, data: &[] };
    /// assert_eq!(
    ///     Encoder::new(Profile::Reference).encode(&no_op, None, &mut buf),
    ///     Err(EncodeError::ExpeditedInReference)
    /// );
    /// ```
    #[inline]
    pub const fn has_expedited(self) -> bool {
        matches!(self, Profile::Spec)
    }

    /// Sub-second units per second in the header: 1000 (ms) for `Spec`, 1 000 000 (µs) for
    /// `Reference`.
    ///
    /// ```
    /// use aydp_proto::Profile;
    /// assert_eq!(Profile::Spec.subsec_per_second(), 1_000);
    /// assert_eq!(Profile::Reference.subsec_per_second(), 1_000_000);
    /// ```
    #[inline]
    pub const fn subsec_per_second(self) -> i64 {
        match self {
            Profile::Spec => 1_000,
            Profile::Reference => 1_000_000,
        }
    }
}

/// Header time of a normal message: seconds from the epoch plus a sub-second count whose unit
/// is the profile's ([`Profile::subsec_per_second`]).
///
/// ```
/// use aydp_proto::{Profile, Timestamp};
/// let t = Timestamp::new(42, 500);
/// assert_eq!(t.subsec_micros(Profile::Spec), 500_000);
/// assert_eq!(Timestamp::from_micros(42, 500_000, Profile::Reference).subsec, 500_000);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Timestamp {
    /// Seconds from the epoch.
    pub seconds: i64,
    /// Sub-seconds, in milliseconds (`Spec`) or microseconds (`Reference`).
    pub subsec: i64,
}

impl Timestamp {
    /// A timestamp from raw header fields.
    ///
    /// ```
    /// use aydp_proto::Timestamp;
    /// let t = Timestamp::new(1_700_000_000, 250);
    /// assert_eq!((t.seconds, t.subsec), (1_700_000_000, 250));
    /// ```
    pub const fn new(seconds: i64, subsec: i64) -> Self {
        Self { seconds, subsec }
    }

    /// A timestamp from seconds and microseconds, converted to the profile's sub-second unit
    /// (truncating to milliseconds for `Spec`).
    ///
    /// ```
    /// use aydp_proto::{Profile, Timestamp};
    /// assert_eq!(Timestamp::from_micros(42, 1_999, Profile::Spec), Timestamp::new(42, 1));
    /// assert_eq!(Timestamp::from_micros(42, 1_999, Profile::Reference), Timestamp::new(42, 1_999));
    /// ```
    pub const fn from_micros(seconds: i64, micros: i64, profile: Profile) -> Self {
        let subsec = match profile {
            Profile::Spec => micros / 1000,
            Profile::Reference => micros,
        };
        Self { seconds, subsec }
    }

    /// The sub-second field in microseconds, read in the given profile (saturating).
    ///
    /// ```
    /// use aydp_proto::{Profile, Timestamp};
    /// let t = Timestamp::new(42, 250);
    /// assert_eq!(t.subsec_micros(Profile::Spec), 250_000);
    /// assert_eq!(t.subsec_micros(Profile::Reference), 250);
    /// assert_eq!(Timestamp::new(0, i64::MAX).subsec_micros(Profile::Spec), i64::MAX);
    /// ```
    pub const fn subsec_micros(&self, profile: Profile) -> i64 {
        match profile {
            Profile::Spec => self.subsec.saturating_mul(1000),
            Profile::Reference => self.subsec,
        }
    }
}
