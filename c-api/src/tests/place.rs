//! Where each message is (`offset`, `wire_len`), the byte-accounting rule of the header, the
//! end of a stream, and no stale message with an error, through the C calls.

use super::*;

/// One event of the one loop: status, offset, wire length, and whether the message struct
/// held nothing but its place (cleared).
type Placed = (i32, u64, u32, bool);

/// The one loop over `stream` in pieces of `chunk` bytes (0: whole), then the end of the
/// stream: every event with its place.
///
/// # Safety
/// `d` is a set-up decoder of the kind `parse` and `finish` take.
unsafe fn one_loop<D, M>(
    parse: Parse<D, M>,
    finish: unsafe extern "C" fn(*mut D, *mut M, *mut pl_error) -> i32,
    place: impl Fn(&M) -> (u64, u32, bool),
    d: *mut D,
    stream: &[u8],
    chunk: usize,
) -> Vec<Placed> {
    let (mut msg, mut err): (M, _) = (zeroed(), pl_error::default());
    let mut out = Vec::new();
    for piece in stream.chunks(if chunk == 0 {
        stream.len().max(1)
    } else {
        chunk
    }) {
        let mut off = 0;
        loop {
            let rest = &piece[off..];
            let mut used = usize::MAX;
            // SAFETY: the caller's promise; a live input and outputs.
            let st = unsafe { parse(d, rest.as_ptr(), rest.len(), &mut used, &mut msg, &mut err) };
            assert!(st >= 0 && used <= rest.len());
            off += used;
            if st == PL_NOTHING {
                break;
            }
            let (o, l, cleared) = place(&msg);
            out.push((st, o, l, cleared));
        }
    }
    loop {
        // SAFETY: as above.
        let st = unsafe { finish(d, &mut msg, &mut err) };
        if st == PL_NOTHING {
            break;
        }
        let (o, l, cleared) = place(&msg);
        out.push((st, o, l, cleared));
    }
    out
}

/// Checks the events of every piece size against the whole, and the rule: every byte fed is
/// in a message's `wire_len` (less `flags_each` flag bytes counted apart), a discard counter,
/// or held. `counted(stats)` is the bytes the counters hold; `framed(stats)`, where the
/// protocol counts its frames' bytes (AEOLUS, GDL90), must equal the wire lengths less flags.
fn check(
    stream: &[u8],
    run: impl Fn(&[u8], usize) -> (Vec<Placed>, u64, u64),
    flags_each: u32,
    frame_starts: impl Fn(&[u8]) -> bool,
) {
    let (whole, counted, framed) = run(stream, 0);
    let messages = whole.iter().filter(|e| e.0 == PL_MESSAGE).count();
    let errors = whole.iter().filter(|e| e.0 == PL_ERROR).count();
    assert!(
        messages >= 5 && errors > 0,
        "{messages} messages and {errors} errors in {} bytes",
        stream.len()
    );
    let in_frames: u64 = whole.iter().map(|e| u64::from(e.2)).sum();
    let less_flags: u64 = whole
        .iter()
        .filter(|e| e.2 > 0)
        .map(|e| u64::from(e.2 - flags_each))
        .sum();
    if flags_each > 0 {
        assert_eq!(
            less_flags, framed,
            "frame_bytes is the wire lengths less the flags"
        );
        assert_eq!(
            counted + framed,
            stream.len() as u64,
            "the byte-accounting rule"
        );
    } else {
        assert_eq!(
            in_frames + counted,
            stream.len() as u64,
            "the byte-accounting rule"
        );
    }
    let mut last_end = 0;
    for &(st, offset, len, cleared) in &whole {
        if len == 0 {
            assert!(
                st == PL_ERROR && cleared,
                "an error without a frame clears the message"
            );
            continue;
        }
        let end = offset + u64::from(len);
        assert!(end <= stream.len() as u64);
        let at = &stream[offset as usize..end as usize];
        assert!(
            frame_starts(at),
            "a frame at {offset}, {len} bytes: {at:02x?}"
        );
        // Frames do not overlap but for a shared flag.
        assert!(offset + u64::from(flags_each / 2) >= last_end);
        last_end = end;
    }
    for &chunk in PIECES {
        let (got, c, f) = run(stream, chunk);
        assert!(
            got == whole && (c, f) == (counted, framed),
            "pieces of {chunk}"
        );
    }
}

