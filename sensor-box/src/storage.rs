//! Flash stores behind the `embedded-storage` NOR flash traits.
//!
//! * [`MemFlash`] is NOR flash over a byte slice: erase sets bytes to `0xFF`,
//!   a write can only clear bits (it ANDs), like real NOR. The QEMU board
//!   hands it a RAM region that survives a warm reset; host tests hand it an
//!   array.
//! * [`FlashWindow`] exposes one range of a bigger flash (the STM32 board uses
//!   it for the settings sector) with offsets starting at 0.
//!
//! ```
//! use embedded_storage::nor_flash::{NorFlash, ReadNorFlash};
//! use sensor_box::storage::MemFlash;
//!
//! let mut mem = [0u8; 2048];
//! let mut flash = MemFlash::new(&mut mem);
//! flash.erase(0, 1024).unwrap();
//! flash.write(0, &[1, 2, 3, 4]).unwrap();
//! let mut buf = [0u8; 4];
//! flash.read(0, &mut buf).unwrap();
//! assert_eq!(buf, [1, 2, 3, 4]);
//! ```

use embedded_storage::nor_flash::{
    ErrorType, NorFlash, NorFlashError, NorFlashErrorKind, ReadNorFlash,
};

/// NOR flash emulated in a byte slice (1 KiB erase pages, 4-byte writes).
#[derive(Debug)]
pub struct MemFlash<'a> {
    mem: &'a mut [u8],
}

impl<'a> MemFlash<'a> {
    /// Erase page size, bytes.
    pub const PAGE: usize = 1024;
    /// Write granularity, bytes.
    pub const WORD: usize = 4;

    /// A flash over `mem`; its capacity is `mem.len()` rounded down to whole pages.
    ///
    /// ```
    /// use embedded_storage::nor_flash::ReadNorFlash;
    /// let mut mem = [0u8; 1500];
    /// assert_eq!(sensor_box::storage::MemFlash::new(&mut mem).capacity(), 1024);
    /// ```
    pub fn new(mem: &'a mut [u8]) -> Self {
        let len = mem.len() - mem.len() % Self::PAGE;
        let (used, _) = mem.split_at_mut(len);
        Self { mem: used }
    }

    fn range(&self, offset: u32, len: usize) -> Result<core::ops::Range<usize>, Error> {
        let start = usize::try_from(offset).map_err(|_| Error::OutOfBounds)?;
        let end = start.checked_add(len).ok_or(Error::OutOfBounds)?;
        if end > self.mem.len() {
            return Err(Error::OutOfBounds);
        }
        Ok(start..end)
    }
}

impl ErrorType for MemFlash<'_> {
    type Error = Error;
}

impl ReadNorFlash for MemFlash<'_> {
    const READ_SIZE: usize = 1;

    fn read(&mut self, offset: u32, bytes: &mut [u8]) -> Result<(), Error> {
        let r = self.range(offset, bytes.len())?;
        let src = self.mem.get(r).ok_or(Error::OutOfBounds)?;
        crate::port::copy_prefix(bytes, src);
        Ok(())
    }

    fn capacity(&self) -> usize {
        self.mem.len()
    }
}

impl NorFlash for MemFlash<'_> {
    const WRITE_SIZE: usize = Self::WORD;
    const ERASE_SIZE: usize = Self::PAGE;

    fn erase(&mut self, from: u32, to: u32) -> Result<(), Error> {
        if from > to {
            return Err(Error::OutOfBounds);
        }
        let len = usize::try_from(to - from).map_err(|_| Error::OutOfBounds)?;
        let r = self.range(from, len)?;
        if !r.start.is_multiple_of(Self::PAGE) || !r.end.is_multiple_of(Self::PAGE) {
            return Err(Error::NotAligned);
        }
        self.mem.get_mut(r).ok_or(Error::OutOfBounds)?.fill(0xFF);
        Ok(())
    }

    fn write(&mut self, offset: u32, bytes: &[u8]) -> Result<(), Error> {
        let r = self.range(offset, bytes.len())?;
        if !r.start.is_multiple_of(Self::WORD) || !r.end.is_multiple_of(Self::WORD) {
            return Err(Error::NotAligned);
        }
        let dst = self.mem.get_mut(r).ok_or(Error::OutOfBounds)?;
        for (d, s) in dst.iter_mut().zip(bytes) {
            *d &= *s; // NOR: programming only clears bits
        }
        Ok(())
    }
}

/// A sub-range `[base, base + len)` of a bigger flash, addressed from 0.
#[derive(Debug)]
pub struct FlashWindow<F> {
    inner: F,
    base: u32,
    len: u32,
}

