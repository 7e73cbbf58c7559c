//! Loading and storing the [`Persisted`] record in flash.
//!
//! # Image layout
//!
//! The record is one image at offset 0 of the store, all fields little-endian:
//!
//! | offset | size | field |
//! |---|---|---|
//! | 0 | 4 | magic `"SBOX"` ([`MAGIC`]) |
//! | 4 | 2 | format version ([`VERSION`] = 2; 1 is still read, see below) |
//! | 6 | 2 | reserved, 0 |
//! | 8 | 4 | payload length `n`, bytes (1..=[`PAYLOAD_MAX`]) |
//! | 12 | 4 | CRC-32/ISO-HDLC over bytes 0..12 and the payload |
//! | 16 | `n` | the record, `postcard`-serialised |
//!
//! The image is padded with `0xFF` (the erased value, so padding programs nothing) to a
//! multiple of the flash's `WRITE_SIZE`, and written in chunks of [`CHUNK`] bytes after
//! erasing the pages it covers. A write cut short by a reset leaves an image whose CRC fails:
//! it then loads as the defaults.
//!
//! # Small stack
//!
//! Neither direction holds the image in RAM. [`store`] serialises the record three times
//! through small postcard flavors: to count its bytes, to compute the CRC, and to write it
//! to flash through a [`CHUNK`]-byte buffer; then it reads the image back to check the CRC.
//! [`load_into`] checks the CRC through a [`WINDOW`]-byte window, then decodes the record in
//! place, field by field: the settings as one postcard value, the AOK arrays one element at
//! a time. The bytes are exactly postcard's encoding of [`Persisted`] (a fixed-size array
//! is its elements in order, a struct its fields in order); decoding the 1.2 KiB record as
//! one serde value would build several copies of its arrays on the stack.
//!
//! # Versions
//!
//! * 2 (current): [`Persisted`].
//! * 1: [`PersistedV1`], the layout before the AOK debug period setting existed. It loads
//!   with its values and the missing field at its default ([`PersistedV1::migrate`]); the
//!   next store writes version 2.
//!
//! Any other version (a store written by a newer firmware) loads as the defaults.
//!
//! ```
//! use firmware_example::MemFlash;
//! use sensor_box::{Persisted, persist};
//!
//! let mut mem = [0u8; 4096];
//! let mut flash = MemFlash::new(&mut mem);
//! assert_eq!(persist::load(&mut flash).map(|l| l.version), Err(persist::StoreError::Empty));
//!
//! let mut record = Persisted::default();
//! record.settings.airspeed_mps = 61.5;
//! persist::store(&mut flash, &record)?;
//! assert_eq!(persist::load_or_default(&mut flash), record);
//! # Ok::<(), persist::StoreError>(())
//! ```

use super::Persisted;
use super::state::{
    AOK_FLASH_WAYPOINTS, AOK_PARAMS, AOK_SETS, AokFlash, Intervals, Settings, StoredWaypoint,
};
use core::fmt;
use crc::{CRC_32_ISO_HDLC, Crc, Digest, NoTable};
use embedded_storage::nor_flash::{NorFlash, ReadNorFlash};
use postcard::ser_flavors::Flavor;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

/// `"SBOX"`: marks a sensor-box settings image.
pub const MAGIC: u32 = u32::from_le_bytes(*b"SBOX");
/// The format version [`store`] writes.
pub const VERSION: u16 = 2;
/// The oldest format version [`load`] still reads.
pub const OLDEST_VERSION: u16 = 1;
/// Bytes before the payload.
pub const HEADER_LEN: usize = 16;

/// Largest postcard varint of a `u32` / zigzagged `i32`, bytes.
const VARINT32_MAX: usize = 5;
/// Largest serialised [`Settings`]: six varint intervals, three `f32`, one varint.
const SETTINGS_MAX: usize = 6 * VARINT32_MAX + 3 * 4 + VARINT32_MAX;
/// Largest serialised [`AokFlash`]: the parameter sets, the start set, the waypoints (four
/// varints each).
const AOK_MAX: usize =
    AOK_SETS * AOK_PARAMS * VARINT32_MAX + 1 + AOK_FLASH_WAYPOINTS * 4 * VARINT32_MAX;
