//! The flash store: round trip, image layout, empty and corrupted stores, the version 1
//! migration, write alignment, and settings surviving a reboot of the App.

use embedded_storage::nor_flash::{ErrorType, NorFlash, ReadNorFlash};
use sensor_box::persist::StoreError;
use sensor_box::persist::legacy::{
    self as persist, CHUNK, HEADER_LEN, IMAGE_MAX, MAGIC, PAYLOAD_MAX, Stored, VERSION,
};
use sensor_box::serial::Ring;
use sensor_box::serial::{PortStats, QueuedSerial};
use sensor_box::state::{AOK_PARAMS, AokFlash, Intervals, StoredWaypoint};
use sensor_box::storage::{Error, MemFlash};
use sensor_box::{App, Persisted, Settings};

/// A record with every field away from its default.
fn sample() -> Persisted {
    let mut aok = AokFlash::default();
    for (s, set) in aok.sets.iter_mut().enumerate() {
        for (p, v) in set.iter_mut().enumerate() {
            *v = (s as i32 * 1000 - p as i32 * 37) * if p % 2 == 0 { 1 } else { -1 };
        }
    }
    aok.start_set = 3;
    aok.waypoints[0] = StoredWaypoint {
        lon: 117_861_000,
        lat: 483_538_000,
        action1: 0xDEAD_BEEF,
        action2: 7,
    };
    aok.waypoints[31] = StoredWaypoint {
        lon: -1,
        lat: i32::MIN,
        action1: u32::MAX,
        action2: 0,
    };
    Persisted {
        settings: Settings {
            intervals: Intervals {
                imu_ms: 10,
                pressure_ms: 6,
                gps_ms: 100,
                temp_ms: 1000,
                wind_ms: 2000,
                info_ms: 500,
            },
            airspeed_mps: 62.5,
            bank_deg: -25.0,
            altitude_m: 1500.0,
            aok_debug_period_ms: 50,
        },
        aok,
    }
}

/// `value` serialised by postcard: the payload of a foreign image, or what the store's
/// hand-written encoder must write for a record.
fn postcard_bytes<T: serde::Serialize>(value: &T) -> Vec<u8> {
    let mut buf = vec![0u8; 2 * PAYLOAD_MAX];
    let n = postcard::to_slice(value, &mut buf).unwrap().len();
    buf.truncate(n);
    buf
}

/// The payload of the image a store of `record` writes on an empty flash.
fn stored_payload(record: &Persisted) -> Vec<u8> {
    let mut mem = [0xFFu8; 4096];
    persist::store(&mut MemFlash::new(&mut mem), record).unwrap();
    let len = u32::from_le_bytes(mem[8..12].try_into().unwrap()) as usize;
    mem[HEADER_LEN..HEADER_LEN + len].to_vec()
}

#[test]
fn the_encoder_writes_postcards_bytes() {
    // The defaults, the sample, and the extremes of every field.
    assert_eq!(
        stored_payload(&Persisted::default()),
        postcard_bytes(&Persisted::default())
    );
    assert_eq!(stored_payload(&sample()), postcard_bytes(&sample()));
    let mut worst = Persisted::default();
    worst.settings.intervals = Intervals {
        imu_ms: u32::MAX,
        pressure_ms: 0,
        gps_ms: 0x7F,
        temp_ms: 0x80,
        wind_ms: 0x3FFF,
        info_ms: 0x4000,
    };
    worst.settings.airspeed_mps = f32::NAN;
    worst.settings.bank_deg = -0.0;
    worst.settings.altitude_m = f32::NEG_INFINITY;
    worst.settings.aok_debug_period_ms = 0x0FFF_FFFF;
    worst.aok.sets = [[i32::MIN; AOK_PARAMS]; 5];
    worst.aok.sets[2] = [i32::MAX; AOK_PARAMS];
    worst.aok.start_set = u8::MAX;
    worst.aok.waypoints = [StoredWaypoint {
        lon: i32::MIN,
        lat: i32::MAX,
        action1: u32::MAX,
        action2: 0x1000_0000,
    }; 32];
    assert_eq!(stored_payload(&worst), postcard_bytes(&worst));
}

