//! The C functions called from Rust, as a C program calls them: these also run under Miri
//! (`cargo +nightly miri test -p protolink-c`), which checks every `unsafe` block they reach.

use core::ffi::c_void;
use core::mem::{MaybeUninit, align_of, size_of};
use core::ptr::{null, null_mut};
use std::boxed::Box;
use std::vec::Vec;

use crate::aeolus::*;
use crate::aok::*;
use crate::aydp::*;
use crate::calls::*;
use crate::gdl90::*;
use crate::*;

mod place;

/// The "gyro" vector of ../shared/vectors/aeolus-frames.json.
const GYRO: &str = "7e3e0100000000000000000000000824fe400000003f0000a0bf0000003c00000000bf267e";

/// A `pl_*_parse` function.
type Parse<D, M> =
    unsafe extern "C" fn(*mut D, *const u8, usize, *mut usize, *mut M, *mut pl_error) -> i32;

/// One byte through `parse`, the C API's one-byte path (an event a rescan left queued comes
/// first, with the byte unused: the callers drain them with [`queued`] first).
///
/// # Safety
/// As `parse`.
unsafe fn byte<D, M>(parse: Parse<D, M>, d: *mut D, b: u8, msg: *mut M, err: *mut pl_error) -> i32 {
    let mut used = 0;
    // SAFETY: the caller's promises; `b` is one readable byte.
    unsafe { parse(d, &b, 1, &mut used, msg, err) }
}

/// One `parse` call on `input` (`*used`: the bytes it took).
///
/// # Safety
/// As `parse`.
unsafe fn slice<D, M>(
    parse: Parse<D, M>,
    d: *mut D,
    input: &[u8],
    used: &mut usize,
    msg: *mut M,
    err: *mut pl_error,
) -> i32 {
    // SAFETY: the caller's promises; `input` is readable.
    unsafe { parse(d, input.as_ptr(), input.len(), used, msg, err) }
}

/// The next event a rescan left queued: `parse` on no bytes.
///
/// # Safety
/// As `parse`.
unsafe fn queued<D, M>(parse: Parse<D, M>, d: *mut D, msg: *mut M, err: *mut pl_error) -> i32 {
    let mut used = 0;
    // SAFETY: the caller's promises; no bytes.
    unsafe { parse(d, null(), 0, &mut used, msg, err) }
}

fn unhex(s: &str) -> Vec<u8> {
    (0..s.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(&s[i..i + 2], 16).unwrap())
        .collect()
}

/// A decoder set up as C sets one up: uninitialised storage, then `init`. (The storage stays a
/// `MaybeUninit`: the decoder's padding is not a valid `[u64; N]`, and only C sees the words.)
fn aeolus_decoder() -> MaybeUninit<pl_aeolus_decoder> {
    let mut d = MaybeUninit::<pl_aeolus_decoder>::uninit();
    // SAFETY: a writable pl_aeolus_decoder.
    assert_eq!(unsafe { pl_aeolus_init(d.as_mut_ptr()) }, 0);
    d
}

fn zeroed<T>() -> T {
    // SAFETY: every type used here is plain numbers and pointers, for which zero is valid.
    unsafe { MaybeUninit::zeroed().assume_init() }
}

#[test]
fn aeolus_gyro_vector_decodes_at_every_split() {
    let frame = unhex(GYRO);
    for split in 0..=frame.len() {
        let mut d = aeolus_decoder();
        let mut msg: pl_aeolus_message = zeroed();
        let mut err = pl_error::default();
        let mut found = 0;
        for part in [&frame[..split], &frame[split..]] {
            let mut off = 0;
            while off < part.len() {
                let mut used = 0;
                // SAFETY: valid pointers to live locals and to `part`.
                let st = unsafe {
                    slice(
                        pl_aeolus_parse,
                        d.as_mut_ptr(),
                        &part[off..],
                        &mut used,
                        &mut msg,
                        &mut err,
                    )
                };
                assert!(used > 0 && used <= part.len() - off);
                off += used;
                if st == PL_MESSAGE {
                    found += 1;
                    assert_eq!(msg.id, PL_AEOLUS_ID_GYRO);
                    // SAFETY: GYRO fills `motion`.
                    let m = unsafe { msg.body.motion };
                    assert_eq!(
                        (m.valid, m.timestamp_ms, m.x, m.y, m.z),
                        (1, 123456.5, 0.5, -1.25, 0.0078125)
                    );
                }
                assert_ne!(st, PL_ERROR);
            }
        }
        assert_eq!(found, 1, "split at {split}");
        let mut stats = pl_aeolus_stats::default();
        // SAFETY: valid pointers.
        assert_eq!(unsafe { pl_aeolus_get_stats(d.as_ptr(), &mut stats) }, 0);
        assert_eq!((stats.frames_ok, stats.flags), (1, 2));
    }
}

#[test]
fn aeolus_encode_writes_the_vector_and_reports_a_short_buffer() {
    let mut m: pl_aeolus_message = zeroed();
    m.id = PL_AEOLUS_ID_GYRO;
    m.body.motion = pl_aeolus_motion {
        valid: 1,
        timestamp_ms: 123456.5,
        x: 0.5,
        y: -1.25,
        z: 0.0078125,
    };
    let mut out = [0u8; PL_AEOLUS_MAX_FRAME_LEN];
    // SAFETY: valid pointers and lengths.
    let n = unsafe { pl_aeolus_encode(&m, out.as_mut_ptr(), out.len()) };
    assert_eq!(out[..n as usize], unhex(GYRO)[..]);
    // SAFETY: as above, a shorter length.
    let short = unsafe { pl_aeolus_encode(&m, out.as_mut_ptr(), n as usize - 1) };
    assert_eq!(short, PL_E_BUFFER_TOO_SMALL);
}

