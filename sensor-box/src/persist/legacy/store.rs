//! Writing an image: the record encoded by hand, byte for byte as postcard encodes it
//! ([`encode`]), into a sink that counts and CRCs the bytes or writes them to flash in
//! chunks, after the newest image or at the start of the freshly erased other area; then the
//! image is read back to check it.

use super::load::Reader;
use super::{
    CHUNK, CRC, HEADER_LEN, MAGIC, PAYLOAD_MAX, StoreError, VERSION, align, area_len, offset,
    round_up, unit_ok,
};
use crate::Persisted;
use crate::state::{AokFlash, Settings, StoredWaypoint};
use crc::{Digest, NoTable};
use embedded_storage::nor_flash::NorFlash;

/// Where encoded bytes go. One `dyn` interface, so that [`encode`] is compiled once for the
/// three passes of a store (count, CRC, write).
trait Sink {
    fn put(&mut self, b: u8);
}

/// A payload [`write_image`] can write: the record, or raw bytes (tests).
trait Payload {
    fn emit(&self, out: &mut dyn Sink);
}

impl Payload for Persisted {
    fn emit(&self, out: &mut dyn Sink) {
        encode(self, out);
    }
}

impl Payload for [u8] {
    fn emit(&self, out: &mut dyn Sink) {
        for &b in self {
            out.put(b);
        }
    }
}

/// A postcard varint: 7 bits a byte, least significant first, the top bit set on every byte
/// but the last.
fn varint(out: &mut dyn Sink, mut v: u32) {
    while v > 0x7F {
        out.put(v as u8 | 0x80);
        v >>= 7;
    }
    out.put(v as u8);
}

/// A postcard `i32`: zigzagged (0, -1, 1, -2, ... as 0, 1, 2, 3, ...), then a varint.
fn zigzag(out: &mut dyn Sink, v: i32) {
    varint(out, ((v << 1) ^ (v >> 31)) as u32);
}

/// A postcard `f32`: 4 bytes, little-endian.
fn float(out: &mut dyn Sink, v: f32) {
    for b in v.to_le_bytes() {
        out.put(b);
    }
}

/// The record, exactly as `postcard` serialises [`Persisted`] (`tests/all/persist.rs` checks
/// both agree, for the defaults and random records): a struct is its fields in order, a
/// fixed-size array its elements in order, `u32` a varint, `i32` a zigzag varint, `f32` 4
/// bytes little-endian, `u8` one byte. The pattern names every field, so a field added to
/// the record does not compile until it is written here (and read in `load.rs`).
fn encode(record: &Persisted, out: &mut dyn Sink) {
    let Persisted {
        settings:
            Settings {
                intervals,
                airspeed_mps,
                bank_deg,
                altitude_m,
                aok_debug_period_ms,
            },
        aok: AokFlash {
            sets,
            start_set,
            waypoints,
        },
    } = record;
    // `Intervals::to_array` names every field of the intervals, in their order.
    for v in intervals.to_array() {
        varint(out, v);
    }
    for v in [airspeed_mps, bank_deg, altitude_m] {
        float(out, *v);
    }
    varint(out, *aok_debug_period_ms);
    for v in sets.iter().flatten() {
        zigzag(out, *v);
    }
    out.put(*start_set);
    for StoredWaypoint {
        lon,
        lat,
        action1,
        action2,
    } in waypoints
    {
        zigzag(out, *lon);
        zigzag(out, *lat);
        varint(out, *action1);
        varint(out, *action2);
    }
}

/// Counts the bytes and feeds them to a CRC.
struct Measure<'c> {
    len: usize,
    digest: Digest<'c, u32, NoTable>,
}

impl Sink for Measure<'_> {
    fn put(&mut self, b: u8) {
        self.len = self.len.saturating_add(1);
        self.digest.update(&[b]);
    }
}

/// Writes the bytes to flash from `at` through a [`CHUNK`]-byte buffer. The first failed
/// write stops the writes, and [`Writer::finish`] reports it.
struct Writer<'f, F> {
    flash: &'f mut F,
    buf: [u8; CHUNK],
    fill: usize,
    at: usize,
    failed: bool,
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

    /// Writes what is left in the buffer. [`StoreError::Flash`] if a write failed.
    fn finish(mut self) -> Result<(), StoreError> {
        if self.failed || self.flush().is_err() {
            return Err(StoreError::Flash);
        }
        Ok(())
    }
}

