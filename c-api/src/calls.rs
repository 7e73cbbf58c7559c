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

/// An event callback type of `pl_*_feed`: `status` is `PL_MESSAGE` (`*msg` holds the message)
/// or `PL_ERROR` (`*err` holds the error, `*msg` as the protocol's `pl_*_parse` leaves it).
/// `$of` names the feed calls that take it.
macro_rules! callback {
    ($callback:ident($msg:ident) of $of:literal) => {
        #[doc = concat!(" An event callback of ", $of, ".")]
        #[doc = " `status` is `PL_MESSAGE` (`*msg` holds the message) or `PL_ERROR` (`*err` holds the"]
        #[doc = " error, `*msg` as the parse call leaves it). Both pointers are valid only during the"]
        #[doc = " call."]
        pub type $callback = Option<
            unsafe extern "C" fn(
                ctx: *mut core::ffi::c_void,
                status: i32,
                msg: *const $msg,
                err: *const pl_error,
            ),
        >;
    };
}

/// The four decoding calls of a decoder (`parse`, `feed`, `finish`, `get_stats`): each only
/// forwards to `face.rs`, and their C documentation is the same for every protocol but for the
/// names and the example's line (`$example`, what a caller does with a message).
macro_rules! decoding_calls {
    (
        $dec:ident (set up by $init:literal) => $msg:ident, $stats:ident, $callback:ident,
        $parse:ident, $feed:ident, $finish:ident, $get_stats:ident, $example:literal
    ) => {
        #[doc = " Decodes `bytes[..len]` up to the next event: stops after the byte that completed a"]
        #[doc = " message or an error and sets `*used` to the bytes it took (all of `len` with"]
        #[doc = " `PL_NOTHING`, 0 for an event a rescan left queued: call until `PL_NOTHING`). One byte"]
        #[doc = " at a time from an interrupt handler is `len` 1. Returns `PL_NOTHING`, `PL_MESSAGE`"]
        #[doc = " (`*msg` filled, with its `offset` and `wire_len`), `PL_ERROR` (`*err` filled, with the"]
        #[doc = " place of the bytes it condemns; `*msg` cleared, or for a frame with a good check whose"]
        #[doc = " typed parse failed, that frame's place and what the struct keeps of it), `PL_E_NULL` or"]
        #[doc = " `PL_E_INVALID`."]
        #[doc = ""]
        #[doc = " ```c"]
        #[doc = " size_t off = 0, used;"]
        #[doc = " int32_t st;"]
        #[doc = concat!(" while ((st = ", stringify!($parse), "(&dec, buf + off, len - off, &used, &msg, &err)) > 0) {")]
        #[doc = "     off += used;"]
        #[doc = concat!("     ", $example)]
        #[doc = " }"]
        #[doc = " ```"]
        #[doc = ""]
        #[doc = " # Safety"]
        #[doc = concat!(" `dec` is NULL or points to a `", stringify!($dec), "` (one `", $init, "` did not set up")]
        #[doc = " gets `PL_E_INVALID`) that nothing else uses during the call; `bytes` is NULL (with `len`"]
        #[doc = " 0) or readable for `len` bytes; `used`, `msg` and `err` are NULL or writable."]
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $parse(
            dec: *mut $dec,
            bytes: *const u8,
            len: usize,
            used: *mut usize,
            msg: *mut $msg,
            err: *mut pl_error,
        ) -> i32 {
            // SAFETY: the caller's promises.
            unsafe { face::parse(dec, bytes, len, used, msg, err) }
        }

        #[doc = " Decodes all of `bytes[..len]` and calls `on_event(ctx, ...)` for every event, in"]
        #[doc = concat!(" order: exactly the events of `", stringify!($parse), "` over the same bytes. Returns")]
        #[doc = " `PL_NOTHING`, `PL_E_NULL` or `PL_E_INVALID`. Use it for a DMA buffer or a datagram."]
        #[doc = ""]
        #[doc = " ```c"]
        #[doc = concat!(" static void on_event(void *ctx, int32_t st, const ", stringify!($msg), " *m, const pl_error *e) {")]
        #[doc = "     if (st == PL_MESSAGE) handle((struct app *)ctx, m);"]
        #[doc = " }"]
        #[doc = concat!(" ", stringify!($feed), "(&dec, dma_buf, n, on_event, &app);")]
        #[doc = " ```"]
        #[doc = ""]
        #[doc = " # Safety"]
        #[doc = concat!(" `dec` is NULL or points to a `", stringify!($dec), "` (one `", $init, "` did not set up")]
        #[doc = " gets `PL_E_INVALID`); `bytes` is NULL (with `len` 0) or readable for `len` bytes;"]
        #[doc = " `on_event` is a function that may be called with `ctx` and does not use `dec`."]
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $feed(
            dec: *mut $dec,
            bytes: *const u8,
            len: usize,
            on_event: $callback,
            ctx: *mut core::ffi::c_void,
        ) -> i32 {
            // SAFETY: the caller's promises.
            unsafe { face::feed(dec, bytes, len, on_event, ctx) }
        }

        #[doc = " The stream ended (a file, a datagram, a quiet line): the next event of its end, one per"]
        #[doc = " call; call until `PL_NOTHING`. A frame still held is given up as `PL_ERR_TRUNCATED` and"]
        #[doc = concat!(" what followed its start is rescanned. Returns as `", stringify!($parse), "`; afterwards")]
        #[doc = " the decoder starts afresh (offsets go on)."]
        #[doc = ""]
        #[doc = " ```c"]
        #[doc = concat!(" while ((st = ", stringify!($finish), "(&dec, &msg, &err)) > 0) if (st == PL_ERROR) count(&err);")]
        #[doc = " ```"]
        #[doc = ""]
        #[doc = " # Safety"]
        #[doc = concat!(" As `", stringify!($parse), "`, for `dec`, `msg` and `err`.")]
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $finish(dec: *mut $dec, msg: *mut $msg, err: *mut pl_error) -> i32 {
            // SAFETY: the caller's promises.
            unsafe { face::finish(dec, msg, err) }
        }

        #[doc = " Copies the decoder's counters into `*stats`. Returns 0, `PL_E_NULL` or `PL_E_INVALID`."]
        #[doc = ""]
        #[doc = " ```c"]
        #[doc = concat!(" ", stringify!($stats), " st;")]
        #[doc = concat!(" ", stringify!($get_stats), "(&dec, &st);")]
        #[doc = " printf(\"%u frames, %u check errors\\n\", st.frames_ok, st.checksum_errors);"]
        #[doc = " ```"]
        #[doc = ""]
        #[doc = " # Safety"]
        #[doc = concat!(" `dec` is NULL or points to a `", stringify!($dec), "` (one `", $init, "` did not set up")]
        #[doc = " gets `PL_E_INVALID`); `stats` is NULL or writable."]
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $get_stats(dec: *const $dec, stats: *mut $stats) -> i32 {
            // SAFETY: the caller's promises.
            unsafe { face::get_stats(dec, stats) }
        }
    };
}

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

