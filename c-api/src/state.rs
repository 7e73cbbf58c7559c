//! The caller-owned states (`pl_*_decoder`): how each lies in its C storage, the tag that
//! proves `init` set it up, the checks every call makes before it reads one, and what a caller
//! can ask the archive about them at run time.
//!
//! A state is an opaque C struct of 64-bit words. Its `init` writes a tag word at its start
//! and the Rust state after it. Every other call on a state first checks, in this order: the
//! pointer is not NULL (else `PL_E_NULL`); it is aligned for the state's type (else
//! `PL_E_INVALID`); its first word is the tag of this kind of state and of this ABI version,
//! read as a plain aligned integer (else `PL_E_INVALID`). Only then is a reference to the Rust
//! state formed, so memory that `init` never wrote (zeros, a fill pattern, garbage, another
//! protocol's state, a state of an archive of another ABI version) is refused, not read as a
//! decoder. The tag has 64 bits, so leftover memory matches it with a probability of 2^-64
//! (no repeated byte matches it), unless what is left there is a state of the same kind: the
//! tag cannot tell a state from what remains of one. The check reads the first 8 bytes only,
//! so any of this library's states passed to another protocol's call is refused without a
//! read past its end.
//!
//! [`pl_abi_version`], [`pl_state_size`] and [`pl_state_align`] let a C program check at run
//! time that the header it was compiled with describes the archive it is linked with.

use crate::{PL_E_INVALID, PL_E_NULL};

/// The ABI version of this archive and header: it changes whenever a state's size, alignment
/// or tag, a struct's layout, or a function's signature or meaning changes, so a program can
/// compare the header's `PL_ABI_VERSION` with the archive's `pl_abi_version()`. Version 1 was
/// the first with tagged states; version 3 counts the bytes fed in each state and gives every
/// message its `offset` and `wire_len`; version 4 gives every error its place too
/// (`pl_error` grew from 16 to 32 bytes) and has every decoder keep the last event's place (the
/// states grew by one word, AEOLUS and GDL90, or two, AYDP and AOK).
pub const PL_ABI_VERSION: u32 = 4;

/// The ABI version of the archive, `PL_ABI_VERSION` of the header it was built with.
///
/// ```c
/// if (pl_abi_version() != PL_ABI_VERSION) halt("protolink.h and libprotolink_c.a differ");
/// ```
#[unsafe(no_mangle)]
pub extern "C" fn pl_abi_version() -> u32 {
    PL_ABI_VERSION
}

/// State kind: `pl_aeolus_decoder`.
pub const PL_STATE_AEOLUS: u32 = 1;
/// State kind: `pl_aydp_decoder`.
pub const PL_STATE_AYDP: u32 = 2;
/// State kind: `pl_aok_device_decoder`.
pub const PL_STATE_AOK_DEVICE: u32 = 3;
/// State kind: `pl_aok_pc_decoder`.
pub const PL_STATE_AOK_PC: u32 = 4;
/// State kind: `pl_gdl90_decoder`.
pub const PL_STATE_GDL90: u32 = 5;

/// Size and alignment of the C state of `kind`.
fn layout(kind: u32) -> Option<(usize, usize)> {
    use crate::{aeolus, aok, aydp, gdl90};
    fn of<S: State>() -> (usize, usize) {
        (core::mem::size_of::<S>(), core::mem::align_of::<S>())
    }
    Some(match kind {
        PL_STATE_AEOLUS => of::<aeolus::pl_aeolus_decoder>(),
        PL_STATE_AYDP => of::<aydp::pl_aydp_decoder>(),
        PL_STATE_AOK_DEVICE => of::<aok::pl_aok_device_decoder>(),
        PL_STATE_AOK_PC => of::<aok::pl_aok_pc_decoder>(),
        PL_STATE_GDL90 => of::<gdl90::pl_gdl90_decoder>(),
        _ => return None,
    })
}

/// The size in bytes of the state of `kind` (`PL_STATE_*`) in this archive, or 0 for a kind
/// it does not know. One function for every state, not one per state: a program compiled
/// against a newer header can ask an older archive about a state it lacks and get 0, and a
/// new protocol adds a kind, not a function.
///
/// ```c
/// if (pl_state_size(PL_STATE_AEOLUS) != sizeof(pl_aeolus_decoder)) halt("wrong header");
/// ```
#[unsafe(no_mangle)]
pub extern "C" fn pl_state_size(kind: u32) -> usize {
    layout(kind).map_or(0, |(size, _)| size)
}

