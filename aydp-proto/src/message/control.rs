//! System control (type 9, Y8): command u8 then arguments.

use super::{too_long, too_short};
use crate::encode::Payload;
use crate::error::{Error, Result};
use crate::layout::system_control as at;

/// System control commands (table 3.10).
///
/// ```
/// use aydp_proto::SystemControl;
/// assert_eq!(SystemControl::parse(&[1, 8, 0]), Ok(SystemControl::RequestData { address: 8 }));
/// assert_eq!(SystemControl::parse(&[2]), Ok(SystemControl::StoreConfiguration));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum SystemControl {
    /// 1: request the value at `address`; the reply is a system value update.
    RequestData {
        /// Address to read.
        address: u16,
    },
    /// 2: store the configuration in non-volatile storage.
    StoreConfiguration,
}

impl SystemControl {
    /// Base type.
    pub const TYPE: u8 = 9;
    /// The data length of [`SystemControl::RequestData`].
    pub const REQUEST_DATA_LEN: usize = at::REQUEST_DATA_LEN;
    /// The data length of [`SystemControl::StoreConfiguration`].
    pub const STORE_CONFIGURATION_LEN: usize = at::STORE_CONFIGURATION_LEN;
    /// The layout: `(field, wire type, data offset)` per field, for tools that describe the
    /// wire format (the Wireshark dissector `protolink wireshark` writes). Little-endian;
    /// `uflt16` is binary16 without a sign.
    ///
    /// ```
    /// use aydp_proto::SystemControl;
    /// // The command byte; request data (1) is followed by the address.
    /// assert_eq!(SystemControl::FIELDS, [("command", "u8", 0), ("address", "u16", 1)]);
    /// assert_eq!(SystemControl::REQUEST_DATA_LEN, 3);
    /// ```
    pub const FIELDS: &'static [(&'static str, &'static str, usize)] = at::FIELDS;

    /// Parse: request data is exactly 3 bytes, store configuration exactly 1.
    ///
    /// ```
    /// use aydp_proto::{Error, SystemControl};
    /// assert_eq!(SystemControl::parse(&[1, 0x00, 0x01]), Ok(SystemControl::RequestData { address: 0x100 }));
    /// let short = Error::PayloadTooShort { msg_type: 9, expected: 3, actual: 2 };
    /// assert_eq!(SystemControl::parse(&[1, 8]), Err(short));
    /// assert_eq!(SystemControl::parse(&[3]), Err(Error::UnknownCommand(3)));
    /// ```
    pub fn parse(data: &[u8]) -> Result<Self> {
        match data {
            [] => Err(too_short(Self::TYPE, 1, 0)),
            [1, a0, a1] => Ok(SystemControl::RequestData {
                address: u16::from_le_bytes([*a0, *a1]),
            }),
            [1, ..] if data.len() < at::REQUEST_DATA_LEN => {
                Err(too_short(Self::TYPE, at::REQUEST_DATA_LEN, data.len()))
            }
            [1, ..] => Err(too_long(Self::TYPE, at::REQUEST_DATA_LEN, data.len())),
            [2] => Ok(SystemControl::StoreConfiguration),
            [2, ..] => Err(too_long(
                Self::TYPE,
                at::STORE_CONFIGURATION_LEN,
                data.len(),
            )),
            [c, ..] => Err(Error::UnknownCommand(*c)),
        }
    }

    fn bytes(&self) -> ([u8; 3], usize) {
        match *self {
            SystemControl::RequestData { address } => {
                let [a0, a1] = address.to_le_bytes();
                ([1, a0, a1], at::REQUEST_DATA_LEN)
            }
            SystemControl::StoreConfiguration => ([2, 0, 0], at::STORE_CONFIGURATION_LEN),
        }
    }
}

impl Payload for SystemControl {
    fn base_type(&self) -> u8 {
        Self::TYPE
    }
    fn buffer_len(&self) -> usize {
        self.bytes().1
    }
    fn data_byte(&self, index: usize) -> u8 {
        self.bytes().0.get(index).copied().unwrap_or(0)
    }
}