#[test]
fn the_encoder_writes_postcards_bytes_for_random_records() {
    use proptest::prelude::*;
    use proptest::test_runner::{Config, TestRunner};

    // Values of every varint length (1 to 5 bytes), signs, and any f32 bit pattern.
    fn u() -> impl Strategy<Value = u32> {
        prop_oneof![0u32..0x80, 0x80u32..0x4000, any::<u32>(), Just(u32::MAX)]
    }
    fn i() -> impl Strategy<Value = i32> {
        prop_oneof![-64i32..64, any::<i32>(), Just(i32::MIN), Just(i32::MAX)]
    }
    fn f() -> impl Strategy<Value = f32> {
        any::<u32>().prop_map(f32::from_bits)
    }
    let waypoint = (i(), i(), u(), u()).prop_map(|(lon, lat, action1, action2)| StoredWaypoint {
        lon,
        lat,
        action1,
        action2,
    });
    let record = (
        prop::collection::vec(u(), 7),
        prop::collection::vec(f(), 3),
        prop::collection::vec(i(), 5 * AOK_PARAMS),
        any::<u8>(),
        prop::collection::vec(waypoint, 32),
    )
        .prop_map(|(u, f, sets, start_set, waypoints)| {
            let mut r = Persisted::default();
            r.settings.intervals = Intervals {
                imu_ms: u[0],
                pressure_ms: u[1],
                gps_ms: u[2],
                temp_ms: u[3],
                wind_ms: u[4],
                info_ms: u[5],
            };
            r.settings.aok_debug_period_ms = u[6];
            r.settings.airspeed_mps = f[0];
            r.settings.bank_deg = f[1];
            r.settings.altitude_m = f[2];
            for (slot, v) in r.aok.sets.iter_mut().flatten().zip(sets) {
                *slot = v;
            }
            r.aok.start_set = start_set;
            r.aok.waypoints.copy_from_slice(&waypoints);
            r
        });
    TestRunner::new(Config::with_cases(256))
        .run(&record, |r| {
            prop_assert_eq!(stored_payload(&r), postcard_bytes(&r));
            Ok(())
        })
        .unwrap();
}

