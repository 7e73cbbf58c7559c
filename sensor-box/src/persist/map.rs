//! The settings map: one `sequential-storage` item per setting group, each with a generation
//! number, two directory items that name every group's newest generation, and a read-back of
//! every item written. This file is the async core (generic over
//! [`embedded_storage_async::nor_flash::NorFlash`]); `mod.rs` drives it from blocking code.

use super::StoreError;
use crate::Persisted;
use crate::state::{AOK_PARAMS, AOK_SETS, StoredWaypoint};
use core::ops::Range;
use embedded_storage_async::nor_flash::NorFlash;
use sequential_storage::cache::{Cache, Uncached};
use sequential_storage::map::{MapConfig, MapStorage};

/// Setting groups, each one map item: the settings, the five AOK parameter sets, the start
/// set, the 32 waypoint slots in eight groups of four, the store policy's debt.
pub const GROUPS: usize = 1 + AOK_SETS + 1 + WAYPOINT_GROUPS + 1;
/// Waypoint slots per item.
pub const WAYPOINTS_PER_GROUP: usize = 4;
/// Waypoint items.
const WAYPOINT_GROUPS: usize = crate::state::AOK_FLASH_WAYPOINTS / WAYPOINTS_PER_GROUP;
/// Largest group payload (a parameter set: 32 `i32`), bytes.
const PAYLOAD_MAX: usize = AOK_PARAMS * 4;
/// An item's value: its generation (`u32`, little-endian), then the payload.
const VALUE_MAX: usize = 4 + PAYLOAD_MAX;
/// A directory's value: its sequence number, then every group's generation.
const DIR_LEN: usize = 4 + 4 * GROUPS;
/// The library's work buffer: the key (one byte) and the largest value, rounded up to a word
/// of up to 16 bytes.
const WORK_LEN: usize = 1 + VALUE_MAX + 15;
/// Keys of the two directory copies.
const DIR_KEYS: [u8; 2] = [0xD0, 0xD1];
/// Writes of one item before a store gives up on it ([`StoreError::Verify`]).
pub const WRITE_ATTEMPTS: usize = 3;
/// Index of the store policy's debt among the groups.
const DEBT_GROUP: usize = GROUPS - 1;

/// The map over `S`, uncached (every fetch scans the pages: no RAM per page or key).
pub type Map<S> = MapStorage<u8, S, Cache<Uncached, Uncached, Uncached, u8>>;

/// The map over `flash` in `range` (whole erase pages, at least two).
///
/// ```
/// use embassy_embedded_hal::adapter::BlockingAsync;
/// use sensor_box::{persist, storage::MemFlash};
/// let mut mem = [0xFFu8; 4096];
/// let mut flash = MemFlash::new(&mut mem);
/// assert!(persist::open_map(BlockingAsync::new(&mut flash), 0..4096).is_ok());
/// assert!(persist::open_map(BlockingAsync::new(&mut flash), 0..1024).is_err()); // one page
/// ```
///
/// # Errors
/// [`StoreError::TooLarge`] when the range is not at least two whole erase pages.
pub fn open<S: NorFlash>(flash: S, range: Range<u32>) -> Result<Map<S>, StoreError> {
    let config = MapConfig::<S>::try_new(range).map_err(|_| StoreError::TooLarge)?;
    Ok(MapStorage::new(flash, config, Cache::new_uncached()))
}

/// The map key of group `g`.
const fn key(g: usize) -> u8 {
    match g {
        0 => 0x01,
        1..=AOK_SETS => 0x10 + (g - 1) as u8,
        6 => 0x18,
        DEBT_GROUP => 0x30,
        _ => 0x20 + (g - 7) as u8,
    }
}

/// The payload length of group `g`, bytes.
const fn payload_len(g: usize) -> usize {
    match g {
        0 => 40,
        1..=AOK_SETS => PAYLOAD_MAX,
        6 => 1,
        DEBT_GROUP => 8,
        _ => WAYPOINTS_PER_GROUP * 16,
    }
}

