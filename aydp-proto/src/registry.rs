//! A system-value registry for devices: addresses mapped to typed slots over caller-owned
//! storage (no allocation), with read-only, bounds and range checks.
//!
//! A device builds a table of [`Slot`]s, each pointing at its own variables, and wraps it in a
//! [`Registry`]. Incoming system value updates are applied with [`Registry::apply`], which
//! either changes exactly what the update names or rejects it with a reason and changes
//! nothing. [`Registry::read`] builds the system value update that answers a request-data
//! command (Y8, section 3.10.1). The firmware reads and writes its own settings through
//! [`Registry::get`] and [`Registry::set`].
//!
//! Arrays are fixed-length: a whole-array update must carry exactly the array's element count
//! (the document warns that changing an array's length can crash a device).
//!
//! ```
//! use aydp_proto::registry::{Cell, Registry, RegistryError, Slot};
//! use aydp_proto::{SystemValueUpdate, UpdateMode};
//!
//! let mut direct = 0u8;
//! let mut name = *b"demo boat\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0";
//! let mut rates = [10u16, 20, 50];
//! let mut slots = [
//!     Slot::value(0x0000, Cell::u8(&mut direct)).with_range(0.0, 1.0),
//!     Slot::value(0x0001, Cell::Chars(&mut name)).read_only(),
//!     Slot::array(0x0100, Cell::U16(&mut rates)),
//! ];
//! let mut reg = Registry::new(&mut slots);
//!
//! let on = SystemValueUpdate { address: 0, mode: UpdateMode::Single, data: &[1] };
//! assert_eq!(reg.apply(&on), Ok(()));
//! assert_eq!(reg.get::<u8>(0, 0), Some(1));
//! let bad = SystemValueUpdate { address: 0, mode: UpdateMode::Single, data: &[2] };
//! assert_eq!(reg.apply(&bad), Err(RegistryError::OutOfRange(0)));
//! let rename = SystemValueUpdate { address: 1, mode: UpdateMode::Single, data: b"x" };
//! assert_eq!(reg.apply(&rename), Err(RegistryError::ReadOnly(1)));
//! let elem = SystemValueUpdate { address: 0x100, mode: UpdateMode::Element { index: 2 }, data: &[100, 0] };
//! assert_eq!(reg.apply(&elem), Ok(()));
//! assert_eq!(reg.get::<u16>(0x100, 2), Some(100));
//!
//! let mut out = [0u8; 16];
//! let reply = reg.read(0x100, &mut out).unwrap();
//! assert_eq!(reply.mode, UpdateMode::Array { count: 3 });
//! assert_eq!(reply.data, &[10, 0, 20, 0, 100, 0]);
//! ```

use core::fmt;

/// How a registry operation failed: [`Registry::apply`], [`Registry::read`] and
/// [`Registry::set`] report nothing else. Each carries the address asked for.
///
/// ```
/// use aydp_proto::registry::RegistryError;
/// assert_eq!(RegistryError::ReadOnly(1).to_string(), "address 0x0001 is read-only");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum RegistryError {
    /// No slot at this address.
    UnknownAddress(u16),
    /// The slot at this address is read-only.
    ReadOnly(u16),
    /// The update mode does not fit the slot (e.g. element update of a scalar).
    WrongMode(u16),
    /// The data length does not fit the slot's type and element count.
    WrongSize(u16),
    /// Element index or array count beyond the slot's length (or, for `read`, beyond what the
    /// update's 32-bit count holds).
    OutOfBounds(u16),
    /// A value is outside the slot's allowed range (or NaN where a range is set).
    OutOfRange(u16),
    /// `read`'s output buffer is too small; a buffer of `needed` bytes holds the value.
    BufferTooSmall {
        /// Bytes the value needs.
        needed: usize,
    },
}

