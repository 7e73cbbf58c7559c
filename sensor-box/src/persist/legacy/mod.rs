//! The settings store of format versions 1 to 3: one [`Persisted`] record per image, in two
//! areas. The firmware reads it once, to migrate it into the settings map (see the
//! [parent module](super)), and writes it only to move its newest image out of the map's
//! range before the migration erases that range.
//!
//! # Store layout
//!
//! The store is split into two equal areas, A (the first half) and B, each a whole number of
//! erase pages (QEMU: two 2 KiB halves of the 4 KiB store; STM32F411: sectors 6 and 7). Images
//! are appended in an area one after the other, each at a multiple of [`align`] bytes, with a
//! sequence number one above the newest image's. Loading takes the valid image with the
//! highest sequence number of both areas. Storing appends the image past the last byte of the
//! newest image's area that is not erased (so never over bytes a torn write may have
//! touched); when it does not fit, it erases the other area and writes the image at its
//! start. A power cut at any point leaves the newest image before the store intact: an erase
//! only ever hits the area that does not hold it, and a write only bytes that were erased.
//! A 128 KiB sector holds 86 images of the largest record (394 of the default one), so a
//! sector is erased once per 86 stores or fewer (see `docs/RELIABILITY.md`, "Power cuts and
//! flash wear").
//!
//! # Image layout
//!
//! All fields little-endian:
//!
//! | offset | size | field |
//! |---|---|---|
//! | 0 | 4 | magic `"SBOX"` ([`MAGIC`]) |
//! | 4 | 2 | format version ([`VERSION`] = 3; 1 and 2 are still read, see below) |
//! | 6 | 2 | reserved, 0 |
//! | 8 | 4 | payload length `n`, bytes (1..=[`PAYLOAD_MAX`]) |
//! | 12 | 4 | sequence number (the first image 1, each store one more) |
//! | 16 | 4 | CRC-32/ISO-HDLC over bytes 0..16 and the payload |
//! | 20 | `n` | the record, `postcard`-serialised |
//!
//! The image is padded with `0xFF` (the erased value, so padding programs nothing) to a
//! multiple of the flash's `WRITE_SIZE` and written in chunks of [`CHUNK`] bytes. A write cut
//! short leaves an image whose CRC fails: it is skipped, and the image before it loads.
//!
//! # Small stack
//!
//! Neither direction holds the image in RAM. [`store`] encodes the record byte by byte into
//! a small sink: to count its bytes, to compute the CRC (twice when there is an image
//! already: the second tells an unchanged record, which is not written again), and to write
//! it to flash through a [`CHUNK`]-byte buffer; then it reads the image back to check the
//! CRC. [`load_into`] finds the newest image and checks CRCs through a [`WINDOW`]-byte
//! window, then decodes the record in place, field by field. The bytes are exactly
//! postcard's encoding of [`Persisted`] (a struct is its fields in order, a fixed-size array
//! its elements in order, a `u32` a varint, an `i32` a zigzag varint, an `f32` 4 bytes
//! little-endian, a `u8` one byte), written and read by hand (`tests/all/persist.rs` checks
//! both against `postcard`): serde's encoder and decoders cost about 1.6 KiB of flash, and
//! decoding the 1.2 KiB record as one serde value would build several copies of its arrays
//! on the stack.
//!
//! # Versions
//!
//! * 3 (current): [`Persisted`] in the A/B layout above.
//! * 2: [`Persisted`], one image at offset 0 of the store with a 16-byte header (bytes 0..12
//!   as above, then the CRC over them and the payload; no sequence number).
//! * 1: as 2, with [`PersistedV1`], the record before the AOK debug period setting existed.
//!   It loads with its values and the missing field at its default
//!   ([`PersistedV1::migrate`]).
//!
//! A version 1 or 2 image is read only at the start of an area (where the firmware before the
//! A/B layout wrote it: offset 0 of the QEMU store, the start of sector 7 on the STM32F411,
//! which is area B), as older than every version 3 image; the next store appends a version 3
//! image after it. An image of a newer version (a store written by a newer firmware) is
//! skipped: the newest image this firmware can read loads, else the defaults.
//!
//! # Files
//!
//! This file is the record format: the header constants, the versions and their migrations,
//! the errors. `load.rs` finds and reads an image in flash, `store.rs` writes one.
//!
//! ```
//! use sensor_box::storage::MemFlash;
//! use sensor_box::{Persisted, persist};
//!
//! let mut mem = [0u8; 4096];
//! let mut flash = MemFlash::new(&mut mem);
//! assert_eq!(persist::legacy::load(&mut flash).map(|l| l.version), Err(persist::StoreError::Empty));
//!
//! let mut record = Persisted::default();
//! record.settings.airspeed_mps = 61.5;
//! assert_eq!(persist::legacy::store(&mut flash, &record)?, persist::legacy::Stored::Erased);
//! assert_eq!(persist::legacy::load(&mut flash)?.record, record);
//! assert_eq!(persist::legacy::store(&mut flash, &record)?, persist::legacy::Stored::Unchanged);
//! record.settings.airspeed_mps = 55.0;
//! assert_eq!(persist::legacy::store(&mut flash, &record)?, persist::legacy::Stored::Appended);
//! # Ok::<(), persist::StoreError>(())
//! ```

