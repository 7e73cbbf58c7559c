//! Loading and storing the [`Persisted`] record in flash: a power cut at any moment keeps each
//! setting at its value before the store or its new value, a store that returned `Ok` is
//! read by every later boot, and a copy that no longer verifies is counted and logged.
//!
//! # Flash layout
//!
//! The store's flash is split by a [`Layout`] into two ranges:
//!
//! * **The settings map** ([`Layout::map`]): a `sequential-storage` map (CRC per item, power
//!   cut safe, wear levelled over its pages), one item per setting group: the [`Settings`],
//!   each of the five AOK parameter sets, the start set, the 32 waypoint slots in eight items
//!   of four, and the store policy's debt (see below). A store writes only the groups that
//!   differ from the map's.
//! * **The format 1-3 store** ([`Layout::legacy`], module [`legacy`]): the A/B images that the
//!   firmware before the map wrote. It is read only while the map holds no directory, once,
//!   to migrate.
//!
//! | board | map | format 1-3 store |
//! |---|---|---|
//! | QEMU lm3s6965evb (8 KiB of RAM emulating flash, 1 KiB pages) | the first 4 KiB | the last 4 KiB (where the firmware before kept its 4 KiB store) |
//! | STM32F411 | sectors 5 and 6 | sectors 6 and 7 (the old place) |
//! | any other flash ([`Layout::for_flash`]) | the first half, if it is two erase pages or more | the second half (the whole flash when the map does not fit: the format 3 store alone) |
//!
//! # Generations and the directory
//!
//! Each item's value is a generation number (`u32`, little-endian; one more with every write
//! of the group) followed by the group's payload (fixed-width little-endian fields). After the
//! groups, a store writes the directory: its own sequence number and every group's newest
//! generation, as two items (keys `0xD0` and `0xD1`, so that one bad copy leaves the other).
//! The map returns the newest copy of an item that verifies; when that copy's generation is
//! below the directory's, a newer copy existed and no longer verifies (a bit flip at rest, a
//! weak bit): boot uses the older copy, counts the group in [`Boot::corrupt_items`] (AYDP
//! 0x0311) and logs "flash store: N corrupt items, older copies used". A generation above the
//! directory's is a store cut between its groups and its directory: the group holds the new
//! value, which is what the store was writing.
//! The next store writes a group whose copy is older than the directory's even when its value
//! did not change, so a corrupt item is counted at one boot, not at every boot after it.
//!
//! # Read-back
//!
//! Every item written is read back twice through the map and compared with what was written;
//! one that differs (a torn word the write landed on, a weak bit) is written again, up to
//! [`WRITE_ATTEMPTS`] times, else the store fails with [`StoreError::Verify`]. A store that
//! returns `Ok` has every item verified and the directory after them.
//!
//! # Migration from formats 1 to 3
//!
//! Boot loads the map when it holds a directory. Else it loads the format 1-3 store and
//! migrates it: if the newest old image lies in the map's range (STM32F411: sector 6), it is
//! first written again into the other old area with the old writer (a power cut keeps the
//! image it copies); then the map's range is erased, every group written and read back, and
//! the directory written last: it is the marker that says the migration is done. A power cut
//! at any point of it boots the old store again and migrates again; the old store is never
//! erased by the migration (only the old area inside the map's range, after its newest image
//! is safe in the other).
//!
//! # The store policy's debt
//!
//! Each store that writes also writes how far the [store policy](crate::store_policy)'s
//! bucket is from full (ms). Boot restores it, counting only the uptime after it, so a
//! command stream with resets stores no faster than one without.
//!
//! # Blocking and async
//!
//! The map's core is async ([`load_map`], [`store_map`], generic over
//! [`embedded_storage_async::nor_flash::NorFlash`]), so an async board can call it natively.
//! The blocking entry points ([`boot`], [`load_or_default`], [`store`], [`store_in`]) wrap
//! the blocking flash in `embassy_embedded_hal::adapter::BlockingAsync` and run the core with
//! `embassy_futures::block_on`: the blocking driver finishes every operation in its first
//! poll. A board whose store runs in an async task (`firmware-embassy`) awaits
//! [`store_in_async`], the same steps as [`store_in`] with the map's store awaited on the
//! flash's async driver. The map runs uncached: each fetch scans the pages, and no RAM is kept per page or
//! key.
//!
//! ```
//! use sensor_box::storage::MemFlash;
//! use sensor_box::{Persisted, persist};
//!
//! let mut mem = [0xFFu8; 8192];
//! let mut flash = MemFlash::new(&mut mem);
//! let layout = persist::Layout::for_flash(&flash);
//! let boot = persist::boot(&mut flash, &layout);
//! assert_eq!(boot.source, persist::Source::Defaults);
//!
//! let mut record = Persisted::default();
//! record.settings.airspeed_mps = 61.5;
//! assert!(matches!(persist::store(&mut flash, &record)?, persist::Stored::Written(_)));
//! assert_eq!(persist::load_or_default(&mut flash), record);
//! assert_eq!(persist::store(&mut flash, &record)?, persist::Stored::Unchanged);
//! record.settings.airspeed_mps = 55.0;
//! assert_eq!(persist::store(&mut flash, &record)?, persist::Stored::Written(1)); // the settings group
//! # Ok::<(), persist::StoreError>(())
//! ```