/// Largest payload of either version (version 1 is smaller), bytes.
pub const PAYLOAD_MAX: usize = SETTINGS_MAX + AOK_MAX;
/// Largest image (header and payload, before padding), bytes.
pub const IMAGE_MAX: usize = HEADER_LEN + PAYLOAD_MAX;

/// Write buffer of [`store`], bytes: every write but the last is this long. A multiple of
/// every power-of-two `WRITE_SIZE` up to 64.
pub const CHUNK: usize = 64;
/// Read window of [`load_into`], bytes: holds the largest value decoded at once (the
/// settings, 47 bytes) from any offset, for a `READ_SIZE` up to 64.
pub const WINDOW: usize = 128;
/// Largest `READ_SIZE` / `WRITE_SIZE` the store handles.
const UNIT_MAX: usize = 64;

/// CRC-32/ISO-HDLC (the zlib / Ethernet CRC-32): 32 bits make a torn or bit-flipped image
/// pass with odds of 2^-32 and catch every burst up to 32 bits; it is the CRC every host
/// tool already has (`zlib.crc32`, `binascii.crc32` in Python), so a flash dump can be
/// checked on a PC. Computed bitwise (`NoTable`): the image is checked once at boot and
/// twice per store, so the 1 KiB lookup table would cost flash for no useful speed.
static CRC: Crc<u32, NoTable> = Crc::<u32, NoTable>::new(&CRC_32_ISO_HDLC);

/// Why a load or a store failed (the one error type of the flash store).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum StoreError {
    /// The flash driver reported an error.
    Flash,
    /// The record (padded to the write size, erased by whole pages) does not fit the store,
    /// or its payload is longer than [`PAYLOAD_MAX`].
    TooLarge,
    /// The flash's `READ_SIZE` or `WRITE_SIZE` is above 64 bytes or not a power of two.
    Unsupported,
    /// Load: the store holds no image (erased, or zero RAM after power-on on QEMU).
    Empty,
    /// Load: the first four bytes are not [`MAGIC`].
    BadMagic,
    /// Load: a format version this firmware cannot read.
    UnsupportedVersion(u16),
    /// Load: the payload length is 0, above [`PAYLOAD_MAX`] or beyond the store.
    BadLength(u32),
    /// Load: the CRC does not match.
    BadCrc,
    /// Load: the payload passed the CRC but is not a record of its version.
    Decode,
    /// Store: the flash does not read back what was written.
    Verify,
}

impl fmt::Display for StoreError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StoreError::Flash => f.write_str("flash driver error"),
            StoreError::TooLarge => f.write_str("record does not fit the store"),
            StoreError::Unsupported => f.write_str("flash read or write unit not supported"),
            StoreError::Empty => f.write_str("store is empty"),
            StoreError::BadMagic => f.write_str("store holds no settings image (bad magic)"),
            StoreError::UnsupportedVersion(v) => write!(f, "unsupported store version {v}"),
            StoreError::BadLength(n) => write!(f, "bad payload length {n}"),
            StoreError::BadCrc => f.write_str("store CRC mismatch"),
            StoreError::Decode => f.write_str("store payload does not decode"),
            StoreError::Verify => f.write_str("flash read-back differs from what was written"),
        }
    }
}

impl core::error::Error for StoreError {}

/// [`Settings`] as format version 1 stored them: without `aok_debug_period_ms`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SettingsV1 {
    /// AEOLUS telemetry intervals.
    pub intervals: Intervals,
    /// Simulated true airspeed, m/s.
    pub airspeed_mps: f32,
    /// Simulated bank angle, degrees.
    pub bank_deg: f32,
    /// Simulated altitude, m.
    pub altitude_m: f32,
}