#[test]
fn aeolus_bad_crc_is_an_error_event_with_its_details() {
    let mut frame = unhex(GYRO);
    let last = frame.len() - 2;
    frame[last] ^= 1; // the CRC's high byte
    let mut d = aeolus_decoder();
    let mut msg: pl_aeolus_message = zeroed();
    let mut err = pl_error::default();
    let mut statuses = Vec::new();
    for &b in &frame {
        // SAFETY: valid pointers.
        statuses.push(unsafe { byte(pl_aeolus_parse, d.as_mut_ptr(), b, &mut msg, &mut err) });
    }
    assert_eq!(statuses.iter().filter(|&&s| s != PL_NOTHING).count(), 1);
    assert_eq!(*statuses.last().unwrap(), PL_ERROR);
    assert_eq!(
        (err.kind, err.id, err.expected),
        (PL_ERR_CHECKSUM_MISMATCH, 62, 0x26BF)
    );
    assert_eq!(err.actual, 0x27BF);
}

#[test]
fn every_function_refuses_null() {
    let mut err = pl_error::default();
    let mut used = 0usize;
    // SAFETY: NULL pointers are what is being tested; nothing is dereferenced.
    unsafe {
        assert_eq!(pl_aeolus_init(null_mut()), PL_E_NULL);
        assert_eq!(
            byte(pl_aeolus_parse, null_mut(), 0, null_mut(), &mut err),
            PL_E_NULL
        );
        assert_eq!(pl_aydp_init(null_mut(), PL_AYDP_SPEC), PL_E_NULL);
        assert_eq!(pl_aok_pc_init(null_mut(), 0, 35), PL_E_NULL);
        assert_eq!(pl_gdl90_init(null_mut()), PL_E_NULL);
        assert_eq!(pl_aeolus_encode(null(), null_mut(), 0), PL_E_NULL);
        assert_eq!(pl_aok_encode_command(null(), null_mut(), 0), PL_E_NULL);
        assert_eq!(
            pl_gdl90_parse(null_mut(), null(), 0, &mut used, null_mut(), &mut err),
            PL_E_NULL
        );
    }
    let mut d = aeolus_decoder();
    let mut msg: pl_aeolus_message = zeroed();
    // SAFETY: a NULL input with a non-zero length is refused before any read.
    let st = unsafe { pl_aeolus_parse(d.as_mut_ptr(), null(), 4, &mut used, &mut msg, &mut err) };
    assert_eq!(st, PL_E_NULL);
}

#[test]
fn aydp_round_trips_in_both_profiles_and_polls_after_a_rescan() {
    for profile in [PL_AYDP_SPEC, PL_AYDP_REFERENCE] {
        let mut m: pl_aydp_message = zeroed();
        m.kind = PL_AYDP_POSITION;
        m.seconds = 42;
        m.subsec = 500;
        m.body.position = pl_aydp_position {
            latitude: 50.5,
            longitude: -1.25,
            altitude: 12.5,
        };
        let mut buf = [0u8; 64];
        // SAFETY: valid pointers and lengths.
        let n = unsafe { pl_aydp_encode(profile, &m, buf.as_mut_ptr(), buf.len()) };
        assert_eq!(n, 43);
        // A false start (FF then the real message) makes the decoder rescan.
        let mut stream = std::vec![0xFF, 0x03, 0xFF];
        stream.extend_from_slice(&buf[..n as usize]);
        let mut d = MaybeUninit::<pl_aydp_decoder>::uninit();
        // SAFETY: writable storage.
        assert_eq!(unsafe { pl_aydp_init(d.as_mut_ptr(), profile) }, 0);
        let d = d.as_mut_ptr();
        let mut got: pl_aydp_message = zeroed();
        let mut err = pl_error::default();
        let mut positions = 0;
        for &b in &stream {
            // SAFETY: `d` was set up by init; valid pointers.
            let mut st = unsafe { byte(pl_aydp_parse, d, b, &mut got, &mut err) };
            while st > 0 {
                if st == PL_MESSAGE {
                    positions += 1;
                    assert_eq!(got.kind, PL_AYDP_POSITION);
                    // SAFETY: a position fills `position`.
                    assert_eq!(unsafe { got.body.position }, unsafe { m.body.position });
                    assert_eq!((got.seconds, got.subsec), (42, 500));
                }
                // SAFETY: as above.
                st = unsafe { queued(pl_aydp_parse, d, &mut got, &mut err) };
            }
        }
        // SAFETY: as above.
        while unsafe { pl_aydp_finish(d, &mut got, &mut err) } > 0 {
            positions += (got.kind == PL_AYDP_POSITION) as i32;
        }
        assert_eq!(positions, 1, "profile {profile}");
    }
}

#[test]
fn aydp_parse_of_a_whole_buffer_hands_data_inside_the_decoder() {
    // Whole frames in the caller's buffer, which the AYDP decoder finds in place: `data` must
    // still point into the decoder, and hold the frame's bytes after the buffer is rewritten.
    let (len, _) = sizes();
    let capture: Vec<u8> = include_bytes!("../../testdata/qemu-uart1-aydp.bin")
        .iter()
        .copied()
        .cycle()
        .take(len)
        .collect();
    let mut d = MaybeUninit::<pl_aydp_decoder>::uninit();
    // SAFETY: writable storage.
    assert_eq!(unsafe { pl_aydp_init(d.as_mut_ptr(), PL_AYDP_SPEC) }, 0);
    let inside = d.as_ptr().cast::<u8>()
        ..d.as_ptr()
            .cast::<u8>()
            .wrapping_add(size_of::<pl_aydp_decoder>());
    let mut buffer = capture.to_vec();
    let (mut msg, mut err): (pl_aydp_message, _) = (zeroed(), pl_error::default());
    let (mut off, mut messages) = (0, 0);
    loop {
        let mut used = 0;
        // SAFETY: a set-up decoder; the rest of a live buffer; live outputs.
        let st = unsafe {
            pl_aydp_parse(
                d.as_mut_ptr(),
                buffer[off..].as_ptr(),
                buffer.len() - off,
                &mut used,
                &mut msg,
                &mut err,
            )
        };
        off += used;
        if st == PL_NOTHING {
            break;
        }
        if st != PL_MESSAGE || msg.data_len == 0 {
            continue;
        }
        messages += 1;
        let at = usize::try_from(msg.offset).expect("a small offset");
        let wire = capture[at..at + msg.wire_len as usize].to_vec();
        assert!(
            inside.contains(&msg.data),
            "message {messages} at {at}: data outside the decoder"
        );
        buffer[at..at + wire.len()].fill(0xA5);
        // SAFETY: a delivered message's data points into the decoder, valid until the next call.
        let data = unsafe { core::slice::from_raw_parts(msg.data, msg.data_len) };
        assert_eq!(
            data,
            &wire[wire.len() - 1 - data.len()..wire.len() - 1],
            "message at {at}"
        );
    }
    // About one message with data every 42 bytes of the capture (24 in Miri's 1,000 bytes).
    assert!(messages * 60 >= len, "{messages} messages in {len} bytes");
}