pub mod legacy;
mod map;

pub use legacy::{PersistedV1, SettingsV1};
pub use map::{
    Directory, Done, GROUPS, Map, MapLoad, Op, Scratch, Stored, WAYPOINTS_PER_GROUP,
    WRITE_ATTEMPTS, directory as map_directory, load as load_map, open as open_map, run as run_map,
    store as store_map,
};

use crate::Persisted;
#[cfg(doc)]
use crate::state::Settings;
#[cfg(feature = "legacy")]
use crate::storage::FlashWindow;
use core::fmt;
use core::ops::Range;
use embassy_embedded_hal::adapter::BlockingAsync;
use embassy_futures::block_on;
use embedded_storage::nor_flash::NorFlash;

/// Why a load or a store failed (the one error type of the flash store).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum StoreError {
    /// The flash driver reported an error.
    Flash,
    /// A range that does not hold the store: a map range of fewer than two erase pages, a
    /// format 3 image that does not fit one area of the old store (its payload longer than
    /// [`legacy::PAYLOAD_MAX`]), or a layout without a map where only the map can store
    /// (without the feature `legacy`).
    TooLarge,
    /// The flash's `READ_SIZE` or `WRITE_SIZE` is above 64 bytes or not a power of two.
    Unsupported,
    /// Load: the store holds no image (erased, or zero RAM after power-on on QEMU).
    Empty,
    /// Load: the first four bytes are not [`legacy::MAGIC`].
    BadMagic,
    /// Load: a format version this firmware cannot read.
    UnsupportedVersion(u16),
    /// Load: the payload length is 0, above [`legacy::PAYLOAD_MAX`] or beyond the store.
    BadLength(u32),
    /// Load: the CRC does not match.
    BadCrc,
    /// Load: the payload passed the CRC but is not a record of its version.
    Decode,
    /// Store: the flash does not read back what was written (after [`WRITE_ATTEMPTS`] writes
    /// of one item).
    Verify,
    /// The settings map refused the flash range or found it corrupt beyond repair.
    Map,
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
            StoreError::Map => f.write_str("settings map unusable"),
        }
    }
}

impl core::error::Error for StoreError {}

/// Bytes a map needs besides its free page: every group and both directories (1 548 bytes
/// with 8-byte item headers and 4-byte words) twice over, so that recycling a page moves
/// little.
pub const MAP_ROOM: u32 = 3072;

