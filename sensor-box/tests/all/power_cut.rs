//! The format 1-3 store (`persist::legacy`, which the STM32F411's migration still writes
//! once): power cuts at every byte of every erase and program of a sequence of stores; after
//! each cut it loads the old record or the new one, never the defaults, and the next store
//! works. The flash model is [`CutFlash`] (`tests/all/common/cut_flash.rs`). The settings map is
//! tested against a more hostile model in `tests/all/flash_faults.rs`.
//!
//! `cargo test -p sensor-box --test all power_cut:: -- --nocapture` prints the figures of
//! `docs/RELIABILITY.md` ("Power cuts and flash wear").

use crate::common::cut_flash::{CutFlash, Tear};
use embedded_storage::nor_flash::NorFlash;
use sensor_box::Persisted;
use sensor_box::persist::legacy as persist;
use sensor_box::state::{AOK_PARAMS, StoredWaypoint};

/// Records of different sizes (about 330 bytes to the largest, 1 504), some repeated.
fn records() -> Vec<Persisted> {
    let small = Persisted::default();
    let mut medium = Persisted::default();
    for (s, set) in medium.aok.sets.iter_mut().enumerate() {
        for (p, v) in set.iter_mut().enumerate() {
            *v = (s as i32 * 1000 - p as i32 * 37) * if p % 2 == 0 { 1 } else { -1 };
        }
    }
    medium.settings.bank_deg = -25.0;
    let mut largest = Persisted::default();
    largest.settings.intervals.gps_ms = u32::MAX;
    largest.aok.sets = [[i32::MIN; AOK_PARAMS]; 5];
    largest.aok.waypoints = [StoredWaypoint {
        lon: i32::MIN,
        lat: i32::MIN,
        action1: u32::MAX,
        action2: u32::MAX,
    }; 32];
    let mut small2 = small.clone();
    small2.settings.airspeed_mps = 40.0;
    let mut medium2 = medium.clone();
    medium2.aok.waypoints[3].lat = 483_538_000;
    medium2.aok.start_set = 2;
    let mut small3 = small2.clone();
    small3.settings.altitude_m = 900.0;
    vec![
        small.clone(),
        medium.clone(),
        small2.clone(),
        largest.clone(),
        medium2.clone(),
        small3.clone(),
        small3,
        medium,
        largest,
        small2,
        medium2,
    ]
}

/// What the cuts of one geometry gave.
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq)]
struct Figures {
    /// Stores cut (every cut point of every store in the sequence, times the tears).
    cuts: u64,
    /// The reboot loaded the record stored before.
    old: u64,
    /// The reboot loaded the record being stored.
    new: u64,
    /// The reboot loaded neither (the defaults, or an error).
    lost: u64,
    /// The store after the reboot failed or did not load back.
    next_failed: u64,
    /// Cut points of the worst store.
    worst_store_steps: u64,
    /// Erase calls and bytes erased by the uncut stores of the sequence.
    erases: u64,
    erased_bytes: u64,
}

fn stored<const W: usize, const E: usize>(f: &mut CutFlash<W, E>, r: &Persisted) -> bool {
    persist::store(f, r).is_ok() && persist::load(f).map(|l| l.record).as_ref() == Ok(r)
}

/// Cuts every `stride`-th step of every store of [`records`] (after the first), with each
/// tear, on a `cap`-byte flash that starts as `fill`.
fn cut_every_store<const W: usize, const E: usize>(cap: usize, fill: u8, stride: u64) -> Figures {
    let recs = records();
    let mut fig = Figures::default();
    let mut base = CutFlash::<W, E>::new(cap, fill);
    assert!(stored(&mut base, &recs[0]));
    for pair in recs.windows(2) {
        let (old, new) = (&pair[0], &pair[1]);
        let mut dry = base.clone();
        dry.reboot();
        assert!(stored(&mut dry, new), "an uncut store works");
        let total = dry.steps;
        fig.erases += dry.erases;
        fig.erased_bytes += dry.erased_bytes;
        fig.worst_store_steps = fig.worst_store_steps.max(total);
        let mut k = 0;
        while k < total {
            for tear in [Tear::Old, Tear::New, Tear::Mixed(k ^ 0x5EED)] {
                let mut f = base.clone();
                f.reboot();
                f.cut_at(k, tear);
                let _ = persist::store(&mut f, new);
                assert!(f.is_dead(), "cut at {k} of {total}");
                f.reboot();
                fig.cuts += 1;
                match persist::load(&mut f) {
                    Ok(l) if &l.record == old => fig.old += 1,
                    Ok(l) if &l.record == new => fig.new += 1,
                    _ => fig.lost += 1,
                }
                if !stored(&mut f, new) {
                    fig.next_failed += 1;
                }
            }
            k += stride;
        }
        base = dry;
    }
    fig
}