#[test]
fn aok_command_round_trip_and_expected_reply() {
    let cmd = pl_aok_item {
        kind: PL_AOK_SET_PARAMETER,
        number: 12,
        value: 1500,
        ..Default::default()
    };
    let mut buf = [0u8; PL_AOK_MAX_FRAME_LEN];
    // SAFETY: valid pointers and lengths.
    let n = unsafe { pl_aok_encode_command(&cmd, buf.as_mut_ptr(), buf.len()) };
    assert_eq!(
        buf[..n as usize],
        [0x73, 0x0c, 0x00, 0x00, 0x05, 0xdc, 0xd5]
    );
    let mut d = MaybeUninit::<pl_aok_device_decoder>::uninit();
    // SAFETY: writable storage.
    assert_eq!(unsafe { pl_aok_device_init(d.as_mut_ptr()) }, 0);
    let mut got = pl_aok_item::default();
    let mut err = pl_error::default();
    let mut used = 0;
    // SAFETY: set up by init; valid pointers.
    let st = unsafe {
        slice(
            pl_aok_device_parse,
            d.as_mut_ptr(),
            &buf[..n as usize],
            &mut used,
            &mut got,
            &mut err,
        )
    };
    let placed = pl_aok_item {
        wire_len: n as u32,
        offset: 0,
        ..cmd
    };
    assert_eq!((st, used, got), (PL_MESSAGE, n as usize, placed));

    // The PC side reads an ack only once told one is expected.
    let mut pc = MaybeUninit::<pl_aok_pc_decoder>::uninit();
    // SAFETY: writable storage.
    assert_eq!(unsafe { pl_aok_pc_init(pc.as_mut_ptr(), 0, 35) }, 0);
    // SAFETY: set up by init; valid pointers.
    unsafe {
        assert_eq!(pl_aok_pc_expect_reply(pc.as_mut_ptr(), &cmd), 0);
        let st = byte(pl_aok_pc_parse, pc.as_mut_ptr(), b'O', &mut got, &mut err);
        assert_eq!((st, got.kind, got.ack), (PL_MESSAGE, PL_AOK_ACK, b'O'));
    }
}

#[test]
fn gdl90_geo_altitude_round_trip() {
    let mut m: pl_gdl90_message = zeroed();
    m.kind = PL_GDL90_GEO_ALTITUDE;
    m.body.geo_altitude = pl_gdl90_geo_altitude {
        altitude_ft: 1500,
        vertical_warning: 0,
        has_vfom: 0,
        vfom_m: 0,
    };
    let mut buf = [0u8; PL_GDL90_MAX_FRAME_LEN];
    // SAFETY: valid pointers and lengths.
    let n = unsafe { pl_gdl90_encode(&m, buf.as_mut_ptr(), buf.len()) };
    assert_eq!(buf[..4], [0x7E, 11, 0x01, 0x2C]);
    let mut d = MaybeUninit::<pl_gdl90_decoder>::uninit();
    // SAFETY: writable storage.
    assert_eq!(unsafe { pl_gdl90_init(d.as_mut_ptr()) }, 0);
    let mut got: pl_gdl90_message = zeroed();
    let mut err = pl_error::default();
    let mut used = 0;
    // SAFETY: set up by init; valid pointers.
    let st = unsafe {
        slice(
            pl_gdl90_parse,
            d.as_mut_ptr(),
            &buf[..n as usize],
            &mut used,
            &mut got,
            &mut err,
        )
    };
    assert_eq!(
        (st, used, got.kind),
        (PL_MESSAGE, n as usize, PL_GDL90_GEO_ALTITUDE)
    );
    // SAFETY: a geo altitude fills `geo_altitude`.
    assert_eq!(unsafe { got.body.geo_altitude }, unsafe {
        m.body.geo_altitude
    });
}

/// What the feed test's callback saw: message IDs, and error kinds.
#[derive(Default)]
struct Seen {
    ids: Vec<u8>,
    errors: Vec<u32>,
}

unsafe extern "C" fn record(
    ctx: *mut core::ffi::c_void,
    status: i32,
    msg: *const pl_aeolus_message,
    err: *const pl_error,
) {
    // SAFETY: `ctx` is the test's `Seen`, and the pointers are valid during the call
    // (pl_aeolus_feed's promise).
    let (seen, msg, err) = unsafe { (&mut *ctx.cast::<Seen>(), &*msg, &*err) };
    match status {
        PL_MESSAGE => seen.ids.push(msg.id),
        PL_ERROR => seen.errors.push(err.kind),
        other => panic!("status {other}"),
    }
}