/// Where the settings map and the format 1-3 store lie in the store's flash (offsets in it).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Layout {
    /// The settings map: whole erase pages, at least two. `None`: the format 3 store alone
    /// (a flash too small for both).
    pub map: Option<Range<u32>>,
    /// The format 1-3 store (two areas of whole erase pages). It may overlap the map's
    /// range by its first area (the migration moves its newest image out first).
    pub legacy: Range<u32>,
}

impl Layout {
    /// The layout of a flash of `capacity` bytes with `erase`-byte pages: the map in the first
    /// half and the old store in the second when a half is two pages or more and holds
    /// [`MAP_ROOM`] bytes besides the page the map keeps free, else the old store alone.
    ///
    /// ```
    /// use sensor_box::persist::Layout;
    /// assert_eq!(Layout::halves(8192, 1024), Layout { map: Some(0..4096), legacy: 4096..8192 });
    /// assert_eq!(Layout::halves(4096, 1024), Layout { map: None, legacy: 0..4096 });
    /// ```
    pub const fn halves(capacity: u32, erase: u32) -> Layout {
        let erase = if erase == 0 { 1 } else { erase };
        let half = capacity / 2 / erase * erase;
        if half >= 2 * erase && half - erase >= MAP_ROOM {
            Layout {
                map: Some(0..half),
                legacy: half..2 * half,
            }
        } else {
            Layout {
                map: None,
                legacy: 0..capacity,
            }
        }
    }

    /// [`Layout::halves`] of `flash`.
    ///
    /// ```
    /// use sensor_box::{persist::Layout, storage::MemFlash};
    /// let mut mem = [0xFFu8; 8192];
    /// assert_eq!(Layout::for_flash(&MemFlash::new(&mut mem)).map, Some(0..4096));
    /// ```
    pub fn for_flash<F: NorFlash>(flash: &F) -> Layout {
        let cap = u32::try_from(flash.capacity()).unwrap_or(u32::MAX);
        Layout::halves(cap, u32::try_from(F::ERASE_SIZE).unwrap_or(u32::MAX))
    }
}

/// Where the boot's record came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Source {
    /// The settings map.
    Map,
    /// The format 1-3 store, of this version, migrated into the map.
    Migrated(u16),
    /// The format 1-3 store, of this version, not migrated (no map in the layout, or the
    /// migration failed: the next boot tries again).
    Legacy(u16),
    /// Nothing valid: the defaults.
    Defaults,
}

/// What [`boot`] loaded.
#[derive(Debug, Clone, PartialEq)]
pub struct Boot {
    /// The record.
    pub record: Persisted,
    /// Where it came from.
    pub source: Source,
    /// Groups whose newest copy did not verify, loaded from an older copy (or the default).
    pub corrupt_items: u32,
    /// The store policy's debt stored with the last store, ms.
    pub store_debt_ms: u64,
}

/// Reads of the map's range by [`settle`]: a torn word with one random bit reads the same
/// every time with odds of 2^-15.
const SETTLE_READS: usize = 16;
/// Bytes [`settle`] compares at once.
const SETTLE_CHUNK: usize = 64;