/// The length of the test streams and the piece sizes each is fed in besides whole. Miri runs
/// these too, on half the bytes and in single bytes only: the same calls and paths (a call that
/// consumes part of its input is the whole stream's), a third of the time.
const LEN: usize = if cfg!(miri) { 1500 } else { 3000 };
const PIECES: &[usize] = if cfg!(miri) { &[1] } else { &[1, 7, 64] };

/// The run of a decoder over `stream` in pieces of `chunk`: its events (`one_loop`), and from
/// its counters (`count`) the bytes they account for outside whole messages (flags, discarded,
/// held) and the bytes of its frames (AEOLUS and GDL90; 0 for the others, whose messages' wire
/// lengths count every byte). `calls` are its `parse`, `finish` and `get_stats`, `d` a set-up
/// decoder.
macro_rules! run {
    ($calls:expr, $Stats:ty, $place:expr, $d:ident, $stream:expr, $chunk:expr, $count:expr) => {{
        let (parse, finish, get_stats) = $calls;
        // SAFETY: a set-up decoder.
        let ev = unsafe { one_loop(parse, finish, $place, $d.as_mut_ptr(), $stream, $chunk) };
        let mut st = <$Stats>::default();
        // SAFETY: as above.
        assert_eq!(unsafe { get_stats($d.as_ptr(), &mut st) }, 0);
        let (counted, frame_bytes): (u32, u32) = $count(&st);
        (ev, u64::from(counted), u64::from(frame_bytes))
    }};
}

fn cycle(capture: &[u8], len: usize) -> Vec<u8> {
    capture.iter().copied().cycle().take(len).collect()
}

#[test]
fn aeolus_places_every_frame_and_accounts_for_every_byte() {
    let good = cycle(
        include_bytes!("../../../testdata/qemu-uart0-aeolus.bin"),
        LEN,
    );
    let stream = hostile(&good, &[0x7E, 0x7D, 0x5E, 0x5D, 0x3E, 0x00], 0xAE01);
    let run = |s: &[u8], chunk| {
        let mut d = aeolus_decoder();
        let place = |m: &pl_aeolus_message| {
            (
                m.offset,
                m.wire_len,
                m.wire_len > 0 || (m.id == 0 && m.data.is_null()),
            )
        };
        let calls = (pl_aeolus_parse, pl_aeolus_finish, pl_aeolus_get_stats);
        let count = |st: &pl_aeolus_stats| {
            (
                st.flags + st.bytes_discarded + st.held_bytes,
                st.frame_bytes,
            )
        };
        run!(calls, pl_aeolus_stats, place, d, s, chunk, count)
    };
    check(&stream, run, 2, |f| f[0] == 0x7E && f[f.len() - 1] == 0x7E);
}

#[test]
fn gdl90_places_every_frame_and_accounts_for_every_byte() {
    // Heartbeat (the ICD's example) and a wrong-length heartbeat (good CRC, typed parse fails).
    let heartbeat = [
        0x7E, 0x00, 0x81, 0x41, 0xDB, 0xD0, 0x08, 0x02, 0xB3, 0x8B, 0x7E,
    ];
    let mut m: pl_gdl90_message = zeroed();
    m.kind = PL_GDL90_UNKNOWN;
    m.id = 0x00;
    let short = [0x81u8, 0x41];
    (m.data, m.data_len) = (short.as_ptr(), short.len());
    let mut bad = [0u8; 32];
    // SAFETY: valid pointers and lengths.
    let n = unsafe { pl_gdl90_encode(&m, bad.as_mut_ptr(), bad.len()) };
    assert!(n > 0);
    let mut good = Vec::new();
    for i in 0..LEN / 15 {
        good.extend_from_slice(&heartbeat);
        if i % 7 == 0 {
            good.extend_from_slice(&bad[..n as usize]);
        }
    }
    let stream = hostile(&good, &[0x7E, 0x7D, 0x5E, 0x5D, 0x00, 0x81], 0x6D190);
    let run = |s: &[u8], chunk| {
        let mut d = MaybeUninit::<pl_gdl90_decoder>::uninit();
        // SAFETY: writable storage.
        assert_eq!(unsafe { pl_gdl90_init(d.as_mut_ptr()) }, 0);
        let place = |m: &pl_gdl90_message| {
            let cleared = m.kind == PL_GDL90_UNKNOWN && m.id == 0 && m.data.is_null();
            (m.offset, m.wire_len, m.wire_len > 0 || cleared)
        };
        let calls = (pl_gdl90_parse, pl_gdl90_finish, pl_gdl90_get_stats);
        let count = |st: &pl_gdl90_stats| {
            (
                st.flags + st.bytes_discarded + st.held_bytes,
                st.frame_bytes,
            )
        };
        run!(calls, pl_gdl90_stats, place, d, s, chunk, count)
    };
    check(&stream, run, 2, |f| f[0] == 0x7E && f[f.len() - 1] == 0x7E);
}

