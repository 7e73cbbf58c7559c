//! The Rust path, exported for the Cortex-M3 bench only (feature `bench`, never in the
//! header): each function runs the crates' own decode loop over a buffer exactly as a Rust
//! firmware would (`push`, or `feed`, then the typed parse of every frame), so that
//! `c-api/bench/cm3.c` measures the C calls and the Rust path on the same bytes, with the same
//! compiler, in the same QEMU run. Each returns the number of messages it parsed.

use core::hint::black_box;

use aeolus_proto::Decode;

use crate::ffi;

/// The messages `typed` finds in the items of `bytes[..len]`, fed to `d` whole (`feed`) or a
/// byte a call (`push`, as a receive interrupt would).
///
/// # Safety
/// `bytes` is readable for `len` bytes (or NULL with `len` 0).
#[inline(always)]
unsafe fn count<D: Decode>(
    mut d: D,
    bytes: *const u8,
    len: usize,
    push: bool,
    typed: impl Fn(D::Item<'_>) -> bool,
) -> u32 {
    // SAFETY: the caller's promise.
    let input = unsafe { ffi::bytes(bytes, len) }.unwrap_or(&[]);
    let mut n = 0u32;
    let mut on_event = |event: Result<D::Item<'_>, D::Error>| {
        if let Ok(item) = event
            && typed(item)
        {
            n += 1;
        }
    };
    if push {
        for b in input {
            d.feed(core::slice::from_ref(b), &mut on_event);
        }
    } else {
        d.feed(input, on_event);
    }
    n
}

/// An AEOLUS decoder of the C library's capacity.
fn aeolus() -> aeolus_proto::Decoder<{ crate::aeolus::PL_AEOLUS_CAPACITY }> {
    aeolus_proto::Decoder::new()
}

/// An AYDP decoder of the C library's capacity, profile Spec.
fn aydp() -> aydp_proto::Decoder<{ crate::aydp::PL_AYDP_CAPACITY }> {
    aydp_proto::Decoder::new(aydp_proto::Profile::Spec)
}

/// The PC side's AOK decoder, firmware 0.35.
fn aok_pc() -> aok_proto::MessageDecoder {
    aok_proto::MessageDecoder::new(aok_proto::FirmwareVersion::new(0, 35))
}

/// Whether a frame's typed parse succeeds (the message kept from the optimiser).
fn aeolus_typed(frame: aeolus_proto::Frame<'_>) -> bool {
    frame.message().map(|m| _ = black_box(&m)).is_ok()
}

/// Whether a frame's typed parse succeeds (the message kept from the optimiser).
fn aydp_typed(frame: aydp_proto::Frame<'_>) -> bool {
    frame.message().map(|m| _ = black_box(&m)).is_ok()
}

/// A message, kept from the optimiser.
fn aok_typed(m: aok_proto::Message) -> bool {
    black_box(&m);
    true
}

/// The exported Rust paths, one a row: its name, the decoder, whether it is fed a byte a call
/// (`push`) or the whole buffer (`feed`), and what counts as a message.
macro_rules! paths {
    ($($(#[$doc:meta])* $name:ident: $decoder:expr, $push:expr, $typed:expr;)*) => {$(
        $(#[$doc])*
        ///
        /// # Safety
        /// `bytes` is readable for `len` bytes.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $name(bytes: *const u8, len: usize) -> u32 {
            // SAFETY: the caller's promise.
            unsafe { count($decoder, bytes, len, $push, $typed) }
        }
    )*};
}

paths! {
    /// AEOLUS, `push` byte by byte, then `frame.message()`.
    pl_bench_rust_aeolus_push: aeolus(), true, aeolus_typed;
    /// AEOLUS, one `feed` over the whole buffer, then `frame.message()`.
    pl_bench_rust_aeolus_feed: aeolus(), false, aeolus_typed;
    /// AYDP (Spec), `push` byte by byte, then `frame.message()`.
    pl_bench_rust_aydp_push: aydp(), true, aydp_typed;
    /// AYDP (Spec), one `feed` over the whole buffer, then `frame.message()`.
    pl_bench_rust_aydp_feed: aydp(), false, aydp_typed;
    /// AOK PC side (firmware 0.35), `push` byte by byte.
    pl_bench_rust_aok_pc_push: aok_pc(), true, aok_typed;
    /// AOK PC side (firmware 0.35), one `feed` over the whole buffer.
    pl_bench_rust_aok_pc_feed: aok_pc(), false, aok_typed;
}