/// Finishes the words that a power cut left torn in the map's range. A cut while a word is
/// programmed (or erased) leaves bits that read differently on every read. The map reads each
/// page's state from one byte of its first and last word, and an item's header once or twice:
/// a torn marker makes a whole page of items come and go between reads, and a torn item
/// header hides the items after it on some reads but not others, so a store that read back
/// fine is not found by a later boot (`tests/all/flash_faults.rs`; the library defect noted in
/// `docs/RELIABILITY.md`). Each chunk of the range is read [`SETTLE_READS`] times; a word that
/// does not read the same every time is programmed with the AND of its reads: the bits the
/// cut was clearing are cleared, which finishes the program the cut interrupted, so every
/// later read, the map's and the next store's, agrees. Runs at boot and before each store.
fn settle<F: NorFlash>(flash: &mut F, range: &Range<u32>) -> Result<u32, StoreError> {
    let word = F::WRITE_SIZE.max(F::READ_SIZE).max(1);
    if !SETTLE_CHUNK.is_multiple_of(word) {
        return Err(StoreError::Unsupported);
    }
    let mut fixed = 0u32;
    let mut at = range.start;
    while at < range.end {
        let n = usize::try_from(range.end - at)
            .unwrap_or(SETTLE_CHUNK)
            .min(SETTLE_CHUNK);
        let mut and = [0xFFu8; SETTLE_CHUNK];
        let mut first = [0u8; SETTLE_CHUNK];
        let mut now = [0u8; SETTLE_CHUNK];
        let mut torn = [false; SETTLE_CHUNK];
        let (Some(a), Some(b)) = (first.get_mut(..n), now.get_mut(..n)) else {
            return Err(StoreError::Unsupported);
        };
        flash.read(at, a).map_err(|_| StoreError::Flash)?;
        for (x, y) in and.iter_mut().zip(a.iter()) {
            *x &= *y;
        }
        for _ in 1..SETTLE_READS {
            flash.read(at, b).map_err(|_| StoreError::Flash)?;
            for (((x, y), z), t) in and
                .iter_mut()
                .zip(b.iter())
                .zip(a.iter())
                .zip(torn.iter_mut())
            {
                *x &= *y;
                *t |= y != z;
            }
        }
        for (w, (bad, fin)) in torn.chunks(word).zip(and.chunks(word)).enumerate() {
            if bad.iter().any(|&t| t) {
                let off = u32::try_from(w * word).map_err(|_| StoreError::TooLarge)?;
                flash
                    .write(at.saturating_add(off), fin)
                    .map_err(|_| StoreError::Flash)?;
                fixed = fixed.saturating_add(1);
            }
        }
        at = at.saturating_add(u32::try_from(n).map_err(|_| StoreError::TooLarge)?);
    }
    Ok(fixed)
}

/// The old store's range of `flash`, addressed from 0.
#[cfg(feature = "legacy")]
fn legacy_window<'f, F: NorFlash>(
    flash: &'f mut F,
    layout: &Layout,
) -> Result<FlashWindow<&'f mut F>, StoreError> {
    let len = layout.legacy.end.saturating_sub(layout.legacy.start);
    FlashWindow::new(flash, layout.legacy.start, len).map_err(|_| StoreError::TooLarge)
}

/// Loads the record: from the map, else from the format 1-3 store (and migrates it), else
/// the defaults; logs which, and any corrupt item. Never panics, whatever the flash holds.
///
/// ```
/// use sensor_box::storage::MemFlash;
/// use sensor_box::{Persisted, persist};
/// let mut mem = [0xFFu8; 8192];
/// let mut flash = MemFlash::new(&mut mem);
/// let layout = persist::Layout::for_flash(&flash);
/// let mut old = Persisted::default();
/// old.settings.bank_deg = -20.0;
/// // A format 3 image, as the firmware before the map wrote it.
/// let mut legacy = sensor_box::storage::FlashWindow::new(&mut flash, 4096, 4096)?;
/// persist::legacy::store(&mut legacy, &old).map_err(|_| sensor_box::storage::Error::Device)?;
/// let boot = persist::boot(&mut flash, &layout);
/// assert_eq!((boot.record.settings.bank_deg, boot.source), (-20.0, persist::Source::Migrated(3)));
/// assert_eq!(persist::boot(&mut flash, &layout).source, persist::Source::Map);
/// # Ok::<(), sensor_box::storage::Error>(())
/// ```
#[inline(always)]
pub fn boot<F: NorFlash>(flash: &mut F, layout: &Layout) -> Boot {
    // Inlined, so the record is built where the caller wants it (1.2 KiB of boot stack).
    let mut record = Persisted::default();
    let info = boot_into(flash, layout, &mut record);
    Boot {
        record,
        source: info.source,
        corrupt_items: info.corrupt_items,
        store_debt_ms: info.store_debt_ms,
    }
}

