//! Reading: the newest valid image found by walking both areas, its header and CRC checked
//! through a small window, then the record decoded in place, field by field.

use super::{
    CRC, HEADER_LEN, LEGACY_HEADER_LEN, Loaded, MAGIC, OLDEST_VERSION, PAYLOAD_MAX, StoreError,
    VERSION, WINDOW, align, area_len, le_u16, le_u32, offset, round_up, unit_ok,
};
use crate::Persisted;
use crate::state::{
    AOK_FLASH_WAYPOINTS, AOK_PARAMS, AOK_SETS, AokFlash, Intervals, Settings, StoredWaypoint,
};
use embedded_storage::nor_flash::NorFlash;

/// A [`WINDOW`]-byte window on the flash, the image it is looking at, and a decoding position.
pub(super) struct Reader<'f, F> {
    pub(super) flash: &'f mut F,
    buf: [u8; WINDOW],
    /// Flash offset of `buf[0]`.
    base: usize,
    /// Valid bytes in `buf`.
    len: usize,
    /// Next byte to decode (flash offset).
    pos: usize,
    /// The image looked at: where its CRC field is (flash offset) and where it ends.
    crc_at: usize,
    end: usize,
}

/// A valid image: where it is, its format version, sequence number and CRC.
#[derive(Debug, Clone, Copy)]
pub(super) struct Image {
    /// Flash offset of its first byte.
    pub(super) start: usize,
    /// Flash offset just past its payload.
    pub(super) end: usize,
    pub(super) version: u16,
    pub(super) seq: u32,
    pub(super) crc: u32,
}

impl Image {
    fn header_len(&self) -> usize {
        if self.version < 3 {
            LEGACY_HEADER_LEN
        } else {
            HEADER_LEN
        }
    }
}

impl<'f, F: NorFlash> Reader<'f, F> {
    pub(super) fn new(flash: &'f mut F) -> Result<Self, StoreError> {
        if !unit_ok(F::READ_SIZE) {
            return Err(StoreError::Unsupported);
        }
        Ok(Reader {
            flash,
            buf: [0; WINDOW],
            base: 0,
            len: 0,
            pos: 0,
            crc_at: 0,
            end: 0,
        })
    }

    /// Reads the window starting at `at` rounded down to the read unit.
    fn fill(&mut self, at: usize) -> Result<(), StoreError> {
        let unit = F::READ_SIZE.max(1);
        let base = at - at % unit;
        let left = self.flash.capacity().saturating_sub(base);
        let n = WINDOW.min(left);
        let n = n - n % unit;
        let dst = self.buf.get_mut(..n).ok_or(StoreError::Flash)?;
        self.flash
            .read(offset(base)?, dst)
            .map_err(|_| StoreError::Flash)?;
        self.base = base;
        self.len = n;
        Ok(())
    }

    /// The `n` bytes from flash offset `at`, read into the window if they are not in it. The
    /// caller keeps `at + n` within the flash (else the tail is stale).
    fn window(&mut self, at: usize, n: usize) -> Result<&[u8], StoreError> {
        let stop = at.saturating_add(n);
        if at < self.base || stop > self.base.saturating_add(self.len) {
            self.fill(at)?;
        }
        let lo = at.saturating_sub(self.base);
        self.buf
            .get(lo..lo.saturating_add(n))
            .ok_or(StoreError::Flash)
    }

    /// The image bytes held in the window from flash offset `from` (up to the image end).
    fn held(&self, from: usize) -> &[u8] {
        let stop = self.end.min(self.base.saturating_add(self.len));
        let lo = from.saturating_sub(self.base);
        let hi = stop.saturating_sub(self.base);
        self.buf.get(lo..hi).unwrap_or(&[])
    }

    /// The CRC of the image from `start` to its end, without its CRC field, read window by
    /// window.
    fn image_crc(&mut self, start: usize) -> Result<u32, StoreError> {
        let mut digest = CRC.digest();
        let mut at = start;
        while at < self.end {
            if at != self.base {
                self.fill(at)?;
            }
            let held = self.held(at);
            if held.is_empty() {
                return Err(StoreError::Flash);
            }
            let before = self.crc_at.saturating_sub(at).min(held.len());
            let after = (self.crc_at + 4).saturating_sub(at).min(held.len());
            digest.update(held.get(..before).unwrap_or(&[]));
            digest.update(held.get(after..).unwrap_or(&[]));
            at = at.saturating_add(held.len());
        }
        Ok(digest.finalize())
    }

    /// The next payload byte.
    fn byte(&mut self) -> Result<u8, StoreError> {
        if self.pos >= self.end {
            return Err(StoreError::Decode);
        }
        if self.pos < self.base || self.pos >= self.base.saturating_add(self.len) {
            self.fill(self.pos)?;
        }
        let b = self
            .buf
            .get(self.pos.wrapping_sub(self.base))
            .copied()
            .ok_or(StoreError::Flash)?;
        self.pos += 1;
        Ok(b)
    }