impl<F: NorFlash> Sink for Writer<'_, F> {
    fn put(&mut self, b: u8) {
        if self.failed {
            return;
        }
        if let Some(slot) = self.buf.get_mut(self.fill) {
            *slot = b;
            self.fill = self.fill.saturating_add(1);
        }
        if self.fill >= CHUNK {
            self.failed = self.flush().is_err();
        }
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
/// assert_eq!(persist::legacy::store(&mut flash, &record)?, persist::legacy::Stored::Appended);
/// assert_eq!(persist::legacy::load(&mut flash)?.record.settings.intervals.gps_ms, 200);
/// assert_eq!(persist::legacy::store(&mut flash, &record)?, persist::legacy::Stored::Unchanged);
/// # Ok::<(), persist::StoreError>(())
/// ```
pub fn store<F: NorFlash>(flash: &mut F, record: &Persisted) -> Result<Stored, StoreError> {
    write(flash, VERSION, record, false)
}

/// The area (offsets in the store) that holds the newest image, if any image is valid.
///
/// ```
/// use sensor_box::storage::MemFlash;
/// use sensor_box::{Persisted, persist};
/// let mut mem = [0xFFu8; 4096];
/// let mut flash = MemFlash::new(&mut mem);
/// assert_eq!(persist::legacy::newest_area(&mut flash), None);
/// persist::legacy::store(&mut flash, &Persisted::default())?;
/// assert_eq!(persist::legacy::newest_area(&mut flash), Some(0..2048));
/// # Ok::<(), persist::StoreError>(())
/// ```
pub fn newest_area<F: NorFlash>(flash: &mut F) -> Option<core::ops::Range<u32>> {
    let half = area_len(flash.capacity(), F::ERASE_SIZE, F::WRITE_SIZE).ok()?;
    let image = Reader::new(flash).ok()?.newest().ok()?;
    let base = if image.start >= half { half } else { 0 };
    Some(offset(base).ok()?..offset(base + half).ok()?)
}

/// Writes the record as the newest image at the start of the area that does not hold the
/// newest image, erasing that area first (the migration moves the newest image out of an
/// area it is about to erase). A power cut keeps the newest image before.
///
/// # Errors
/// As [`store`].
///
/// ```
/// use sensor_box::storage::MemFlash;
/// use sensor_box::{Persisted, persist};
/// let mut mem = [0xFFu8; 4096];
/// let mut flash = MemFlash::new(&mut mem);
/// persist::legacy::store(&mut flash, &Persisted::default())?;
/// persist::legacy::store_in_other_area(&mut flash, &Persisted::default())?;
/// assert_eq!(persist::legacy::newest_area(&mut flash), Some(2048..4096));
/// # Ok::<(), persist::StoreError>(())
/// ```
pub fn store_in_other_area<F: NorFlash>(
    flash: &mut F,
    record: &Persisted,
) -> Result<Stored, StoreError> {
    write(flash, VERSION, record, true)
}

/// The payload's length, and the CRC of an image with this header (bytes 0..16) and
/// payload.
fn measure<P: Payload + ?Sized>(head: &[u8], payload: &P) -> (usize, u32) {
    let mut measure = Measure {
        len: 0,
        digest: CRC.digest(),
    };
    measure.digest.update(head);
    payload.emit(&mut measure);
    (measure.len, measure.digest.finalize())
}

/// Writes raw payload bytes as an image of format `version` (in the version 3 layout), as
/// [`store`] writes a record. Tests use it to write images a newer firmware would, or
/// foreign payloads (`postcard::to_slice` of any value gives the bytes of its record).
///
/// # Errors
/// As [`store`].
///
/// ```
/// use sensor_box::storage::MemFlash;
/// use sensor_box::persist;
/// let mut mem = [0xFFu8; 4096];
/// let mut flash = MemFlash::new(&mut mem);
/// persist::legacy::write_image(&mut flash, 9, &[1, 2, 3])?;
/// assert_eq!(persist::legacy::load(&mut flash).map(|l| l.version), Err(persist::StoreError::UnsupportedVersion(9)));
/// # Ok::<(), persist::StoreError>(())
/// ```
pub fn write_image<F: NorFlash>(
    flash: &mut F,
    version: u16,
    payload: &[u8],
) -> Result<Stored, StoreError> {
    write(flash, version, payload, false)
}

/// [`store`] and [`write_image`]: writes the payload as the newest image of format
/// `version`, unless the newest image holds it already; with `other`, always, at the start of
/// the other area.
fn write<F: NorFlash, P: Payload + ?Sized>(
    flash: &mut F,
    version: u16,
    payload: &P,
    other: bool,
) -> Result<Stored, StoreError> {
    if !unit_ok(F::WRITE_SIZE) || !unit_ok(F::READ_SIZE) {
        return Err(StoreError::Unsupported);
    }
    let half = area_len(flash.capacity(), F::ERASE_SIZE, F::WRITE_SIZE)?;
    // Pass 1: the payload length.
    let (len, _) = measure(&[], payload);
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
        if !other
            && n.version == version
            && n.end - n.start == HEADER_LEN + len
            && measure(&head[..16], payload).1 == n.crc
        {
            return Ok(Stored::Unchanged);
        }
        seq = n.seq.wrapping_add(1);
        area = if n.start >= half { half } else { 0 };
    }
    head[12..16].copy_from_slice(&seq.to_le_bytes());
    // Pass 3: the CRC over header bytes 0..16, then the payload.
    let (_, crc) = measure(&head[..16], payload);
    head[16..20].copy_from_slice(&crc.to_le_bytes());

    // Past everything written in the newest image's area, or the start of the other one.
    let mut at = Reader::new(&mut *flash)?.used_end(area, area + half)?;
    let mut done = Stored::Appended;
    if other || at + padded > area + half {
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
        failed: false,
    };
    for &b in &head {
        writer.put(b);
    }
    payload.emit(&mut writer);
    writer.finish()?;

    // Read back: the image must be there, CRC and all.
    match Reader::new(flash)?.check(at, area + half, false, u16::MAX) {
        Ok(_) => Ok(done),
        Err(_) => Err(StoreError::Verify),
    }
}
