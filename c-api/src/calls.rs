//! Every C function of the decoders and encoders, in the header's order (cbindgen writes the
//! functions in the order it reads them, and reads this file whole), with the C documentation
//! the header carries. Each only forwards: the decoding calls to `face.rs`, written once over
//! `face::Proto`, the encoders to `encode.rs` and their protocol's conversion, so that a
//! protocol file holds only what differs (its C structs and how an item fills them).

use aok_proto::{CommandDecoder, FirmwareVersion, MessageDecoder};

use crate::PL_E_BAD_TAG;
use crate::aeolus::{self, *};
use crate::aok::{self, *};
use crate::aydp::{self, *};
use crate::gdl90::{self, *};
use crate::{encode, face, pl_error};

// AEOLUS.

/// Sets up `dec` as a fresh decoder that accepts frames without a CRC (`00 00`, as the spec
/// allows). Returns 0, `PL_E_NULL`, or `PL_E_INVALID` (`dec` not aligned for its type).
///
/// ```c
/// pl_aeolus_decoder dec;
/// pl_aeolus_init(&dec);
/// ```
///
/// # Safety
/// `dec` is NULL or points to writable memory for a `pl_aeolus_decoder`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_aeolus_init(dec: *mut pl_aeolus_decoder) -> i32 {
    // SAFETY: the caller's promise.
    unsafe { face::init(dec, aeolus::Inner::new()) }
}

/// Sets up `dec` as a fresh strict decoder: frames without a CRC are errors
/// (`PL_ERR_MISSING_CRC`). Returns 0, `PL_E_NULL`, or `PL_E_INVALID` (`dec` not aligned).
///
/// ```c
/// pl_aeolus_decoder dec;
/// pl_aeolus_init_strict(&dec);
/// ```
///
/// # Safety
/// `dec` is NULL or points to writable memory for a `pl_aeolus_decoder`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_aeolus_init_strict(dec: *mut pl_aeolus_decoder) -> i32 {
    // SAFETY: the caller's promise.
    unsafe { face::init(dec, aeolus::Inner::strict()) }
}

/// Decodes `bytes[..len]` up to the next event: stops after the byte that completed a message
/// or an error and sets `*used` to the bytes it took (all of `len` with `PL_NOTHING`). One
/// byte at a time from an interrupt handler is `len` 1. Returns `PL_NOTHING`, `PL_MESSAGE`
/// (`*msg` filled, with its `offset` and `wire_len`), `PL_ERROR` (`*err` filled; `*msg`
/// cleared, or for a good frame whose typed parse failed its ID, raw data and place),
/// `PL_E_NULL` or `PL_E_INVALID`.
///
/// ```c
/// size_t off = 0, used;
/// int32_t st;
/// while ((st = pl_aeolus_parse(&dec, buf + off, len - off, &used, &msg, &err)) > 0) {
///     off += used;
///     if (st == PL_MESSAGE && msg.id == PL_AEOLUS_ID_GYRO) use_rates(&msg.body.motion);
/// }
/// ```
///
/// # Safety
/// `dec` is NULL or points to a `pl_aeolus_decoder` (one `pl_aeolus_init*` did not set up gets
/// `PL_E_INVALID`) that nothing else uses during the call; `bytes` is NULL (with `len` 0) or
/// readable for `len` bytes; `used`, `msg` and `err` are NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_aeolus_parse(
    dec: *mut pl_aeolus_decoder,
    bytes: *const u8,
    len: usize,
    used: *mut usize,
    msg: *mut pl_aeolus_message,
    err: *mut pl_error,
) -> i32 {
    // SAFETY: the caller's promises.
    unsafe { face::parse(dec, bytes, len, used, msg, err) }
}

/// An event callback of `pl_aeolus_feed`: `status` is `PL_MESSAGE` (`*msg` holds the message)
/// or `PL_ERROR` (`*err` holds the error, `*msg` as `pl_aeolus_parse` leaves it). Both
/// pointers are valid only during the call.
pub type pl_aeolus_callback = Option<
    unsafe extern "C" fn(
        ctx: *mut core::ffi::c_void,
        status: i32,
        msg: *const pl_aeolus_message,
        err: *const pl_error,
    ),
>;