    /// The next postcard `u32`: a varint of at most 5 bytes, as postcard reads it (the fifth
    /// byte may carry only the top 4 bits).
    fn u32(&mut self) -> Result<u32, StoreError> {
        let mut out = 0u32;
        for i in 0..5 {
            let b = self.byte()?;
            out |= u32::from(b & 0x7F) << (7 * i);
            if b & 0x80 == 0 {
                return if i == 4 && b > 0x0F {
                    Err(StoreError::Decode)
                } else {
                    Ok(out)
                };
            }
        }
        Err(StoreError::Decode)
    }

    /// The next postcard `i32`: a zigzag varint.
    fn i32(&mut self) -> Result<i32, StoreError> {
        let u = self.u32()?;
        Ok(((u >> 1) as i32) ^ -((u & 1) as i32))
    }

    /// The next postcard `f32`: 4 bytes, little-endian.
    fn f32(&mut self) -> Result<f32, StoreError> {
        let mut b = [0u8; 4];
        for x in b.iter_mut() {
            *x = self.byte()?;
        }
        Ok(f32::from_le_bytes(b))
    }

    /// Checks the image at `start`, which must end by `limit`: the header (a version 1 or 2
    /// image only where `legacy`, a version above `newest` is refused) and the CRC.
    pub(super) fn check(
        &mut self,
        start: usize,
        limit: usize,
        legacy: bool,
        newest: u16,
    ) -> Result<Image, StoreError> {
        let head = self.window(start, HEADER_LEN)?;
        if head.iter().all(|&b| b == 0xFF) || head.iter().all(|&b| b == 0) {
            return Err(StoreError::Empty);
        }
        if le_u32(head, 0) != MAGIC {
            return Err(StoreError::BadMagic);
        }
        let version = le_u16(head, 4);
        let len_field = le_u32(head, 8);
        let (hlen, seq) = if version > newest || version < OLDEST_VERSION {
            return Err(StoreError::UnsupportedVersion(version));
        } else if version >= 3 {
            (HEADER_LEN, le_u32(head, 12))
        } else if legacy {
            (LEGACY_HEADER_LEN, 0)
        } else {
            return Err(StoreError::UnsupportedVersion(version));
        };
        let crc = le_u32(head, hlen - 4);
        let len = usize::try_from(len_field).unwrap_or(usize::MAX);
        let end = start.saturating_add(hlen).saturating_add(len);
        if len == 0 || len > PAYLOAD_MAX || end > limit {
            return Err(StoreError::BadLength(len_field));
        }
        self.crc_at = start + hlen - 4;
        self.end = end;
        if self.image_crc(start)? != crc {
            return Err(StoreError::BadCrc);
        }
        Ok(Image {
            start,
            end,
            version,
            seq,
            crc,
        })
    }

    /// Flash offset past the last byte of `base..limit` that is not erased (`0xFF`), rounded
    /// up to [`align`]: everything from there to `limit` is erased.
    pub(super) fn used_end(&mut self, base: usize, limit: usize) -> Result<usize, StoreError> {
        let mut end = limit;
        while end > base {
            let from = end.saturating_sub(WINDOW).max(base);
            let part = self.window(from, end - from)?;
            if let Some(i) = part.iter().rposition(|&b| b != 0xFF) {
                return round_up(from + i + 1, align(F::WRITE_SIZE)).ok_or(StoreError::TooLarge);
            }
            end = from;
        }
        Ok(base)
    }

    /// The newest image of a version this firmware reads, in either area; else why there is
    /// none ([`StoreError::Empty`] when no area holds anything that looks like an image).
    pub(super) fn newest(&mut self) -> Result<Image, StoreError> {
        let half = area_len(self.flash.capacity(), F::ERASE_SIZE, F::WRITE_SIZE)?;
        let step = align(F::WRITE_SIZE);
        let mut best: Option<Image> = None;
        let mut why = StoreError::Empty;
        for base in [0, half] {
            let limit = base + half;
            // An image is longer than a header: none starts in the last header's length
            // of the area (whose window would run past the flash's end).
            let used = self
                .used_end(base, limit)?
                .min(limit.saturating_sub(HEADER_LEN));
            let mut at = base;
            while at < used {
                match self.check(at, limit, at == base, VERSION) {
                    Ok(image) => {
                        at = round_up(image.end, step).ok_or(StoreError::TooLarge)?;
                        if best.is_none_or(|b| image.seq > b.seq) {
                            best = Some(image);
                        }
                    }
                    Err(StoreError::Flash) => return Err(StoreError::Flash),
                    Err(StoreError::Empty) => at += step,
                    Err(StoreError::BadMagic) if at != base => at += step,
                    Err(e) => {
                        why = e;
                        at += step;
                    }
                }
            }
        }
        best.ok_or(why)
    }
}

/// Fails to compile when a field is added to the record: [`decode`] walks the fields by
/// hand and must learn about it.
#[allow(dead_code)]
fn layout_guard(p: &Persisted) {
    let Persisted {
        settings:
            Settings {
                intervals:
                    Intervals {
                        imu_ms: _,
                        pressure_ms: _,
                        gps_ms: _,
                        temp_ms: _,
                        wind_ms: _,
                        info_ms: _,
                    },
                airspeed_mps: _,
                bank_deg: _,
                altitude_m: _,
                aok_debug_period_ms: _,
            },
        aok:
            AokFlash {
                sets: _,
                start_set: _,
                waypoints: _,
            },
    } = p;
    let StoredWaypoint {
        lon: _,
        lat: _,
        action1: _,
        action2: _,
    } = StoredWaypoint::default();
}

