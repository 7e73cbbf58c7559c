//! The encoding calls' common part, written once: every `pl_*_encode*` checks the message
//! pointer, its raw data and the caller's buffer here, then its protocol's conversion writes
//! one whole frame of it into the buffer.

use crate::PL_E_NULL;
use crate::ffi;
use crate::message::Raw;

/// `pl_*_encode*`: hands `*msg`, its raw data and the buffer `out[..cap]` to `frame`, which
/// writes one whole frame there and returns its length or a `PL_E_*` code. Returns that
/// length, or `PL_E_NULL` (`msg`, its data or `out`), `PL_E_BUFFER_TOO_SMALL` (`cap` beyond
/// a slice) or `frame`'s code.
///
/// # Safety
/// `msg` is NULL or readable, with its raw data (see [`Raw`]) NULL with length 0 or readable
/// for its length; `out` is NULL or writable for `cap` bytes, and aliases neither.
pub(crate) unsafe fn frame<M: Raw>(
    msg: *const M,
    out: *mut u8,
    cap: usize,
    frame: impl FnOnce(&M, &[u8], &mut [u8]) -> Result<usize, i32>,
) -> i32 {
    // SAFETY: the caller's promise: NULL or readable.
    let Some(msg) = (unsafe { msg.as_ref() }) else {
        return PL_E_NULL;
    };
    let (data, len) = msg.raw();
    // SAFETY: the caller's promise for the raw data.
    let Some(data) = (unsafe { ffi::bytes(data, len) }) else {
        return PL_E_NULL;
    };
    // SAFETY: the caller's promise for `out[..cap]`.
    let out = match unsafe { ffi::buffer(out, cap) } {
        Ok(out) => out,
        Err(code) => return code,
    };
    match frame(msg, data, out) {
        Ok(n) => ffi::length(n),
        Err(code) => code,
    }
}