/// What [`boot_into`] found, besides the record.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BootInfo {
    /// Where the record came from.
    pub source: Source,
    /// Groups whose newest copy did not verify, loaded from an older copy (or the default).
    pub corrupt_items: u32,
    /// The store policy's debt stored with the last store, ms.
    pub store_debt_ms: u64,
}

/// [`boot`] into `record` (which must hold the defaults), in place: the App builds its
/// record once.
///
/// ```
/// use sensor_box::storage::MemFlash;
/// use sensor_box::{Persisted, persist};
/// let mut mem = [0xFFu8; 8192];
/// let mut flash = MemFlash::new(&mut mem);
/// let mut record = Persisted::default();
/// let layout = persist::Layout::for_flash(&flash);
/// let info = persist::boot_into(&mut flash, &layout, &mut record);
/// assert_eq!((info.source, info.corrupt_items), (persist::Source::Defaults, 0));
/// ```
#[inline(never)]
pub fn boot_into<F: NorFlash>(flash: &mut F, layout: &Layout, record: &mut Persisted) -> BootInfo {
    let mut info = BootInfo {
        source: Source::Defaults,
        corrupt_items: 0,
        store_debt_ms: 0,
    };
    if let Some(range) = layout.map.clone() {
        match settle(flash, &range) {
            Ok(0) => {}
            Ok(n) => crate::warn!("flash store: {=u32} torn words finished", n),
            Err(e) => crate::warn!("flash store: reading the map for torn words: {}", e),
        }
        let mut scratch = Scratch::new();
        let found = open_map(BlockingAsync::new(&mut *flash), range)
            .and_then(|mut m| block_on(load_map(&mut m, record, &mut scratch)));
        match found {
            Ok(Some(l)) => {
                info.source = Source::Map;
                info.corrupt_items = l.corrupt;
                info.store_debt_ms = l.debt_ms;
                log_boot(&info);
                return info;
            }
            Ok(_) => {}
            Err(e) => {
                crate::warn!("flash store: settings map: {}", e);
                *record = Persisted::default();
            }
        }
    }
    boot_legacy(flash, layout, record, &mut info);
    log_boot(&info);
    info
}

/// The format 1-3 store, read while the map holds no directory, and migrated into the map
/// (feature `legacy`).
#[cfg(feature = "legacy")]
fn boot_legacy<F: NorFlash>(
    flash: &mut F,
    layout: &Layout,
    record: &mut Persisted,
    info: &mut BootInfo,
) {
    let old = legacy_window(flash, layout).and_then(|mut w| legacy::load_into(&mut w, record));
    match old {
        Ok(version) => {
            info.source = Source::Legacy(version);
            if layout.map.is_some() {
                match migrate(flash, layout, record) {
                    Ok(()) => info.source = Source::Migrated(version),
                    Err(e) => crate::warn!("flash store: migration failed: {}", e),
                }
            }
        }
        Err(StoreError::Empty) => {}
        Err(e) => crate::warn!("flash store: format 1-3 store: {}", e),
    }
}

/// Without the feature `legacy`, the format 1-3 store is not read: a board that never ran a
/// firmware before the map (the QEMU board, whose flash is RAM that starts zeroed) boots with
/// the defaults when the map is empty.
#[cfg(not(feature = "legacy"))]
fn boot_legacy<F: NorFlash>(_: &mut F, _: &Layout, _: &mut Persisted, _: &mut BootInfo) {}

fn log_boot(boot: &BootInfo) {
    match boot.source {
        Source::Map if boot.corrupt_items == 0 => crate::info!("flash store: settings loaded"),
        Source::Map => crate::warn!(
            "flash store: {=u32} corrupt items, older copies used",
            boot.corrupt_items
        ),
        Source::Migrated(v) => crate::warn!(
            "flash store: settings migrated from format {=u16} to the settings map",
            v
        ),
        Source::Legacy(v) => crate::warn!("flash store: settings loaded from format {=u16}", v),
        Source::Defaults => crate::warn!("flash store: empty, using the default settings"),
    }
}