/// Encodes group `g` of `record` (and the policy `debt_ms`) into `out`; its length.
fn encode(record: &Persisted, debt_ms: u64, g: usize, out: &mut [u8]) -> usize {
    let mut w = Put { out, at: 0 };
    match g {
        0 => {
            let s = &record.settings;
            for v in s.intervals.to_array() {
                w.bytes(&v.to_le_bytes());
            }
            for v in [s.airspeed_mps, s.bank_deg, s.altitude_m] {
                w.bytes(&v.to_le_bytes());
            }
            w.bytes(&s.aok_debug_period_ms.to_le_bytes());
        }
        1..=AOK_SETS => {
            for v in record.aok.sets.get(g - 1).into_iter().flatten() {
                w.bytes(&v.to_le_bytes());
            }
        }
        6 => w.bytes(&[record.aok.start_set]),
        DEBT_GROUP => w.bytes(&debt_ms.to_le_bytes()),
        _ => {
            let first = (g - 7) * WAYPOINTS_PER_GROUP;
            let slots = record
                .aok
                .waypoints
                .get(first..first + WAYPOINTS_PER_GROUP)
                .unwrap_or(&[]);
            for p in slots {
                w.bytes(&p.lon.to_le_bytes());
                w.bytes(&p.lat.to_le_bytes());
                w.bytes(&p.action1.to_le_bytes());
                w.bytes(&p.action2.to_le_bytes());
            }
        }
    }
    w.at
}

/// A bounded writer into a payload buffer.
struct Put<'a> {
    out: &'a mut [u8],
    at: usize,
}

impl Put<'_> {
    fn bytes(&mut self, b: &[u8]) {
        if let Some(dst) = self.out.get_mut(self.at..self.at + b.len()) {
            dst.copy_from_slice(b);
            self.at += b.len();
        }
    }
}

/// The little-endian words of `b`, four bytes each.
fn words(b: &[u8]) -> impl Iterator<Item = [u8; 4]> + '_ {
    b.chunks_exact(4)
        .map(|c| <[u8; 4]>::try_from(c).unwrap_or([0; 4]))
}

/// Decodes group `g` from `p` into `record` (or `debt_ms`). `false` (nothing changed) when
/// the length is not the group's.
fn decode(record: &mut Persisted, debt_ms: &mut u64, g: usize, p: &[u8]) -> bool {
    if p.len() != payload_len(g) {
        return false;
    }
    match g {
        0 => {
            let mut w = [0u32; 10];
            for (d, b) in w.iter_mut().zip(words(p)) {
                *d = u32::from_le_bytes(b);
            }
            let [a, b, c, d, e, f, air, bank, alt, dbg] = w;
            let s = &mut record.settings;
            s.intervals = crate::state::Intervals::from_array([a, b, c, d, e, f]);
            s.airspeed_mps = f32::from_bits(air);
            s.bank_deg = f32::from_bits(bank);
            s.altitude_m = f32::from_bits(alt);
            s.aok_debug_period_ms = dbg;
        }
        1..=AOK_SETS => {
            if let Some(set) = record.aok.sets.get_mut(g - 1) {
                for (d, b) in set.iter_mut().zip(words(p)) {
                    *d = i32::from_le_bytes(b);
                }
            }
        }
        6 => record.aok.start_set = p.first().copied().unwrap_or(0),
        DEBT_GROUP => {
            let mut b = [0u8; 8];
            b.copy_from_slice(p.get(..8).unwrap_or(&[0; 8]));
            *debt_ms = u64::from_le_bytes(b);
        }
        _ => {
            let first = (g - 7) * WAYPOINTS_PER_GROUP;
            let mut w = words(p);
            let slots = record
                .aok
                .waypoints
                .get_mut(first..first + WAYPOINTS_PER_GROUP)
                .unwrap_or(&mut []);
            for slot in slots {
                let mut next = || w.next().map_or(0, u32::from_le_bytes);
                let (lon, lat, action1, action2) = (next(), next(), next(), next());
                *slot = StoredWaypoint {
                    lon: lon as i32,
                    lat: lat as i32,
                    action1,
                    action2,
                };
            }
        }
    }
    true
}