/// Decodes all of `bytes[..len]` and calls `on_event(ctx, ...)` for every event, in order:
/// exactly the events of `pl_aeolus_parse` over the same bytes. Returns `PL_NOTHING`,
/// `PL_E_NULL` or `PL_E_INVALID`. Use it for a DMA buffer or a datagram.
///
/// ```c
/// static void on_event(void *ctx, int32_t st, const pl_aeolus_message *m, const pl_error *e) {
///     if (st == PL_MESSAGE) handle((struct app *)ctx, m);
/// }
/// pl_aeolus_feed(&dec, dma_buf, n, on_event, &app);
/// ```
///
/// # Safety
/// `dec` is NULL or points to a `pl_aeolus_decoder` (one `pl_aeolus_init*` did not set up gets
/// `PL_E_INVALID`); `bytes` is NULL (with `len` 0) or readable for `len` bytes; `on_event` is a
/// function that may be called with `ctx` and does not use `dec`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_aeolus_feed(
    dec: *mut pl_aeolus_decoder,
    bytes: *const u8,
    len: usize,
    on_event: pl_aeolus_callback,
    ctx: *mut core::ffi::c_void,
) -> i32 {
    // SAFETY: the caller's promises.
    unsafe { face::feed(dec, bytes, len, on_event, ctx) }
}

/// The stream ended (a file, a datagram, a quiet line): the next event of its end, one per
/// call; call until `PL_NOTHING`. A frame still held is given up as `PL_ERR_TRUNCATED`.
/// Returns as `pl_aeolus_parse`; afterwards the decoder starts afresh (offsets go on).
///
/// ```c
/// while ((st = pl_aeolus_finish(&dec, &msg, &err)) > 0) if (st == PL_ERROR) count(&err);
/// ```
///
/// # Safety
/// As `pl_aeolus_parse`, for `dec`, `msg` and `err`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_aeolus_finish(
    dec: *mut pl_aeolus_decoder,
    msg: *mut pl_aeolus_message,
    err: *mut pl_error,
) -> i32 {
    // SAFETY: the caller's promises.
    unsafe { face::finish(dec, msg, err) }
}

/// Copies the decoder's counters into `*stats`. Returns 0, `PL_E_NULL` or `PL_E_INVALID`.
///
/// ```c
/// pl_aeolus_stats st;
/// pl_aeolus_get_stats(&dec, &st);
/// printf("%u frames, %u CRC errors\n", st.frames_ok, st.checksum_errors);
/// ```
///
/// # Safety
/// `dec` is NULL or points to a `pl_aeolus_decoder` (one `pl_aeolus_init*` did not set up gets
/// `PL_E_INVALID`); `stats` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_aeolus_get_stats(
    dec: *const pl_aeolus_decoder,
    stats: *mut pl_aeolus_stats,
) -> i32 {
    // SAFETY: the caller's promises.
    unsafe { face::get_stats(dec, stats) }
}

/// Encodes `*msg` as one whole frame (flags, escapes, CRC) into `out[..cap]`. Returns the
/// frame's length, or `PL_E_NULL`, `PL_E_BUFFER_TOO_SMALL` (`PL_AEOLUS_MAX_FRAME_LEN` bytes
/// are always enough but for LOG and unknown IDs), `PL_E_INVALID` (a text longer than
/// `PL_AEOLUS_TEXT_CAPACITY`).
///
/// ```c
/// pl_aeolus_message m = { .id = PL_AEOLUS_ID_GYRO };
/// m.body.motion = (pl_aeolus_motion){ .valid = 1, .timestamp_ms = 1000.0, .x = 0.5f };
/// uint8_t frame[PL_AEOLUS_MAX_FRAME_LEN];
/// int32_t n = pl_aeolus_encode(&m, frame, sizeof frame);
/// if (n > 0) uart_write(frame, (size_t)n);
/// ```
///
/// # Safety
/// `msg` is NULL or readable with `data` readable for `data_len` bytes (or NULL when 0);
/// `out` is NULL or writable for `cap` bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_aeolus_encode(
    msg: *const pl_aeolus_message,
    out: *mut u8,
    cap: usize,
) -> i32 {
    // SAFETY: the caller's promises.
    unsafe { encode::frame(msg, out, cap, aeolus::encode) }
}

/// Bytes on the wire, worst case, of an AEOLUS frame with `data_len` data bytes (every byte
/// escaped): size a buffer for LOG messages with it.
///
/// ```c
/// uint8_t buf[64];
/// assert(pl_aeolus_max_encoded_len(28) <= sizeof buf);
/// ```
#[unsafe(no_mangle)]
pub extern "C" fn pl_aeolus_max_encoded_len(data_len: usize) -> usize {
    aeolus::max_encoded_len(data_len)
}