/// Loads the record ([`boot`] over [`Layout::for_flash`]), or the defaults.
///
/// ```
/// use sensor_box::storage::MemFlash;
/// use sensor_box::{Persisted, persist};
/// let mut mem = [0x5Au8; 8192]; // garbage
/// assert_eq!(persist::load_or_default(&mut MemFlash::new(&mut mem)), Persisted::default());
/// ```
pub fn load_or_default<F: NorFlash>(flash: &mut F) -> Persisted {
    let layout = Layout::for_flash(flash);
    boot(flash, &layout).record
}

/// Makes the map hold `record` from scratch: moves the old store's newest image out of the
/// map's range, erases the range, writes every group and the directory.
#[cfg(feature = "legacy")]
fn migrate<F: NorFlash>(
    flash: &mut F,
    layout: &Layout,
    record: &Persisted,
) -> Result<(), StoreError> {
    fresh(flash, layout, record, 0).map(|_| ())
}

fn fresh<F: NorFlash>(
    flash: &mut F,
    layout: &Layout,
    record: &Persisted,
    debt_ms: u64,
) -> Result<Stored, StoreError> {
    let range = layout.map.clone().ok_or(StoreError::TooLarge)?;
    #[cfg(feature = "legacy")]
    {
        let mut w = legacy_window(flash, layout)?;
        if let Some(area) = legacy::newest_area(&mut w) {
            let start = layout.legacy.start.saturating_add(area.start);
            let end = layout.legacy.start.saturating_add(area.end);
            if start < range.end && range.start < end {
                move_out(&mut w, record)?;
            }
        }
    }
    let mut scratch = Scratch::new();
    let mut map = open_map(BlockingAsync::new(&mut *flash), range.clone())?;
    block_on(store_map(
        &mut map,
        record,
        debt_ms,
        Some(range),
        &mut scratch,
    ))
}

/// Writes `record` into the old store's area that does not hold its newest image (feature
/// `legacy`).
#[cfg(feature = "legacy")]
fn move_out<F: NorFlash>(w: &mut F, record: &Persisted) -> Result<(), StoreError> {
    legacy::store_in_other_area(w, record).map(|_| ())
}

/// The format 3 store alone, for a layout without a map (feature `legacy`).
#[cfg(feature = "legacy")]
fn store_legacy<F: NorFlash>(
    flash: &mut F,
    layout: &Layout,
    record: &Persisted,
) -> Result<Stored, StoreError> {
    let mut w = legacy_window(flash, layout)?;
    match legacy::store(&mut w, record)? {
        legacy::Stored::Unchanged => Ok(Stored::Unchanged),
        _ => Ok(Stored::Written(1)),
    }
}

/// Without the feature `legacy`, a layout without a map cannot store.
#[cfg(not(feature = "legacy"))]
fn store_legacy<F: NorFlash>(_: &mut F, _: &Layout, _: &Persisted) -> Result<Stored, StoreError> {
    Err(StoreError::TooLarge)
}

/// Stores `record` ([`store_in`] over [`Layout::for_flash`], no policy debt).
///
/// # Errors
/// As [`store_in`].
///
/// ```
/// use sensor_box::storage::MemFlash;
/// use sensor_box::{Persisted, persist};
/// let mut mem = [0xFFu8; 8192];
/// let mut flash = MemFlash::new(&mut mem);
/// let mut record = Persisted::default();
/// record.aok.start_set = 3;
/// persist::store(&mut flash, &record)?;
/// assert_eq!(persist::load_or_default(&mut flash).aok.start_set, 3);
/// # Ok::<(), persist::StoreError>(())
/// ```
pub fn store<F: NorFlash>(flash: &mut F, record: &Persisted) -> Result<Stored, StoreError> {
    let layout = Layout::for_flash(flash);
    store_in(flash, &layout, record, 0)
}

