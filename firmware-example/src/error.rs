//! The crate's error type.

use core::fmt;
use embedded_storage::nor_flash::{NorFlashError, NorFlashErrorKind};

/// Errors of the board-independent layer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Error {
    /// A flash access outside the store.
    OutOfBounds,
    /// A flash offset or length that is not a multiple of the write or erase size.
    NotAligned,
    /// The flash hardware reported a failure (programming, erase, protection).
    Device,
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
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
    /// use firmware_example::Error;
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