mod load;
mod store;

pub use load::{load, load_into};
pub use store::{Stored, newest_area, store, store_in_other_area, write_image};

use super::StoreError;
use crate::Persisted;
use crate::state::{AOK_FLASH_WAYPOINTS, AOK_PARAMS, AOK_SETS, AokFlash, Intervals, Settings};
use crc::{CRC_32_ISO_HDLC, Crc, NoTable};
use serde::{Deserialize, Serialize};

/// `"SBOX"`: marks a sensor-box settings image.
pub const MAGIC: u32 = u32::from_le_bytes(*b"SBOX");
/// The format version [`store`] writes.
pub const VERSION: u16 = 3;
/// The oldest format version [`load`] still reads.
pub const OLDEST_VERSION: u16 = 1;
/// Bytes before the payload (version 3).
pub const HEADER_LEN: usize = 20;
/// Bytes before the payload in versions 1 and 2 (no sequence number).
pub const LEGACY_HEADER_LEN: usize = 16;

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
/// Read window of [`load_into`] and [`store`], bytes: holds an image header (20 bytes) from
/// any offset, for a `READ_SIZE` up to 64.
pub const WINDOW: usize = 128;
/// Largest `READ_SIZE` / `WRITE_SIZE` the store handles.
const UNIT_MAX: usize = 64;

/// CRC-32/ISO-HDLC (the zlib / Ethernet CRC-32): 32 bits make a torn or bit-flipped image
/// pass with odds of 2^-32 and catch every burst up to 32 bits; it is the CRC every host
/// tool already has (`zlib.crc32`, `binascii.crc32` in Python), so a flash dump can be
/// checked on a PC. Computed bitwise (`NoTable`): the image is checked once at boot and
/// twice per store, so the 1 KiB lookup table would cost flash for no useful speed.
static CRC: Crc<u32, NoTable> = Crc::<u32, NoTable>::new(&CRC_32_ISO_HDLC);

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
    /// use sensor_box::{Settings, persist::legacy::SettingsV1, state::Intervals};
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
    /// use sensor_box::persist::legacy::{PersistedV1, SettingsV1};
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

/// Where images may start in an area: a multiple of this many bytes, the flash's write
/// unit and at least 4.
///
/// ```
/// assert_eq!(sensor_box::persist::legacy::align(1), 4);
/// assert_eq!(sensor_box::persist::legacy::align(8), 8);
/// ```
pub const fn align(write_size: usize) -> usize {
    if write_size > 4 { write_size } else { 4 }
}

/// The length of each of the two areas of a `capacity`-byte store with `erase`-byte pages:
/// half the store, rounded down to whole pages.
fn area_len(capacity: usize, erase: usize, write: usize) -> Result<usize, StoreError> {
    let erase = erase.max(1);
    let half = capacity / 2 / erase * erase;
    if half == 0 || !half.is_multiple_of(align(write)) {
        return Err(StoreError::TooLarge);
    }
    Ok(half)
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