#[test]
fn aydp_places_every_message_and_accounts_for_every_byte() {
    let good = cycle(include_bytes!("../../../testdata/qemu-uart1-aydp.bin"), LEN);
    let stream = hostile(&good, &[0xFF, 0x80, 0x00, 0x07, 0x2B], 0xA7D9);
    let run = |s: &[u8], chunk| {
        let mut d = MaybeUninit::<pl_aydp_decoder>::uninit();
        // SAFETY: writable storage.
        assert_eq!(unsafe { pl_aydp_init(d.as_mut_ptr(), PL_AYDP_SPEC) }, 0);
        let place = |m: &pl_aydp_message| {
            let cleared = m.kind == PL_AYDP_UNKNOWN && m.seconds == 0 && m.data.is_null();
            (m.offset, m.wire_len, m.wire_len > 0 || cleared)
        };
        let calls = (pl_aydp_parse, pl_aydp_finish, pl_aydp_get_stats);
        let count = |st: &pl_aydp_stats| (st.bytes_discarded + st.held_bytes, 0);
        run!(calls, pl_aydp_stats, place, d, s, chunk, count)
    };
    check(&stream, run, 0, |f| f[0] == 0xFF);
}

#[test]
fn aok_places_every_frame_and_accounts_for_every_byte() {
    let good = cycle(include_bytes!("../../../testdata/qemu-uart2-aok.bin"), LEN);
    let stream = hostile(&good, &[0x63, 0x67, 0x47, 0x78, 0x57, 0x1c, 0x00], 0xA0C);
    let run = |s: &[u8], chunk| {
        let mut d = MaybeUninit::<pl_aok_device_decoder>::uninit();
        // SAFETY: writable storage.
        assert_eq!(unsafe { pl_aok_device_init(d.as_mut_ptr()) }, 0);
        let place = |m: &pl_aok_item| {
            let cleared = *m == pl_aok_item::default();
            (m.offset, m.wire_len, m.wire_len > 0 || cleared)
        };
        let calls = (
            pl_aok_device_parse,
            pl_aok_device_finish,
            pl_aok_device_get_stats,
        );
        let count = |st: &pl_aok_stats| (st.bytes_discarded + st.held_bytes, 0);
        run!(calls, pl_aok_stats, place, d, s, chunk, count)
    };
    check(&stream, run, 0, |f| !f.is_empty());
}

#[test]
fn an_error_never_passes_the_previous_message() {
    let mut stream = unhex(GYRO);
    let mut bad = unhex(GYRO);
    let last = bad.len() - 2;
    bad[last] ^= 1; // the CRC's high byte
    stream.extend_from_slice(&bad[1..]); // the gyro's closing flag opens it
    let mut d = aeolus_decoder();
    let d = d.as_mut_ptr();
    let (mut msg, mut err): (pl_aeolus_message, _) = (zeroed(), pl_error::default());
    let mut used = 0;
    // SAFETY: a set-up decoder, a live input and outputs.
    let st = unsafe { slice(pl_aeolus_parse, d, &stream, &mut used, &mut msg, &mut err) };
    assert_eq!(
        (st, msg.id, msg.offset, msg.wire_len),
        (PL_MESSAGE, 62, 0, 37)
    );
    let rest = &stream[used..];
    // SAFETY: as above.
    let st = unsafe { slice(pl_aeolus_parse, d, rest, &mut used, &mut msg, &mut err) };
    assert_eq!((st, err.kind), (PL_ERROR, PL_ERR_CHECKSUM_MISMATCH));
    assert!(msg.id == 0 && msg.data.is_null() && msg.data_len == 0 && msg.wire_len == 0);
    // The error's own place: the bad frame, flag to flag (its opening flag is the first
    // frame's closing one).
    assert_eq!((err.offset, err.wire_len), (36, (stream.len() - 36) as u32));
    // SAFETY: every member of the body is plain numbers.
    assert_eq!(unsafe { msg.body.motion }, pl_aeolus_motion::default());
}