/// The alignment in bytes of the state of `kind` (`PL_STATE_*`) in this archive, or 0 for a
/// kind it does not know (see `pl_state_size`).
///
/// ```c
/// if (pl_state_align(PL_STATE_AEOLUS) != _Alignof(pl_aeolus_decoder)) halt("wrong header");
/// ```
#[unsafe(no_mangle)]
pub extern "C" fn pl_state_align(kind: u32) -> usize {
    layout(kind).map_or(0, |(_, align)| align)
}

/// A C state type (`pl_*_decoder`) and the Rust state it holds.
///
/// # Safety
/// `Self` is a `#[repr(C)]` struct of integers (every bit pattern valid) for which
/// [`fits::<Self>()`](fits) holds, and no other `State` has the same `KIND`.
pub(crate) unsafe trait State {
    /// The Rust state.
    type Inner;
    /// Its `PL_STATE_*`, in its tag.
    const KIND: u32;
}

/// How a state lies in its C storage: the tag, then the Rust state.
#[repr(C)]
struct Tagged<D> {
    tag: u64,
    inner: D,
}

/// The tag of a state of `kind` in this ABI version.
const fn tag(kind: u32) -> u64 {
    tag_of(kind, PL_ABI_VERSION)
}

/// The tag of a state of `kind` in ABI `version`: a magic number and the kind in the low half,
/// the version in the high half. No two kinds or versions share a tag, and no repeated byte is
/// one.
const fn tag_of(kind: u32, version: u32) -> u64 {
    const MAGIC: u32 = 0x7E1A_9C00;
    (MAGIC | (kind & 0xFF)) as u64 | (version as u64) << 32
}

/// Whether the C storage `S` can hold a tagged `S::Inner` (each protocol file asserts it at
/// compile time, on every target).
pub(crate) const fn fits<S: State>() -> bool {
    core::mem::size_of::<Tagged<S::Inner>>() <= core::mem::size_of::<S>()
        && core::mem::align_of::<Tagged<S::Inner>>() <= core::mem::align_of::<S>()
}

