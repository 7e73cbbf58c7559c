//! Reading the image: the header and CRC checked through a small window, then the record
//! decoded in place, field by field.

use super::{
    CRC, HEADER_LEN, Loaded, MAGIC, OLDEST_VERSION, PAYLOAD_MAX, SETTINGS_MAX, SettingsV1,
    StoreError, VERSION, WINDOW, le_u16, le_u32, offset, unit_ok,
};
use crate::Persisted;
use crate::state::{AOK_FLASH_WAYPOINTS, AOK_PARAMS, AOK_SETS, AokFlash, Settings, StoredWaypoint};
use embedded_storage::nor_flash::ReadNorFlash;
use serde::de::DeserializeOwned;

/// A [`WINDOW`]-byte window on the image in flash, and a decoding position in it.
pub(super) struct Reader<'f, F> {
    flash: &'f mut F,
    buf: [u8; WINDOW],
    /// Flash offset of `buf[0]`.
    base: usize,
    /// Valid bytes in `buf`.
    len: usize,
    /// Next byte to decode (flash offset).
    pos: usize,
    /// End of the image (flash offset): nothing at or after it belongs to the record.
    end: usize,
}

impl<'f, F: ReadNorFlash> Reader<'f, F> {
    fn new(flash: &'f mut F) -> Result<Self, StoreError> {
        if !unit_ok(F::READ_SIZE) {
            return Err(StoreError::Unsupported);
        }
        let mut r = Reader {
            flash,
            buf: [0; WINDOW],
            base: 0,
            len: 0,
            pos: 0,
            end: HEADER_LEN,
        };
        r.fill(0)?;
        if r.len < HEADER_LEN {
            return Err(StoreError::Empty);
        }
        Ok(r)
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

    /// The image bytes held in the window from flash offset `from` (up to the image end).
    fn held(&self, from: usize) -> &[u8] {
        let stop = self.end.min(self.base.saturating_add(self.len));
        let lo = from.saturating_sub(self.base);
        let hi = stop.saturating_sub(self.base);
        self.buf.get(lo..hi).unwrap_or(&[])
    }

    /// The CRC of header bytes 0..12 and the payload, read window by window.
    fn image_crc(&mut self) -> Result<u32, StoreError> {
        let mut digest = CRC.digest();
        let mut at = 0;
        while at < self.end {
            if at != self.base {
                self.fill(at)?;
            }
            let held = self.held(at);
            if held.is_empty() {
                return Err(StoreError::Flash);
            }
            if at == 0 {
                // Skip the CRC field itself.
                digest.update(held.get(..12).unwrap_or(&[]));
                digest.update(held.get(HEADER_LEN..).unwrap_or(&[]));
            } else {
                digest.update(held);
            }
            at = at.saturating_add(held.len());
        }
        Ok(digest.finalize())
    }

    /// Decodes the next postcard value.
    fn take<T: DeserializeOwned>(&mut self) -> Result<T, StoreError> {
        let want = self.pos.saturating_add(SETTINGS_MAX).min(self.end);
        if self.pos < self.base || want > self.base.saturating_add(self.len) {
            self.fill(self.pos)?;
        }
        let held = self.held(self.pos);
        let (value, rest) = postcard::take_from_bytes::<T>(held).map_err(|_| StoreError::Decode)?;
        self.pos = self
            .pos
            .saturating_add(held.len().saturating_sub(rest.len()));
        Ok(value)
    }
}

/// Checks the header (the version only if `known_version`) and the CRC; returns the version
/// and a reader at the payload.
pub(super) fn open<F: ReadNorFlash>(
    flash: &mut F,
    known_version: bool,
) -> Result<(u16, Reader<'_, F>), StoreError> {
    let mut r = Reader::new(flash)?;
    let head = r.held(0);
    if head.iter().all(|&b| b == 0xFF) || head.iter().all(|&b| b == 0) {
        return Err(StoreError::Empty);
    }
    if le_u32(head, 0) != MAGIC {
        return Err(StoreError::BadMagic);
    }
    let version = le_u16(head, 4);
    if known_version && !(OLDEST_VERSION..=VERSION).contains(&version) {
        return Err(StoreError::UnsupportedVersion(version));
    }
    let len_field = le_u32(head, 8);
    let crc = le_u32(head, 12);
    let len = usize::try_from(len_field).unwrap_or(usize::MAX);
    let end = HEADER_LEN.saturating_add(len);
    if len == 0 || len > PAYLOAD_MAX || end > r.flash.capacity() {
        return Err(StoreError::BadLength(len_field));
    }
    r.end = end;
    if r.image_crc()? != crc {
        return Err(StoreError::BadCrc);
    }
    r.pos = HEADER_LEN;
    Ok((version, r))
}

/// Fails to compile when a field is added to the record: [`decode`] walks the fields by
/// hand and must learn about it.
#[allow(dead_code)]
fn layout_guard(p: &Persisted) {
    let Persisted {
        settings: _,
        aok:
            AokFlash {
                sets: _,
                start_set: _,
                waypoints: _,
            },
    } = p;
}

/// Decodes the payload field by field, into `record` when given (else only checks it).
fn decode<F: ReadNorFlash>(
    r: &mut Reader<'_, F>,
    version: u16,
    mut record: Option<&mut Persisted>,
) -> Result<(), StoreError> {
    r.pos = HEADER_LEN;
    let settings = if version == VERSION {
        r.take::<Settings>()?
    } else {
        r.take::<SettingsV1>()?.migrate()
    };
    if let Some(rec) = record.as_deref_mut() {
        rec.settings = settings;
    }
    for s in 0..AOK_SETS {
        for p in 0..AOK_PARAMS {
            let v = r.take::<i32>()?;
            if let Some(slot) = record
                .as_deref_mut()
                .and_then(|rec| rec.aok.sets.get_mut(s))
                .and_then(|set| set.get_mut(p))
            {
                *slot = v;
            }
        }
    }
    let start_set = r.take::<u8>()?;
    if let Some(rec) = record.as_deref_mut() {
        rec.aok.start_set = start_set;
    }
    for i in 0..AOK_FLASH_WAYPOINTS {
        let w = r.take::<StoredWaypoint>()?;
        if let Some(slot) = record
            .as_deref_mut()
            .and_then(|rec| rec.aok.waypoints.get_mut(i))
        {
            *slot = w;
        }
    }
    if r.pos != r.end {
        return Err(StoreError::Decode);
    }
    Ok(())
}

/// Loads the record into `record`, in place; returns the format version it was stored in.
/// On an error `record` is left as it was: the payload is decoded once to check it, and a
/// second time into `record`.
///
/// # Errors
/// [`StoreError::Empty`] for an erased or blank store; [`StoreError::BadMagic`],
/// [`StoreError::UnsupportedVersion`], [`StoreError::BadLength`], [`StoreError::BadCrc`] or
/// [`StoreError::Decode`] for a corrupt one; [`StoreError::Flash`] if the driver failed;
/// [`StoreError::Unsupported`] for a read unit above 64 bytes.
///
/// ```
/// use sensor_box::storage::MemFlash;
/// use sensor_box::{Persisted, persist};
/// let mut mem = [0xFFu8; 2048];
/// let mut flash = MemFlash::new(&mut mem);
/// let mut stored = Persisted::default();
/// stored.settings.bank_deg = -12.5;
/// persist::store(&mut flash, &stored)?;
/// let mut record = Persisted::default();
/// assert_eq!(persist::load_into(&mut flash, &mut record)?, persist::VERSION);
/// assert_eq!(record, stored);
/// # Ok::<(), persist::StoreError>(())
/// ```
pub fn load_into<F: ReadNorFlash>(
    flash: &mut F,
    record: &mut Persisted,
) -> Result<u16, StoreError> {
    let (version, mut r) = open(flash, true)?;
    decode(&mut r, version, None)?;
    decode(&mut r, version, Some(record))?;
    Ok(version)
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
/// persist::store(&mut flash, &Persisted::default())?;
/// let loaded = persist::load(&mut flash)?;
/// assert_eq!((loaded.record, loaded.version), (Persisted::default(), persist::VERSION));
/// # Ok::<(), persist::StoreError>(())
/// ```
pub fn load<F: ReadNorFlash>(flash: &mut F) -> Result<Loaded, StoreError> {
    let mut record = Persisted::default();
    let version = load_into(flash, &mut record)?;
    Ok(Loaded { record, version })
}

/// Loads the record, or gives the defaults (and logs a warning) when the store is missing or
/// corrupt. Never panics, whatever the flash holds.
///
/// ```
/// use sensor_box::storage::MemFlash;
/// use sensor_box::{Persisted, persist};
/// let mut mem = [0x5Au8; 1024]; // garbage
/// assert_eq!(persist::load_or_default(&mut MemFlash::new(&mut mem)), Persisted::default());
/// ```
#[inline(always)]
pub fn load_or_default<F: ReadNorFlash>(flash: &mut F) -> Persisted {
    // Inlined, so the record is built where the caller wants it instead of being copied out
    // of this function's frame (1.2 KiB of boot stack).
    let mut record = Persisted::default();
    load_logged(flash, &mut record);
    record
}

/// [`load_into`], and the log line that says what happened.
#[inline(never)]
fn load_logged<F: ReadNorFlash>(flash: &mut F, record: &mut Persisted) {
    match load_into(flash, record) {
        Ok(VERSION) => crate::info!("flash store: settings loaded"),
        Ok(old) => crate::warn!(
            "flash store: settings migrated from version {=u16} to {=u16}",
            old,
            VERSION
        ),
        Err(StoreError::Empty) => {
            crate::warn!("flash store: empty, using the default settings");
        }
        Err(e) => crate::warn!("flash store: {}, using the default settings", e),
    }
}