#[test]
fn aeolus_feed_gives_every_event_to_the_callback_in_order() {
    let gyro = unhex(GYRO);
    let mut stream = gyro.clone();
    let mut bad = gyro.clone();
    let last = bad.len() - 2;
    bad[last] ^= 0xFF; // a CRC mismatch between two good frames
    stream.extend_from_slice(&bad);
    stream.extend_from_slice(&gyro);
    let mut d = aeolus_decoder();
    let mut seen = Seen::default();
    let ctx = (&mut seen as *mut Seen).cast();
    // SAFETY: a set-up decoder, a live input, a callback that reads its arguments as promised.
    let st = unsafe {
        pl_aeolus_feed(
            d.as_mut_ptr(),
            stream.as_ptr(),
            stream.len(),
            Some(record),
            ctx,
        )
    };
    assert_eq!(st, PL_NOTHING);
    assert_eq!(seen.ids, [PL_AEOLUS_ID_GYRO, PL_AEOLUS_ID_GYRO]);
    assert_eq!(seen.errors, [PL_ERR_CHECKSUM_MISMATCH]);
    // SAFETY: no callback: refused before anything is read.
    let st = unsafe { pl_aeolus_feed(d.as_mut_ptr(), stream.as_ptr(), 1, None, ctx) };
    assert_eq!(st, PL_E_NULL);
}

/// An event of a parse call, as the tests below compare them: the status, the error, and what
/// the message says (AEOLUS: its ID and data bytes; AOK: the item).
type Event = (i32, pl_error, Vec<u8>, pl_aok_item);

/// A hostile stream: `good` (frames of the protocol) cut into pieces with random bytes between
/// them, a quarter of those drawn from `alphabet` (the protocol's start and control bytes),
/// deterministic for `seed`.
fn hostile(good: &[u8], alphabet: &[u8], seed: u64) -> Vec<u8> {
    let mut state = seed;
    let mut next = || {
        // splitmix64
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    };
    let mut out = Vec::new();
    let mut rest = good;
    while !rest.is_empty() {
        let take = (next() % 64) as usize + 1;
        let (piece, after) = rest.split_at(take.min(rest.len()));
        out.extend_from_slice(piece);
        rest = after;
        for _ in 0..next() % 12 {
            let r = next();
            out.push(if r % 4 == 0 {
                alphabet[(r >> 8) as usize % alphabet.len()]
            } else {
                (r >> 16) as u8
            });
        }
    }
    out
}

/// The events of `parse` over `stream` handed over in pieces of `chunk` bytes, each piece
/// taken by [`parse_all`]. `parse` returns the status, the bytes used and the event.
fn chunked(
    stream: &[u8],
    chunk: usize,
    mut parse: impl FnMut(&[u8]) -> (i32, usize, Event),
) -> Vec<Event> {
    let mut events = Vec::new();
    for piece in stream.chunks(chunk) {
        parse_all(piece, &mut parse, &mut events);
    }
    events
}

/// Calls `parse` on `piece` until it has consumed it and has nothing more to give (a call on
/// the empty rest gives what a rescan still holds), adding each event to `events`.
fn parse_all(
    piece: &[u8],
    parse: &mut impl FnMut(&[u8]) -> (i32, usize, Event),
    events: &mut Vec<Event>,
) {
    let mut off = 0;
    loop {
        let (st, used, event) = parse(&piece[off..]);
        assert!(
            st >= 0 && used <= piece.len() - off,
            "status {st}, used {used}"
        );
        off += used;
        if st == PL_NOTHING {
            assert_eq!(
                off,
                piece.len(),
                "nothing found before the end of the piece"
            );
            return;
        }
        events.push(event);
    }
}

/// Stream lengths and chunk sizes: shorter under Miri, which runs these too (single bytes and
/// the whole stream, the two ends of the range).
fn sizes() -> (usize, &'static [usize]) {
    if cfg!(miri) {
        (1000, &[1, 1000])
    } else {
        (6000, &[1, 2, 3, 5, 8, 13, 64, 6000])
    }
}

#[test]
fn aeolus_parse_in_any_pieces_gives_the_byte_calls_events_and_counters() {
    let (len, chunks) = sizes();
    let capture = include_bytes!("../../testdata/qemu-uart0-aeolus.bin");
    let stream = hostile(&capture[..len], &[0x7E, 0x7D, 0x5E, 0x5D, 0x00], 0xAE);
    let event = |st: i32, msg: &pl_aeolus_message, err: &pl_error| -> Event {
        let data = if st == PL_MESSAGE && msg.data_len > 0 {
            // SAFETY: a delivered message's data points into the decoder, valid until the next
            // call on it; copied at once.
            unsafe { core::slice::from_raw_parts(msg.data, msg.data_len) }.to_vec()
        } else {
            Vec::new()
        };
        let id = if st == PL_MESSAGE { msg.id } else { 0 };
        let err = if st == PL_ERROR {
            *err
        } else {
            pl_error::default()
        };
        (st, err, [&[id][..], &data].concat(), pl_aok_item::default())
    };
    let stats = |d: &MaybeUninit<pl_aeolus_decoder>| {
        let mut s = pl_aeolus_stats::default();
        // SAFETY: a set-up decoder, a live output.
        assert_eq!(unsafe { pl_aeolus_get_stats(d.as_ptr(), &mut s) }, 0);
        s
    };
    let mut d = aeolus_decoder();
    let (mut msg, mut err): (pl_aeolus_message, _) = (zeroed(), pl_error::default());
    let mut expected = Vec::new();
    for &b in &stream {
        // SAFETY: a set-up decoder, live outputs.
        let st = unsafe { byte(pl_aeolus_parse, d.as_mut_ptr(), b, &mut msg, &mut err) };
        if st != PL_NOTHING {
            expected.push(event(st, &msg, &err));
        }
    }
    let expected_stats = stats(&d);
    assert!(expected.len() > 10 && expected.iter().any(|e| e.0 == PL_ERROR));
    for &chunk in chunks {
        let mut d = aeolus_decoder();
        let p = d.as_mut_ptr();
        let got = chunked(&stream, chunk, |rest| {
            let mut used = usize::MAX;
            // SAFETY: a set-up decoder, a live input and outputs.
            let st = unsafe { slice(pl_aeolus_parse, p, rest, &mut used, &mut msg, &mut err) };
            (st, used, event(st, &msg, &err))
        });
        assert!(got == expected, "pieces of {chunk}: the events differ");
        assert_eq!(stats(&d), expected_stats, "pieces of {chunk}");
    }
}