// AOK, both sides.

/// Sets up the device side's decoder. Returns 0, `PL_E_NULL` or `PL_E_INVALID` (`dec` not
/// aligned for its type).
///
/// ```c
/// pl_aok_device_decoder dec;
/// pl_aok_device_init(&dec);
/// ```
///
/// # Safety
/// `dec` is NULL or points to writable memory for a `pl_aok_device_decoder`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_aok_device_init(dec: *mut pl_aok_device_decoder) -> i32 {
    // SAFETY: the caller's promise.
    unsafe { face::init(dec, CommandDecoder::new()) }
}

/// Device side: decodes the PC's bytes `bytes[..len]` up to the next event, as
/// `pl_aeolus_parse` (`*cmd` holds a command; a rescan's further events come first with
/// `*used` 0: call until `PL_NOTHING`). `PL_ERROR` clears `*cmd`.
///
/// ```c
/// size_t off = 0, used;
/// int32_t st;
/// while ((st = pl_aok_device_parse(&dec, buf + off, len - off, &used, &cmd, &err)) > 0) {
///     off += used;
///     if (st == PL_MESSAGE && cmd.kind == PL_AOK_RESET) reboot();
/// }
/// ```
///
/// # Safety
/// `dec` is NULL or points to a `pl_aok_device_decoder` (one `pl_aok_device_init` did not set
/// up gets `PL_E_INVALID`) that nothing else uses during the call; `bytes` is NULL (with `len`
/// 0) or readable for `len` bytes; `used`, `cmd` and `err` are NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_aok_device_parse(
    dec: *mut pl_aok_device_decoder,
    bytes: *const u8,
    len: usize,
    used: *mut usize,
    cmd: *mut pl_aok_item,
    err: *mut pl_error,
) -> i32 {
    // SAFETY: the caller's promises.
    unsafe { face::parse(dec, bytes, len, used, cmd, err) }
}

/// Device side: decodes all of `bytes[..len]` and calls `on_event(ctx, ...)` for every event,
/// in order (exactly those of `pl_aok_device_parse`). Returns `PL_NOTHING`, `PL_E_NULL` or
/// `PL_E_INVALID`.
///
/// ```c
/// pl_aok_device_feed(&dec, rx_buf, n, on_command, &app);
/// ```
///
/// # Safety
/// `dec` is NULL or points to a `pl_aok_device_decoder` (one `pl_aok_device_init` did not set up
/// gets `PL_E_INVALID`); `bytes` is NULL (with `len` 0) or readable for `len` bytes; `on_event` may
/// be called with `ctx` and does not use `dec`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_aok_device_feed(
    dec: *mut pl_aok_device_decoder,
    bytes: *const u8,
    len: usize,
    on_event: pl_aok_callback,
    ctx: *mut core::ffi::c_void,
) -> i32 {
    // SAFETY: the caller's promises.
    unsafe { face::feed(dec, bytes, len, on_event, ctx) }
}

/// Device side: the PC's stream ended or its line went quiet: a partial command is given up
/// (`PL_ERR_TRUNCATED`) and what followed it rescanned. One event per call; call until
/// `PL_NOTHING`.
///
/// ```c
/// while ((st = pl_aok_device_finish(&dec, &cmd, &err)) > 0) if (st == PL_MESSAGE) run(&cmd);
/// ```
///
/// # Safety
/// As `pl_aok_device_parse`, for `dec`, `cmd` and `err`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_aok_device_finish(
    dec: *mut pl_aok_device_decoder,
    cmd: *mut pl_aok_item,
    err: *mut pl_error,
) -> i32 {
    // SAFETY: the caller's promises.
    unsafe { face::finish(dec, cmd, err) }
}

/// Device side: the decoder's counters. Returns 0, `PL_E_NULL` or `PL_E_INVALID`.
///
/// ```c
/// pl_aok_stats st;
/// pl_aok_device_get_stats(&dec, &st);
/// ```
///
/// # Safety
/// `dec` is NULL or points to a `pl_aok_device_decoder` (one `pl_aok_device_init` did not set up
/// gets `PL_E_INVALID`); `stats` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_aok_device_get_stats(
    dec: *const pl_aok_device_decoder,
    stats: *mut pl_aok_stats,
) -> i32 {
    // SAFETY: the caller's promises.
    unsafe { face::get_stats(dec, stats) }
}

