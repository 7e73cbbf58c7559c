//! Writing the image: the record serialised through small postcard flavors (count and CRC,
//! then write in chunks after the erase), then read back to check it.

use super::load::open;
use super::{
    CHUNK, CRC, HEADER_LEN, MAGIC, PAYLOAD_MAX, StoreError, VERSION, offset, round_up, unit_ok,
};
use crate::Persisted;
use crc::{Digest, NoTable};
use embedded_storage::nor_flash::NorFlash;
use postcard::ser_flavors::Flavor;
use serde::Serialize;

/// Counts the serialised bytes and feeds them to a CRC.
struct Measure<'c> {
    len: usize,
    digest: Digest<'c, u32, NoTable>,
}

impl Flavor for Measure<'_> {
    type Output = (usize, u32);

    fn try_push(&mut self, data: u8) -> postcard::Result<()> {
        self.try_extend(&[data])
    }

    fn try_extend(&mut self, data: &[u8]) -> postcard::Result<()> {
        self.len = self.len.saturating_add(data.len());
        self.digest.update(data);
        Ok(())
    }

    fn finalize(self) -> postcard::Result<(usize, u32)> {
        Ok((self.len, self.digest.finalize()))
    }
}

/// Writes the bytes to flash from offset 0 through a [`CHUNK`]-byte buffer.
struct Writer<'f, F> {
    flash: &'f mut F,
    buf: [u8; CHUNK],
    fill: usize,
    at: usize,
}

impl<F: NorFlash> Writer<'_, F> {
    /// Writes the buffer, padded with 0xFF to the write unit.
    fn flush(&mut self) -> Result<(), StoreError> {
        let n = round_up(self.fill, F::WRITE_SIZE).ok_or(StoreError::TooLarge)?;
        if let Some(pad) = self.buf.get_mut(self.fill..n) {
            pad.fill(0xFF);
        }
        let data = self.buf.get(..n).ok_or(StoreError::Unsupported)?;
        if !data.is_empty() {
            self.flash
                .write(offset(self.at)?, data)
                .map_err(|_| StoreError::Flash)?;
        }
        self.at = self.at.saturating_add(n);
        self.fill = 0;
        Ok(())
    }
}

impl<F: NorFlash> Flavor for Writer<'_, F> {
    type Output = ();

    fn try_push(&mut self, data: u8) -> postcard::Result<()> {
        if let Some(slot) = self.buf.get_mut(self.fill) {
            *slot = data;
            self.fill = self.fill.saturating_add(1);
        }
        if self.fill >= CHUNK {
            self.flush()
                .map_err(|_| postcard::Error::SerializeBufferFull)?;
        }
        Ok(())
    }

    fn finalize(mut self) -> postcard::Result<()> {
        self.flush()
            .map_err(|_| postcard::Error::SerializeBufferFull)
    }
}

/// Writes the record in the current format ([`VERSION`]).
///
/// # Errors
/// [`StoreError::TooLarge`] if the image does not fit the store, [`StoreError::Flash`] if the
/// driver failed, [`StoreError::Verify`] if the flash does not read back the image,
/// [`StoreError::Unsupported`] for a read or write unit above 64 bytes.
///
/// ```
/// use sensor_box::storage::MemFlash;
/// use sensor_box::{Persisted, persist};
/// let mut mem = [0u8; 4096];
/// let mut flash = MemFlash::new(&mut mem);
/// let mut record = Persisted::default();
/// record.settings.intervals.gps_ms = 200;
/// persist::store(&mut flash, &record)?;
/// assert_eq!(persist::load(&mut flash)?.record.settings.intervals.gps_ms, 200);
/// # Ok::<(), persist::StoreError>(())
/// ```
pub fn store<F: NorFlash>(flash: &mut F, record: &Persisted) -> Result<(), StoreError> {
    write_image(flash, VERSION, record)
}

/// Writes any serialisable record as an image of format `version`. [`store`] uses it with
/// [`VERSION`]; tests use it to write older formats (e.g. a [`PersistedV1`](super::PersistedV1) as version 1).
///
/// # Errors
/// As [`store`].
///
/// ```
/// use sensor_box::storage::MemFlash;
/// use sensor_box::persist::{self, PersistedV1, SettingsV1};
/// use sensor_box::state::{AokFlash, Intervals};
/// let mut mem = [0u8; 4096];
/// let mut flash = MemFlash::new(&mut mem);
/// let old = PersistedV1 {
///     settings: SettingsV1 { intervals: Intervals::SPEC, airspeed_mps: 40.0, bank_deg: 10.0, altitude_m: 500.0 },
///     aok: AokFlash::default(),
/// };
/// persist::write_image(&mut flash, 1, &old)?;
/// let loaded = persist::load(&mut flash)?;
/// assert_eq!(loaded.version, 1);
/// assert_eq!(loaded.record.settings.airspeed_mps, 40.0);
/// # Ok::<(), persist::StoreError>(())
/// ```
pub fn write_image<F: NorFlash, T: Serialize + ?Sized>(
    flash: &mut F,
    version: u16,
    record: &T,
) -> Result<(), StoreError> {
    if !unit_ok(F::WRITE_SIZE) || !unit_ok(F::READ_SIZE) {
        return Err(StoreError::Unsupported);
    }
    // Pass 1: the payload length.
    let measure = Measure {
        len: 0,
        digest: CRC.digest(),
    };
    let (len, _) =
        postcard::serialize_with_flavor(record, measure).map_err(|_| StoreError::TooLarge)?;
    if len > PAYLOAD_MAX {
        return Err(StoreError::TooLarge);
    }
    let mut head = [0u8; HEADER_LEN];
    head[0..4].copy_from_slice(&MAGIC.to_le_bytes());
    head[4..6].copy_from_slice(&version.to_le_bytes());
    head[8..12].copy_from_slice(&offset(len)?.to_le_bytes());

    // Pass 2: the CRC over header bytes 0..12, then the payload.
    let mut digest = CRC.digest();
    digest.update(&head[..12]);
    let measure = Measure { len: 0, digest };
    let (_, crc) =
        postcard::serialize_with_flavor(record, measure).map_err(|_| StoreError::TooLarge)?;
    head[12..16].copy_from_slice(&crc.to_le_bytes());

    let padded = round_up(HEADER_LEN + len, F::WRITE_SIZE).ok_or(StoreError::TooLarge)?;
    let erase_end = round_up(padded, F::ERASE_SIZE).ok_or(StoreError::TooLarge)?;
    if erase_end > flash.capacity() {
        return Err(StoreError::TooLarge);
    }
    flash
        .erase(0, offset(erase_end)?)
        .map_err(|_| StoreError::Flash)?;

    // Pass 3: header and payload to flash.
    let mut writer = Writer {
        flash: &mut *flash,
        buf: [0xFF; CHUNK],
        fill: 0,
        at: 0,
    };
    for &b in &head {
        writer.try_push(b).map_err(|_| StoreError::Flash)?;
    }
    postcard::serialize_with_flavor(record, writer).map_err(|_| StoreError::Flash)?;

    // Read back: the image must be there, CRC and all.
    match open(flash, false) {
        Ok(_) => Ok(()),
        Err(_) => Err(StoreError::Verify),
    }
}