/// The AOK item or error of a parse call, as [`Event`].
fn aok_event(st: i32, item: &pl_aok_item, err: &pl_error) -> Event {
    let item = if st == PL_MESSAGE {
        *item
    } else {
        pl_aok_item::default()
    };
    let err = if st == PL_ERROR {
        *err
    } else {
        pl_error::default()
    };
    (st, err, Vec::new(), item)
}

/// One side of the AOK C face: its decoder's set-up and calls.
struct AokSide<D> {
    init: fn(*mut D) -> i32,
    parse: unsafe extern "C" fn(
        *mut D,
        *const u8,
        usize,
        *mut usize,
        *mut pl_aok_item,
        *mut pl_error,
    ) -> i32,
    get_stats: unsafe extern "C" fn(*const D, *mut pl_aok_stats) -> i32,
    /// Whether the test stream makes a byte call leave events for `poll`.
    rescans: bool,
}

impl<D> AokSide<D> {
    fn init(&self) -> MaybeUninit<D> {
        let mut d = MaybeUninit::<D>::uninit();
        assert_eq!((self.init)(d.as_mut_ptr()), 0);
        d
    }

    /// One `parse` call on `rest` with the set-up decoder at `d`: the status, the bytes used
    /// and the event.
    fn parse_once(
        &self,
        d: *mut D,
        rest: &[u8],
        item: &mut pl_aok_item,
        err: &mut pl_error,
    ) -> (i32, usize, Event) {
        let mut used = usize::MAX;
        // SAFETY: a set-up decoder, a live input and outputs.
        let st = unsafe { (self.parse)(d, rest.as_ptr(), rest.len(), &mut used, item, err) };
        (st, used, aok_event(st, item, err))
    }

    fn stats(&self, d: &MaybeUninit<D>) -> pl_aok_stats {
        let mut s = pl_aok_stats::default();
        // SAFETY: a set-up decoder, a live output.
        assert_eq!(unsafe { (self.get_stats)(d.as_ptr(), &mut s) }, 0);
        s
    }

    /// `parse` over `stream` in pieces of each of `chunks` gives the events and counters of
    /// `parse` a byte at a time, drained with `queued`.
    fn parse_matches_the_byte_calls(&self, stream: &[u8], chunks: &[usize]) {
        let mut d = self.init();
        let (mut item, mut err) = (pl_aok_item::default(), pl_error::default());
        let mut expected = Vec::new();
        for &b in stream {
            // SAFETY: a set-up decoder, live outputs.
            let mut st = unsafe { byte(self.parse, d.as_mut_ptr(), b, &mut item, &mut err) };
            while st > 0 {
                expected.push(aok_event(st, &item, &err));
                // SAFETY: as above.
                st = unsafe { queued(self.parse, d.as_mut_ptr(), &mut item, &mut err) };
            }
        }
        let expected_stats = self.stats(&d);
        assert!(expected.len() > 10 && expected.iter().any(|e| e.0 == PL_ERROR));
        for &chunk in chunks {
            let mut d = self.init();
            let d_ptr = d.as_mut_ptr();
            let got = chunked(stream, chunk, |rest| {
                self.parse_once(d_ptr, rest, &mut item, &mut err)
            });
            assert!(got == expected, "pieces of {chunk}: the events differ");
            assert_eq!(self.stats(&d), expected_stats, "pieces of {chunk}");
        }
        // The calls mixed: the first byte of every 5 by `byte`, without the `queued` its
        // contract asks for, then `parse` on the other four, which must give what that byte
        // left held first.
        let mut d = self.init();
        let d_ptr = d.as_mut_ptr();
        let (mut got, mut held_first) = (Vec::new(), 0);
        let mut parse = |rest: &[u8]| self.parse_once(d_ptr, rest, &mut item, &mut err);
        for piece in stream.chunks(5) {
            let (&first, rest) = piece.split_first().expect("chunks are not empty");
            let (mut one, mut one_err) = (pl_aok_item::default(), pl_error::default());
            // SAFETY: a set-up decoder (the one `parse` uses, not used at the same time),
            // live outputs.
            let st = unsafe { byte(self.parse, d_ptr, first, &mut one, &mut one_err) };
            if st > 0 {
                got.push(aok_event(st, &one, &one_err));
                // What `poll` would give now, asked of a copy of the decoder: the next
                // `parse` must give it at once, with no byte used.
                // SAFETY: the decoder is plain words, set up; the copy is its own.
                let mut copy = unsafe { d_ptr.cast::<MaybeUninit<D>>().read() };
                // SAFETY: the copy is a set-up decoder, live outputs.
                let held = unsafe { queued(self.parse, copy.as_mut_ptr(), &mut one, &mut one_err) };
                if held > 0 {
                    let (st, used, event) = parse(rest);
                    assert_eq!(
                        (st, used, &event),
                        (held, 0, &aok_event(held, &one, &one_err)),
                        "parse after a byte call that left an event held"
                    );
                    got.push(event);
                    held_first += 1;
                }
            }
            parse_all(rest, &mut parse, &mut got);
        }
        // The device side's stream leaves events held after a byte call (a rescan), often
        // enough to test that above; in the PC side's no byte call leaves one.
        if self.rescans {
            assert!(held_first > 0, "no byte call left an event held");
        }
        assert!(
            got == expected,
            "byte and slice calls mixed: the events differ"
        );
        assert_eq!(self.stats(&d), expected_stats, "byte and slice calls mixed");
    }
}