#[test]
fn gdl90_ends_a_stream() {
    let heartbeat = [
        0x7E, 0x00, 0x81, 0x41, 0xDB, 0xD0, 0x08, 0x02, 0xB3, 0x8B, 0x7E,
    ];
    let mut d = MaybeUninit::<pl_gdl90_decoder>::uninit();
    // SAFETY: writable storage.
    assert_eq!(unsafe { pl_gdl90_init(d.as_mut_ptr()) }, 0);
    let d = d.as_mut_ptr();
    let (mut msg, mut err): (pl_gdl90_message, _) = (zeroed(), pl_error::default());
    let mut used = 0;
    // A heartbeat cut after 6 bytes, then the end of the stream.
    // SAFETY: a set-up decoder, a live input and outputs.
    unsafe {
        assert_eq!(
            pl_gdl90_parse(d, heartbeat.as_ptr(), 6, &mut used, &mut msg, &mut err),
            PL_NOTHING
        );
        let mut st = pl_gdl90_stats::default();
        pl_gdl90_get_stats(d, &mut st);
        assert_eq!(st.held_bytes, 5);
        assert_eq!(pl_gdl90_finish(d, &mut msg, &mut err), PL_ERROR);
        assert_eq!((err.kind, msg.wire_len), (PL_ERR_TRUNCATED, 0));
        // The frame cut short: its flag and the five bytes held.
        assert_eq!((err.offset, err.wire_len), (0, 6));
        assert_eq!(pl_gdl90_finish(d, &mut msg, &mut err), PL_NOTHING);
        pl_gdl90_get_stats(d, &mut st);
        assert_eq!(st.held_bytes, 0);
        // The decoder starts afresh; offsets go on from the 6 bytes fed.
        let st = slice(pl_gdl90_parse, d, &heartbeat, &mut used, &mut msg, &mut err);
        assert_eq!(
            (st, msg.kind, msg.offset, msg.wire_len),
            (PL_MESSAGE, PL_GDL90_HEARTBEAT, 6, 11)
        );
        assert_eq!(pl_gdl90_finish(d, &mut msg, &mut err), PL_NOTHING);
    }
}

/// Every error has its place in the `pl_error`: an AYDP checksum failure at its 0xFF, for its
/// whole length, after noise; an AOK frame with a bad checksum from its first byte.
#[test]
fn errors_carry_their_place() {
    let mut d = MaybeUninit::<pl_aydp_decoder>::uninit();
    // SAFETY: writable storage.
    assert_eq!(unsafe { pl_aydp_init(d.as_mut_ptr(), PL_AYDP_SPEC) }, 0);
    let d = d.as_mut_ptr();
    let (mut msg, mut err): (pl_aydp_message, _) = (zeroed(), pl_error::default());
    // Two noise bytes, then an expedited heartbeat whose checksum is off by one.
    let wire = [0x00, 0x11, 0xFF, 0x80, 0x07, 0, 0, 0, 0x79];
    let mut events = Vec::new();
    for byte in &wire {
        let mut used = 0;
        // SAFETY: a set-up decoder, a live input and outputs.
        let st = unsafe { pl_aydp_parse(d, byte, 1, &mut used, &mut msg, &mut err) };
        if st == PL_ERROR {
            events.push((err.kind, err.offset, err.wire_len, msg.wire_len));
        }
    }
    assert_eq!(events, [(PL_ERR_CHECKSUM_MISMATCH, 2, 7, 0)]);

    let mut d = MaybeUninit::<pl_aok_pc_decoder>::uninit();
    // SAFETY: writable storage.
    assert_eq!(unsafe { pl_aok_pc_init(d.as_mut_ptr(), 0, 30) }, 0);
    let d = d.as_mut_ptr();
    let (mut item, mut err): (pl_aok_item, _) = (zeroed(), pl_error::default());
    // A debug frame with a broken checksum (the host tool's test of the same).
    let wire = [0x1C, 0x56, 0xFF, 0xFF, 0xFF, 0xFE, 0x58];
    let mut used = 0;
    // SAFETY: as above.
    let st =
        unsafe { pl_aok_pc_parse(d, wire.as_ptr(), wire.len(), &mut used, &mut item, &mut err) };
    assert_eq!((st, err.kind), (PL_ERROR, PL_ERR_CHECKSUM_MISMATCH));
    assert_eq!((err.offset, err.wire_len), (0, 7));
}