impl<F: NorFlash> FlashWindow<F> {
    /// A window on `inner`. `base` and `len` must be whole erase pages of
    /// `inner` and lie inside it.
    ///
    /// ```
    /// use embedded_storage::nor_flash::{NorFlash, ReadNorFlash};
    /// use sensor_box::storage::{FlashWindow, MemFlash};
    /// let mut mem = [0xFFu8; 4096];
    /// let mut w = FlashWindow::new(MemFlash::new(&mut mem), 2048, 1024)?;
    /// w.write(0, &[0, 0, 0, 0])?;
    /// assert_eq!(w.capacity(), 1024);
    /// drop(w);
    /// assert_eq!(&mem[2048..2052], &[0, 0, 0, 0]);
    /// # Ok::<(), sensor_box::storage::Error>(())
    /// ```
    pub fn new(inner: F, base: u32, len: u32) -> Result<Self, Error> {
        let page = u32::try_from(F::ERASE_SIZE).map_err(|_| Error::NotAligned)?;
        if page == 0 || !base.is_multiple_of(page) || !len.is_multiple_of(page) {
            return Err(Error::NotAligned);
        }
        let end = base.checked_add(len).ok_or(Error::OutOfBounds)?;
        if usize::try_from(end).map_or(true, |e| e > inner.capacity()) {
            return Err(Error::OutOfBounds);
        }
        Ok(Self { inner, base, len })
    }

    /// Gives the flash back.
    ///
    /// ```
    /// # use sensor_box::storage::{FlashWindow, MemFlash};
    /// let mut mem = [0u8; 1024];
    /// let w = FlashWindow::new(MemFlash::new(&mut mem), 0, 1024)?;
    /// let _flash: MemFlash = w.into_inner();
    /// # Ok::<(), sensor_box::storage::Error>(())
    /// ```
    pub fn into_inner(self) -> F {
        self.inner
    }

    fn translate(&self, offset: u32, len: usize) -> Result<u32, Error> {
        let len = u32::try_from(len).map_err(|_| Error::OutOfBounds)?;
        let end = offset.checked_add(len).ok_or(Error::OutOfBounds)?;
        if end > self.len {
            return Err(Error::OutOfBounds);
        }
        self.base.checked_add(offset).ok_or(Error::OutOfBounds)
    }
}

impl<F: NorFlash> ErrorType for FlashWindow<F> {
    type Error = Error;
}

impl<F: NorFlash> ReadNorFlash for FlashWindow<F> {
    const READ_SIZE: usize = F::READ_SIZE;

    fn read(&mut self, offset: u32, bytes: &mut [u8]) -> Result<(), Error> {
        let at = self.translate(offset, bytes.len())?;
        self.inner
            .read(at, bytes)
            .map_err(|e| Error::from_flash(&e))
    }

    fn capacity(&self) -> usize {
        usize::try_from(self.len).unwrap_or(0)
    }
}

impl<F: NorFlash> NorFlash for FlashWindow<F> {
    const WRITE_SIZE: usize = F::WRITE_SIZE;
    const ERASE_SIZE: usize = F::ERASE_SIZE;

    fn erase(&mut self, from: u32, to: u32) -> Result<(), Error> {
        let len = to.checked_sub(from).ok_or(Error::OutOfBounds)?;
        let start = self.translate(from, usize::try_from(len).map_err(|_| Error::OutOfBounds)?)?;
        let end = start.checked_add(len).ok_or(Error::OutOfBounds)?;
        self.inner
            .erase(start, end)
            .map_err(|e| Error::from_flash(&e))
    }

    fn write(&mut self, offset: u32, bytes: &[u8]) -> Result<(), Error> {
        let at = self.translate(offset, bytes.len())?;
        self.inner
            .write(at, bytes)
            .map_err(|e| Error::from_flash(&e))
    }
}

/// Errors of the flash stores in this module.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(all(feature = "defmt", target_os = "none"), derive(defmt::Format))]
pub enum Error {
    /// A flash access outside the store.
    OutOfBounds,
    /// A flash offset or length that is not a multiple of the write or erase size.
    NotAligned,
    /// The flash hardware reported a failure (programming, erase, protection).
    Device,
}

impl core::fmt::Display for Error {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            Error::OutOfBounds => "flash access out of bounds",
            Error::NotAligned => "flash access not aligned",
            Error::Device => "flash device failure",
        })
    }
}

impl core::error::Error for Error {}

impl NorFlashError for Error {
    fn kind(&self) -> NorFlashErrorKind {
        match self {
            Error::OutOfBounds => NorFlashErrorKind::OutOfBounds,
            Error::NotAligned => NorFlashErrorKind::NotAligned,
            Error::Device => NorFlashErrorKind::Other,
        }
    }
}

impl Error {
    /// Maps any NOR flash error onto this crate's error.
    ///
    /// ```
    /// use embedded_storage::nor_flash::NorFlashErrorKind;
    /// use sensor_box::storage::Error;
    /// assert_eq!(Error::from_flash(&NorFlashErrorKind::Other), Error::Device);
    /// ```
    pub fn from_flash<E: NorFlashError>(e: &E) -> Error {
        match e.kind() {
            NorFlashErrorKind::OutOfBounds => Error::OutOfBounds,
            NorFlashErrorKind::NotAligned => Error::NotAligned,
            _ => Error::Device,
        }
    }
}