/// Sets up the PC side's decoder for a device running firmware `major.minor` (<= 0.30 sends
/// headerless parameter replies, >= 0.31 headed ones; DECISIONS.md K4). Returns 0, `PL_E_NULL`
/// or `PL_E_INVALID` (`dec` not aligned for its type).
///
/// ```c
/// pl_aok_pc_decoder dec;
/// pl_aok_pc_init(&dec, 0, 35);
/// ```
///
/// # Safety
/// `dec` is NULL or points to writable memory for a `pl_aok_pc_decoder`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_aok_pc_init(dec: *mut pl_aok_pc_decoder, major: u8, minor: u8) -> i32 {
    // SAFETY: the caller's promise.
    unsafe { face::init(dec, MessageDecoder::new(FirmwareVersion::new(major, minor))) }
}

/// PC side: tell the decoder which reply the command just sent asks for (an ack, a parameter,
/// 16 parameters, a waypoint), so that it reads the device's answer. Returns 0, `PL_E_NULL`,
/// `PL_E_INVALID` (`dec`), `PL_E_BAD_TAG` or `PL_E_OUT_OF_RANGE` (as `pl_aok_encode_command`).
///
/// ```c
/// pl_aok_item get = { .kind = PL_AOK_READ_PARAMETER, .number = 12 };
/// n = pl_aok_encode_command(&get, buf, sizeof buf);
/// uart_write(buf, n);
/// pl_aok_pc_expect_reply(&dec, &get);
/// ```
///
/// # Safety
/// `dec` is NULL or points to a `pl_aok_pc_decoder` (one `pl_aok_pc_init` did not set up gets
/// `PL_E_INVALID`); `cmd` is NULL or readable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_aok_pc_expect_reply(
    dec: *mut pl_aok_pc_decoder,
    cmd: *const pl_aok_item,
) -> i32 {
    // SAFETY: the caller's promises.
    unsafe { aok::expect_reply(dec, cmd) }
}

/// PC side: decodes the device's bytes `bytes[..len]` up to the next event, as
/// `pl_aok_device_parse` (`*msg` holds a debug value, an ack, a parameter or a waypoint).
///
/// ```c
/// size_t off = 0, used;
/// int32_t st;
/// while ((st = pl_aok_pc_parse(&dec, buf + off, len - off, &used, &msg, &err)) > 0) {
///     off += used;
///     if (st == PL_MESSAGE && msg.kind == PL_AOK_DEBUG) plot(msg.number, msg.value);
/// }
/// ```
///
/// # Safety
/// As `pl_aok_device_parse`, with a `pl_aok_pc_decoder`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_aok_pc_parse(
    dec: *mut pl_aok_pc_decoder,
    bytes: *const u8,
    len: usize,
    used: *mut usize,
    msg: *mut pl_aok_item,
    err: *mut pl_error,
) -> i32 {
    // SAFETY: the caller's promises.
    unsafe { face::parse(dec, bytes, len, used, msg, err) }
}

/// PC side: decodes all of `bytes[..len]`, `on_event(ctx, ...)` for every event in order
/// (exactly those of `pl_aok_pc_parse`). Returns `PL_NOTHING`, `PL_E_NULL` or `PL_E_INVALID`.
///
/// ```c
/// pl_aok_pc_feed(&dec, rx_buf, n, on_message, &app);
/// ```
///
/// # Safety
/// As `pl_aok_device_feed`, with a `pl_aok_pc_decoder`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_aok_pc_feed(
    dec: *mut pl_aok_pc_decoder,
    bytes: *const u8,
    len: usize,
    on_event: pl_aok_callback,
    ctx: *mut core::ffi::c_void,
) -> i32 {
    // SAFETY: the caller's promises.
    unsafe { face::feed(dec, bytes, len, on_event, ctx) }
}

/// PC side: the device's stream ended or its line went quiet; one event per call, call until
/// `PL_NOTHING` (as `pl_aok_device_finish`).
///
/// ```c
/// while ((st = pl_aok_pc_finish(&dec, &msg, &err)) > 0) if (st == PL_MESSAGE) handle(&msg);
/// ```
///
/// # Safety
/// As `pl_aok_device_parse`, with a `pl_aok_pc_decoder`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_aok_pc_finish(
    dec: *mut pl_aok_pc_decoder,
    msg: *mut pl_aok_item,
    err: *mut pl_error,
) -> i32 {
    // SAFETY: the caller's promises.
    unsafe { face::finish(dec, msg, err) }
}