/// CRC-32/ISO-HDLC written out bit by bit (reflected 0x04C11DB7, init and xorout all ones),
/// independent of the `crc` crate the firmware uses.
fn crc32_iso_hdlc(bytes: &[u8]) -> u32 {
    let mut crc = 0xFFFF_FFFFu32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = if crc & 1 != 0 {
                (crc >> 1) ^ 0xEDB8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

#[test]
fn the_reference_crc_is_crc_32_iso_hdlc() {
    assert_eq!(crc32_iso_hdlc(b"123456789"), 0xCBF4_3926);
}

#[test]
fn round_trip() {
    let mut mem = [0u8; 4096];
    let mut flash = MemFlash::new(&mut mem);
    let record = sample();
    persist::store(&mut flash, &record).unwrap();
    let loaded = persist::load(&mut flash).unwrap();
    assert_eq!(loaded.version, 3);
    assert_eq!(loaded.record, record);
    assert_eq!(load_or_default(&mut flash), record);
}

#[test]
fn the_image_layout() {
    let mut mem = [0xFFu8; 4096];
    persist::store(&mut MemFlash::new(&mut mem), &sample()).unwrap();
    assert_eq!(&mem[0..4], b"SBOX");
    assert_eq!(MAGIC, 0x584F_4253);
    assert_eq!(
        &mem[4..8],
        &[0x03, 0x00, 0x00, 0x00],
        "version 3, reserved 0"
    );
    assert_eq!(&mem[12..16], &[1, 0, 0, 0], "the first image: sequence 1");
    let len = u32::from_le_bytes(mem[8..12].try_into().unwrap()) as usize;
    let payload = &mem[HEADER_LEN..HEADER_LEN + len];
    let mut buf = [0u8; PAYLOAD_MAX];
    assert_eq!(postcard::to_slice(&sample(), &mut buf).unwrap(), payload);
    // The CRC covers header bytes 0..16 (the sequence number too) and the payload.
    let mut covered = mem[..16].to_vec();
    covered.extend_from_slice(payload);
    assert_eq!(
        u32::from_le_bytes(mem[16..20].try_into().unwrap()),
        crc32_iso_hdlc(&covered)
    );
    // The settings come first: intervals as varints, then the three f32, then the AOK period.
    assert_eq!(
        &payload[..22],
        &[
            10, 6, 100, 0xE8, 0x07, 0xD0, 0x0F, 0xF4, 0x03, // 10 6 100 1000 2000 500
            0x00, 0x00, 0x7A, 0x42, // 62.5
            0x00, 0x00, 0xC8, 0xC1, // -25.0
            0x00, 0x80, 0xBB, 0x44, // 1500.0
            50,   // AOK debug period
        ]
    );
    // The flash was erased already: nothing else was touched.
    assert!(mem[HEADER_LEN + len..].iter().all(|&b| b == 0xFF));

    // The next store appends at the next multiple of 4, with sequence 2; the first image
    // stays.
    let mut changed = sample();
    changed.settings.bank_deg = 5.0;
    let first = mem[..HEADER_LEN + len].to_vec();
    assert_eq!(
        persist::store(&mut MemFlash::new(&mut mem), &changed),
        Ok(Stored::Appended)
    );
    let at = (HEADER_LEN + len).div_ceil(4) * 4;
    assert_eq!(&mem[..HEADER_LEN + len], &first[..]);
    assert_eq!(&mem[at..at + 4], b"SBOX");
    assert_eq!(&mem[at + 12..at + 16], &[2, 0, 0, 0]);
    assert_eq!(
        persist::load(&mut MemFlash::new(&mut mem)).unwrap().record,
        changed
    );
}

#[test]
fn the_payload_bound_is_exact() {
    // The largest record: every varint at its 5-byte maximum.
    let mut worst = Persisted::default();
    worst.settings.intervals = Intervals {
        imu_ms: u32::MAX,
        pressure_ms: u32::MAX,
        gps_ms: u32::MAX,
        temp_ms: u32::MAX,
        wind_ms: u32::MAX,
        info_ms: u32::MAX,
    };
    worst.settings.aok_debug_period_ms = u32::MAX;
    worst.aok.sets = [[i32::MIN; AOK_PARAMS]; 5];
    worst.aok.start_set = u8::MAX;
    worst.aok.waypoints = [StoredWaypoint {
        lon: i32::MIN,
        lat: i32::MIN,
        action1: u32::MAX,
        action2: u32::MAX,
    }; 32];
    let mut buf = [0u8; PAYLOAD_MAX + 64];
    assert_eq!(
        postcard::to_slice(&worst, &mut buf).unwrap().len(),
        PAYLOAD_MAX
    );
    assert_eq!(PAYLOAD_MAX, 1488);
    assert_eq!(IMAGE_MAX, 1508);
    let mut mem = [0u8; 4096];
    let mut flash = MemFlash::new(&mut mem);
    persist::store(&mut flash, &worst).unwrap();
    assert_eq!(persist::load(&mut flash).unwrap().record, worst);
}

#[test]
fn an_empty_store_gives_the_defaults() {
    // Erased NOR flash.
    let mut mem = [0xFFu8; 4096];
    let mut flash = MemFlash::new(&mut mem);
    assert_eq!(persist::load(&mut flash), Err(StoreError::Empty));
    assert_eq!(load_or_default(&mut flash), Persisted::default());
    // QEMU's RAM-backed store after power-on: zeros.
    let mut mem = [0u8; 4096];
    let mut flash = MemFlash::new(&mut mem);
    assert_eq!(persist::load(&mut flash), Err(StoreError::Empty));
    assert_eq!(load_or_default(&mut flash), Persisted::default());
}

#[test]
fn a_corrupted_store_gives_the_defaults() {
    let mut clean = [0xFFu8; 4096];
    persist::store(&mut MemFlash::new(&mut clean), &sample()).unwrap();
    let len = u32::from_le_bytes(clean[8..12].try_into().unwrap()) as usize;

    let flipped = |at: usize| {
        let mut mem = clean;
        mem[at] ^= 0xFF;
        let mut flash = MemFlash::new(&mut mem);
        (
            persist::load(&mut flash).map(|l| l.record),
            load_or_default(&mut flash),
        )
    };
    // The reasons, byte by byte.
    assert_eq!(flipped(0).0, Err(StoreError::BadMagic));
    assert_eq!(flipped(4).0, Err(StoreError::UnsupportedVersion(0x00FC)));
    assert_eq!(
        flipped(6).0,
        Err(StoreError::BadCrc),
        "reserved bytes are covered"
    );
    assert_eq!(
        flipped(10).0,
        Err(StoreError::BadLength(len as u32 ^ 0x00FF_0000))
    );
    assert_eq!(
        flipped(13).0,
        Err(StoreError::BadCrc),
        "the sequence is covered"
    );
    assert_eq!(flipped(17).0, Err(StoreError::BadCrc));
    assert_eq!(flipped(HEADER_LEN + 100).0, Err(StoreError::BadCrc));
    // Every single flipped byte of the image: an error, the defaults, never a panic.
    for at in 0..HEADER_LEN + len {
        let (loaded, record) = flipped(at);
        assert!(loaded.is_err(), "byte {at}");
        assert_eq!(record, Persisted::default(), "byte {at}");
    }
    // And single bit flips in the payload.
    for at in HEADER_LEN..HEADER_LEN + len {
        for bit in 0..8 {
            let mut mem = clean;
            mem[at] ^= 1 << bit;
            assert_eq!(
                persist::load(&mut MemFlash::new(&mut mem)).map(|l| l.version),
                Err(StoreError::BadCrc)
            );
        }
    }
}

#[test]
fn a_torn_write_gives_the_defaults() {
    // The reset came after the first 256 bytes: the rest is still erased.
    let mut mem = [0xFFu8; 4096];
    persist::store(&mut MemFlash::new(&mut mem), &sample()).unwrap();
    mem[256..].fill(0xFF);
    assert_eq!(
        persist::load(&mut MemFlash::new(&mut mem)).map(|l| l.version),
        Err(StoreError::BadCrc)
    );
}

#[test]
fn garbage_never_panics() {
    // Deterministic xorshift: 2000 stores of random bytes, some with a valid-looking header.
    let mut x = 0x2545_F491_4F6C_DD1Du64;
    let mut next = || {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        x
    };
    for case in 0..2000 {
        let mut mem = [0u8; 2048];
        for b in mem.iter_mut() {
            *b = next() as u8;
        }
        if case % 2 == 0 {
            mem[0..4].copy_from_slice(b"SBOX");
            mem[4] = (case % 4) as u8; // versions 0 and 2
            mem[5] = 0;
            let len = (next() % 1600) as u32;
            mem[8..12].copy_from_slice(&len.to_le_bytes());
        }
        let mut flash = MemFlash::new(&mut mem);
        assert!(persist::load(&mut flash).is_err(), "case {case}");
        assert_eq!(load_or_default(&mut flash), Persisted::default());
    }
}

#[test]
fn a_valid_crc_over_a_foreign_payload_is_a_decode_error() {
    let mut mem = [0u8; 4096];
    let mut flash = MemFlash::new(&mut mem);
    // Too short for a record.
    persist::write_image(&mut flash, VERSION, &postcard_bytes(&[1u8, 2, 3])).unwrap();
    assert_eq!(persist::load(&mut flash), Err(StoreError::Decode));
    // A whole record plus trailing bytes.
    persist::write_image(
        &mut flash,
        VERSION,
        &postcard_bytes(&(Persisted::default(), 7u8)),
    )
    .unwrap();
    assert_eq!(persist::load(&mut flash), Err(StoreError::Decode));
    assert_eq!(load_or_default(&mut flash), Persisted::default());
}

#[test]
fn a_newer_version_gives_the_defaults() {
    let mut mem = [0u8; 4096];
    let mut flash = MemFlash::new(&mut mem);
    persist::write_image(&mut flash, 4, &postcard_bytes(&sample())).unwrap();
    assert_eq!(
        persist::load(&mut flash),
        Err(StoreError::UnsupportedVersion(4))
    );
    assert_eq!(load_or_default(&mut flash), Persisted::default());
    // Behind an image this firmware reads, the newer one is skipped.
    let mut mem = [0xFFu8; 4096];
    let mut flash = MemFlash::new(&mut mem);
    persist::store(&mut flash, &sample()).unwrap();
    persist::write_image(&mut flash, 4, &postcard_bytes(&Persisted::default())).unwrap();
    assert_eq!(persist::load(&mut flash).unwrap().record, sample());
}

/// The images the firmware before the A/B layout (format versions 1 and 2, one image at
/// offset 0) wrote: `tests/data/v1-qemu-4k.bin` and `v2-qemu-4k.bin` are the QEMU board's
/// whole 4 KiB store as that code left it (written with its `persist::write_image` and
/// `persist::store` on zeroed RAM).
const V1_STORE: &[u8; 4096] = include_bytes!("../data/v1-qemu-4k.bin");
const V2_STORE: &[u8; 4096] = include_bytes!("../data/v2-qemu-4k.bin");

/// The AOK data in both images.
fn legacy_aok() -> AokFlash {
    let mut aok = AokFlash::default();
    aok.sets[1][3] = -1234;
    aok.sets[4][31] = 77;
    aok.start_set = 4;
    aok.waypoints[0] = StoredWaypoint {
        lon: 117_861_000,
        lat: 483_538_000,
        action1: 0xDEAD_BEEF,
        action2: 7,
    };
    aok
}

#[test]
fn the_old_images_are_what_the_old_code_wrote() {
    // Version 2: the 16-byte header, CRC over bytes 0..12 and the payload, at offset 0.
    let len = u32::from_le_bytes(V2_STORE[8..12].try_into().unwrap()) as usize;
    assert_eq!(&V2_STORE[..8], b"SBOX\x02\0\0\0");
    let mut covered = V2_STORE[..12].to_vec();
    covered.extend_from_slice(&V2_STORE[16..16 + len]);
    assert_eq!(
        u32::from_le_bytes(V2_STORE[12..16].try_into().unwrap()),
        crc32_iso_hdlc(&covered)
    );
    let mut buf = [0u8; PAYLOAD_MAX];
    let mut v2 = sample();
    v2.aok = legacy_aok();
    assert_eq!(
        postcard::to_slice(&v2, &mut buf).unwrap(),
        &V2_STORE[16..16 + len]
    );
    assert_eq!(&V1_STORE[..8], b"SBOX\x01\0\0\0");
}

#[test]
fn a_version_1_store_is_migrated() {
    let mut mem = *V1_STORE;
    let mut flash = MemFlash::new(&mut mem);
    let loaded = persist::load(&mut flash).unwrap();
    assert_eq!(loaded.version, 1);
    let s = loaded.record.settings;
    assert_eq!(s.intervals, Intervals::SPEC);
    assert_eq!(
        (s.airspeed_mps, s.bank_deg, s.altitude_m),
        (40.0, -15.0, 300.0)
    );
    // The field version 1 did not have takes its default.
    assert_eq!(s.aok_debug_period_ms, 20);
    assert_eq!(loaded.record.aok, legacy_aok());
    assert_eq!(load_or_default(&mut flash), loaded.record);

    // The App boots from it where the firmware before the map kept it (the second half of
    // the QEMU board's 8 KiB), migrates it into the map, and stores into the map.
    let mut mem8 = [0xFFu8; 8192];
    mem8[4096..].copy_from_slice(V1_STORE);
    let mut flash = MemFlash::new(&mut mem8);
    let layout = sensor_box::persist::Layout::for_flash(&flash);
    let mut app = App::new(&mut flash, 0);
    assert_eq!(app.shared.settings().bank_deg, -15.0);
    assert_eq!(app.shared.flight.params().bank_deg, -15.0);
    app.shared.persisted.settings.airspeed_mps = 41.0;
    app.shared.requests.store = true;
    poll_app(&mut app, &mut flash);
    assert_eq!(app.shared.counters.store_failures, 0);
    let boot = sensor_box::persist::boot(&mut flash, &layout);
    assert_eq!(boot.source, sensor_box::persist::Source::Map);
    assert_eq!(boot.record.settings.aok_debug_period_ms, 20);
    assert_eq!(boot.record.settings.airspeed_mps, 41.0);
    assert_eq!(boot.record.aok, legacy_aok());
}

#[test]
fn a_version_2_store_is_migrated_on_either_board() {
    let mut v2 = sample();
    v2.aok = legacy_aok();
    // QEMU: the old image at offset 0 of the store (area A).
    // STM32F411: the old image at the start of sector 7, now area B (the store is sectors 6
    // and 7), with sector 6 erased before it.
    let mut qemu = *V2_STORE;
    let mut stm32 = [0xFFu8; 4096];
    stm32[2048..].copy_from_slice(&V2_STORE[..2048]);
    for mem in [&mut qemu[..], &mut stm32[..]] {
        let mut flash = MemFlash::new(mem);
        let loaded = persist::load(&mut flash).unwrap();
        assert_eq!((loaded.version, &loaded.record), (2, &v2));
        // Stored unchanged, it is still written: in version 3 (on QEMU in area B, as the old
        // code erased only the first 1 KiB page of area A and the RAM behind it is zero).
        assert!(matches!(
            persist::store(&mut flash, &v2),
            Ok(Stored::Appended | Stored::Erased)
        ));
        let loaded = persist::load(&mut flash).unwrap();
        assert_eq!((loaded.version, &loaded.record), (3, &v2));
        assert_eq!(persist::store(&mut flash, &v2), Ok(Stored::Unchanged));
        // Once the area is full, the other is erased and the old image is gone.
        let mut changed = v2.clone();
        let mut erased = false;
        for i in 0..12 {
            changed.settings.bank_deg = i as f32;
            erased |= persist::store(&mut flash, &changed) == Ok(Stored::Erased);
        }
        assert!(erased);
        assert_eq!(persist::load(&mut flash).unwrap().record, changed);
    }
    // A version 1 or 2 image anywhere but the start of an area is not read.
    let mut mem = [0xFFu8; 4096];
    mem[1024..2048].copy_from_slice(&V2_STORE[..1024]);
    assert_eq!(
        persist::load(&mut MemFlash::new(&mut mem)).map(|l| l.version),
        Err(StoreError::UnsupportedVersion(2))
    );
}

#[test]
fn an_unchanged_record_is_not_written_again() {
    let mut flash = Strict::<8> {
        mem: vec![0xFFu8; 4096],
        writes: Vec::new(),
        broken: false,
    };
    assert_eq!(persist::store(&mut flash, &sample()), Ok(Stored::Appended));
    let writes = flash.writes.len();
    let before = flash.mem.clone();
    assert_eq!(persist::store(&mut flash, &sample()), Ok(Stored::Unchanged));
    assert_eq!(flash.writes.len(), writes, "no write");
    assert_eq!(flash.mem, before, "no erase");
    // Any change is written.
    let mut changed = sample();
    changed.aok.waypoints[5].action2 = 1;
    assert_eq!(persist::store(&mut flash, &changed), Ok(Stored::Appended));
    assert_eq!(persist::load(&mut flash).unwrap().record, changed);
}

#[test]
fn a_record_too_big_for_the_store_is_refused_and_the_old_one_kept() {
    // Two 1 KiB areas: the largest record (1 508 bytes) does not fit one.
    let mut mem = [0u8; 2048];
    let mut flash = MemFlash::new(&mut mem);
    persist::store(&mut flash, &Persisted::default()).unwrap();
    let mut big = sample();
    big.aok.sets = [[i32::MIN; AOK_PARAMS]; 5];
    big.aok.waypoints = [StoredWaypoint {
        lon: i32::MIN,
        lat: i32::MIN,
        action1: u32::MAX,
        action2: u32::MAX,
    }; 32];
    assert_eq!(persist::store(&mut flash, &big), Err(StoreError::TooLarge));
    assert_eq!(
        persist::load(&mut flash).unwrap().record,
        Persisted::default()
    );
}

/// A NOR flash that insists on its sizes: `W`-byte writes, 4-byte reads, 2 KiB pages. It
/// records every write and refuses to program bits that are not erased.
struct Strict<const W: usize = 8> {
    mem: Vec<u8>,
    writes: Vec<(u32, usize)>,
    broken: bool,
}

impl<const W: usize> ErrorType for Strict<W> {
    type Error = Error;
}

impl<const W: usize> ReadNorFlash for Strict<W> {
    const READ_SIZE: usize = 4;
    fn read(&mut self, offset: u32, bytes: &mut [u8]) -> Result<(), Error> {
        let o = offset as usize;
        if !o.is_multiple_of(4) || !bytes.len().is_multiple_of(4) {
            return Err(Error::NotAligned);
        }
        bytes.copy_from_slice(self.mem.get(o..o + bytes.len()).ok_or(Error::OutOfBounds)?);
        Ok(())
    }
    fn capacity(&self) -> usize {
        self.mem.len()
    }
}

impl<const W: usize> NorFlash for Strict<W> {
    const WRITE_SIZE: usize = W;
    const ERASE_SIZE: usize = 2048;
    fn erase(&mut self, from: u32, to: u32) -> Result<(), Error> {
        if !from.is_multiple_of(2048) || !to.is_multiple_of(2048) {
            return Err(Error::NotAligned);
        }
        self.mem
            .get_mut(from as usize..to as usize)
            .ok_or(Error::OutOfBounds)?
            .fill(0xFF);
        Ok(())
    }
    fn write(&mut self, offset: u32, bytes: &[u8]) -> Result<(), Error> {
        let o = offset as usize;
        if !o.is_multiple_of(W) || !bytes.len().is_multiple_of(W) {
            return Err(Error::NotAligned);
        }
        self.writes.push((offset, bytes.len()));
        if self.broken {
            return Ok(()); // claims success, programs nothing
        }
        let dst = self
            .mem
            .get_mut(o..o + bytes.len())
            .ok_or(Error::OutOfBounds)?;
        if dst.iter().any(|&b| b != 0xFF) {
            return Err(Error::Device); // not erased
        }
        dst.copy_from_slice(bytes);
        Ok(())
    }
}

#[test]
fn writes_are_aligned_chunks_after_an_erase() {
    let mut flash = Strict::<8> {
        mem: vec![0u8; 4096],
        writes: Vec::new(),
        broken: false,
    };
    let record = sample();
    // Blank (zero) RAM: area A is not erased, so the store erases area B and writes there.
    assert_eq!(persist::store(&mut flash, &record), Ok(Stored::Erased));
    let start = 2048;
    let len = u32::from_le_bytes(flash.mem[start + 8..start + 12].try_into().unwrap()) as usize;
    let padded = (HEADER_LEN + len).div_ceil(8) * 8;
    // Consecutive 64-byte chunks from the area's start covering the padded image; the last
    // one is shorter but still whole write units.
    let mut at = start;
    for (i, &(offset, n)) in flash.writes.iter().enumerate() {
        assert_eq!(offset as usize, at);
        if i + 1 < flash.writes.len() {
            assert_eq!(n, CHUNK);
        } else {
            assert!(n <= CHUNK && n.is_multiple_of(8));
        }
        at += n;
    }
    assert_eq!(at, start + padded);
    assert_eq!(flash.writes.len(), padded.div_ceil(CHUNK));
    assert_eq!(persist::load(&mut flash).unwrap().record, record);
    // A second store does not fit after the first in area B: it erases area A first (the
    // strict flash refuses to program unerased bytes).
    let mut changed = record.clone();
    changed.settings.bank_deg = 5.0;
    persist::store(&mut flash, &changed).unwrap();
    assert_eq!(persist::load(&mut flash).unwrap().record, changed);
}

#[test]
fn an_odd_or_huge_write_unit_is_unsupported() {
    let mut odd = Strict::<3> {
        mem: vec![0u8; 4096],
        writes: Vec::new(),
        broken: false,
    };
    assert_eq!(
        persist::store(&mut odd, &sample()),
        Err(StoreError::Unsupported)
    );
    let mut huge = Strict::<128> {
        mem: vec![0u8; 4096],
        writes: Vec::new(),
        broken: false,
    };
    assert_eq!(
        persist::store(&mut huge, &sample()),
        Err(StoreError::Unsupported)
    );
    assert!(odd.writes.is_empty() && huge.writes.is_empty());
    // Nothing was erased either: the store still reads as blank (zeros).
    assert_eq!(
        persist::load(&mut odd).map(|l| l.version),
        Err(StoreError::Empty)
    );
}

#[test]
fn a_one_byte_write_unit_works() {
    let mut flash = Strict::<1> {
        mem: vec![0xFFu8; 4096],
        writes: Vec::new(),
        broken: false,
    };
    persist::store(&mut flash, &sample()).unwrap();
    assert_eq!(persist::load(&mut flash).unwrap().record, sample());
}

#[test]
fn a_flash_that_does_not_program_fails_verification() {
    let mut flash = Strict::<8> {
        mem: vec![0u8; 4096],
        writes: Vec::new(),
        broken: true,
    };
    assert_eq!(
        persist::store(&mut flash, &sample()),
        Err(StoreError::Verify)
    );
    assert_eq!(
        persist::load(&mut flash).map(|l| l.version),
        Err(StoreError::Empty)
    );
}

/// One App poll with idle ports.
fn poll_app<F: NorFlash>(app: &mut App, flash: &mut F) {
    let mut q: Vec<Ring<8192>> = (0..6).map(|_| Ring::new()).collect();
    let stats = [PortStats::new(), PortStats::new(), PortStats::new()];
    let [q0, q1, q2, q3, q4, q5] = &mut q[..] else {
        unreachable!()
    };
    let (mut u0, _i0) = QueuedSerial::split(q0, q1, &stats[0], || {});
    let (mut u1, _i1) = QueuedSerial::split(q2, q3, &stats[1], || {});
    let (mut u2, _i2) = QueuedSerial::split(q4, q5, &stats[2], || {});
    app.poll(0, &mut u0, &mut u1, &mut u2, flash);
}

#[test]
fn settings_stored_by_the_app_come_back_after_a_reboot() {
    let mut mem = [0u8; 8192];
    let mut flash = MemFlash::new(&mut mem);
    let mut app = App::new(&mut flash, 0);
    assert_eq!(
        app.shared.persisted,
        Persisted::default(),
        "empty store: defaults"
    );
    app.shared.persisted = sample();
    app.shared.requests.store = true;
    poll_app(&mut app, &mut flash);
    assert!(!app.shared.requests.store);
    assert_eq!(app.shared.counters.store_failures, 0);

    // Warm reset: the flash survives, the App starts again.
    let app = App::new(&mut flash, 0);
    assert_eq!(app.shared.persisted, sample());
    assert_eq!(app.shared.flight.params().airspeed_mps, 62.5);
}

#[test]
fn the_app_boots_with_defaults_from_a_corrupt_store() {
    let mut mem = [0xFFu8; 4096];
    persist::store(&mut MemFlash::new(&mut mem), &sample()).unwrap();
    mem[HEADER_LEN + 3] ^= 0x40;
    let app = App::new(&mut MemFlash::new(&mut mem), 0);
    assert_eq!(app.shared.persisted, Persisted::default());
}

#[test]
fn a_failed_store_is_counted_by_the_app() {
    let mut flash = Strict::<8> {
        mem: vec![0u8; 4096],
        writes: Vec::new(),
        broken: true,
    };
    let mut app = App::new(&mut flash, 0);
    app.shared.requests.store = true;
    poll_app(&mut app, &mut flash);
    assert_eq!(app.shared.counters.store_failures, 1);
}

#[test]
fn load_into_leaves_the_record_alone_on_an_error() {
    let mut mem = [0u8; 4096];
    let mut flash = MemFlash::new(&mut mem);
    // Good settings and the first parameter set, then the payload ends: the CRC is right, the
    // decode fails after the point where a one-pass decoder would have written the settings.
    persist::write_image(
        &mut flash,
        VERSION,
        &postcard_bytes(&(sample().settings, [7i32; AOK_PARAMS])),
    )
    .unwrap();
    let mut record = Persisted::default();
    record.settings.bank_deg = 1.5;
    let before = record.clone();
    assert_eq!(
        persist::load_into(&mut flash, &mut record),
        Err(StoreError::Decode)
    );
    assert_eq!(record, before);
    assert_eq!(load_or_default(&mut flash), Persisted::default());
}

#[test]
fn load_into_fills_the_record_in_place() {
    let mut mem = [0u8; 4096];
    let mut flash = MemFlash::new(&mut mem);
    persist::store(&mut flash, &sample()).unwrap();
    let mut record = Persisted::default();
    assert_eq!(persist::load_into(&mut flash, &mut record), Ok(3));
    assert_eq!(record, sample());
}

/// The format 1-3 store's record, or the defaults (what the firmware before the map loaded).
fn load_or_default<F: NorFlash>(flash: &mut F) -> Persisted {
    persist::load(flash).map(|l| l.record).unwrap_or_default()
}
