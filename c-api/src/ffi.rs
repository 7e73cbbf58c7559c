//! What every protocol file shares: the error struct, and the checked conversions from C
//! pointers to Rust slices and buffers. These and the state checks of `state.rs` are all of
//! the crate's pointer checks.

use crate::{PL_E_BUFFER_TOO_SMALL, PL_E_NULL, PL_ERR_CHECKSUM_MISMATCH, PL_ERR_WRONG_LENGTH};

/// An error event: its kind (`PL_ERR_*`), where the kind has them the message ID and two
/// values (see each `PL_ERR_*` for their meaning; 0 otherwise), and its place: the bytes it
/// condemns, as a message's place.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct pl_error {
    /// `PL_ERR_*`.
    pub kind: u32,
    /// The message ID or type the error concerns, 0 if none.
    pub id: u32,
    /// The expected value (a length, a computed checksum), 0 if none.
    pub expected: u32,
    /// The value received (a length, a received checksum, a byte), 0 if none.
    pub actual: u32,
    /// The length on the wire of the bytes the error condemns: a frame with a bad check, flag
    /// to flag (AEOLUS, GDL90) or from its first byte (AYDP, AOK); a frame cut short, from its
    /// opening flag or first byte to the last byte held; an AYDP length error, the six header
    /// bytes judged.
    pub wire_len: u32,
    /// The first of those bytes, counted in bytes fed since the decoder's init.
    pub offset: u64,
}

impl pl_error {
    /// An error of `kind` with its details (its place is written when it is handed over).
    pub(crate) const fn new(kind: u32, id: u32, expected: u32, actual: u32) -> Self {
        Self {
            kind,
            id,
            expected,
            actual,
            wire_len: 0,
            offset: 0,
        }
    }

    /// An error of `kind` without details.
    pub(crate) const fn kind(kind: u32) -> Self {
        Self::new(kind, 0, 0, 0)
    }

    /// A failed check (`PL_ERR_CHECKSUM_MISMATCH`), as every protocol reports one: the
    /// message ID or type, the check computed, the check received.
    pub(crate) fn checksum(id: u8, computed: impl Into<u32>, received: impl Into<u32>) -> Self {
        Self::new(
            PL_ERR_CHECKSUM_MISMATCH,
            id.into(),
            computed.into(),
            received.into(),
        )
    }

    /// A typed message of the wrong data length (`PL_ERR_WRONG_LENGTH`).
    pub(crate) fn wrong_length(id: u8, expected: impl Into<u32>, actual: impl Into<u32>) -> Self {
        Self::new(
            PL_ERR_WRONG_LENGTH,
            id.into(),
            expected.into(),
            actual.into(),
        )
    }
}

/// A count as a `u32` field, saturating.
pub(crate) fn sat32(n: usize) -> u32 {
    u32::try_from(n).unwrap_or(u32::MAX)
}

/// The input bytes `ptr[..len]`: `None` when `ptr` is NULL with a non-zero length or `len` is
/// more than a slice may hold; an empty slice for `len == 0`.
///
/// # Safety
/// When `ptr` is not NULL it must point to `len` readable bytes that stay unchanged for `'a`.
pub(crate) unsafe fn bytes<'a>(ptr: *const u8, len: usize) -> Option<&'a [u8]> {
    if len == 0 {
        return Some(&[]);
    }
    if ptr.is_null() || len > isize::MAX as usize {
        return None;
    }
    // SAFETY: not NULL, at most isize::MAX bytes, readable for `len` bytes (the caller's
    // promise); u8 has alignment 1 and every bit pattern is valid.
    Some(unsafe { core::slice::from_raw_parts(ptr, len) })
}

/// The output buffer `ptr[..len]`, or the negative return code to give back.
///
/// # Safety
/// When `ptr` is not NULL it must point to `len` writable bytes that nothing else accesses
/// for `'a`.
pub(crate) unsafe fn buffer<'a>(ptr: *mut u8, len: usize) -> Result<&'a mut [u8], i32> {
    if ptr.is_null() {
        return Err(PL_E_NULL);
    }
    if len > isize::MAX as usize {
        return Err(PL_E_BUFFER_TOO_SMALL);
    }
    // SAFETY: not NULL, at most isize::MAX bytes, writable and unaliased for `len` bytes (the
    // caller's promise); every bit pattern is a valid u8.
    Ok(unsafe { core::slice::from_raw_parts_mut(ptr, len) })
}

/// A frame length as the encoders' `int32_t` return value.
pub(crate) fn length(n: usize) -> i32 {
    i32::try_from(n).unwrap_or(PL_E_BUFFER_TOO_SMALL)
}

/// A struct built from the fields of the same names of another (a Rust message and its C
/// struct, either way): `fields!(v => pl_aydp_position { latitude, longitude, altitude })`.
macro_rules! fields {
    ($from:expr => $to:path { $($field:ident),* $(,)? }) => {{
        let from = $from;
        $to { $($field: from.$field),* }
    }};
}
pub(crate) use fields;