/// PC side: the decoder's counters. Returns 0, `PL_E_NULL` or `PL_E_INVALID`.
///
/// ```c
/// pl_aok_stats st;
/// pl_aok_pc_get_stats(&dec, &st);
/// ```
///
/// # Safety
/// As `pl_aok_device_get_stats`, with a `pl_aok_pc_decoder`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_aok_pc_get_stats(
    dec: *const pl_aok_pc_decoder,
    stats: *mut pl_aok_stats,
) -> i32 {
    // SAFETY: the caller's promises.
    unsafe { face::get_stats(dec, stats) }
}

/// An event callback of `pl_aok_device_feed` and `pl_aok_pc_feed`: `status` is `PL_MESSAGE`
/// (`*item` holds the command or message) or `PL_ERROR` (`*err`; `*item` cleared). Both
/// pointers are valid only during the call.
pub type pl_aok_callback = Option<
    unsafe extern "C" fn(
        ctx: *mut core::ffi::c_void,
        status: i32,
        item: *const pl_aok_item,
        err: *const pl_error,
    ),
>;

/// Encodes a command (PC to device) into `out[..cap]`. Returns its length, or `PL_E_NULL`,
/// `PL_E_BAD_TAG` (not a command kind), `PL_E_OUT_OF_RANGE` (motor, slot or stick out of
/// range) or `PL_E_BUFFER_TOO_SMALL` (`PL_AOK_MAX_FRAME_LEN` is always enough).
///
/// ```c
/// pl_aok_item set = { .kind = PL_AOK_SET_PARAMETER, .number = 12, .value = 1500 };
/// uint8_t buf[PL_AOK_MAX_FRAME_LEN];
/// int32_t n = pl_aok_encode_command(&set, buf, sizeof buf);   /* 73 0C 00 00 05 DC D5 */
/// ```
///
/// # Safety
/// `cmd` is NULL or readable; `out` is NULL or writable for `cap` bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_aok_encode_command(
    cmd: *const pl_aok_item,
    out: *mut u8,
    cap: usize,
) -> i32 {
    // SAFETY: the caller's promises.
    unsafe { encode::frame(cmd, out, cap, |cmd, _, out| aok::command_frame(cmd, out)) }
}

/// Encodes a device message (device to PC) into `out[..cap]`: a debug value, an ack ('O',
/// 'E', 'I'), a parameter reply (headed `FF NUM ...` if `headed`, else the firmware <= 0.30
/// form) or a waypoint. Returns its length, or `PL_E_NULL`, `PL_E_BAD_TAG` (not a message
/// kind), `PL_E_OUT_OF_RANGE` (an ack byte or slot outside the protocol) or
/// `PL_E_BUFFER_TOO_SMALL`.
///
/// ```c
/// pl_aok_item dbg = { .kind = PL_AOK_DEBUG, .number = 86, .value = 3 };
/// uint8_t buf[PL_AOK_MAX_FRAME_LEN];
/// int32_t n = pl_aok_encode_message(&dbg, 1, buf, sizeof buf);   /* 7 bytes */
/// ```
///
/// # Safety
/// `msg` is NULL or readable; `out` is NULL or writable for `cap` bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_aok_encode_message(
    msg: *const pl_aok_item,
    headed: u8,
    out: *mut u8,
    cap: usize,
) -> i32 {
    // SAFETY: the caller's promises.
    unsafe {
        encode::frame(msg, out, cap, |msg, _, out| {
            aok::message_frame(msg, headed, out)
        })
    }
}

// AYDP, both profiles.

/// Sets up `dec` as a fresh decoder for `profile` (`PL_AYDP_SPEC` or `PL_AYDP_REFERENCE`).
/// Returns 0, `PL_E_NULL`, `PL_E_BAD_TAG` (another profile) or `PL_E_INVALID` (`dec` not
/// aligned for its type).
///
/// ```c
/// pl_aydp_decoder dec;
/// pl_aydp_init(&dec, PL_AYDP_REFERENCE);
/// ```
///
/// # Safety
/// `dec` is NULL or points to writable memory for a `pl_aydp_decoder`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_aydp_init(dec: *mut pl_aydp_decoder, profile: u32) -> i32 {
    let Some(d) = aydp::decoder(profile) else {
        return PL_E_BAD_TAG;
    };
    // SAFETY: the caller's promise.
    unsafe { face::init(dec, d) }
}