/// Declares the C state types of a protocol: the header's constants of their storage (`WORDS`,
/// `SIZE`, `ALIGN`; `$of` names the states in their documentation) and, for each, a
/// `#[repr(C)]` struct of that many `u64` words that holds `Inner`, a state of kind `KIND`.
/// Checks at compile time that the state fits and that its size and alignment are `SIZE` and
/// `ALIGN`.
macro_rules! c_states {
    (
        $words:ident = $w:literal, $size:ident = $s:literal, $align:ident = $a:literal, of $of:literal;
        $( $(#[$doc:meta])* $state:ident: $inner:ty, $kind:expr; )+
    ) => {
        #[doc = concat!(" 64-bit words in ", $of, ".")]
        pub const $words: usize = $w;
        #[doc = concat!(" Size of ", $of, " in bytes:")]
        #[doc = " the tag and the decoder (an upper bound over the supported targets)."]
        pub const $size: usize = $s;
        #[doc = concat!(" Alignment of ", $of, " in bytes.")]
        pub const $align: usize = $a;
        $(
            $(#[$doc])*
            #[repr(C)]
            pub struct $state {
                /// Opaque.
                pub opaque: [u64; $words],
            }
            // SAFETY: plain words; `fits` is asserted below; no other state has this kind.
            unsafe impl $crate::state::State for $state {
                type Inner = $inner;
                const KIND: u32 = $kind;
            }
            const _: () = assert!($crate::state::fits::<$state>());
            const _: () = assert!($size == core::mem::size_of::<$state>());
            const _: () = assert!(core::mem::align_of::<$inner>() <= $align);
        )+
    };
}
pub(crate) use c_states;

/// Writes the tag and a fresh Rust state `value` into the C state. Returns 0, `PL_E_NULL`,
/// or `PL_E_INVALID` for a pointer not aligned for `S` (nothing written).
///
/// # Safety
/// `state` is NULL or valid for writes of an `S`.
pub(crate) unsafe fn init<S: State>(state: *mut S, value: S::Inner) -> i32 {
    if state.is_null() {
        return PL_E_NULL;
    }
    if !state.is_aligned() {
        return PL_E_INVALID;
    }
    // SAFETY: not NULL, aligned for `S`, valid for writes of an `S` (the caller's promise),
    // which can hold a `Tagged<S::Inner>` (`fits`, the `State` promise). Whatever was there
    // before is plain bytes: nothing to drop.
    unsafe {
        state.cast::<Tagged<S::Inner>>().write(Tagged {
            tag: tag(S::KIND),
            inner: value,
        })
    };
    0
}

/// Checks `state` before anything of it is read as a Rust state: `PL_E_NULL` for NULL,
/// `PL_E_INVALID` for a pointer not aligned for `S` or a first word that is not the tag of
/// an `S` of this ABI version. Reads the first 8 bytes only, as one aligned `u64`.
///
/// # Safety
/// `state` is NULL or points to at least 8 readable bytes.
unsafe fn check<S: State>(state: *const S) -> Result<(), i32> {
    if state.is_null() {
        return Err(PL_E_NULL);
    }
    if !state.is_aligned() {
        return Err(PL_E_INVALID);
    }
    // SAFETY: not NULL, aligned for `S` and so for `u64` (`S` starts with the tag and is at
    // least as aligned as it), 8 readable bytes (the caller's promise); every bit pattern is
    // a valid `u64`. No reference to the state is formed.
    let found = unsafe { state.cast::<u64>().read() };
    if found == tag(S::KIND) {
        Ok(())
    } else {
        Err(PL_E_INVALID)
    }
}

/// The Rust state behind a C state pointer, or the code to return: `PL_E_NULL`,
/// `PL_E_INVALID` (see [`check`]).
///
/// # Safety
/// `state` is NULL or points to at least 8 readable bytes; if those hold the tag of an `S`,
/// it is an `S` that `init` set up, that nothing else accesses for `'a`.
pub(crate) unsafe fn checked<'a, S: State>(state: *mut S) -> Result<&'a mut S::Inner, i32> {
    // SAFETY: the caller's promise.
    unsafe { check(state) }?;
    // SAFETY: the tag is there, so `init` wrote a `Tagged<S::Inner>` at this aligned address
    // (the caller's promise), and nothing else accesses it for `'a`.
    Ok(unsafe { &mut (*state.cast::<Tagged<S::Inner>>()).inner })
}

/// The Rust state behind a `const` C state pointer, read only (see [`checked`]).
///
/// # Safety
/// As [`checked`], but nothing writes to it for `'a`.
pub(crate) unsafe fn checked_ref<'a, S: State>(state: *const S) -> Result<&'a S::Inner, i32> {
    // SAFETY: the caller's promise.
    unsafe { check(state) }?;
    // SAFETY: as in `checked`; shared access only.
    Ok(unsafe { &(*state.cast::<Tagged<S::Inner>>()).inner })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::aeolus::pl_aeolus_decoder;
    use crate::calls::{pl_aeolus_init, pl_aeolus_parse};
    use crate::{PL_NOTHING, pl_error};
    use core::mem::MaybeUninit;

    const KINDS: [u32; 5] = [
        PL_STATE_AEOLUS,
        PL_STATE_AYDP,
        PL_STATE_AOK_DEVICE,
        PL_STATE_AOK_PC,
        PL_STATE_GDL90,
    ];

    #[test]
    fn tags_differ_by_kind_and_version_and_are_no_repeated_byte() {
        for (i, &a) in KINDS.iter().enumerate() {
            for &b in &KINDS[i + 1..] {
                assert_ne!(tag(a), tag(b));
            }
            assert_ne!(tag(a), tag_of(a, PL_ABI_VERSION + 1));
            assert_ne!(tag(a), tag_of(a, 0));
            for byte in 0..=255u8 {
                assert_ne!(tag(a), u64::from_ne_bytes([byte; 8]));
            }
        }
    }

    #[test]
    fn a_state_of_another_abi_version_is_refused_untouched() {
        let mut d = MaybeUninit::<pl_aeolus_decoder>::uninit();
        let p = d.as_mut_ptr();
        // SAFETY: writable storage for the state; the tag is its first word (aligned).
        unsafe {
            assert_eq!(pl_aeolus_init(p), 0);
            p.cast::<u64>()
                .write(tag_of(PL_STATE_AEOLUS, PL_ABI_VERSION + 1));
        }
        let (mut msg, mut err) = (MaybeUninit::uninit(), pl_error::new(7, 7, 7, 7));
        let mut used = 0;
        // SAFETY: a state (refused), live outputs.
        let st = unsafe { pl_aeolus_parse(p, &0x7E, 1, &mut used, msg.as_mut_ptr(), &mut err) };
        assert_eq!((st, err), (PL_E_INVALID, pl_error::new(7, 7, 7, 7)));
        // The same state with this version's tag back is a decoder again.
        // SAFETY: as above.
        unsafe { p.cast::<u64>().write(tag(PL_STATE_AEOLUS)) };
        // SAFETY: a set-up state, live outputs.
        let st = unsafe { pl_aeolus_parse(p, &0x7E, 1, &mut used, msg.as_mut_ptr(), &mut err) };
        assert_eq!(st, PL_NOTHING);
    }
}