impl SettingsV1 {
    /// The current settings: these values, and the default for what version 1 lacked.
    ///
    /// ```
    /// use sensor_box::{Settings, persist::SettingsV1, state::Intervals};
    /// let old = SettingsV1 { intervals: Intervals::SPEC, airspeed_mps: 40.0, bank_deg: -15.0, altitude_m: 300.0 };
    /// assert_eq!(old.migrate().aok_debug_period_ms, Settings::default().aok_debug_period_ms);
    /// ```
    pub fn migrate(self) -> Settings {
        Settings {
            intervals: self.intervals,
            airspeed_mps: self.airspeed_mps,
            bank_deg: self.bank_deg,
            altitude_m: self.altitude_m,
            ..Settings::default()
        }
    }
}

/// The record of format version 1: [`SettingsV1`], then the AOK data as in version 2.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PersistedV1 {
    /// The settings, version 1.
    pub settings: SettingsV1,
    /// The AOK parameter sets and waypoints (unchanged since version 1).
    pub aok: AokFlash,
}

impl PersistedV1 {
    /// The current record: the version 1 values, and the defaults for what version 1 did
    /// not hold (`aok_debug_period_ms`).
    ///
    /// ```
    /// use sensor_box::persist::{PersistedV1, SettingsV1};
    /// use sensor_box::{Settings, state::{AokFlash, Intervals}};
    /// let old = PersistedV1 {
    ///     settings: SettingsV1 { intervals: Intervals::SPEC, airspeed_mps: 40.0, bank_deg: -15.0, altitude_m: 300.0 },
    ///     aok: AokFlash::default(),
    /// };
    /// let new = old.migrate();
    /// assert_eq!(new.settings.bank_deg, -15.0);
    /// assert_eq!(new.settings.aok_debug_period_ms, Settings::default().aok_debug_period_ms);
    /// ```
    pub fn migrate(self) -> Persisted {
        Persisted {
            settings: self.settings.migrate(),
            aok: self.aok,
        }
    }
}

/// A record read from the store, and the format version it was stored in.
#[derive(Debug, Clone, PartialEq)]
pub struct Loaded {
    /// The record, migrated to the current format.
    pub record: Persisted,
    /// The format version found in the store ([`VERSION`], or an older one that was
    /// migrated).
    pub version: u16,
}

/// `n` rounded up to a multiple of `k` (`k == 0` counts as 1); `None` on overflow.
const fn round_up(n: usize, k: usize) -> Option<usize> {
    let k = if k == 0 { 1 } else { k };
    match n.checked_add(k - 1) {
        Some(m) => Some(m / k * k),
        None => None,
    }
}

/// Whether the store can use a flash with this read or write unit.
const fn unit_ok(unit: usize) -> bool {
    unit.is_power_of_two() && unit <= UNIT_MAX
}

fn le_u16(b: &[u8], at: usize) -> u16 {
    let mut a = [0u8; 2];
    if let Some(s) = b.get(at..at.wrapping_add(2)) {
        a.copy_from_slice(s);
    }
    u16::from_le_bytes(a)
}

fn le_u32(b: &[u8], at: usize) -> u32 {
    let mut a = [0u8; 4];
    if let Some(s) = b.get(at..at.wrapping_add(4)) {
        a.copy_from_slice(s);
    }
    u32::from_le_bytes(a)
}

fn offset(at: usize) -> Result<u32, StoreError> {
    u32::try_from(at).map_err(|_| StoreError::TooLarge)
}

// ------------------------------------------------------------------------------- loading

/// A [`WINDOW`]-byte window on the image in flash, and a decoding position in it.
struct Reader<'f, F> {
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
fn open<F: ReadNorFlash>(
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
/// use firmware_example::MemFlash;
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
/// use firmware_example::MemFlash;
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
/// use firmware_example::MemFlash;
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

// ------------------------------------------------------------------------------- storing

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
/// use firmware_example::MemFlash;
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
/// [`VERSION`]; tests use it to write older formats (e.g. a [`PersistedV1`] as version 1).
///
/// # Errors
/// As [`store`].
///
/// ```
/// use firmware_example::MemFlash;
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