/// Decodes `bytes[..len]` up to the next event, as `pl_aeolus_parse`. A rescan after an error
/// can find further messages among bytes already held: they come first, one a call, with
/// `*used` 0, so call again (with the rest, or `len` 0) until `PL_NOTHING`. `PL_ERROR` with a
/// good checksum but a failed typed parse leaves the raw data and place in `*msg`; any other
/// error clears it.
///
/// ```c
/// size_t off = 0, used;
/// int32_t st;
/// while ((st = pl_aydp_parse(&dec, buf + off, len - off, &used, &msg, &err)) > 0) {
///     off += used;
///     if (st == PL_MESSAGE) handle(&msg);
/// }
/// ```
///
/// # Safety
/// `dec` is NULL or points to a `pl_aydp_decoder` (one `pl_aydp_init` did not set up gets
/// `PL_E_INVALID`) that nothing else uses during the call; `bytes` is NULL (with `len` 0) or
/// readable for `len` bytes; `used`, `msg` and `err` are NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_aydp_parse(
    dec: *mut pl_aydp_decoder,
    bytes: *const u8,
    len: usize,
    used: *mut usize,
    msg: *mut pl_aydp_message,
    err: *mut pl_error,
) -> i32 {
    // SAFETY: the caller's promises.
    unsafe { face::parse(dec, bytes, len, used, msg, err) }
}

/// An event callback of `pl_aydp_feed` (see `pl_aeolus_callback`).
pub type pl_aydp_callback = Option<
    unsafe extern "C" fn(
        ctx: *mut core::ffi::c_void,
        status: i32,
        msg: *const pl_aydp_message,
        err: *const pl_error,
    ),
>;

/// Decodes all of `bytes[..len]` and calls `on_event(ctx, ...)` for every event, in order:
/// exactly the events of `pl_aydp_parse`. Returns `PL_NOTHING`, `PL_E_NULL` or
/// `PL_E_INVALID`.
///
/// ```c
/// pl_aydp_feed(&dec, dma_buf, n, on_event, &app);
/// ```
///
/// # Safety
/// `dec` is NULL or points to a `pl_aydp_decoder` (one `pl_aydp_init` did not set up gets
/// `PL_E_INVALID`); `bytes` is NULL (with `len` 0) or readable for `len` bytes; `on_event` may be
/// called with `ctx` and does not use `dec`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_aydp_feed(
    dec: *mut pl_aydp_decoder,
    bytes: *const u8,
    len: usize,
    on_event: pl_aydp_callback,
    ctx: *mut core::ffi::c_void,
) -> i32 {
    // SAFETY: the caller's promises.
    unsafe { face::feed(dec, bytes, len, on_event, ctx) }
}

/// The stream ended: what is still held is given up (`PL_ERR_TRUNCATED`) and rescanned. One
/// event per call (as `pl_aydp_parse`); call until `PL_NOTHING`.
///
/// ```c
/// while ((st = pl_aydp_finish(&dec, &msg, &err)) > 0) if (st == PL_MESSAGE) handle(&msg);
/// ```
///
/// # Safety
/// As `pl_aydp_parse`, for `dec`, `msg` and `err`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_aydp_finish(
    dec: *mut pl_aydp_decoder,
    msg: *mut pl_aydp_message,
    err: *mut pl_error,
) -> i32 {
    // SAFETY: the caller's promises.
    unsafe { face::finish(dec, msg, err) }
}

/// Copies the decoder's counters into `*stats`. Returns 0, `PL_E_NULL` or `PL_E_INVALID`.
///
/// ```c
/// pl_aydp_stats st;
/// pl_aydp_get_stats(&dec, &st);
/// ```
///
/// # Safety
/// `dec` is NULL or points to a `pl_aydp_decoder` (one `pl_aydp_init` did not set up gets
/// `PL_E_INVALID`); `stats` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_aydp_get_stats(
    dec: *const pl_aydp_decoder,
    stats: *mut pl_aydp_stats,
) -> i32 {
    // SAFETY: the caller's promises.
    unsafe { face::get_stats(dec, stats) }
}

/// The `index`-th satellite of a decoded fix detail message. Returns 0, `PL_E_NULL`, or
/// `PL_E_BAD_TAG` (not a fix detail message, or `index` beyond its count).
///
/// ```c
/// pl_aydp_satellite sat;
/// for (uint32_t i = 0; pl_aydp_satellite_at(&msg, i, &sat) == 0; i++) show(&sat);
/// ```
///
/// # Safety
/// `msg` is NULL or a message whose `data` is readable for `data_len` bytes; `sat` is NULL or
/// writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_aydp_satellite_at(
    msg: *const pl_aydp_message,
    index: u32,
    sat: *mut pl_aydp_satellite,
) -> i32 {
    // SAFETY: the caller's promises.
    unsafe {
        aydp::nth(msg, PL_AYDP_FIX_DETAIL, sat, |data| {
            aydp::satellite(data, index)
        })
    }
}

