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

/// A C state type whose decoder follows the contract, with its C message and stats structs.
pub(crate) trait Proto: State<Inner = Face<Self::Dec>> {
    /// The protocol crate's decoder.
    type Dec: Decode;
    /// The C message struct (`pl_*_message`, `pl_aok_item`).
    type Msg;
    /// The C counters struct (`pl_*_stats`).
    type Stats;
    /// What [`Proto::fill`] and [`Proto::frame_len`] need of the decoder, read before each
    /// event (AEOLUS and GDL90: `frame_bytes`; the AOK PC side: its reply form).
    type Ctx: Copy;
    /// The decoder's item may borrow the slice given to `decode` (AYDP): `parse` then decodes
    /// one byte at a time, so that a message's `data` points into the decoder, as promised.
    const BYTEWISE: bool = false;
    /// The decoder gives at most one event a byte and its `feed` has a per-byte path faster
    /// than `decode` on one byte (AEOLUS, GDL90): `parse` on one byte takes that path.
    const ONE_EVENT_A_BYTE: bool = false;

    /// A message struct holding nothing: every field 0, pointers NULL (what `PL_ERROR` leaves
    /// in it unless the error concerns a whole frame).
    fn empty() -> Self::Msg;
    /// The bytes fed that the decoder holds, undecided.
    fn held(d: &Self::Dec) -> usize;
    /// See [`Proto::Ctx`].
    fn context(d: &Self::Dec) -> Self::Ctx;
    /// Fills `msg` from an item (and `err`, for a frame with a good check whose typed parse
    /// failed, leaving its raw data in `msg`); returns the status and the item's wire length,
    /// or 0 where [`Proto::frame_len`] tells it.
    fn fill(
        item: <Self::Dec as Decode>::Item<'_>,
        ctx: Self::Ctx,
        msg: &mut Self::Msg,
        err: &mut pl_error,
    ) -> (i32, usize);
    /// An error as the C struct.
    fn error(e: <Self::Dec as Decode>::Error) -> pl_error;
    /// The wire length of the frame an event just ended, from the counters (AEOLUS, GDL90:
    /// the `frame_bytes` counted since `ctx`, with the two flags), 0 when none was counted.
    fn frame_len(_d: &Self::Dec, _ctx: Self::Ctx) -> usize {
        0
    }
    /// Writes a message's place in the stream into `msg`.
    fn place(msg: &mut Self::Msg, offset: u64, wire_len: u32);
    /// The counters as the C struct.
    fn stats(d: &Self::Dec) -> Self::Stats;
}

/// An event callback of `pl_*_feed` (each protocol names its own type, of this shape).
pub(crate) type Callback<M> =
    Option<unsafe extern "C" fn(*mut core::ffi::c_void, i32, *const M, *const pl_error)>;

/// One event into the caller's structs: the status and the item's wire length (0: ask
/// [`Proto::frame_len`]). On `PL_ERROR`, `msg` holds only what belongs to the error: nothing,
/// or the raw frame whose typed parse failed.
#[inline(always)]
fn convert<P: Proto>(
    event: Result<<P::Dec as Decode>::Item<'_>, <P::Dec as Decode>::Error>,
    ctx: P::Ctx,
    msg: &mut P::Msg,
    err: &mut pl_error,
) -> (i32, usize) {
    match event {
        Ok(item) => P::fill(item, ctx, msg, err),
        Err(e) => {
            *msg = P::empty();
            *err = P::error(e);
            (PL_ERROR, 0)
        }
    }
}

/// The wire length of a flag-framed frame (AEOLUS, GDL90) from the `frame_bytes` counter
/// before and after its event (the bytes between its flags): with both flags, 0 when the
/// event counted no frame.
pub(crate) fn flagged_len(before: u32, after: u32) -> usize {
    match after.wrapping_sub(before) {
        0 => 0,
        n => n as usize + 2,
    }
}

/// An event of `decode` on `input` (or of `end`, on nothing) as the item or the error.
fn result<'a, D: Decode>(
    d: &'a D,
    input: &'a [u8],
    event: Event<D::Found, D::Error>,
) -> Result<D::Item<'a>, D::Error> {
    match event {
        Event::Found(found) => Ok(d.item(input, found)),
        Event::Error(e) => Err(e),
        Event::Truncated(_) => Err(D::TRUNCATED),
    }
}

/// After an event of `used` bytes: counts them and writes the message's place (it ends where
/// the bytes the decoder still holds begin). Returns `status`.
/// It takes the count and the decoder apart, the decoder shared: `msg` may point into the
/// decoder, and a unique borrow of the whole state here would invalidate that pointer (Miri).
fn placed<P: Proto>(
    fed: &mut u64,
    dec: &P::Dec,
    used: usize,
    (status, len): (i32, usize),
    ctx: P::Ctx,
    msg: &mut P::Msg,
) -> i32 {
    *fed = fed.wrapping_add(used as u64);
    let len = if len > 0 { len } else { P::frame_len(dec, ctx) };
    if len > 0 {
        let end = fed.wrapping_sub(P::held(dec) as u64);
        P::place(msg, end.wrapping_sub(len as u64), sat32(len));
    }
    status
}

/// One byte through the crate's per-byte path (`Proto::ONE_EVENT_A_BYTE`: nothing can be
/// queued, so the byte is used): the status.
#[inline(always)]
fn one_byte<P: Proto>(
    f: &mut Face<P::Dec>,
    byte: &[u8],
    msg: &mut P::Msg,
    err: &mut pl_error,
) -> i32 {
    let ctx = P::context(&f.dec);
    let mut event = (PL_NOTHING, 0);
    f.dec.feed(byte, |e| event = convert::<P>(e, ctx, msg, err));
    if event.0 == PL_NOTHING {
        f.fed = f.fed.wrapping_add(1);
        return PL_NOTHING;
    }
    placed::<P>(&mut f.fed, &f.dec, 1, event, ctx, msg)
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
        let ctx = P::context(&f.dec);
        let (n, event) = f.dec.decode(chunk);
        used += n;
        let event = match event {
            None => {
                f.fed = f.fed.wrapping_add(n as u64);
                if used >= input.len() {
                    return (used, PL_NOTHING);
                }
                continue;
            }
            Some(event) => result(&f.dec, chunk, event),
        };
        let event = convert::<P>(event, ctx, msg, err);
        return (used, placed::<P>(&mut f.fed, &f.dec, n, event, ctx, msg));
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
    if P::ONE_EVENT_A_BYTE && input.len() == 1 {
        *used = 1;
        return one_byte::<P>(f, input, msg, err);
    }
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
    let ctx = P::context(&f.dec);
    let Some(event) = f.dec.end() else {
        return PL_NOTHING;
    };
    let event = result(&f.dec, &[], event);
    let event = convert::<P>(event, ctx, msg, err);
    placed::<P>(&mut f.fed, &f.dec, 0, event, ctx, msg)
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