fn report(name: &str, fig: Figures) {
    let stores = records().len() - 1;
    println!(
        "{name}: {} cuts (worst store {} cut points): old record {}, new record {}, lost {}, next store failed {}; {} stores erased {} times ({} bytes)",
        fig.cuts,
        fig.worst_store_steps,
        fig.old,
        fig.new,
        fig.lost,
        fig.next_failed,
        stores,
        fig.erases,
        fig.erased_bytes
    );
}

#[test]
fn a_power_cut_anywhere_keeps_the_old_record_or_the_new_one() {
    // The QEMU store: 4 KiB of MemFlash geometry (1 KiB pages, 4-byte words), blank RAM.
    let fig = cut_every_store::<4, 1024>(4096, 0x00, 1);
    report("4 KiB, 1 KiB pages, 4-byte words", fig);
    assert_eq!((fig.lost, fig.next_failed), (0, 0), "{fig:?}");
}

#[test]
fn a_power_cut_anywhere_keeps_the_old_record_or_the_new_one_byte_writes() {
    // The STM32F4's shape scaled down: two sectors, byte programming, erased flash.
    let fig = cut_every_store::<1, 4096>(8192, 0xFF, 1);
    report("8 KiB, 4 KiB sectors, 1-byte writes", fig);
    assert_eq!((fig.lost, fig.next_failed), (0, 0), "{fig:?}");
}

#[test]
fn the_model_tears_as_documented() {
    let mut f = CutFlash::<4, 1024>::new(2048, 0x00);
    f.cut_at(1030, Tear::Old);
    assert!(f.erase(0, 2048).is_err());
    assert!(f.is_dead());
    assert!(f.mem[..1030].iter().all(|&b| b == 0xFF));
    assert!(f.mem[1030..].iter().all(|&b| b == 0x00));
    assert!(f.write(0, &[0; 4]).is_err(), "dead until reboot");
    f.reboot();
    f.cut_at(6, Tear::New);
    assert!(
        f.write(0, &[1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12])
            .is_err()
    );
    assert_eq!(
        &f.mem[..12],
        &[1, 2, 3, 4, 5, 6, 7, 8, 0xFF, 0xFF, 0xFF, 0xFF]
    );
    f.reboot();
    f.cut_at(5, Tear::Old);
    assert!(f.write(8, &[0; 8]).is_err());
    assert_eq!(
        &f.mem[..16],
        &[1, 2, 3, 4, 5, 6, 7, 8, 0, 0, 0, 0, 0xFF, 0xFF, 0xFF, 0xFF]
    );
    f.reboot();
    f.cut_at(100, Tear::Mixed(7));
    assert!(f.erase(1024, 2048).is_err());
    let erased = f.mem[1124..].iter().filter(|&&b| b == 0xFF).count();
    assert!(erased > 300 && erased < 700, "{erased}");
}

#[test]
fn the_stm32f411_sectors_wear_as_documented_and_survive_sampled_cuts() {
    // Sectors 6 and 7: two 128 KiB areas, byte writes. The largest record, changed every
    // time: 86 images fit an area, so 200 stores erase twice (1/86 per store).
    let largest = &records()[3];
    let mut flash = CutFlash::<1, { 128 * 1024 }>::new(256 * 1024, 0xFF);
    assert!(stored(&mut flash, largest));
    let mut erases = 0;
    let mut sampled = 0;
    let mut prev = largest.clone();
    for i in 0..200u32 {
        let mut next = largest.clone();
        next.settings.intervals.imu_ms = 1000 + i;
        let mut dry = flash.clone();
        dry.reboot();
        assert!(stored(&mut dry, &next));
        let total = dry.steps;
        // A few cuts in every tenth store, and 24 in each store that erases.
        let cuts = if dry.erases > 0 {
            24
        } else if i % 10 == 0 {
            3
        } else {
            0
        };
        for c in 0..cuts {
            let k = total * c / cuts + c;
            for tear in [Tear::Old, Tear::New, Tear::Mixed(k)] {
                let mut f = flash.clone();
                f.reboot();
                f.cut_at(k.min(total - 1), tear);
                let _ = persist::store(&mut f, &next);
                f.reboot();
                let got = persist::load(&mut f).map(|l| l.record);
                assert!(
                    got.as_ref() == Ok(&prev) || got.as_ref() == Ok(&next),
                    "store {i}, cut {k} of {total}, {tear:?}"
                );
                sampled += 1;
            }
        }
        erases += dry.erases;
        flash = dry;
        prev = next;
    }
    println!(
        "2 x 128 KiB, 1-byte writes: 200 stores (after a first) of the largest record erased {erases} times; {sampled} sampled cuts kept the old or the new record"
    );
    assert_eq!(erases, 2, "an area holds 86 images of 1 508 bytes");
}