/// The `index`-th entry of a decoded direct output message. Returns 0, `PL_E_NULL`, or
/// `PL_E_BAD_TAG` (not a direct output message, or `index` beyond its count).
///
/// ```c
/// pl_aydp_output_entry e;
/// for (uint32_t i = 0; pl_aydp_output_entry_at(&msg, i, &e) == 0; i++) set_output(&e);
/// ```
///
/// # Safety
/// As `pl_aydp_satellite_at`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_aydp_output_entry_at(
    msg: *const pl_aydp_message,
    index: u32,
    entry: *mut pl_aydp_output_entry,
) -> i32 {
    // SAFETY: the caller's promises.
    unsafe {
        aydp::nth(msg, PL_AYDP_DIRECT_OUTPUT, entry, |data| {
            aydp::entry(data, index)
        })
    }
}

/// Encodes `*msg` in `profile` as one whole message (header, data, checksum) into
/// `out[..cap]`: expedited if `msg->expedited`, else normal with `seconds`/`subsec`. Returns
/// its length, or `PL_E_NULL`, `PL_E_BAD_TAG` (kind or profile), `PL_E_BUFFER_TOO_SMALL`,
/// `PL_E_OUT_OF_RANGE` (a base type above 126) or `PL_E_INVALID` (fix detail or direct output
/// data whose count disagrees, an update mode or control command outside 1..=3 / 1..=2, or
/// an expedited message in `PL_AYDP_REFERENCE`, which has no expedited header).
///
/// ```c
/// pl_aydp_message m = { .kind = PL_AYDP_WIND_SPEED, .seconds = 42, .subsec = 500000 };
/// m.body.value = 3.5f;
/// uint8_t buf[64];
/// int32_t n = pl_aydp_encode(PL_AYDP_REFERENCE, &m, buf, sizeof buf);   /* 27 */
/// ```
///
/// # Safety
/// `msg` is NULL or readable, with `data` (and `body.update.value` for an update) readable
/// for their lengths; `out` is NULL or writable for `cap` bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_aydp_encode(
    profile: u32,
    msg: *const pl_aydp_message,
    out: *mut u8,
    cap: usize,
) -> i32 {
    let Some(p) = aydp::profile(profile) else {
        return PL_E_BAD_TAG;
    };
    // SAFETY: the caller's promises, `body.update.value` included (`aydp::encode` reads it).
    unsafe {
        encode::frame(msg, out, cap, |msg, data, out| {
            aydp::encode(p, msg, data, out)
        })
    }
}

// GDL90.

/// Sets up `dec` as a fresh GDL90 decoder. Returns 0, `PL_E_NULL` or `PL_E_INVALID` (`dec` not
/// aligned for its type).
///
/// ```c
/// pl_gdl90_decoder dec;
/// pl_gdl90_init(&dec);
/// ```
///
/// # Safety
/// `dec` is NULL or points to writable memory for a `pl_gdl90_decoder`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_gdl90_init(dec: *mut pl_gdl90_decoder) -> i32 {
    // SAFETY: the caller's promise.
    unsafe { face::init(dec, gdl90::Inner::new()) }
}

/// Decodes `bytes[..len]` up to the next event, as `pl_aeolus_parse`. `PL_ERROR` clears
/// `*msg`; for a frame with a good CRC whose typed parse failed (`PL_ERR_WRONG_LENGTH`,
/// `PL_ERR_OUT_OF_RANGE`) it also gives that frame's `offset` and `wire_len`.
///
/// ```c
/// size_t off = 0, used;
/// int32_t st;
/// while ((st = pl_gdl90_parse(&dec, buf + off, len - off, &used, &msg, &err)) > 0) {
///     off += used;
///     if (st == PL_MESSAGE && msg.kind == PL_GDL90_OWNSHIP) show(&msg.body.report);
/// }
/// ```
///
/// # Safety
/// `dec` is NULL or points to a `pl_gdl90_decoder` (one `pl_gdl90_init` did not set up gets
/// `PL_E_INVALID`) that nothing else uses during the call; `bytes` is NULL (with `len` 0) or
/// readable for `len` bytes; `used`, `msg` and `err` are NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_gdl90_parse(
    dec: *mut pl_gdl90_decoder,
    bytes: *const u8,
    len: usize,
    used: *mut usize,
    msg: *mut pl_gdl90_message,
    err: *mut pl_error,
) -> i32 {
    // SAFETY: the caller's promises.
    unsafe { face::parse(dec, bytes, len, used, msg, err) }
}