#[test]
fn aok_device_parse_in_any_pieces_gives_the_byte_calls_events_and_counters() {
    let (len, chunks) = sizes();
    let capture = include_bytes!("../../testdata/qemu-uart2-aok.bin");
    let good: Vec<u8> = capture.iter().copied().cycle().take(len).collect();
    let stream = hostile(&good, &[0x63, 0x67, 0x47, 0x78, 0x57, 0x1c, 0x00], 0xA0C);
    let side = AokSide {
        // SAFETY: writable storage.
        init: |d| unsafe { pl_aok_device_init(d) },
        parse: pl_aok_device_parse,
        get_stats: pl_aok_device_get_stats,
        rescans: true,
    };
    side.parse_matches_the_byte_calls(&stream, chunks);
}

#[test]
fn aok_pc_parse_in_any_pieces_gives_the_byte_calls_events_and_counters() {
    let (len, chunks) = sizes();
    // Debug values (-2 and 1 for value 86), the device's answers the PC side reads most.
    let frames = [
        0x1c, 0x56, 0xff, 0xff, 0xff, 0xfe, 0x57, 0x1c, 0x56, 0, 0, 0, 1, 0x57,
    ];
    let good: Vec<u8> = frames.iter().copied().cycle().take(len).collect();
    let stream = hostile(&good, &[0x1c, 0x56, 0x57, 0x4b, 0x00, 0xff], 0x9C);
    let side = AokSide {
        // SAFETY: writable storage.
        init: |d| unsafe { pl_aok_pc_init(d, 0, 35) },
        parse: pl_aok_pc_parse,
        get_stats: pl_aok_pc_get_stats,
        rescans: false,
    };
    side.parse_matches_the_byte_calls(&stream, chunks);
}

/// Output storage filled with 0x5A: a refused call must leave every byte of it as it was. (On
/// the heap: moving a `MaybeUninit<T>` would not keep the bytes of `T`'s padding.)
struct Out<T>(Box<MaybeUninit<T>>);

impl<T> Out<T> {
    fn new() -> Self {
        let mut m = Box::new(MaybeUninit::<T>::uninit());
        // SAFETY: writable for one `T`.
        unsafe {
            m.as_mut_ptr()
                .cast::<u8>()
                .write_bytes(0x5A, size_of::<T>())
        };
        Self(m)
    }

    fn ptr(&mut self) -> *mut T {
        self.0.as_mut_ptr()
    }

    fn untouched(&self) -> bool {
        // SAFETY: every byte was written by `new`; a refused call writes none.
        let bytes =
            unsafe { core::slice::from_raw_parts(self.0.as_ptr().cast::<u8>(), size_of::<T>()) };
        bytes.iter().all(|&b| b == 0x5A)
    }
}

/// A feed callback that notes it was called (`ctx` is a `bool`).
unsafe extern "C" fn called<M>(
    ctx: *mut core::ffi::c_void,
    _: i32,
    _: *const M,
    _: *const pl_error,
) {
    // SAFETY: the tests pass a live `bool`.
    unsafe { *ctx.cast::<bool>() = true };
}

/// The bytes every call below feeds: the start of an AEOLUS frame, an AYDP start byte, an AOK
/// command byte (none completes anything).
const BYTES: [u8; 4] = [0x7E, 0x3E, 0xFF, 0x63];

/// The statuses of every call on the state at `p` but `init` (valid other arguments), and
/// whether every call was refused and left every output untouched.
type Calls = unsafe fn(*mut u8) -> (Vec<i32>, bool);

/// Whether every status is `PL_E_INVALID`.
fn refused(st: &[i32]) -> bool {
    st.iter().all(|&s| s == PL_E_INVALID)
}

/// One kind of state: its name, its `init` on the storage at a pointer, and its other calls.
struct Kind {
    name: &'static str,
    init: unsafe fn(*mut u8) -> i32,
    calls: Calls,
}

/// The decoding calls of one kind of state `D`, with message struct `M` and stats struct `S`,
/// and what [`calls`] feeds them.
struct Api<D, M, S> {
    parse: Parse<D, M>,
    feed: unsafe extern "C" fn(*mut D, *const u8, usize, Callback<M>, *mut c_void) -> i32,
    finish: unsafe extern "C" fn(*mut D, *mut M, *mut pl_error) -> i32,
    get_stats: unsafe extern "C" fn(*const D, *mut S) -> i32,
    /// The byte of the one-byte parse call.
    byte: u8,
}

/// A `pl_*_callback`.
type Callback<M> = Option<unsafe extern "C" fn(*mut c_void, i32, *const M, *const pl_error)>;

/// The statuses of `api`'s calls on the state at `p` (a byte, the events queued, a slice, a
/// feed, the end of the stream, the counters), and whether every call was refused and left
/// every output untouched.
///
/// # Safety
/// `p` is storage for any state, or a misaligned pointer into it.
unsafe fn calls<D, M, S>(api: Api<D, M, S>, p: *mut u8) -> (Vec<i32>, bool) {
    let d = p.cast::<D>();
    let (mut msg, mut err, mut used) = (Out::<M>::new(), Out::new(), Out::<usize>::new());
    let mut stats = Out::<S>::new();
    let mut fed = false;
    let ctx = (&mut fed as *mut bool).cast();
    // SAFETY: the state at `p` is what is tested; the other arguments are live.
    let st = unsafe {
        std::vec![
            byte(api.parse, d, api.byte, msg.ptr(), err.ptr()),
            queued(api.parse, d, msg.ptr(), err.ptr()),
            (api.parse)(d, BYTES.as_ptr(), 4, used.ptr(), msg.ptr(), err.ptr()),
            (api.feed)(d, BYTES.as_ptr(), 4, Some(called::<M>), ctx),
            (api.finish)(d, msg.ptr(), err.ptr()),
            (api.get_stats)(d, stats.ptr()),
        ]
    };
    // Outputs are only compared after refusals: an accepted call may write them.
    let untouched =
        refused(&st) && msg.untouched() && err.untouched() && used.untouched() && stats.untouched();
    (st, untouched && !fed)
}