/// The directory: which generation of each group the last complete store wrote.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Directory {
    /// One more with every store that wrote something.
    pub seq: u32,
    /// Each group's generation (0: never written).
    pub gens: [u32; GROUPS],
}

impl Directory {
    fn to_bytes(self) -> [u8; DIR_LEN] {
        let mut b = [0u8; DIR_LEN];
        for (d, v) in b
            .chunks_exact_mut(4)
            .zip(core::iter::once(self.seq).chain(self.gens))
        {
            d.copy_from_slice(&v.to_le_bytes());
        }
        b
    }

    fn from_bytes(b: &[u8]) -> Option<Directory> {
        if b.len() != DIR_LEN {
            return None;
        }
        let mut w = words(b).map(u32::from_le_bytes);
        let seq = w.next()?;
        let mut gens = [0u32; GROUPS];
        for (g, v) in gens.iter_mut().zip(w) {
            *g = v;
        }
        Some(Directory { seq, gens })
    }
}

/// What [`load`] found in the map.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MapLoad {
    /// Groups whose newest copy the directory names did not verify: an older copy (or, with
    /// none, the default) was used.
    pub corrupt: u32,
    /// The store policy's debt stored with the last store, ms.
    pub debt_ms: u64,
}

fn flash_err<E>(e: &sequential_storage::Error<E>) -> StoreError {
    match e {
        sequential_storage::Error::Storage { .. } => StoreError::Flash,
        _ => StoreError::Map,
    }
}

/// The buffers of the map operations, kept by the caller (one frame on the blocking boards)
/// rather than in the futures, so that every operation shares them: the library's work
/// buffer (a key and the largest value, where a fetched value is read in place) and the value
/// being written.
#[derive(Debug)]
pub struct Scratch {
    work: [u8; WORK_LEN],
    item: [u8; VALUE_MAX],
}

impl Scratch {
    /// Zeroed buffers (about 280 bytes).
    ///
    /// ```
    /// let s = sensor_box::persist::Scratch::new();
    /// assert!(core::mem::size_of_val(&s) < 300);
    /// ```
    pub const fn new() -> Self {
        Scratch {
            work: [0; WORK_LEN],
            item: [0; VALUE_MAX],
        }
    }
}

impl Default for Scratch {
    fn default() -> Self {
        Self::new()
    }
}

/// The value of `key`, read into `work` (`None`: no valid item).
async fn fetch<'w, S: NorFlash>(
    map: &mut Map<S>,
    key: u8,
    work: &'w mut [u8; WORK_LEN],
) -> Result<Option<&'w [u8]>, StoreError> {
    match map.fetch_item::<&'w [u8]>(work, &key).await {
        Ok(v) => Ok(v),
        Err(sequential_storage::Error::Storage { .. }) => Err(StoreError::Flash),
        // Corruption the library could not repair reads as no item: the directory tells
        // whether one should have been there.
        Err(_) => Ok(None),
    }
}

/// The generation at the start of a fetched value (0 for a value shorter than one).
fn generation(v: &[u8]) -> u32 {
    v.get(..4)
        .and_then(|b| <[u8; 4]>::try_from(b).ok())
        .map_or(0, u32::from_le_bytes)
}

