//! The decoding calls of every protocol, written once: `init`, `parse`, `feed`, `finish` and
//! `get_stats` over the decoder contract ([`Decode`]). Each protocol file implements [`Proto`]
//! (its C message struct and how an event fills it) and exports one-line `pl_*` shims that
//! call these functions; no decoding logic is repeated per protocol.
//!
//! A C state holds a [`Face`]: the decoder and the number of bytes fed to it since `init`.
//! An event's message ends where the bytes the decoder still holds begin, so a message's
//! `offset` is `fed - held_bytes() - wire_len`, whatever slices the bytes came in.

use aeolus_proto::{Decode, Event};

use crate::ffi::{self, pl_error, sat32};
use crate::state::{self, State};
use crate::{PL_E_NULL, PL_ERROR, PL_NOTHING};

/// What a C state holds after its tag: the decoder, and the bytes fed to it since `init`.
pub(crate) struct Face<D> {
    /// The protocol crate's decoder.
    pub(crate) dec: D,
    /// Bytes fed since `init` (wrapping), `finish` included: the offsets count from here.
    fed: u64,
}

impl<D> Face<D> {
    /// A fresh decoder, nothing fed.
    pub(crate) const fn new(dec: D) -> Self {
        Self { dec, fed: 0 }
    }
}

/// The event of a decoder `D`, as its `decode` and `end` give it.
type EventOf<D> = Event<<D as Decode>::Found, <D as Decode>::Error>;

/// A C state type whose decoder follows the contract, with its C message and stats structs.
pub(crate) trait Proto: State<Inner = Face<Self::Dec>> {
    /// The protocol crate's decoder.
    type Dec: Decode;
    /// The C message struct (`pl_*_message`, `pl_aok_item`).
    type Msg;
    /// The C counters struct (`pl_*_stats`).
    type Stats;
    /// The decoder's item may borrow the slice given to `decode` (AYDP): `parse` then decodes
    /// one byte at a time, so that a message's `data` points into the decoder, as promised.
    const BYTEWISE: bool = false;

    /// A message struct holding nothing: every field 0, pointers NULL (what `PL_ERROR` leaves
    /// in it unless the error concerns a whole frame).
    fn empty() -> Self::Msg;
    /// The bytes fed that the decoder holds, undecided.
    fn held(d: &Self::Dec) -> usize;
    /// A counter read before each event, from which [`Proto::message`] and [`Proto::error`]
    /// work out a frame's wire length (AEOLUS and GDL90: `frame_bytes`); 0 where the item
    /// knows its own length.
    fn mark(_d: &Self::Dec) -> u32 {
        0
    }
    /// Fills `msg` from an item (and `err`, for a frame with a good check whose typed parse
    /// failed, leaving its raw data in `msg`); returns the status and the frame's wire length.
    fn message(
        d: &Self::Dec,
        item: <Self::Dec as Decode>::Item<'_>,
        mark: u32,
        msg: &mut Self::Msg,
        err: &mut pl_error,
    ) -> (i32, usize);
    /// An error as the C struct, and the wire length of the whole frame it concerns (a frame
    /// with a good check whose typed parse failed), 0 for none.
    fn error(d: &Self::Dec, e: <Self::Dec as Decode>::Error, mark: u32) -> (pl_error, usize);
    /// Writes a message's place in the stream into `msg`.
    fn place(msg: &mut Self::Msg, offset: u64, wire_len: u32);
    /// The counters as the C struct.
    fn stats(d: &Self::Dec) -> Self::Stats;
}

/// An event callback of `pl_*_feed` (each protocol names its own type, of this shape).
pub(crate) type Callback<M> =
    Option<unsafe extern "C" fn(*mut core::ffi::c_void, i32, *const M, *const pl_error)>;

/// Hands one event of `decode` (on `input`, `used` bytes of it used) or `end` to the caller's
/// structs and returns the status. On `PL_ERROR`, `msg` holds only what belongs to the error:
/// nothing, or the raw frame whose typed parse failed, with its place.
fn deliver<P: Proto>(
    f: &mut Face<P::Dec>,
    input: &[u8],
    used: usize,
    event: EventOf<P::Dec>,
    mark: u32,
    msg: &mut P::Msg,
    err: &mut pl_error,
) -> i32 {
    f.fed = f.fed.wrapping_add(used as u64);
    let end = f.fed.wrapping_sub(P::held(&f.dec) as u64);
    let failure = match event {
        Event::Found(found) => {
            let (status, len) = P::message(&f.dec, f.dec.item(input, found), mark, msg, err);
            if len > 0 {
                P::place(msg, end.wrapping_sub(len as u64), sat32(len));
            }
            return status;
        }
        Event::Error(e) => e,
        Event::Truncated(_) => <P::Dec as Decode>::TRUNCATED,
    };
    *msg = P::empty();
    let (e, len) = P::error(&f.dec, failure, mark);
    *err = e;
    if len > 0 {
        P::place(msg, end.wrapping_sub(len as u64), sat32(len));
    }
    PL_ERROR
}

/// Decodes `input` up to the first event (`bytewise`: one byte a `decode` call) and hands it
/// to the caller's structs: the bytes used and the status (`PL_NOTHING`: every byte used, no
/// event). The one place `decode` is called, for `parse` and `feed` alike: with a second call
/// site LLVM keeps AOK's `decode` out of line, where a slice copy's length check in it
/// (`Held::keep`) survives and the panic-never link of `tests/firmware.sh` fails.
fn step<P: Proto>(
    f: &mut Face<P::Dec>,
    input: &[u8],
    bytewise: bool,
    msg: &mut P::Msg,
    err: &mut pl_error,
) -> (usize, i32) {
    let mut used = 0;
    loop {
        let rest = input.get(used..).unwrap_or(&[]);
        let chunk = if bytewise {
            rest.get(..1).unwrap_or(&[])
        } else {
            rest
        };
        let mark = P::mark(&f.dec);
        let (n, event) = f.dec.decode(chunk);
        used += n;
        match event {
            Some(event) => return (used, deliver::<P>(f, chunk, n, event, mark, msg, err)),
            None => f.fed = f.fed.wrapping_add(n as u64),
        }
        if used >= input.len() {
            return (used, PL_NOTHING);
        }
    }
}

/// `pl_*_init`: writes the tag and a fresh decoder `dec`.
///
/// # Safety
/// `state` is NULL or valid for writes of a `P`.
pub(crate) unsafe fn init<P: Proto>(state: *mut P, dec: P::Dec) -> i32 {
    // SAFETY: the caller's promise; `fits` is asserted in each protocol file.
    unsafe { state::init(state, Face::new(dec)) }
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
    let (n, status) = step::<P>(f, input, P::BYTEWISE, msg, err);
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
    let (mut msg, mut err) = (P::empty(), pl_error::default());
    let mut rest = input;
    loop {
        let (n, status) = step::<P>(f, rest, false, &mut msg, &mut err);
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
    let mark = P::mark(&f.dec);
    match f.dec.end() {
        Some(event) => deliver::<P>(f, &[], 0, event, mark, msg, err),
        None => PL_NOTHING,
    }
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
    *out = P::stats(&f.dec);
    0
}