/// `calls` on the PC side, after `pl_aok_pc_expect_reply` (a parameter read).
///
/// # Safety
/// As [`calls`].
unsafe fn aok_pc_calls(p: *mut u8) -> (Vec<i32>, bool) {
    let get = pl_aok_item {
        kind: PL_AOK_READ_PARAMETER,
        number: 12,
        ..Default::default()
    };
    // SAFETY: the caller's promise; `get` is live.
    let expect = unsafe { pl_aok_pc_expect_reply(p.cast(), &get) };
    let api = Api {
        parse: pl_aok_pc_parse,
        feed: pl_aok_pc_feed,
        finish: pl_aok_pc_finish,
        get_stats: pl_aok_pc_get_stats,
        byte: 0x1C,
    };
    // SAFETY: the caller's promise.
    let (mut st, untouched) = unsafe { calls(api, p) };
    st.insert(0, expect);
    let untouched = untouched && refused(&st);
    (st, untouched)
}

/// Every kind of state (the AEOLUS strict init and the AYDP Reference profile write the same
/// tags as these).
const KINDS: [Kind; 5] = [
    Kind {
        name: "AEOLUS",
        // SAFETY: the caller passes storage for any state, or a misaligned pointer into it.
        init: |p| unsafe { pl_aeolus_init(p.cast()) },
        // SAFETY: as above.
        calls: |p| unsafe {
            calls(
                Api {
                    parse: pl_aeolus_parse,
                    feed: pl_aeolus_feed,
                    finish: pl_aeolus_finish,
                    get_stats: pl_aeolus_get_stats,
                    byte: BYTES[0],
                },
                p,
            )
        },
    },
    Kind {
        name: "AYDP",
        // SAFETY: the caller passes storage for any state, or a misaligned pointer into it.
        init: |p| unsafe { pl_aydp_init(p.cast(), PL_AYDP_SPEC) },
        // SAFETY: as above.
        calls: |p| unsafe {
            calls(
                Api {
                    parse: pl_aydp_parse,
                    feed: pl_aydp_feed,
                    finish: pl_aydp_finish,
                    get_stats: pl_aydp_get_stats,
                    byte: BYTES[2],
                },
                p,
            )
        },
    },
    Kind {
        name: "AOK device",
        // SAFETY: the caller passes storage for any state, or a misaligned pointer into it.
        init: |p| unsafe { pl_aok_device_init(p.cast()) },
        // SAFETY: as above.
        calls: |p| unsafe {
            calls(
                Api {
                    parse: pl_aok_device_parse,
                    feed: pl_aok_device_feed,
                    finish: pl_aok_device_finish,
                    get_stats: pl_aok_device_get_stats,
                    byte: BYTES[3],
                },
                p,
            )
        },
    },
    Kind {
        name: "AOK PC",
        // SAFETY: the caller passes storage for any state, or a misaligned pointer into it.
        init: |p| unsafe { pl_aok_pc_init(p.cast(), 0, 35) },
        calls: aok_pc_calls,
    },
    Kind {
        name: "GDL90",
        // SAFETY: the caller passes storage for any state, or a misaligned pointer into it.
        init: |p| unsafe { pl_gdl90_init(p.cast()) },
        // SAFETY: as above.
        calls: |p| unsafe {
            calls(
                Api {
                    parse: pl_gdl90_parse,
                    feed: pl_gdl90_feed,
                    finish: pl_gdl90_finish,
                    get_stats: pl_gdl90_get_stats,
                    byte: BYTES[0],
                },
                p,
            )
        },
    },
];

/// Storage for any state, as a C union of them: aligned for each, large enough for each and 8
/// bytes more (for a state moved to an odd address).
#[repr(C, align(8))]
struct AnyState([u8; ANY_STATE_LEN]);

const ANY_STATE_LEN: usize = 8 + {
    let sizes = [
        PL_AEOLUS_DECODER_SIZE,
        PL_AYDP_DECODER_SIZE,
        PL_AOK_DECODER_SIZE,
        PL_GDL90_DECODER_SIZE,
    ];
    let (mut max, mut i) = (0, 0);
    while i < sizes.len() {
        if sizes[i] > max {
            max = sizes[i];
        }
        i += 1;
    }
    max
};

impl AnyState {
    fn filled(byte: u8) -> Self {
        Self([byte; ANY_STATE_LEN])
    }

    /// Random bytes, deterministic for `seed`.
    fn random(seed: u64) -> Self {
        let mut s = Self::filled(0);
        let mut x = seed;
        for b in s.0.iter_mut() {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            *b = (x >> 24) as u8;
        }
        s
    }
}

/// Every call on every kind of state whose storage holds `bytes` (never set up by `init`)
/// returns `PL_E_INVALID` and writes nothing: not the state, not an output.
fn refused_untouched(bytes: impl Fn() -> AnyState, what: &str) {
    for kind in &KINDS {
        let mut mem = bytes();
        let before = mem.0;
        // SAFETY: storage for any state, filled with `bytes`.
        let (st, untouched) = unsafe { (kind.calls)(mem.0.as_mut_ptr()) };
        assert!(refused(&st), "{} state {what}: {st:?}", kind.name);
        assert!(
            untouched,
            "{} state {what}: an output was written",
            kind.name
        );
        assert!(
            mem.0 == before,
            "{} state {what}: the state was written",
            kind.name
        );
    }
}

#[test]
fn a_state_set_up_by_its_init_is_accepted_by_every_call() {
    for kind in &KINDS {
        let mut mem = AnyState::filled(0xA5);
        let p = mem.0.as_mut_ptr();
        // SAFETY: storage for any state.
        let (st, _) = unsafe {
            assert_eq!((kind.init)(p), 0, "{}", kind.name);
            (kind.calls)(p)
        };
        assert!(st.iter().all(|&s| s >= 0), "{}: {st:?}", kind.name);
    }
}

#[test]
fn a_state_never_set_up_filled_with_zeros_is_refused() {
    refused_untouched(|| AnyState::filled(0x00), "filled with 0x00");
}