/// Decodes the payload field by field, into `record` when given (else only checks it). The
/// record holds four primitive types (`u32` and `i32` varints, `f32`, `u8`), read by hand as
/// postcard writes them (`tests/all/persist.rs` checks both agree): a serde decoder per type
/// costs flash. Version 1's settings are version 2's without the last field.
fn decode<F: NorFlash>(
    r: &mut Reader<'_, F>,
    image: &Image,
    mut record: Option<&mut Persisted>,
) -> Result<(), StoreError> {
    r.pos = image.start + image.header_len();
    r.end = image.end;
    let mut i = [0u32; 6];
    for v in i.iter_mut() {
        *v = r.u32()?;
    }
    let mut f = [0f32; 3];
    for v in f.iter_mut() {
        *v = r.f32()?;
    }
    let aok_debug_period_ms = if image.version >= 2 {
        r.u32()?
    } else {
        Settings::default().aok_debug_period_ms
    };
    if let Some(rec) = record.as_deref_mut() {
        let [airspeed_mps, bank_deg, altitude_m] = f;
        rec.settings = Settings {
            intervals: Intervals::from_array(i),
            airspeed_mps,
            bank_deg,
            altitude_m,
            aok_debug_period_ms,
        };
    }
    for s in 0..AOK_SETS {
        for p in 0..AOK_PARAMS {
            let v = r.i32()?;
            if let Some(slot) = record
                .as_deref_mut()
                .and_then(|rec| rec.aok.sets.get_mut(s))
                .and_then(|set| set.get_mut(p))
            {
                *slot = v;
            }
        }
    }
    let start_set = r.byte()?;
    if let Some(rec) = record.as_deref_mut() {
        rec.aok.start_set = start_set;
    }
    for n in 0..AOK_FLASH_WAYPOINTS {
        let w = StoredWaypoint {
            lon: r.i32()?,
            lat: r.i32()?,
            action1: r.u32()?,
            action2: r.u32()?,
        };
        if let Some(slot) = record
            .as_deref_mut()
            .and_then(|rec| rec.aok.waypoints.get_mut(n))
        {
            *slot = w;
        }
    }
    if r.pos != r.end {
        return Err(StoreError::Decode);
    }
    Ok(())
}

/// Loads the newest valid image's record into `record`, in place; returns the format version
/// it was stored in. On an error `record` is left as it was: the payload is decoded once to
/// check it, and a second time into `record`.
///
/// # Errors
/// [`StoreError::Empty`] for an erased or blank store; when no image is valid, why the last
/// candidate failed: [`StoreError::BadMagic`] (garbage at the start of an area),
/// [`StoreError::UnsupportedVersion`], [`StoreError::BadLength`] or [`StoreError::BadCrc`];
/// [`StoreError::Decode`] when the newest image passes its CRC but is no record;
/// [`StoreError::Flash`] if the driver failed; [`StoreError::Unsupported`] for a read unit
/// above 64 bytes; [`StoreError::TooLarge`] for a store smaller than two erase pages.
///
/// ```
/// use sensor_box::storage::MemFlash;
/// use sensor_box::{Persisted, persist};
/// let mut mem = [0xFFu8; 2048];
/// let mut flash = MemFlash::new(&mut mem);
/// let mut stored = Persisted::default();
/// stored.settings.bank_deg = -12.5;
/// persist::legacy::store(&mut flash, &stored)?;
/// let mut record = Persisted::default();
/// assert_eq!(persist::legacy::load_into(&mut flash, &mut record)?, persist::legacy::VERSION);
/// assert_eq!(record, stored);
/// # Ok::<(), persist::StoreError>(())
/// ```
pub fn load_into<F: NorFlash>(flash: &mut F, record: &mut Persisted) -> Result<u16, StoreError> {
    let mut r = Reader::new(flash)?;
    let image = r.newest()?;
    decode(&mut r, &image, None)?;
    decode(&mut r, &image, Some(record))?;
    Ok(image.version)
}

/// Reads the record and tells why there is none.
///
/// # Errors
/// As [`load_into`].
///
/// ```
/// use sensor_box::storage::MemFlash;
/// use sensor_box::{Persisted, persist};
/// let mut mem = [0xFFu8; 2048];
/// let mut flash = MemFlash::new(&mut mem);
/// persist::legacy::store(&mut flash, &Persisted::default())?;
/// let loaded = persist::legacy::load(&mut flash)?;
/// assert_eq!((loaded.record, loaded.version), (Persisted::default(), persist::legacy::VERSION));
/// # Ok::<(), persist::StoreError>(())
/// ```
pub fn load<F: NorFlash>(flash: &mut F) -> Result<Loaded, StoreError> {
    let mut record = Persisted::default();
    let version = load_into(flash, &mut record)?;
    Ok(Loaded { record, version })
}
