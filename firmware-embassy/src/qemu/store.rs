//! The settings store of the QEMU board: `sensor-box`'s [`MemFlash`] over the `.flash_emu`
//! RAM region, with both faces the store task needs.
//!
//! [`links::store`](crate::links::store) takes a flash that is both blocking
//! (`embedded_storage`: the boot, the torn-word guard before a store, the first store into a
//! map without a directory) and async (`embedded_storage_async`: the map's writes and reads
//! during a store). `embassy-embedded-hal`'s `BlockingAsync` gives only the async face, so
//! this wrapper gives both, each call going straight to the RAM copy (nothing ever waits).

use embedded_storage::nor_flash::{ErrorType, NorFlash, ReadNorFlash};
use sensor_box::storage::MemFlash;

/// [`MemFlash`] with the blocking and the async NOR flash traits.
pub struct Store(pub MemFlash<'static>);

impl ErrorType for Store {
    type Error = <MemFlash<'static> as ErrorType>::Error;
}

impl ReadNorFlash for Store {
    const READ_SIZE: usize = MemFlash::READ_SIZE;

    fn read(&mut self, offset: u32, bytes: &mut [u8]) -> Result<(), Self::Error> {
        self.0.read(offset, bytes)
    }

    fn capacity(&self) -> usize {
        self.0.capacity()
    }
}

impl NorFlash for Store {
    const WRITE_SIZE: usize = MemFlash::WRITE_SIZE;
    const ERASE_SIZE: usize = MemFlash::ERASE_SIZE;

    fn erase(&mut self, from: u32, to: u32) -> Result<(), Self::Error> {
        self.0.erase(from, to)
    }

    fn write(&mut self, offset: u32, bytes: &[u8]) -> Result<(), Self::Error> {
        self.0.write(offset, bytes)
    }
}

impl embedded_storage_async::nor_flash::ReadNorFlash for Store {
    const READ_SIZE: usize = MemFlash::READ_SIZE;

    async fn read(&mut self, offset: u32, bytes: &mut [u8]) -> Result<(), Self::Error> {
        self.0.read(offset, bytes)
    }

    fn capacity(&self) -> usize {
        self.0.capacity()
    }
}

impl embedded_storage_async::nor_flash::NorFlash for Store {
    const WRITE_SIZE: usize = MemFlash::WRITE_SIZE;
    const ERASE_SIZE: usize = MemFlash::ERASE_SIZE;

    async fn erase(&mut self, from: u32, to: u32) -> Result<(), Self::Error> {
        self.0.erase(from, to)
    }

    async fn write(&mut self, offset: u32, bytes: &[u8]) -> Result<(), Self::Error> {
        self.0.write(offset, bytes)
    }
}