/// Issue 44's case: before the tag, the PC side's one-byte parse call on this state built an invalid
/// `ReplyForm` (Miri: "constructing invalid value of type aok_proto::ReplyForm: at
/// .<enum-tag>, encountered 0xa5, but expected a valid enum tag").
#[test]
fn an_aok_pc_state_never_set_up_filled_with_0xa5_is_refused() {
    let mut d = MaybeUninit::<pl_aok_pc_decoder>::uninit();
    let p = d.as_mut_ptr();
    // SAFETY: writable storage for the state.
    unsafe {
        p.cast::<u8>()
            .write_bytes(0xA5, size_of::<pl_aok_pc_decoder>())
    };
    let (mut item, mut err) = (Out::new(), Out::new());
    // SAFETY: the state is what is tested; live outputs.
    let st = unsafe { byte(pl_aok_pc_parse, p, 0x1C, item.ptr(), err.ptr()) };
    assert_eq!(st, PL_E_INVALID);
    assert!(item.untouched() && err.untouched());
}

/// Every state filled with 0xA5: before the tag, the AEOLUS, GDL90 and AOK PC ones were
/// undefined behaviour (AEOLUS and GDL90: "enum value has invalid tag: 0xa5"; AOK PC, above),
/// and the AYDP and AOK device ones were read as decoders.
#[test]
fn a_state_never_set_up_filled_with_0xa5_is_refused() {
    refused_untouched(|| AnyState::filled(0xA5), "filled with 0xA5");
    refused_untouched(|| AnyState::filled(0xFF), "filled with 0xFF");
}

#[test]
fn a_state_never_set_up_holding_random_bytes_is_refused() {
    for seed in [1, 0xA5A5, 0x1234_5678_9ABC_DEF0] {
        refused_untouched(|| AnyState::random(seed), "of random bytes");
    }
}

#[test]
fn a_state_set_up_for_another_protocol_is_refused_and_stays_good() {
    for (i, other) in KINDS.iter().enumerate() {
        for (j, kind) in KINDS.iter().enumerate() {
            if i == j {
                continue;
            }
            let mut mem = AnyState::filled(0);
            let p = mem.0.as_mut_ptr();
            // SAFETY: storage for any state.
            let (st, untouched) = unsafe {
                assert_eq!((other.init)(p), 0);
                (kind.calls)(p)
            };
            assert!(
                refused(&st),
                "{} call on a state set up as {}: {st:?}",
                kind.name,
                other.name
            );
            assert!(
                untouched,
                "{} call on a state set up as {} wrote",
                kind.name, other.name
            );
            // The other protocol's state is still one (its padding is not compared: it is
            // not initialised memory in Rust's model).
            // SAFETY: a set-up state of `other`.
            let (st, _) = unsafe { (other.calls)(p) };
            assert!(
                st.iter().all(|&s| s >= 0),
                "{} state afterwards: {st:?}",
                other.name
            );
        }
    }
}

#[test]
fn a_misaligned_state_is_refused_by_init_and_every_call() {
    for kind in &KINDS {
        // `init` on an odd address writes nothing.
        let mut mem = AnyState::filled(0);
        // SAFETY: one byte into the storage: as large as any state, not aligned for one.
        let st = unsafe { (kind.init)(mem.0.as_mut_ptr().add(1)) };
        assert_eq!(st, PL_E_INVALID, "{} init", kind.name);
        assert!(mem.0 == [0; ANY_STATE_LEN], "{} init wrote", kind.name);
        // A good state moved to an odd address, tag and all, is refused before it is read.
        let mut good = AnyState::filled(0);
        let mut moved = AnyState::filled(0);
        // SAFETY: storage for any state, and a copy of its bytes one byte further on.
        let (st, untouched) = unsafe {
            assert_eq!((kind.init)(good.0.as_mut_ptr()), 0);
            core::ptr::copy_nonoverlapping(
                good.0.as_ptr(),
                moved.0.as_mut_ptr().add(1),
                ANY_STATE_LEN - 8,
            );
            (kind.calls)(moved.0.as_mut_ptr().add(1))
        };
        assert!(
            refused(&st),
            "{} moved to an odd address: {st:?}",
            kind.name
        );
        assert!(
            untouched,
            "{} moved to an odd address: an output was written",
            kind.name
        );
    }
}

#[test]
fn the_archive_reports_its_abi_version_and_the_header_sizes() {
    assert_eq!(state::pl_abi_version(), state::PL_ABI_VERSION);
    use state::{
        PL_STATE_AEOLUS, PL_STATE_AOK_DEVICE, PL_STATE_AOK_PC, PL_STATE_AYDP, PL_STATE_GDL90,
    };
    /// A state's kind, its Rust size and the header's size.
    fn row<T>(kind: u32, header: usize) -> (u32, usize, usize) {
        (kind, size_of::<T>(), header)
    }
    let states = [
        row::<pl_aeolus_decoder>(PL_STATE_AEOLUS, PL_AEOLUS_DECODER_SIZE),
        row::<pl_aydp_decoder>(PL_STATE_AYDP, PL_AYDP_DECODER_SIZE),
        row::<pl_aok_device_decoder>(PL_STATE_AOK_DEVICE, PL_AOK_DECODER_SIZE),
        row::<pl_aok_pc_decoder>(PL_STATE_AOK_PC, PL_AOK_DECODER_SIZE),
        row::<pl_gdl90_decoder>(PL_STATE_GDL90, PL_GDL90_DECODER_SIZE),
    ];
    for (kind, size, header) in states {
        assert_eq!(
            (state::pl_state_size(kind), size),
            (header, header),
            "kind {kind}"
        );
        assert_eq!(
            state::pl_state_align(kind),
            align_of::<u64>(),
            "kind {kind}"
        );
    }
    for unknown in [0, 6, u32::MAX] {
        assert_eq!(
            (
                state::pl_state_size(unknown),
                state::pl_state_align(unknown)
            ),
            (0, 0)
        );
    }
}