impl fmt::Display for RegistryError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Self::UnknownAddress(a) => write!(f, "no system value at address {a:#06x}"),
            Self::ReadOnly(a) => write!(f, "address {a:#06x} is read-only"),
            Self::WrongMode(a) => write!(f, "update mode does not fit address {a:#06x}"),
            Self::WrongSize(a) => write!(f, "data size does not fit address {a:#06x}"),
            Self::OutOfBounds(a) => write!(f, "index or count out of bounds at {a:#06x}"),
            Self::OutOfRange(a) => write!(f, "value out of range for address {a:#06x}"),
            Self::BufferTooSmall { needed } => {
                write!(f, "buffer too small: {needed} bytes needed")
            }
        }
    }
}

impl core::error::Error for RegistryError {}

type Result<T> = core::result::Result<T, RegistryError>;
use crate::header::array_at;
use crate::message::{SystemValueUpdate, UpdateMode};

/// Whether the protocol may write a slot.
///
/// ```
/// use aydp_proto::registry::{Access, Cell, Slot};
/// let mut serial = 1234u32;
/// assert_eq!(Slot::value(0x0002, Cell::u32(&mut serial)).read_only().access, Access::ReadOnly);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Access {
    /// Updates are rejected with [`RegistryError::ReadOnly`].
    ReadOnly,
    /// Updates are applied after the checks.
    ReadWrite,
}