/// Stores the groups of `record` that changed, and the store policy's `debt_ms` with them;
/// the first store into an empty map (no directory) writes all of them after moving any old
/// image out of the map's range. Without a map in the layout, writes a format 3 image.
///
/// # Errors
/// [`StoreError::Flash`] when the driver fails, [`StoreError::Verify`] when an item does not
/// read back after [`WRITE_ATTEMPTS`] writes, [`StoreError::Map`] when the map is corrupt
/// beyond the library's repair. Every setting then boots with its value before the store or
/// its new one.
///
/// ```
/// use sensor_box::storage::MemFlash;
/// use sensor_box::{Persisted, persist};
/// let mut mem = [0xFFu8; 8192];
/// let mut flash = MemFlash::new(&mut mem);
/// let layout = persist::Layout::for_flash(&flash);
/// persist::store_in(&mut flash, &layout, &Persisted::default(), 120_000)?;
/// assert_eq!(persist::boot(&mut flash, &layout).store_debt_ms, 120_000);
/// # Ok::<(), persist::StoreError>(())
/// ```
pub fn store_in<F: NorFlash>(
    flash: &mut F,
    layout: &Layout,
    record: &Persisted,
    debt_ms: u64,
) -> Result<Stored, StoreError> {
    let Some(range) = layout.map.clone() else {
        return store_legacy(flash, layout, record);
    };
    settle(flash, &range)?;
    let mut scratch = Scratch::new();
    let done = open_map(BlockingAsync::new(&mut *flash), range)
        .and_then(|mut map| block_on(store_map(&mut map, record, debt_ms, None, &mut scratch)));
    match done {
        // No directory: the first store, or a migration that did not finish.
        Err(StoreError::Empty) => fresh(flash, layout, record, debt_ms),
        done => done,
    }
}