/// An event callback of `pl_gdl90_feed` (see `pl_aeolus_callback`).
pub type pl_gdl90_callback = Option<
    unsafe extern "C" fn(
        ctx: *mut core::ffi::c_void,
        status: i32,
        msg: *const pl_gdl90_message,
        err: *const pl_error,
    ),
>;

/// Decodes all of `bytes[..len]` and calls `on_event(ctx, ...)` for every event, in order:
/// exactly the events of `pl_gdl90_parse`. Returns `PL_NOTHING`, `PL_E_NULL` or
/// `PL_E_INVALID`.
///
/// ```c
/// pl_gdl90_feed(&dec, datagram, n, on_event, &app);
/// ```
///
/// # Safety
/// `dec` is NULL or points to a `pl_gdl90_decoder` (one `pl_gdl90_init` did not set up gets
/// `PL_E_INVALID`); `bytes` is NULL (with `len` 0) or readable for `len` bytes; `on_event` may be
/// called with `ctx` and does not use `dec`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_gdl90_feed(
    dec: *mut pl_gdl90_decoder,
    bytes: *const u8,
    len: usize,
    on_event: pl_gdl90_callback,
    ctx: *mut core::ffi::c_void,
) -> i32 {
    // SAFETY: the caller's promises.
    unsafe { face::feed(dec, bytes, len, on_event, ctx) }
}

/// The stream (or a datagram) ended: a frame still held is given up as `PL_ERR_TRUNCATED`.
/// One event per call; call until `PL_NOTHING`. Afterwards the decoder starts afresh.
///
/// ```c
/// while ((st = pl_gdl90_finish(&dec, &msg, &err)) > 0) if (st == PL_ERROR) count(&err);
/// ```
///
/// # Safety
/// As `pl_gdl90_parse`, for `dec`, `msg` and `err`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_gdl90_finish(
    dec: *mut pl_gdl90_decoder,
    msg: *mut pl_gdl90_message,
    err: *mut pl_error,
) -> i32 {
    // SAFETY: the caller's promises.
    unsafe { face::finish(dec, msg, err) }
}

/// Copies the decoder's counters into `*stats`. Returns 0, `PL_E_NULL` or `PL_E_INVALID`.
///
/// ```c
/// pl_gdl90_stats st;
/// pl_gdl90_get_stats(&dec, &st);
/// ```
///
/// # Safety
/// `dec` is NULL or points to a `pl_gdl90_decoder` (one `pl_gdl90_init` did not set up gets
/// `PL_E_INVALID`); `stats` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_gdl90_get_stats(
    dec: *const pl_gdl90_decoder,
    stats: *mut pl_gdl90_stats,
) -> i32 {
    // SAFETY: the caller's promises.
    unsafe { face::get_stats(dec, stats) }
}

/// Encodes `*msg` as one whole frame into `out[..cap]`. Returns its length, or `PL_E_NULL`,
/// `PL_E_BAD_TAG` (kind), `PL_E_INVALID` (a track, heading or datum kind outside its list) or
/// `PL_E_BUFFER_TOO_SMALL` (`PL_GDL90_MAX_FRAME_LEN` is enough for every typed message).
/// Values beyond a field's range are clamped or sent as "invalid", as each GDL90 field says.
///
/// ```c
/// pl_gdl90_message m = { .kind = PL_GDL90_GEO_ALTITUDE };
/// m.body.geo_altitude = (pl_gdl90_geo_altitude){ .altitude_ft = 1500 };
/// uint8_t buf[PL_GDL90_MAX_FRAME_LEN];
/// int32_t n = pl_gdl90_encode(&m, buf, sizeof buf);
/// ```
///
/// # Safety
/// `msg` is NULL or readable with `data` readable for `data_len` bytes; `out` is NULL or
/// writable for `cap` bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn pl_gdl90_encode(
    msg: *const pl_gdl90_message,
    out: *mut u8,
    cap: usize,
) -> i32 {
    // SAFETY: the caller's promises.
    unsafe { encode::frame(msg, out, cap, gdl90::encode) }
}
