//! Writing an image: the record serialised through small postcard flavors (count, CRC, then
//! write in chunks after the newest image or at the start of the freshly erased other
//! area), then read back to check it.

use super::load::Reader;
use super::{
    CHUNK, CRC, HEADER_LEN, MAGIC, PAYLOAD_MAX, StoreError, VERSION, align, area_len, offset,
    round_up, unit_ok,
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

/// What a successful [`store`] did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Stored {
    /// The newest image already holds this record: nothing was erased or written.
    Unchanged,
    /// The image was written after the newest one, in its area: no erase.
    Appended,
    /// The newest image's area was full: the other area was erased and the image written at
    /// its start.
    Erased,
}

/// Writes the record in the current format ([`VERSION`]) as the newest image, unless the
/// newest image already holds it. A power cut at any point keeps the image that was newest
/// before (see the [module](super) documentation).
///
/// # Errors
/// [`StoreError::TooLarge`] if the image does not fit one area, [`StoreError::Flash`] if the
/// driver failed, [`StoreError::Verify`] if the flash does not read back the image,
/// [`StoreError::Unsupported`] for a read or write unit above 64 bytes. The newest image
/// before the store still loads after any of them.
///
/// ```
/// use sensor_box::storage::MemFlash;
/// use sensor_box::{Persisted, persist};
/// let mut mem = [0xFFu8; 4096];
/// let mut flash = MemFlash::new(&mut mem);
/// let mut record = Persisted::default();
/// record.settings.intervals.gps_ms = 200;
/// assert_eq!(persist::store(&mut flash, &record)?, persist::Stored::Appended);
/// assert_eq!(persist::load(&mut flash)?.record.settings.intervals.gps_ms, 200);
/// assert_eq!(persist::store(&mut flash, &record)?, persist::Stored::Unchanged);
/// # Ok::<(), persist::StoreError>(())
/// ```
pub fn store<F: NorFlash>(flash: &mut F, record: &Persisted) -> Result<Stored, StoreError> {
    write_image(flash, VERSION, record)
}

/// The CRC of an image of `version` with this header and record.
fn image_crc<T: Serialize + ?Sized>(head: &[u8], record: &T) -> Result<u32, StoreError> {
    let mut digest = CRC.digest();
    digest.update(head);
    let measure = Measure { len: 0, digest };
    let (_, crc) =
        postcard::serialize_with_flavor(record, measure).map_err(|_| StoreError::TooLarge)?;
    Ok(crc)
}

/// Writes any serialisable record as an image of format `version` (in the version 3
/// layout), as [`store`] does. [`store`] uses it with [`VERSION`]; tests use it to write
/// images a newer firmware would, or foreign payloads.
///
/// # Errors
/// As [`store`].
///
/// ```
/// use sensor_box::storage::MemFlash;
/// use sensor_box::{Persisted, persist};
/// let mut mem = [0xFFu8; 4096];
/// let mut flash = MemFlash::new(&mut mem);
/// persist::write_image(&mut flash, 9, &Persisted::default())?;
/// assert_eq!(persist::load(&mut flash).map(|l| l.version), Err(persist::StoreError::UnsupportedVersion(9)));
/// # Ok::<(), persist::StoreError>(())
/// ```
pub fn write_image<F: NorFlash, T: Serialize + ?Sized>(
    flash: &mut F,
    version: u16,
    record: &T,
) -> Result<Stored, StoreError> {
    if !unit_ok(F::WRITE_SIZE) || !unit_ok(F::READ_SIZE) {
        return Err(StoreError::Unsupported);
    }
    let half = area_len(flash.capacity(), F::ERASE_SIZE, F::WRITE_SIZE)?;
    // Pass 1: the payload length.
    let measure = Measure {
        len: 0,
        digest: CRC.digest(),
    };
    let (len, _) =
        postcard::serialize_with_flavor(record, measure).map_err(|_| StoreError::TooLarge)?;
    let padded = round_up(HEADER_LEN + len, align(F::WRITE_SIZE)).ok_or(StoreError::TooLarge)?;
    if len > PAYLOAD_MAX || padded > half {
        return Err(StoreError::TooLarge);
    }
    let mut head = [0u8; HEADER_LEN];
    head[0..4].copy_from_slice(&MAGIC.to_le_bytes());
    head[4..6].copy_from_slice(&version.to_le_bytes());
    head[8..12].copy_from_slice(&offset(len)?.to_le_bytes());

    // The newest image: the record may be in it already; the next goes after it.
    let newest = match Reader::new(&mut *flash)?.newest() {
        Ok(image) => Some(image),
        Err(StoreError::Flash) => return Err(StoreError::Flash),
        Err(_) => None,
    };
    let mut seq = 1;
    let mut area = 0;
    if let Some(n) = newest {
        // Pass 2 (only with an image): this record as that image would hold it.
        head[12..16].copy_from_slice(&n.seq.to_le_bytes());
        if n.version == version
            && n.end - n.start == HEADER_LEN + len
            && image_crc(&head[..16], record)? == n.crc
        {
            return Ok(Stored::Unchanged);
        }
        seq = n.seq.wrapping_add(1);
        area = if n.start >= half { half } else { 0 };
    }
    head[12..16].copy_from_slice(&seq.to_le_bytes());
    // Pass 3: the CRC over header bytes 0..16, then the payload.
    let crc = image_crc(&head[..16], record)?;
    head[16..20].copy_from_slice(&crc.to_le_bytes());

    // Past everything written in the newest image's area, or the start of the other one.
    let mut at = Reader::new(&mut *flash)?.used_end(area, area + half)?;
    let mut done = Stored::Appended;
    if at + padded > area + half {
        area = half - area;
        flash
            .erase(offset(area)?, offset(area + half)?)
            .map_err(|_| StoreError::Flash)?;
        at = area;
        done = Stored::Erased;
    }

    // Pass 4: header and payload to flash.
    let mut writer = Writer {
        flash: &mut *flash,
        buf: [0xFF; CHUNK],
        fill: 0,
        at,
    };
    for &b in &head {
        writer.try_push(b).map_err(|_| StoreError::Flash)?;
    }
    postcard::serialize_with_flavor(record, writer).map_err(|_| StoreError::Flash)?;

    // Read back: the image must be there, CRC and all.
    match Reader::new(flash)?.check(at, area + half, false, u16::MAX) {
        Ok(_) => Ok(done),
        Err(_) => Err(StoreError::Verify),
    }
}
