//! The decoding calls of every protocol, written once: `init`, `parse`, `feed`, `finish` and
//! `get_stats` over the decoder contract ([`Decode`]), driven through its one adapter,
//! [`Stream`], which gives every event its place. Each protocol file implements [`Proto`] (its
//! C message and stats structs, how an item fills the one and the counters the other), and
//! `calls.rs` exports the one-line `pl_*` shims that call these functions; no decoding logic
//! is repeated per protocol.
//!
//! A C state holds a [`Stream`]: the decoder and the bytes it has used since `init`, from
//! which each event's `offset` and `wire_len` come, whatever slices the bytes came in.

/// The adapter every C state holds (`frame_io::Stream`, as the protocol crates re-export it).
pub(crate) use aeolus_proto::Stream;
use aeolus_proto::{Decode, Place};

use crate::ffi::{self, pl_error, sat32};
use crate::message::Placed;
use crate::state::{self, State};
use crate::{PL_E_NULL, PL_ERROR, PL_NOTHING};

/// A C state type whose decoder follows the contract, with its C message and stats structs:
/// what differs between the protocols, and all that the calls below need of one.
pub(crate) trait Proto: State<Inner = Stream<Self::Dec>> {
    /// The protocol crate's decoder.
    type Dec: Decode;
    /// The C message struct (`pl_*_message`, `pl_aok_item`).
    type Msg: Placed;
    /// The C counters struct (`pl_*_stats`).
    type Stats;
    /// A message struct holding nothing: every field 0, pointers NULL, a kind "unknown" where
    /// the struct has one (what `PL_ERROR` leaves in it unless the error concerns a whole
    /// frame).
    const EMPTY: Self::Msg;
    /// Fills `msg` from an item (and `err`, for a frame with a good check whose typed parse
    /// failed, leaving its raw data in `msg`); returns the status.
    fn fill(item: <Self::Dec as Decode>::Item<'_>, msg: &mut Self::Msg, err: &mut pl_error) -> i32;
    /// An error as the C struct.
    fn error(e: <Self::Dec as Decode>::Error) -> pl_error;
    /// Whether an error concerns a whole frame with a good check whose typed parse failed
    /// (GDL90), so that its place goes into the message struct as a message's does.
    fn parse_failed(_e: &<Self::Dec as Decode>::Error) -> bool {
        false
    }
    /// The counters as the C struct (see [`stats`]).
    fn stats(d: &Self::Dec) -> Self::Stats;
}

/// A decoder's counters as its C struct: the named counters of its `stats()`, as they are,
/// and `held_bytes` from its `held_bytes()`, saturating. Each protocol names the counters it
/// has: `stats!(d => pl_aydp_stats { frames_ok, checksum_errors, ... })`.
macro_rules! stats {
    ($d:expr => $c:ident { $($counter:ident),* $(,)? }) => {{
        let s = $d.stats();
        $c { $($counter: s.$counter,)* held_bytes: $crate::ffi::sat32($d.held_bytes()) }
    }};
}
pub(crate) use stats;

/// An event callback of `pl_*_feed` (each protocol names its own type, of this shape).
pub(crate) type Callback<M> =
    Option<unsafe extern "C" fn(*mut core::ffi::c_void, i32, *const M, *const pl_error)>;

/// One event into the caller's structs: the status. An item, and an error about a frame whose
/// typed parse failed, write their place into `msg`; any other error leaves `msg` holding
/// nothing. Every error writes its place into `err`.
#[inline(always)]
#[allow(clippy::type_complexity)] // spelt out: what `Stream` hands over
fn convert<P: Proto>(
    (place, event): (
        Place,
        Result<<P::Dec as Decode>::Item<'_>, <P::Dec as Decode>::Error>,
    ),
    msg: &mut P::Msg,
    err: &mut pl_error,
) -> i32 {
    let status = match event {
        Ok(item) => {
            let status = P::fill(item, msg, err);
            msg.place(place.offset, sat32(place.len));
            status
        }
        Err(e) => {
            *msg = P::EMPTY;
            if P::parse_failed(&e) {
                msg.place(place.offset, sat32(place.len));
            }
            *err = P::error(e);
            PL_ERROR
        }
    };
    if status == PL_ERROR {
        (err.offset, err.wire_len) = (place.offset, sat32(place.len));
    }
    status
}

/// Decodes `input` up to the first event and hands it to the caller's structs: the bytes
/// used and the status (`PL_NOTHING`: every byte used, no event). An item found in place in
/// `input` (AYDP's whole frames) is first copied into the decoder ([`Stream::next_kept`]), so
/// that a message's `data` points into the decoder, as the header promises. The one place
/// `decode` is called, for `parse` and `feed` alike: with a second call site LLVM keeps AOK's
/// `decode` out of line, where a slice copy's length check in it (`Held::keep`) survives and
/// the panic-never link of `tests/firmware.sh` fails.
fn step<P: Proto>(
    f: &mut Stream<P::Dec>,
    input: &[u8],
    msg: &mut P::Msg,
    err: &mut pl_error,
) -> (usize, i32) {
    match f.next_kept(input) {
        (used, Some(event)) => (used, convert::<P>(event, msg, err)),
        (used, None) => (used, PL_NOTHING),
    }
}

/// `pl_*_init`: writes the tag and a fresh decoder `dec`.
///
/// # Safety
/// `state` is NULL or valid for writes of a `P`.
pub(crate) unsafe fn init<P: Proto>(state: *mut P, dec: P::Dec) -> i32 {
    // SAFETY: the caller's promise; `fits` is asserted in each protocol file.
    unsafe { state::init(state, Stream::new(dec)) }
}

/// `pl_*_parse`: decodes `bytes[..len]` up to the first event (one a call; an event a rescan
/// left queued comes first, with `*used` 0).
///
/// # Safety
/// `state` is NULL or a state (see `state::checked`) that nothing else uses during the call;
/// `bytes` is NULL (with `len` 0) or readable for `len` bytes; `used`, `msg`, `err` are NULL
/// or writable; none alias.
pub(crate) unsafe fn parse<P: Proto>(
    state: *mut P,
    bytes: *const u8,
    len: usize,
    used: *mut usize,
    msg: *mut P::Msg,
    err: *mut pl_error,
) -> i32 {
    // SAFETY: the caller's promise, checked before it is read.
    let f = match unsafe { state::checked(state) } {
        Ok(f) => f,
        Err(code) => return code,
    };
    // SAFETY: the caller's promises.
    let (Some(msg), Some(err), Some(input), Some(used)) = (
        unsafe { msg.as_mut() },
        unsafe { err.as_mut() },
        unsafe { ffi::bytes(bytes, len) },
        unsafe { used.as_mut() },
    ) else {
        return PL_E_NULL;
    };
    let (n, status) = step::<P>(f, input, msg, err);
    *used = n;
    status
}

/// `pl_*_feed`: every event of `bytes[..len]` to `on_event`, in order.
///
/// # Safety
/// As [`parse`] for `state` and `bytes`; `on_event` may be called with `ctx` and does not use
/// `state`.
pub(crate) unsafe fn feed<P: Proto>(
    state: *mut P,
    bytes: *const u8,
    len: usize,
    on_event: Callback<P::Msg>,
    ctx: *mut core::ffi::c_void,
) -> i32 {
    // SAFETY: the caller's promise, checked before it is read.
    let f = match unsafe { state::checked(state) } {
        Ok(f) => f,
        Err(code) => return code,
    };
    // SAFETY: the caller's promises.
    let (Some(input), Some(call)) = (unsafe { ffi::bytes(bytes, len) }, on_event) else {
        return PL_E_NULL;
    };
    let (mut msg, mut err) = (P::EMPTY, pl_error::default());
    let mut rest = input;
    loop {
        let (n, status) = step::<P>(f, rest, &mut msg, &mut err);
        if status == PL_NOTHING {
            return PL_NOTHING;
        }
        rest = rest.get(n..).unwrap_or(&[]);
        // SAFETY: the caller's promise: `call` may be called with `ctx`; both pointers are to
        // live locals for the duration of the call.
        unsafe { call(ctx, status, &msg, &err) };
    }
}

/// `pl_*_finish`: the next event of the end of the stream, `PL_NOTHING` once there is none.
///
/// # Safety
/// As [`parse`] for `state`, `msg` and `err`.
pub(crate) unsafe fn finish<P: Proto>(state: *mut P, msg: *mut P::Msg, err: *mut pl_error) -> i32 {
    // SAFETY: the caller's promise, checked before it is read.
    let f = match unsafe { state::checked(state) } {
        Ok(f) => f,
        Err(code) => return code,
    };
    // SAFETY: the caller's promises.
    let (Some(msg), Some(err)) = (unsafe { msg.as_mut() }, unsafe { err.as_mut() }) else {
        return PL_E_NULL;
    };
    let Some(event) = f.end_event() else {
        return PL_NOTHING;
    };
    convert::<P>(event, msg, err)
}

/// `pl_*_get_stats`: copies the counters into `*out`.
///
/// # Safety
/// `state` is NULL or a state (see `state::checked_ref`) that nothing writes during the call;
/// `out` is NULL or writable.
pub(crate) unsafe fn get_stats<P: Proto>(state: *const P, out: *mut P::Stats) -> i32 {
    // SAFETY: the caller's promise, checked before it is read.
    let f = match unsafe { state::checked_ref(state) } {
        Ok(f) => f,
        Err(code) => return code,
    };
    // SAFETY: the caller's promise (the decoder is only read).
    let Some(out) = (unsafe { out.as_mut() }) else {
        return PL_E_NULL;
    };
    *out = P::stats(f.decoder());
    0
}
