//! System value update (type 8, Y8): update type u8, address u16, u32, data.

use super::too_short;
use crate::encode::Payload;
use crate::error::{Error, Result};
use crate::header::{array_at, put};
use crate::layout::system_value_update as at;

/// Which part of a value an update writes (table 3.7).
///
/// ```
/// use aydp_proto::UpdateMode;
/// assert_eq!(UpdateMode::Element { index: 4 }.code(), 3);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum UpdateMode {
    /// 1: a single value; the u32 field is 0.
    Single,
    /// 2: the entire array, `count` elements.
    Array {
        /// Number of elements in the data.
        count: u32,
    },
    /// 3: one element of an array.
    Element {
        /// Element index.
        index: u32,
    },
}

impl UpdateMode {
    /// The update type byte.
    ///
    /// ```
    /// use aydp_proto::UpdateMode;
    /// assert_eq!(UpdateMode::Single.code(), 1);
    /// assert_eq!(UpdateMode::Array { count: 3 }.code(), 2);
    /// ```
    pub const fn code(&self) -> u8 {
        match self {
            UpdateMode::Single => 1,
            UpdateMode::Array { .. } => 2,
            UpdateMode::Element { .. } => 3,
        }
    }

    /// The "array size or element" field.
    ///
    /// ```
    /// use aydp_proto::UpdateMode;
    /// assert_eq!(UpdateMode::Single.field(), 0);
    /// assert_eq!(UpdateMode::Array { count: 3 }.field(), 3);
    /// assert_eq!(UpdateMode::Element { index: 4 }.field(), 4);
    /// ```
    pub const fn field(&self) -> u32 {
        match *self {
            UpdateMode::Single => 0,
            UpdateMode::Array { count } => count,
            UpdateMode::Element { index } => index,
        }
    }
}

/// System value update (type 8). The data is kept as bytes: only the device knows the type.
///
/// ```
/// use aydp_proto::{SystemValueUpdate, UpdateMode};
/// let u = SystemValueUpdate::parse(&[1, 0, 0, 0, 0, 0, 0, 1]).unwrap();
/// assert_eq!(u, SystemValueUpdate { address: 0, mode: UpdateMode::Single, data: &[1] });
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SystemValueUpdate<'a> {
    /// Address (table 3.9 and the device's own map).
    pub address: u16,
    /// Update mode.
    pub mode: UpdateMode,
    /// The value bytes, little-endian.
    pub data: &'a [u8],
}

impl<'a> SystemValueUpdate<'a> {
    /// Base type.
    pub const TYPE: u8 = 8;
    /// Bytes before the value data.
    pub const HEADER_LEN: usize = at::VALUE;
    /// The layout: `(field, wire type, data offset)` per field of the head, for tools that describe the
    /// wire format (the Wireshark dissector `protolink wireshark` writes). Little-endian;
    /// `uflt16` is binary16 without a sign.
    ///
    /// ```
    /// use aydp_proto::SystemValueUpdate;
    /// assert_eq!(SystemValueUpdate::FIELDS[2], ("field", "u32", 3));
    /// // The value bytes follow the head.
    /// assert_eq!(SystemValueUpdate::HEADER_LEN, 7);
    /// ```
    pub const FIELDS: &'static [(&'static str, &'static str, usize)] = at::FIELDS;

    /// Parse: at least 7 bytes, a known mode, and a zero field for single-value updates.
    ///
    /// ```
    /// use aydp_proto::{Error, SystemValueUpdate, UpdateMode};
    /// // Mode 3 (element 2) at address 0x0100, then the value bytes.
    /// let u = SystemValueUpdate::parse(&[3, 0x00, 0x01, 2, 0, 0, 0, 100, 0]).unwrap();
    /// assert_eq!((u.address, u.mode, u.data), (0x100, UpdateMode::Element { index: 2 }, &[100, 0][..]));
    /// assert_eq!(SystemValueUpdate::parse(&[1, 0, 0, 5, 0, 0, 0, 1]), Err(Error::NonZeroSingleIndex(5)));
    /// assert_eq!(SystemValueUpdate::parse(&[4, 0, 0, 0, 0, 0, 0]), Err(Error::UnknownUpdateMode(4)));
    /// ```
    pub fn parse(data: &'a [u8]) -> Result<Self> {
        let Some(value) = data.get(Self::HEADER_LEN..) else {
            return Err(too_short(Self::TYPE, Self::HEADER_LEN, data.len()));
        };
        let h: [u8; at::VALUE] = array_at(data, 0);
        let address = u16::from_le_bytes(array_at(&h, at::ADDRESS));
        let field = u32::from_le_bytes(array_at(&h, at::FIELD));
        let mode = match h[at::MODE] {
            1 if field == 0 => UpdateMode::Single,
            1 => return Err(Error::NonZeroSingleIndex(field)),
            2 => UpdateMode::Array { count: field },
            3 => UpdateMode::Element { index: field },
            m => return Err(Error::UnknownUpdateMode(m)),
        };
        Ok(Self {
            address,
            mode,
            data: value,
        })
    }

    fn head(&self) -> [u8; at::VALUE] {
        let mut h = [0u8; Self::HEADER_LEN];
        h[at::MODE] = self.mode.code();
        put(&mut h, at::ADDRESS, &self.address.to_le_bytes());
        put(&mut h, at::FIELD, &self.mode.field().to_le_bytes());
        h
    }
}

impl Payload for SystemValueUpdate<'_> {
    fn base_type(&self) -> u8 {
        Self::TYPE
    }
    fn buffer_len(&self) -> usize {
        self.data.len().saturating_add(Self::HEADER_LEN)
    }
    fn data_byte(&self, index: usize) -> u8 {
        match index.checked_sub(Self::HEADER_LEN) {
            None => self.head().get(index).copied().unwrap_or(0),
            Some(i) => self.data.get(i).copied().unwrap_or(0),
        }
    }
    fn write_data(&self, out: &mut [u8]) {
        put(out, 0, &self.head());
        put(out, Self::HEADER_LEN, self.data);
    }
}