/// The newest directory of the two copies, if either verifies.
///
/// # Errors
/// [`StoreError::Flash`] when the driver fails.
///
/// ```
/// use embassy_embedded_hal::adapter::BlockingAsync;
/// use embassy_futures::block_on;
/// use sensor_box::{Persisted, persist, storage::MemFlash};
/// let mut mem = [0xFFu8; 4096];
/// let mut flash = MemFlash::new(&mut mem);
/// let mut map = persist::open_map(BlockingAsync::new(&mut flash), 0..4096)?;
/// let mut s = persist::Scratch::new();
/// assert_eq!(block_on(persist::map_directory(&mut map, &mut s))?, None);
/// block_on(persist::store_map(&mut map, &Persisted::default(), 0, Some(0..4096), &mut s))?;
/// assert_eq!(block_on(persist::map_directory(&mut map, &mut s))?.map(|d| d.seq), Some(1));
/// # Ok::<(), persist::StoreError>(())
/// ```
pub async fn directory<S: NorFlash>(
    map: &mut Map<S>,
    s: &mut Scratch,
) -> Result<Option<Directory>, StoreError> {
    let mut best: Option<Directory> = None;
    for k in DIR_KEYS {
        let found = fetch(map, k, &mut s.work).await?;
        if let Some(d) = found.and_then(Directory::from_bytes)
            && best.is_none_or(|b| d.seq > b.seq)
        {
            best = Some(d);
        }
    }
    Ok(best)
}

/// Loads every group into `record`. `Ok(None)`: the map holds no directory (never written, or
/// a migration that did not finish), and `record` is untouched.
///
/// # Errors
/// [`StoreError::Flash`] when the driver fails.
///
/// ```
/// use embassy_embedded_hal::adapter::BlockingAsync;
/// use embassy_futures::block_on;
/// use sensor_box::{Persisted, persist, storage::MemFlash};
/// let mut mem = [0xFFu8; 4096];
/// let mut flash = MemFlash::new(&mut mem);
/// let mut map = persist::open_map(BlockingAsync::new(&mut flash), 0..4096)?;
/// let mut s = persist::Scratch::new();
/// let mut stored = Persisted::default();
/// stored.aok.sets[2][5] = -40;
/// block_on(persist::store_map(&mut map, &stored, 60_000, Some(0..4096), &mut s))?;
/// let mut record = Persisted::default();
/// let found = block_on(persist::load_map(&mut map, &mut record, &mut s))?;
/// assert_eq!(found.map(|l| (l.corrupt, l.debt_ms)), Some((0, 60_000)));
/// assert_eq!(record, stored);
/// # Ok::<(), persist::StoreError>(())
/// ```
pub async fn load<S: NorFlash>(
    map: &mut Map<S>,
    record: &mut Persisted,
    s: &mut Scratch,
) -> Result<Option<MapLoad>, StoreError> {
    let Some(dir) = directory(map, s).await? else {
        return Ok(None);
    };
    let mut out = MapLoad {
        corrupt: 0,
        debt_ms: 0,
    };
    for (g, &want) in dir.gens.iter().enumerate() {
        let got = match fetch(map, key(g), &mut s.work).await? {
            Some(v) if v.len() >= 4 => {
                let payload = v.get(4..).unwrap_or(&[]);
                if decode(record, &mut out.debt_ms, g, payload) {
                    generation(v)
                } else {
                    0
                }
            }
            _ => 0,
        };
        if got < want {
            out.corrupt = out.corrupt.saturating_add(1);
        }
    }
    Ok(Some(out))
}

/// Writes the first `len` bytes of `s.item` under `key`, then reads them back twice; again
/// (up to [`WRITE_ATTEMPTS`] times) while a read differs.
async fn write_verified<S: NorFlash>(
    map: &mut Map<S>,
    key: u8,
    len: usize,
    s: &mut Scratch,
) -> Result<(), StoreError> {
    for _ in 0..WRITE_ATTEMPTS {
        let value = s.item.get(..len).unwrap_or(&[]);
        map.store_item(&mut s.work, &key, &value)
            .await
            .map_err(|e| flash_err(&e))?;
        let mut same = true;
        for _ in 0..2 {
            let back = fetch(map, key, &mut s.work).await?;
            same &= back == s.item.get(..len);
        }
        if same {
            return Ok(());
        }
    }
    Err(StoreError::Verify)
}

