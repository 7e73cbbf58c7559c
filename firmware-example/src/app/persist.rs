//! Loading and storing the [`Persisted`] record in flash.
//!
//! STUB: to be implemented (postcard, versioned, with a CRC; see the firmware issue).

use super::Persisted;
use embedded_storage::nor_flash::{NorFlash, ReadNorFlash};

/// Why a store failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StoreError {
    /// The flash driver reported an error.
    Flash,
    /// The record does not fit the store.
    TooLarge,
}

/// Loads the record, or gives the defaults (and logs a warning) when the store is missing or
/// corrupt.
pub fn load_or_default<F: ReadNorFlash>(flash: &mut F) -> Persisted {
    let _ = flash;
    Persisted::default()
}

/// Writes the record.
///
/// # Errors
/// [`StoreError`].
pub fn store<F: NorFlash>(flash: &mut F, record: &Persisted) -> Result<(), StoreError> {
    let _ = (flash, record);
    Ok(())
}