/// [`store_in`] for a board whose store runs in an async task (`firmware-embassy`): the same
/// steps, with the map's store ([`store_map`]) awaited on the flash's async driver. The
/// torn-word guard before it (reads of the map's range, and a program for each torn word),
/// the first store into a map without a directory (the old store's newest image moved out of
/// the map's range, the range erased: as [`store_in`]) and a layout without a map go through
/// the blocking driver of the same flash.
///
/// # Errors
/// As [`store_in`].
///
/// ```
/// use embassy_futures::block_on;
/// use sensor_box::storage::{Error, MemFlash};
/// use sensor_box::{Persisted, persist};
/// # use embedded_storage::nor_flash as b;
/// # use embedded_storage_async::nor_flash as a;
/// // A flash with a blocking and an async driver, as `embassy_stm32::flash::Flash<Async>`.
/// struct Both<'m>(MemFlash<'m>);
/// # impl b::ErrorType for Both<'_> { type Error = Error; }
/// # impl b::ReadNorFlash for Both<'_> {
/// #     const READ_SIZE: usize = 1;
/// #     fn read(&mut self, o: u32, x: &mut [u8]) -> Result<(), Error> { b::ReadNorFlash::read(&mut self.0, o, x) }
/// #     fn capacity(&self) -> usize { b::ReadNorFlash::capacity(&self.0) }
/// # }
/// # impl b::NorFlash for Both<'_> {
/// #     const WRITE_SIZE: usize = MemFlash::WORD;
/// #     const ERASE_SIZE: usize = MemFlash::PAGE;
/// #     fn erase(&mut self, f: u32, t: u32) -> Result<(), Error> { b::NorFlash::erase(&mut self.0, f, t) }
/// #     fn write(&mut self, o: u32, x: &[u8]) -> Result<(), Error> { b::NorFlash::write(&mut self.0, o, x) }
/// # }
/// # impl a::ReadNorFlash for Both<'_> {
/// #     const READ_SIZE: usize = 1;
/// #     async fn read(&mut self, o: u32, x: &mut [u8]) -> Result<(), Error> { b::ReadNorFlash::read(&mut self.0, o, x) }
/// #     fn capacity(&self) -> usize { b::ReadNorFlash::capacity(&self.0) }
/// # }
/// # impl a::NorFlash for Both<'_> {
/// #     const WRITE_SIZE: usize = MemFlash::WORD;
/// #     const ERASE_SIZE: usize = MemFlash::PAGE;
/// #     async fn erase(&mut self, f: u32, t: u32) -> Result<(), Error> { b::NorFlash::erase(&mut self.0, f, t) }
/// #     async fn write(&mut self, o: u32, x: &[u8]) -> Result<(), Error> { b::NorFlash::write(&mut self.0, o, x) }
/// # }
/// let mut mem = [0xFFu8; 8192];
/// let mut flash = Both(MemFlash::new(&mut mem));
/// let layout = persist::Layout::halves(8192, 1024);
/// let mut s = persist::Scratch::new();
/// let mut r = Persisted::default();
/// r.settings.bank_deg = -25.0;
/// // The first store: every group, the map's range erased first.
/// let first = block_on(persist::store_in_async(&mut flash, &layout, &r, 90_000, &mut s))?;
/// assert!(matches!(first, persist::Stored::Written(n) if usize::from(n) == persist::GROUPS));
/// r.aok.start_set = 4;
/// let second = block_on(persist::store_in_async(&mut flash, &layout, &r, 0, &mut s))?;
/// assert_eq!(second, persist::Stored::Written(2)); // the start set and the debt
/// let boot = persist::boot(&mut flash, &layout);
/// assert_eq!((boot.record, boot.source, boot.store_debt_ms), (r, persist::Source::Map, 0));
///
/// // The STM32F411's overlap, scaled: a format 3 image in the old store's first area, inside
/// // the map's range, and a map without a directory (a migration that did not finish).
/// let mut mem = [0xFFu8; 8192];
/// let mut flash = Both(MemFlash::new(&mut mem));
/// let layout = persist::Layout { map: Some(0..4096), legacy: 2048..6144 };
/// let mut old = Persisted::default();
/// old.settings.altitude_m = 300.0;
/// let mut w = sensor_box::storage::FlashWindow::new(&mut flash.0, 2048, 4096).map_err(|_| persist::StoreError::TooLarge)?;
/// persist::legacy::store(&mut w, &old)?;
/// assert_eq!(persist::legacy::newest_area(&mut w), Some(0..2048)); // inside the map's range
/// let mut new = old.clone();
/// new.aok.start_set = 1;
/// // The map's first store moves the old image out of the map's range, then writes every group.
/// block_on(persist::store_in_async(&mut flash, &layout, &new, 0, &mut s))?;
/// let mut w = sensor_box::storage::FlashWindow::new(&mut flash.0, 2048, 4096).map_err(|_| persist::StoreError::TooLarge)?;
/// assert_eq!(persist::legacy::newest_area(&mut w), Some(2048..4096)); // moved out first
/// let boot = persist::boot(&mut flash, &layout);
/// assert_eq!((boot.record, boot.source), (new, persist::Source::Map));
/// # Ok::<(), persist::StoreError>(())
/// ```
pub async fn store_in_async<F>(
    flash: &mut F,
    layout: &Layout,
    record: &Persisted,
    debt_ms: u64,
    scratch: &mut Scratch,
) -> Result<Stored, StoreError>
where
    F: NorFlash + embedded_storage_async::nor_flash::NorFlash,
{
    let Some(range) = layout.map.clone() else {
        return store_legacy(flash, layout, record);
    };
    settle(flash, &range)?;
    let done = match open_map(&mut *flash, range) {
        Ok(mut map) => store_map(&mut map, record, debt_ms, None, scratch).await,
        Err(e) => Err(e),
    };
    match done {
        // No directory: the first store, or a migration that did not finish.
        Err(StoreError::Empty) => fresh(flash, layout, record, debt_ms),
        done => done,
    }
}