callback!(pl_aeolus_callback(pl_aeolus_message) of "`pl_aeolus_feed`");

decoding_calls! {
    pl_aeolus_decoder (set up by "pl_aeolus_init*") => pl_aeolus_message, pl_aeolus_stats, pl_aeolus_callback,
    pl_aeolus_parse, pl_aeolus_feed, pl_aeolus_finish, pl_aeolus_get_stats,
    "if (st == PL_MESSAGE && msg.id == PL_AEOLUS_ID_GYRO) use_rates(&msg.body.motion);"
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

callback!(pl_aok_callback(pl_aok_item) of "`pl_aok_device_feed` and `pl_aok_pc_feed`");

decoding_calls! {
    pl_aok_device_decoder (set up by "pl_aok_device_init") => pl_aok_item, pl_aok_stats, pl_aok_callback,
    pl_aok_device_parse, pl_aok_device_feed, pl_aok_device_finish, pl_aok_device_get_stats,
    "if (st == PL_MESSAGE && msg.kind == PL_AOK_RESET) reboot();"
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

decoding_calls! {
    pl_aok_pc_decoder (set up by "pl_aok_pc_init") => pl_aok_item, pl_aok_stats, pl_aok_callback,
    pl_aok_pc_parse, pl_aok_pc_feed, pl_aok_pc_finish, pl_aok_pc_get_stats,
    "if (st == PL_MESSAGE && msg.kind == PL_AOK_DEBUG) plot(msg.number, msg.value);"
}

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

callback!(pl_aydp_callback(pl_aydp_message) of "`pl_aydp_feed`");

decoding_calls! {
    pl_aydp_decoder (set up by "pl_aydp_init") => pl_aydp_message, pl_aydp_stats, pl_aydp_callback,
    pl_aydp_parse, pl_aydp_feed, pl_aydp_finish, pl_aydp_get_stats,
    "if (st == PL_MESSAGE && msg.kind == PL_AYDP_POSITION) plot(&msg.body.position);"
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

callback!(pl_gdl90_callback(pl_gdl90_message) of "`pl_gdl90_feed`");

decoding_calls! {
    pl_gdl90_decoder (set up by "pl_gdl90_init") => pl_gdl90_message, pl_gdl90_stats, pl_gdl90_callback,
    pl_gdl90_parse, pl_gdl90_feed, pl_gdl90_finish, pl_gdl90_get_stats,
    "if (st == PL_MESSAGE && msg.kind == PL_GDL90_OWNSHIP) show(&msg.body.report);"
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
