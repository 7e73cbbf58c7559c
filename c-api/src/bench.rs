//! The Rust path, exported for the Cortex-M3 bench only (feature `bench`, never in the
//! header): each function runs the crates' own decode loop over a buffer exactly as a Rust
//! firmware would (`push`, or `feed`, then the typed parse of every frame), so that
//! `c-api/bench/cm3.c` measures the C calls and the Rust path on the same bytes, with the same
//! compiler, in the same QEMU run. Each returns the number of messages it parsed.

use core::hint::black_box;

use aeolus_proto::Decode;

use crate::ffi;

/// # Safety
/// `bytes` is readable for `len` bytes (or NULL with `len` 0).
unsafe fn input<'a>(bytes: *const u8, len: usize) -> &'a [u8] {
    // SAFETY: the caller's promise.
    unsafe { ffi::bytes(bytes, len) }.unwrap_or(&[])
}

/// AEOLUS, `push` byte by byte, then `frame.message()`.
///
/// # Safety
/// `bytes` is readable for `len` bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_bench_rust_aeolus_push(bytes: *const u8, len: usize) -> u32 {
    let mut d = aeolus_proto::Decoder::<{ crate::aeolus::PL_AEOLUS_CAPACITY }>::new();
    let mut n = 0u32;
    // SAFETY: the caller's promise.
    for b in unsafe { input(bytes, len) } {
        d.feed(core::slice::from_ref(b), |ev| {
            if let Ok(frame) = ev
                && let Ok(m) = frame.message()
            {
                black_box(&m);
                n += 1;
            }
        });
    }
    n
}

/// AEOLUS, `feed` over the whole buffer, then `frame.message()`.
///
/// # Safety
/// `bytes` is readable for `len` bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_bench_rust_aeolus_feed(bytes: *const u8, len: usize) -> u32 {
    let mut d = aeolus_proto::Decoder::<{ crate::aeolus::PL_AEOLUS_CAPACITY }>::new();
    let mut n = 0u32;
    // SAFETY: the caller's promise.
    d.feed(unsafe { input(bytes, len) }, |ev| {
        if let Ok(frame) = ev
            && let Ok(m) = frame.message()
        {
            black_box(&m);
            n += 1;
        }
    });
    n
}

/// AYDP (Spec), `push` and `poll`, then `frame.message()`.
///
/// # Safety
/// `bytes` is readable for `len` bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_bench_rust_aydp_push(bytes: *const u8, len: usize) -> u32 {
    let mut d =
        aydp_proto::Decoder::<{ crate::aydp::PL_AYDP_CAPACITY }>::new(aydp_proto::Profile::Spec);
    let mut n = 0u32;
    // SAFETY: the caller's promise.
    for &b in unsafe { input(bytes, len) } {
        d.feed(&[b], |e| {
            if let Ok(frame) = e
                && let Ok(m) = frame.message()
            {
                black_box(&m);
                n += 1;
            }
        });
    }
    n
}

/// AYDP (Spec), `feed`, then `frame.message()`.
///
/// # Safety
/// `bytes` is readable for `len` bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_bench_rust_aydp_feed(bytes: *const u8, len: usize) -> u32 {
    let mut d =
        aydp_proto::Decoder::<{ crate::aydp::PL_AYDP_CAPACITY }>::new(aydp_proto::Profile::Spec);
    let mut n = 0u32;
    // SAFETY: the caller's promise.
    d.feed(unsafe { input(bytes, len) }, |ev| {
        if let Ok(frame) = ev
            && let Ok(m) = frame.message()
        {
            black_box(&m);
            n += 1;
        }
    });
    n
}

/// AOK PC side (the device's messages), `push` and `poll`.
///
/// # Safety
/// `bytes` is readable for `len` bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_bench_rust_aok_pc_push(bytes: *const u8, len: usize) -> u32 {
    let mut d = aok_proto::MessageDecoder::new(aok_proto::FirmwareVersion::new(0, 35));
    let mut n = 0u32;
    // SAFETY: the caller's promise.
    for &b in unsafe { input(bytes, len) } {
        d.feed(&[b], |e| {
            if let Ok(m) = e {
                black_box(&m);
                n += 1;
            }
        });
    }
    n
}

/// AOK PC side, `feed`.
///
/// # Safety
/// `bytes` is readable for `len` bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_bench_rust_aok_pc_feed(bytes: *const u8, len: usize) -> u32 {
    let mut d = aok_proto::MessageDecoder::new(aok_proto::FirmwareVersion::new(0, 35));
    let mut n = 0u32;
    // SAFETY: the caller's promise.
    d.feed(unsafe { input(bytes, len) }, |ev| {
        if let Ok(m) = ev {
            black_box(&m);
            n += 1;
        }
    });
    n
}
