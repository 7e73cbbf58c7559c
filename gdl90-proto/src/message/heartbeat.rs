//! Heartbeat, ID 0 (ICD 3.1).

use super::layout::heartbeat as f;
use super::{check_len, emit_into};
use crate::{EncodeError, Error};

/// Heartbeat (ID 0): the unit's status, the UTC time stamp and last second's receive counts.
///
/// ```
/// use gdl90_proto::message::Heartbeat;
/// // The ICD's example (section 2.2.4): 7E 00 81 41 DB D0 08 02 B3 8B 7E.
/// let hb = Heartbeat::parse(&[0x81, 0x41, 0xDB, 0xD0, 0x08, 0x02]).unwrap();
/// assert!(hb.gps_position_valid && hb.uat_initialized && hb.utc_ok);
/// assert_eq!(hb.seconds_since_midnight, 0xD0DB); // 14:51:07Z
/// assert_eq!((hb.uplink_messages, hb.basic_long_messages), (1, 2));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Heartbeat {
    /// Status 1 bit 7: the GPS position is valid (available for ADS-B transmission).
    pub gps_position_valid: bool,
    /// Status 1 bit 6: the unit needs maintenance.
    pub maintenance_required: bool,
    /// Status 1 bit 5: IDENT talkback.
    pub ident: bool,
    /// Status 1 bit 4: address type talkback.
    pub address_talkback: bool,
    /// Status 1 bit 3: GPS battery low.
    pub gps_battery_low: bool,
    /// Status 1 bit 2: ATC services talkback (RATCS).
    pub atc_services: bool,
    /// Status 1 bit 0: the unit is initialised.
    pub uat_initialized: bool,
    /// Status 2 bit 6: CSA requested.
    pub csa_requested: bool,
    /// Status 2 bit 5: CSA not available.
    pub csa_not_available: bool,
    /// Status 2 bit 0: UTC timing is valid (the time stamp can be trusted).
    pub utc_ok: bool,
    /// Seconds since 0000Z, 17 bits (0..=131071; a day has 86400). Encoding clamps.
    pub seconds_since_midnight: u32,
    /// Uplink messages received in the last second (5 bits, 0..=31). Encoding clamps.
    pub uplink_messages: u8,
    /// Basic and long messages received in the last second (10 bits, 0..=1023). Encoding
    /// clamps.
    pub basic_long_messages: u16,
}

impl Heartbeat {
    /// The message ID.
    pub const ID: u8 = 0;
    /// The data length in bytes (after the ID, before the CRC).
    pub const LEN: usize = f::LEN;
    /// The largest time stamp (17 bits).
    pub const MAX_SECONDS: u32 = 0x1_FFFF;

    /// Parses the data bytes. Reserved bits are ignored.
    ///
    /// ```
    /// use gdl90_proto::{Error, message::Heartbeat};
    /// let hb = Heartbeat::parse(&[0x81, 0x41, 0xDB, 0xD0, 0x08, 0x02]).unwrap();
    /// assert_eq!(hb.seconds_since_midnight, 53467);
    /// let short = Heartbeat::parse(&[0x81, 0x41, 0xDB, 0xD0, 0x08]);
    /// assert_eq!(short, Err(Error::WrongLength { id: 0, expected: 6, actual: 5 }));
    /// ```
    ///
    /// # Errors
    /// [`Error::WrongLength`] unless `data` is exactly [`Self::LEN`] bytes.
    pub fn parse(data: &[u8]) -> Result<Self, Error> {
        check_len(Self::ID, Self::LEN, data)?;
        let high = f::TIMESTAMP_BIT16.get(data) as u32;
        Ok(Heartbeat {
            gps_position_valid: f::GPS_POSITION_VALID.get_flag(data),
            maintenance_required: f::MAINTENANCE_REQUIRED.get_flag(data),
            ident: f::IDENT.get_flag(data),
            address_talkback: f::ADDRESS_TALKBACK.get_flag(data),
            gps_battery_low: f::GPS_BATTERY_LOW.get_flag(data),
            atc_services: f::ATC_SERVICES.get_flag(data),
            uat_initialized: f::UAT_INITIALIZED.get_flag(data),
            csa_requested: f::CSA_REQUESTED.get_flag(data),
            csa_not_available: f::CSA_NOT_AVAILABLE.get_flag(data),
            utc_ok: f::UTC_OK.get_flag(data),
            seconds_since_midnight: high << 16 | f::TIMESTAMP.get(data) as u32,
            uplink_messages: f::UPLINK_COUNT.get(data) as u8,
            basic_long_messages: f::BASIC_LONG_COUNT.get(data) as u16,
        })
    }

    /// Writes the data bytes into `out` (reserved bits zero, out-of-range values clamped);
    /// returns [`Self::LEN`].
    ///
    /// ```
    /// use gdl90_proto::message::Heartbeat;
    /// let hb = Heartbeat { seconds_since_midnight: 200_000, uplink_messages: 40, ..Heartbeat::default() };
    /// let mut data = [0u8; Heartbeat::LEN];
    /// assert_eq!(hb.emit(&mut data), Ok(6));
    /// // Both clamped: 131071 s (the time stamp's bit 16 is in status 2), 31 uplink messages.
    /// assert_eq!(data, [0x00, 0x80, 0xFF, 0xFF, 0xF8, 0x00]);
    /// ```
    ///
    /// # Errors
    /// [`EncodeError::BufferTooSmall`] if `out` is shorter than [`Self::LEN`].
    pub fn emit(&self, out: &mut [u8]) -> Result<usize, EncodeError> {
        emit_into(out, Self::LEN, |d| {
            f::GPS_POSITION_VALID.put_flag(d, self.gps_position_valid);
            f::MAINTENANCE_REQUIRED.put_flag(d, self.maintenance_required);
            f::IDENT.put_flag(d, self.ident);
            f::ADDRESS_TALKBACK.put_flag(d, self.address_talkback);
            f::GPS_BATTERY_LOW.put_flag(d, self.gps_battery_low);
            f::ATC_SERVICES.put_flag(d, self.atc_services);
            f::UAT_INITIALIZED.put_flag(d, self.uat_initialized);
            f::CSA_REQUESTED.put_flag(d, self.csa_requested);
            f::CSA_NOT_AVAILABLE.put_flag(d, self.csa_not_available);
            f::UTC_OK.put_flag(d, self.utc_ok);
            let seconds = self.seconds_since_midnight.min(Self::MAX_SECONDS);
            f::TIMESTAMP_BIT16.put(d, (seconds >> 16) as u64);
            f::TIMESTAMP.put(d, (seconds & 0xFFFF) as u64);
            let uplink = (self.uplink_messages as u64).min(f::UPLINK_COUNT.max());
            f::UPLINK_COUNT.put(d, uplink);
            let basic = (self.basic_long_messages as u64).min(f::BASIC_LONG_COUNT.max());
            f::BASIC_LONG_COUNT.put(d, basic);
        })
    }

    /// The data length [`Self::emit`] writes.
    ///
    /// ```
    /// use gdl90_proto::message::Heartbeat;
    /// assert_eq!(Heartbeat::default().buffer_len(), 6);
    /// ```
    pub const fn buffer_len(&self) -> usize {
        Self::LEN
    }
}