/// What a successful store did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Stored {
    /// The map already holds every group as the record has it: nothing was written.
    Unchanged,
    /// This many groups were written (and the directory).
    Written(u8),
}

/// Erases the pages of `range` that are not erased already, one at a time: a migration cut
/// short by a reset (on the STM32F411 the boot that migrates erases up to three 128 KiB
/// sectors, 1 to 4 s each, under an 8 s watchdog) does not erase again what it erased
/// before, so the next boot gets further.
async fn erase_pages<S: NorFlash>(flash: &mut S, range: Range<u32>) -> Result<(), StoreError> {
    let page = u32::try_from(S::ERASE_SIZE).map_err(|_| StoreError::TooLarge)?;
    let mut at = range.start;
    let mut buf = [0u8; 64];
    let unit = S::READ_SIZE.max(1);
    if page == 0 || !buf.len().is_multiple_of(unit) {
        return Err(StoreError::Unsupported);
    }
    while at < range.end {
        let end = at.saturating_add(page).min(range.end);
        let mut blank = true;
        let mut p = at;
        while blank && p < end {
            let n = usize::try_from(end - p).unwrap_or(buf.len()).min(buf.len());
            let chunk = buf.get_mut(..n).ok_or(StoreError::Unsupported)?;
            flash.read(p, chunk).await.map_err(|_| StoreError::Flash)?;
            blank = chunk.iter().all(|&b| b == 0xFF);
            p = p.saturating_add(u32::try_from(n).map_err(|_| StoreError::TooLarge)?);
        }
        if !blank {
            flash.erase(at, end).await.map_err(|_| StoreError::Flash)?;
        }
        at = end;
    }
    Ok(())
}

/// Stores the groups of `record` that differ from the map's (with the policy's `debt_ms`
/// when any does), each read back; then the directory, twice. With `fresh` (the map's
/// range), erases the pages of the range that are not blank first and writes every group
/// (the first store, or a migration).
///
/// # Errors
/// [`StoreError::Flash`] from the driver, [`StoreError::Verify`] when an item never reads
/// back as written, [`StoreError::Map`] for a map the library refuses.
///
/// ```
/// use embassy_embedded_hal::adapter::BlockingAsync;
/// use embassy_futures::block_on;
/// use sensor_box::{Persisted, persist, storage::MemFlash};
/// let mut mem = [0xFFu8; 4096];
/// let mut flash = MemFlash::new(&mut mem);
/// let mut map = persist::open_map(BlockingAsync::new(&mut flash), 0..4096)?;
/// let mut s = persist::Scratch::new();
/// let mut r = Persisted::default();
/// block_on(persist::store_map(&mut map, &r, 0, Some(0..4096), &mut s))?;
/// assert_eq!(block_on(persist::store_map(&mut map, &r, 0, None, &mut s))?, persist::Stored::Unchanged);
/// r.aok.start_set = 2;
/// // The start set, and the debt with it.
/// assert_eq!(block_on(persist::store_map(&mut map, &r, 0, None, &mut s))?, persist::Stored::Written(1));
/// # Ok::<(), persist::StoreError>(())
/// ```
pub async fn store<S: NorFlash>(
    map: &mut Map<S>,
    record: &Persisted,
    debt_ms: u64,
    fresh: Option<Range<u32>>,
    s: &mut Scratch,
) -> Result<Stored, StoreError> {
    let mut dir = Directory {
        seq: 0,
        gens: [0; GROUPS],
    };
    if let Some(range) = fresh.clone() {
        erase_pages(map.flash(), range).await?;
    } else {
        dir = directory(map, s).await?.ok_or(StoreError::Empty)?;
    }
    let mut written = 0u8;
    for g in 0..GROUPS {
        if g == DEBT_GROUP && written == 0 {
            break; // the debt alone is never worth a write
        }
        let n = encode(record, debt_ms, g, s.item.get_mut(4..).unwrap_or(&mut []));
        let total = 4 + n;
        let current = if fresh.is_some() {
            None
        } else {
            fetch(map, key(g), &mut s.work).await?
        };
        let named = dir.gens.get(g).copied().unwrap_or(0);
        let cur_gen = match current {
            Some(v) if v.len() >= 4 => {
                // Unchanged, unless this is an older copy whose newer one no longer verifies:
                // written again, so the corrupt item is counted at one boot, not every boot.
                if v.get(4..) == s.item.get(4..total) && generation(v) >= named {
                    continue;
                }
                generation(v)
            }
            _ => 0,
        };
        let gen_new = named.max(cur_gen).wrapping_add(1);
        if let Some(d) = s.item.get_mut(..4) {
            d.copy_from_slice(&gen_new.to_le_bytes());
        }
        write_verified(map, key(g), total, s).await?;
        if let Some(slot) = dir.gens.get_mut(g) {
            *slot = gen_new;
        }
        written = written.saturating_add(1);
    }
    if written == 0 {
        return Ok(Stored::Unchanged);
    }
    dir.seq = dir.seq.wrapping_add(1);
    let bytes = dir.to_bytes();
    if let Some(d) = s.item.get_mut(..DIR_LEN) {
        d.copy_from_slice(&bytes);
    }
    for k in DIR_KEYS {
        write_verified(map, k, DIR_LEN, s).await?;
    }
    Ok(Stored::Written(written))
}