/// Caller-owned storage of a slot: a slice of elements (one element for a scalar).
/// `Chars` is a fixed `char[N]` text, NUL-padded.
///
/// ```
/// use aydp_proto::registry::Cell;
/// let mut rates = [10u16, 20, 50];
/// let cell = Cell::U16(&mut rates);
/// assert_eq!((cell.len(), cell.element_size()), (3, 2));
/// ```
#[derive(Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub enum Cell<'a> {
    /// `uint8` elements.
    U8(&'a mut [u8]),
    /// `uint16` elements.
    U16(&'a mut [u16]),
    /// `uint32` elements.
    U32(&'a mut [u32]),
    /// `int32` elements.
    I32(&'a mut [i32]),
    /// `flt32` elements.
    F32(&'a mut [f32]),
    /// `flt64` elements.
    F64(&'a mut [f64]),
    /// `char[N]` text.
    Chars(&'a mut [u8]),
}

macro_rules! scalar_ctor {
    ($name:ident, $t:ty, $v:ident) => {
        #[doc = concat!("A one-element `", stringify!($t), "` cell over `value`.")]
        ///
        /// ```
        /// use aydp_proto::registry::Cell;
        #[doc = concat!("let mut value = ", stringify!($t), "::MAX;")]
        #[doc = concat!("let cell = Cell::", stringify!($name), "(&mut value);")]
        #[doc = concat!(
            "assert_eq!(cell, Cell::", stringify!($v), "(&mut [", stringify!($t), "::MAX]));"
        )]
        /// ```
        pub fn $name(value: &'a mut $t) -> Self {
            Cell::$v(core::slice::from_mut(value))
        }
    };
}

impl<'a> Cell<'a> {
    scalar_ctor!(u8, u8, U8);
    scalar_ctor!(u16, u16, U16);
    scalar_ctor!(u32, u32, U32);
    scalar_ctor!(i32, i32, I32);
    scalar_ctor!(f32, f32, F32);
    scalar_ctor!(f64, f64, F64);

    /// Bytes per element on the wire.
    ///
    /// ```
    /// use aydp_proto::registry::Cell;
    /// let (mut a, mut b) = (0u16, 0f64);
    /// assert_eq!(Cell::u16(&mut a).element_size(), 2);
    /// assert_eq!(Cell::f64(&mut b).element_size(), 8);
    /// ```
    pub const fn element_size(&self) -> usize {
        match self {
            Cell::U8(_) | Cell::Chars(_) => 1,
            Cell::U16(_) => 2,
            Cell::U32(_) | Cell::I32(_) | Cell::F32(_) => 4,
            Cell::F64(_) => 8,
        }
    }

    /// Number of elements.
    ///
    /// ```
    /// use aydp_proto::registry::Cell;
    /// let mut name = *b"boat\0\0\0\0";
    /// assert_eq!(Cell::Chars(&mut name).len(), 8);
    /// ```
    pub const fn len(&self) -> usize {
        match self {
            Cell::U8(s) | Cell::Chars(s) => s.len(),
            Cell::U16(s) => s.len(),
            Cell::U32(s) => s.len(),
            Cell::I32(s) => s.len(),
            Cell::F32(s) => s.len(),
            Cell::F64(s) => s.len(),
        }
    }

    /// Whether the cell holds no element.
    ///
    /// ```
    /// use aydp_proto::registry::Cell;
    /// assert!(Cell::F32(&mut []).is_empty());
    /// ```
    pub const fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Element `i` of wire bytes `b` as f64 (for range checks), `None` for text.
    fn wire_value(&self, b: &[u8]) -> Option<f64> {
        Some(match self {
            Cell::Chars(_) => return None,
            Cell::U8(_) => b.first().copied().unwrap_or(0) as f64,
            Cell::U16(_) => u16::from_le_bytes(array_at(b, 0)) as f64,
            Cell::U32(_) => u32::from_le_bytes(array_at(b, 0)) as f64,
            Cell::I32(_) => i32::from_le_bytes(array_at(b, 0)) as f64,
            Cell::F32(_) => f32::from_le_bytes(array_at(b, 0)) as f64,
            Cell::F64(_) => f64::from_le_bytes(array_at(b, 0)),
        })
    }

    /// Store one element from its wire bytes.
    fn store(&mut self, index: usize, b: &[u8]) {
        match self {
            Cell::U8(s) | Cell::Chars(s) => set(s, index, b.first().copied().unwrap_or(0)),
            Cell::U16(s) => set(s, index, u16::from_le_bytes(array_at(b, 0))),
            Cell::U32(s) => set(s, index, u32::from_le_bytes(array_at(b, 0))),
            Cell::I32(s) => set(s, index, i32::from_le_bytes(array_at(b, 0))),
            Cell::F32(s) => set(s, index, f32::from_le_bytes(array_at(b, 0))),
            Cell::F64(s) => set(s, index, f64::from_le_bytes(array_at(b, 0))),
        }
    }

    /// Write element `index` as wire bytes into `out` (at most 8 bytes).
    fn load(&self, index: usize, out: &mut [u8]) {
        let bytes: ([u8; 8], usize) = match self {
            Cell::U8(s) | Cell::Chars(s) => wide(get(s, index).to_le_bytes()),
            Cell::U16(s) => wide(get(s, index).to_le_bytes()),
            Cell::U32(s) => wide(get(s, index).to_le_bytes()),
            Cell::I32(s) => wide(get(s, index).to_le_bytes()),
            Cell::F32(s) => wide(get(s, index).to_le_bytes()),
            Cell::F64(s) => wide(get(s, index).to_le_bytes()),
        };
        crate::header::put(out, 0, bytes.0.get(..bytes.1).unwrap_or(&[]));
    }
}

fn wide<const K: usize>(b: [u8; K]) -> ([u8; 8], usize) {
    (array_at(&b, 0), K)
}

fn set<T>(s: &mut [T], i: usize, v: T) {
    if let Some(d) = s.get_mut(i) {
        *d = v;
    }
}

fn get<T: Copy + Default>(s: &[T], i: usize) -> T {
    s.get(i).copied().unwrap_or_default()
}

/// One registered address.
///
/// ```
/// use aydp_proto::registry::{Access, Cell, Slot};
/// let mut interval_ms = 1000u32;
/// let s = Slot::value(0x0200, Cell::u32(&mut interval_ms)).with_range(10.0, 60_000.0);
/// assert_eq!(s.access, Access::ReadWrite);
/// ```
#[derive(Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Slot<'a> {
    /// The 16-bit address.
    pub address: u16,
    /// Read-only or read-write.
    pub access: Access,
    /// `true`: an array (modes 2 and 3). `false`: a single value (mode 1). `Chars` text
    /// accepts all three modes.
    pub is_array: bool,
    /// Inclusive allowed range, checked on every numeric element of an update.
    pub range: Option<(f64, f64)>,
    /// The storage.
    pub cell: Cell<'a>,
}

impl<'a> Slot<'a> {
    /// A read-write single value (use a one-element cell) or a `Chars` text.
    ///
    /// ```
    /// use aydp_proto::registry::{Access, Cell, Slot};
    /// let mut direct = 0u8;
    /// let slot = Slot::value(0x0000, Cell::u8(&mut direct));
    /// assert_eq!((slot.address, slot.access, slot.is_array), (0x0000, Access::ReadWrite, false));
    /// ```
    pub const fn value(address: u16, cell: Cell<'a>) -> Self {
        Self {
            address,
            access: Access::ReadWrite,
            is_array: false,
            range: None,
            cell,
        }
    }

    /// A read-write fixed-length array.
    ///
    /// ```
    /// use aydp_proto::registry::{Cell, Slot};
    /// let mut rates = [10u16, 20, 50];
    /// let slot = Slot::array(0x0100, Cell::U16(&mut rates));
    /// assert!(slot.is_array);
    /// assert_eq!(slot.cell.len(), 3);
    /// ```
    pub const fn array(address: u16, cell: Cell<'a>) -> Self {
        Self {
            address,
            access: Access::ReadWrite,
            is_array: true,
            range: None,
            cell,
        }
    }

    /// Make the slot read-only for the protocol.
    ///
    /// ```
    /// use aydp_proto::registry::{Cell, Registry, RegistryError, Slot};
    /// use aydp_proto::{SystemValueUpdate, UpdateMode};
    /// let mut serial = 1234u32;
    /// let mut slots = [Slot::value(0x0002, Cell::u32(&mut serial)).read_only()];
    /// let mut reg = Registry::new(&mut slots);
    /// let update = SystemValueUpdate { address: 2, mode: UpdateMode::Single, data: &[0; 4] };
    /// assert_eq!(reg.apply(&update), Err(RegistryError::ReadOnly(2)));
    /// ```
    pub const fn read_only(mut self) -> Self {
        self.access = Access::ReadOnly;
        self
    }

    /// Restrict numeric values to `min..=max` (NaN is then rejected too).
    ///
    /// ```
    /// use aydp_proto::registry::{Cell, Registry, RegistryError, Slot};
    /// let mut gain = 1.0f32;
    /// let mut slots = [Slot::value(0x0300, Cell::f32(&mut gain)).with_range(0.0, 2.0)];
    /// let mut reg = Registry::new(&mut slots);
    /// assert_eq!(reg.set(0x0300, 0, 1.5f32), Ok(()));
    /// assert_eq!(reg.set(0x0300, 0, 2.5f32), Err(RegistryError::OutOfRange(0x0300)));
    /// assert_eq!(reg.set(0x0300, 0, f32::NAN), Err(RegistryError::OutOfRange(0x0300)));
    /// ```
    pub const fn with_range(mut self, min: f64, max: f64) -> Self {
        self.range = Some((min, max));
        self
    }

    fn is_text(&self) -> bool {
        matches!(self.cell, Cell::Chars(_))
    }

    /// Check an update against this slot; returns (first element, element count) to write.
    fn check(&self, update: &SystemValueUpdate<'_>) -> Result<(usize, usize)> {
        let a = self.address;
        if self.access == Access::ReadOnly {
            return Err(RegistryError::ReadOnly(a));
        }
        let size = self.cell.element_size();
        let n = self.cell.len();
        let data = update.data.len();
        let (first, count) = match update.mode {
            UpdateMode::Single if self.is_text() => {
                if data > n {
                    return Err(RegistryError::WrongSize(a));
                }
                (0, data)
            }
            UpdateMode::Single if self.is_array => return Err(RegistryError::WrongMode(a)),
            UpdateMode::Single => {
                if data != size {
                    return Err(RegistryError::WrongSize(a));
                }
                (0, 1)
            }
            _ if !self.is_array && !self.is_text() => return Err(RegistryError::WrongMode(a)),
            UpdateMode::Array { count } => {
                if count as usize != n || count as u64 > n as u64 {
                    return Err(RegistryError::OutOfBounds(a));
                }
                if Some(data) != n.checked_mul(size) {
                    return Err(RegistryError::WrongSize(a));
                }
                (0, n)
            }
            UpdateMode::Element { index } => {
                if index as u64 >= n as u64 {
                    return Err(RegistryError::OutOfBounds(a));
                }
                if data != size {
                    return Err(RegistryError::WrongSize(a));
                }
                (index as usize, 1)
            }
        };
        if let Some((min, max)) = self.range {
            for chunk in update.data.chunks_exact(size) {
                if let Some(v) = self.cell.wire_value(chunk) {
                    // `!(a <= b)` also rejects NaN.
                    if !(min <= v && v <= max) {
                        return Err(RegistryError::OutOfRange(a));
                    }
                }
            }
        }
        Ok((first, count))
    }
}

/// A table of slots, searched by address.
///
/// See the [module documentation](self) for a full example.
///
/// ```
/// use aydp_proto::registry::{Cell, Registry, Slot};
/// let mut direct = 0u8;
/// let mut slots = [Slot::value(0x0000, Cell::u8(&mut direct))];
/// let mut reg = Registry::new(&mut slots);
/// reg.set(0x0000, 0, 1u8).unwrap();
/// assert_eq!(reg.get::<u8>(0x0000, 0), Some(1));
/// ```
#[derive(Debug)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Registry<'s, 'a> {
    slots: &'s mut [Slot<'a>],
}

/// Element types that [`Registry::get`] and [`Registry::set`] read and write.
///
/// ```
/// use aydp_proto::registry::{Cell, Registry, Slot};
/// let mut rates = [10u16, 20];
/// let mut slots = [Slot::array(0x0100, Cell::U16(&mut rates))];
/// let reg = Registry::new(&mut slots);
/// assert_eq!(reg.get::<u16>(0x0100, 1), Some(20));
/// assert_eq!(reg.get::<u32>(0x0100, 1), None); // another type
/// ```
pub trait Element: Copy + Sized {
    /// Read element `index` of a cell of the matching type.
    ///
    /// ```
    /// use aydp_proto::registry::{Cell, Element};
    /// let mut rates = [10u16, 20];
    /// let cell = Cell::U16(&mut rates);
    /// assert_eq!(<u16 as Element>::read(&cell, 1), Some(20));
    /// assert_eq!(<u8 as Element>::read(&cell, 1), None);
    /// ```
    fn read(cell: &Cell<'_>, index: usize) -> Option<Self>;
    /// Write element `index`; `false` if the type or index does not fit.
    ///
    /// ```
    /// use aydp_proto::registry::{Cell, Element};
    /// let mut rates = [10u16, 20];
    /// let mut cell = Cell::U16(&mut rates);
    /// assert!(<u16 as Element>::write(&mut cell, 1, 25));
    /// assert!(!<u16 as Element>::write(&mut cell, 2, 25));
    /// assert_eq!(rates, [10, 25]);
    /// ```
    fn write(cell: &mut Cell<'_>, index: usize, value: Self) -> bool;
    /// The value as f64, for range checks (`None`: no range applies).
    ///
    /// ```
    /// use aydp_proto::registry::Element;
    /// assert_eq!(Element::as_f64(7u8), Some(7.0));
    /// ```
    fn as_f64(self) -> Option<f64>;
}

macro_rules! element {
    ($t:ty, $($v:ident)|+) => {
        impl Element for $t {
            fn read(cell: &Cell<'_>, index: usize) -> Option<Self> {
                match cell {
                    $(Cell::$v(s))|+ => s.get(index).copied(),
                    #[allow(unreachable_patterns)]
                    _ => None,
                }
            }
            fn write(cell: &mut Cell<'_>, index: usize, value: Self) -> bool {
                match cell {
                    $(Cell::$v(s))|+ => match s.get_mut(index) {
                        Some(d) => {
                            *d = value;
                            true
                        }
                        None => false,
                    },
                    #[allow(unreachable_patterns)]
                    _ => false,
                }
            }
            fn as_f64(self) -> Option<f64> {
                Some(self as f64)
            }
        }
    };
}
element!(u8, U8 | Chars);
element!(u16, U16);
element!(u32, U32);
element!(i32, I32);
element!(f32, F32);
element!(f64, F64);

impl<'s, 'a> Registry<'s, 'a> {
    /// Wrap a table. Addresses should be unique; the first match wins.
    ///
    /// ```
    /// use aydp_proto::registry::{Cell, Registry, Slot};
    /// let (mut a, mut b) = (1u8, 2u8);
    /// let mut slots = [Slot::value(5, Cell::u8(&mut a)), Slot::value(5, Cell::u8(&mut b))];
    /// assert_eq!(Registry::new(&mut slots).get::<u8>(5, 0), Some(1));
    /// ```
    pub fn new(slots: &'s mut [Slot<'a>]) -> Self {
        Self { slots }
    }

    /// The slot at `address`.
    ///
    /// ```
    /// use aydp_proto::registry::{Cell, Registry, Slot};
    /// let mut rates = [10u16, 20, 50];
    /// let mut slots = [Slot::array(0x0100, Cell::U16(&mut rates))];
    /// let reg = Registry::new(&mut slots);
    /// assert_eq!(reg.slot(0x0100).map(|s| s.cell.len()), Some(3));
    /// assert!(reg.slot(0x0200).is_none());
    /// ```
    pub fn slot(&self, address: u16) -> Option<&Slot<'a>> {
        self.slots.iter().find(|s| s.address == address)
    }

    fn slot_mut(&mut self, address: u16) -> Result<&mut Slot<'a>> {
        self.slots
            .iter_mut()
            .find(|s| s.address == address)
            .ok_or(RegistryError::UnknownAddress(address))
    }

    /// Apply a system value update, or reject it with the reason and change nothing.
    ///
    /// ```
    /// use aydp_proto::registry::{Cell, Registry, RegistryError, Slot};
    /// use aydp_proto::{SystemValueUpdate, UpdateMode};
    /// let mut rates = [10u16, 20, 50];
    /// let mut slots = [Slot::array(0x0100, Cell::U16(&mut rates))];
    /// let mut reg = Registry::new(&mut slots);
    /// let all = [1, 0, 2, 0, 3, 0];
    /// let update = SystemValueUpdate { address: 0x100, mode: UpdateMode::Array { count: 3 }, data: &all };
    /// assert_eq!(reg.apply(&update), Ok(()));
    /// let single = SystemValueUpdate { address: 0x100, mode: UpdateMode::Single, data: &[9, 0] };
    /// assert_eq!(reg.apply(&single), Err(RegistryError::WrongMode(0x100)));
    /// drop(reg);
    /// assert_eq!(rates, [1, 2, 3]);
    /// ```
    pub fn apply(&mut self, update: &SystemValueUpdate<'_>) -> Result<()> {
        let slot = self.slot_mut(update.address)?;
        let (first, count) = slot.check(update)?;
        let size = slot.cell.element_size();
        if slot.is_text() && update.mode == UpdateMode::Single {
            // Text: the new string, NUL-padded to the slot's length.
            let n = slot.cell.len();
            for i in 0..n {
                let b = update.data.get(i).copied().unwrap_or(0);
                slot.cell.store(i, &[b]);
            }
            return Ok(());
        }
        for (k, chunk) in update.data.chunks_exact(size).take(count).enumerate() {
            slot.cell.store(first.saturating_add(k), chunk);
        }
        Ok(())
    }

    /// Build the system value update that answers "request data" for `address`, writing the
    /// value bytes into `out`. Scalars answer in mode 1; arrays and text answer with the whole
    /// array in mode 2.
    ///
    /// ```
    /// use aydp_proto::registry::{Cell, Registry, RegistryError, Slot};
    /// use aydp_proto::UpdateMode;
    /// let mut interval_ms = 1000u32;
    /// let mut slots = [Slot::value(0x0200, Cell::u32(&mut interval_ms))];
    /// let reg = Registry::new(&mut slots);
    /// let mut out = [0u8; 8];
    /// let reply = reg.read(0x0200, &mut out).unwrap();
    /// assert_eq!((reply.mode, reply.data), (UpdateMode::Single, &[0xE8, 0x03, 0, 0][..]));
    /// assert_eq!(reg.read(0x0200, &mut [0u8; 2]), Err(RegistryError::BufferTooSmall { needed: 4 }));
    /// ```
    pub fn read<'o>(&self, address: u16, out: &'o mut [u8]) -> Result<SystemValueUpdate<'o>> {
        let slot = self
            .slot(address)
            .ok_or(RegistryError::UnknownAddress(address))?;
        let size = slot.cell.element_size();
        let n = slot.cell.len();
        let total = n.saturating_mul(size);
        let Some(dst) = out.get_mut(..total) else {
            return Err(RegistryError::BufferTooSmall { needed: total });
        };
        for (i, chunk) in dst.chunks_exact_mut(size).enumerate() {
            slot.cell.load(i, chunk);
        }
        let mode = if slot.is_array || slot.is_text() {
            UpdateMode::Array {
                count: u32::try_from(n).map_err(|_| RegistryError::OutOfBounds(address))?,
            }
        } else {
            UpdateMode::Single
        };
        let data: &'o [u8] = dst;
        Ok(SystemValueUpdate {
            address,
            mode,
            data,
        })
    }

    /// Read element `index` at `address` as `T` (`None` if absent or of another type).
    ///
    /// ```
    /// use aydp_proto::registry::{Cell, Registry, Slot};
    /// let mut rates = [10u16, 20, 50];
    /// let mut slots = [Slot::array(0x0100, Cell::U16(&mut rates))];
    /// let reg = Registry::new(&mut slots);
    /// assert_eq!(reg.get::<u16>(0x0100, 2), Some(50));
    /// assert_eq!(reg.get::<u16>(0x0100, 3), None);
    /// assert_eq!(reg.get::<f32>(0x0100, 0), None);
    /// ```
    pub fn get<T: Element>(&self, address: u16, index: usize) -> Option<T> {
        T::read(&self.slot(address)?.cell, index)
    }

    /// Set element `index` at `address` from the device itself: read-only does not apply
    /// (the device owns its values), but the type, bounds and range checks do.
    ///
    /// ```
    /// use aydp_proto::registry::{Cell, Registry, RegistryError, Slot};
    /// let mut serial = 0u32;
    /// let mut slots = [Slot::value(0x0002, Cell::u32(&mut serial)).read_only()];
    /// let mut reg = Registry::new(&mut slots);
    /// assert_eq!(reg.set(0x0002, 0, 1234u32), Ok(())); // read-only binds the protocol only
    /// assert_eq!(reg.set(0x0002, 0, 1u8), Err(RegistryError::WrongSize(0x0002)));
    /// assert_eq!(reg.set(0x0002, 1, 1u32), Err(RegistryError::OutOfBounds(0x0002)));
    /// assert_eq!(reg.set(0x0009, 0, 1u32), Err(RegistryError::UnknownAddress(0x0009)));
    /// ```
    pub fn set<T: Element>(&mut self, address: u16, index: usize, value: T) -> Result<()> {
        let slot = self.slot_mut(address)?;
        // (Nested rather than a let chain: the crate's MSRV is 1.87.)
        if let (Some((min, max)), Some(v)) = (slot.range, value.as_f64()) {
            if !(min <= v && v <= max) {
                return Err(RegistryError::OutOfRange(address));
            }
        }
        if T::write(&mut slot.cell, index, value) {
            Ok(())
        } else if index >= slot.cell.len() {
            Err(RegistryError::OutOfBounds(address))
        } else {
            Err(RegistryError::WrongSize(address))
        }
    }

    /// All slots.
    ///
    /// ```
    /// use aydp_proto::registry::{Cell, Registry, Slot};
    /// let (mut a, mut b) = (0u8, 0u16);
    /// let mut slots = [Slot::value(1, Cell::u8(&mut a)), Slot::value(2, Cell::u16(&mut b))];
    /// let reg = Registry::new(&mut slots);
    /// let addresses: Vec<u16> = reg.slots().iter().map(|s| s.address).collect();
    /// assert_eq!(addresses, [1, 2]);
    /// ```
    pub fn slots(&self) -> &[Slot<'a>] {
        self.slots
    }
}