/// One operation on the map, for a caller that picks the operation at run time ([`run`]). The
/// blocking entry points call [`load`] and [`store`] directly: one dispatching state machine
/// cost the QEMU image about 1 KiB more.
#[derive(Debug)]
pub enum Op<'a> {
    /// [`load`] into the record.
    Load(&'a mut Persisted),
    /// Whether the map holds a [`directory`].
    HasDirectory,
    /// [`store`] the record with the policy's debt (`fresh`: the map's range, to start over).
    Store(&'a Persisted, u64, Option<Range<u32>>),
}

/// What [`run`] did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Done {
    /// [`Op::Load`]'s result.
    Loaded(Option<MapLoad>),
    /// [`Op::HasDirectory`]'s answer.
    HasDirectory(bool),
    /// [`Op::Store`]'s result.
    Stored(Stored),
}

/// Runs `op` on the map: the async entry point an async board drives (natively, or through
/// `embassy_futures::block_on` as the blocking boards do).
///
/// # Errors
/// The operation's.
///
/// ```
/// use embassy_embedded_hal::adapter::BlockingAsync;
/// use embassy_futures::block_on;
/// use sensor_box::persist::{self, Done, Op};
/// use sensor_box::{Persisted, storage::MemFlash};
/// let mut mem = [0xFFu8; 4096];
/// let mut flash = MemFlash::new(&mut mem);
/// let mut map = persist::open_map(BlockingAsync::new(&mut flash), 0..4096)?;
/// let mut s = persist::Scratch::new();
/// assert_eq!(block_on(persist::run_map(&mut map, Op::HasDirectory, &mut s))?, Done::HasDirectory(false));
/// let r = Persisted::default();
/// block_on(persist::run_map(&mut map, Op::Store(&r, 0, Some(0..4096)), &mut s))?;
/// assert_eq!(block_on(persist::run_map(&mut map, Op::HasDirectory, &mut s))?, Done::HasDirectory(true));
/// # Ok::<(), persist::StoreError>(())
/// ```
pub async fn run<S: NorFlash>(
    map: &mut Map<S>,
    op: Op<'_>,
    s: &mut Scratch,
) -> Result<Done, StoreError> {
    match op {
        Op::Load(record) => load(map, record, s).await.map(Done::Loaded),
        Op::HasDirectory => directory(map, s)
            .await
            .map(|d| Done::HasDirectory(d.is_some())),
        Op::Store(record, debt_ms, fresh) => store(map, record, debt_ms, fresh, s)
            .await
            .map(Done::Stored),
    }
}
