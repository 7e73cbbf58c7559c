//! Stream behaviour of the decoder: noise, flags, escapes, overflow, CRC errors, short frames,
//! strict mode, counters; every stream test repeats with the input split at every byte
//! boundary; 1,000 random messages in random garbage; 1 MiB of random bytes.

use crate::common;
use aeolus_proto::Decode;
use aeolus_proto::{message::*, *};
use common::{Rng, events, hex};

type Events = Vec<Result<(u8, Vec<u8>), Error>>;

/// TOAST "hi" with its CRC.
const HI: [u8; 8] = [0x7E, 0x52, b'h', b'i', 0x00, 0x73, 0xEC, 0x7E];

/// Runs `bytes` through a fresh decoder whole, then split in two at every byte boundary
/// (two `feed` calls on the same decoder), and checks all runs agree. Returns the
/// events and the final counters.
fn run_split<const N: usize>(strict: bool, bytes: &[u8]) -> (Events, Stats) {
    let fresh = || {
        if strict {
            Decoder::<N>::strict()
        } else {
            Decoder::<N>::new()
        }
    };
    let mut whole = fresh();
    let expected = events(&mut whole, bytes);
    for cut in 0..=bytes.len() {
        let mut d = fresh();
        let mut got = events(&mut d, &bytes[..cut]);
        got.extend(events(&mut d, &bytes[cut..]));
        assert_eq!(got, expected, "split at {cut}");
        assert_eq!(d.stats(), whole.stats(), "counters, split at {cut}");
    }
    check_accounting(&whole, bytes.len());
    (expected, whole.stats())
}

/// Every byte is a flag, part of a delivered frame, discarded, or still pending.
fn check_accounting<const N: usize>(d: &Decoder<N>, pushed: usize) {
    let s = d.stats();
    assert_eq!(
        s.flags as usize + s.frame_bytes as usize + s.bytes_discarded as usize + d.held_bytes(),
        pushed,
        "byte accounting {s:?}"
    );
}

fn ok(raw: &[u8]) -> Result<(u8, Vec<u8>), Error> {
    Ok((raw[0], raw.to_vec()))
}

const HI_RAW: [u8; 6] = [0x52, b'h', b'i', 0x00, 0x73, 0xEC];

#[test]
fn garbage_before_the_first_flag_is_dropped() {
    let mut s = vec![0x01, 0x52, 0xFF, 0x7D, 0x5E, 0x00];
    s.extend_from_slice(&HI);
    let (ev, st) = run_split::<64>(true, &s);
    assert_eq!(ev, [ok(&HI_RAW)]);
    assert_eq!(st.bytes_discarded, 6);
    assert_eq!(st.frames_ok, 1);
}

#[test]
fn repeated_flags_between_frames_are_skipped() {
    let mut s = HI.to_vec();
    s.extend_from_slice(&[0x7E, 0x7E, 0x7E]);
    s.extend_from_slice(&HI);
    let (ev, st) = run_split::<64>(true, &s);
    assert_eq!(ev, [ok(&HI_RAW), ok(&HI_RAW)]);
    assert_eq!(st.flags, 7);
    assert_eq!(st.bytes_discarded, 0);
    // A shared flag between frames works too.
    let mut shared = HI.to_vec();
    shared.extend_from_slice(&HI[1..]);
    let (ev, _) = run_split::<64>(true, &shared);
    assert_eq!(ev, [ok(&HI_RAW), ok(&HI_RAW)]);
}

#[test]
fn escape_right_before_a_flag_aborts_and_the_flag_opens_the_next_frame() {
    // 7E 52 68 7D | 7E 52 'h' 'i' 00 CRC 7E
    let mut s = vec![0x7E, 0x52, 0x68, 0x7D];
    s.extend_from_slice(&HI);
    let (ev, st) = run_split::<64>(true, &s);
    assert_eq!(ev, [Err(Error::EscapedFlag), ok(&HI_RAW)]);
    assert_eq!(st.bad_escapes, 1);
    assert_eq!(st.bytes_discarded, 3);
}

#[test]
fn escape_followed_by_an_invalid_byte_drops_the_frame_until_the_next_flag() {
    // 7D 41 is not a valid escape; the rest of that frame (to the next flag) is dropped.
    let mut s = vec![0x7E, 0x52, 0x7D, 0x41, 0x33, 0x34];
    s.extend_from_slice(&HI);
    let (ev, st) = run_split::<64>(true, &s);
    assert_eq!(ev, [Err(Error::InvalidEscape), ok(&HI_RAW)]);
    assert_eq!(st.bad_escapes, 1);
    assert_eq!(st.bytes_discarded, 5);
}

#[test]
fn overflow_then_clean_resync() {
    // 40 data bytes into a decoder of 16: overflow at byte 17, then the next frame arrives.
    let mut long = [0u8; max_encoded_len(40)];
    let n = encode_frame(81, &[0x11; 40], &[], CrcMode::Compute, &mut long).unwrap();
    let mut s = long[..n].to_vec();
    s.extend_from_slice(&HI);
    let (ev, st) = run_split::<16>(true, &s);
    assert_eq!(ev, [Err(Error::Overflow), ok(&HI_RAW)]);
    assert_eq!(st.overflows, 1);
    assert_eq!(st.frames_ok, 1);
    // A frame of exactly the capacity fits.
    let mut exact = [0u8; 64];
    let n = encode_frame(81, &[0x22; 13], &[], CrcMode::Compute, &mut exact).unwrap();
    let (ev, _) = run_split::<16>(true, &exact[..n]);
    assert!(matches!(ev[..], [Ok((81, ref raw))] if raw.len() == 16));
}

#[test]
fn crc_mismatch_carries_the_id_and_the_next_frame_survives() {
    let mut bad = HI.to_vec();
    bad[3] ^= 0x01; // 'i' -> 'h'
    bad.extend_from_slice(&HI[1..]);
    let (ev, st) = run_split::<64>(true, &bad);
    assert!(matches!(
        ev[0],
        Err(Error::ChecksumMismatch {
            id: 0x52,
            received: 0xEC73,
            ..
        })
    ));
    assert_eq!(ev[1], ok(&HI_RAW));
    assert_eq!((st.checksum_errors, st.frames_ok), (1, 1));
}

#[test]
fn frames_too_short_for_an_id_and_a_crc() {
    let s = hex("7e527e7e52007e7e520000007e");
    let (ev, st) = run_split::<64>(false, &s);
    // One byte, two bytes, then ID + 00 00 with no data: a valid (empty, unchecked) frame.
    assert_eq!(
        ev,
        [
            Err(Error::TooShort),
            Err(Error::TooShort),
            ok(&[0x52, 0, 0, 0])
        ]
    );
    assert_eq!(st.too_short, 2);
    assert_eq!(st.frames_no_crc, 1);
    // The same without the trailing zero data byte: ID + 00 00 alone.
    let (ev, _) = run_split::<64>(false, &hex("7e5200007e"));
    assert_eq!(ev, [ok(&[0x52, 0, 0])]);
}

#[test]
fn strict_mode_rejects_frames_without_crc_but_not_a_real_zero_crc() {
    let (ev, st) = run_split::<64>(true, &hex("7e526e6f206372630000007e"));
    assert_eq!(ev, [Err(Error::MissingCrc { id: 82 })]);
    assert_eq!(st.missing_crc, 1);
    // Find data whose genuine CRC is 0x0000: strict mode must accept it as checked.
    let mut rng = Rng(7);
    let data = loop {
        let d = rng.bytes(4);
        if crc::checksum(&[&[0x51u8][..], &d].concat()) == 0 {
            break d;
        }
    };
    let mut wire = [0u8; 32];
    let n = encode_frame(0x51, &data, &[], CrcMode::Compute, &mut wire).unwrap();
    let mut d = Decoder::<64>::strict();
    let mut checked = Vec::new();
    d.feed(&wire[..n], |ev| checked.push(ev.map(|f| f.has_crc())));
    assert_eq!(checked, [Ok(true)]);
}

/// Random garbage: rich in flags and escapes.
fn garbage(rng: &mut Rng, max: u64) -> Vec<u8> {
    let n = rng.below(max + 1) as usize;
    (0..n)
        .map(|_| match rng.below(8) {
            0 => FLAG,
            1 => ESCAPE,
            _ => rng.byte(),
        })
        .collect()
}

fn random_message(rng: &mut Rng) -> Vec<u8> {
    let msg = match rng.below(6) {
        0 => Message::Gyro(Gyro {
            valid: true,
            timestamp_ms: rng.f64(),
            x: rng.f32(),
            y: rng.f32(),
            z: rng.f32(),
        }),
        1 => Message::Accel(Accel {
            valid: false,
            timestamp_ms: rng.f64(),
            x: rng.f32(),
            y: rng.f32(),
            z: rng.f32(),
        }),
        2 => Message::Pressure(Pressure {
            valid: true,
            timestamp_ms: rng.f64(),
            static_mbar: rng.f32(),
            pitot_mbar: rng.f32(),
            airspeed_mps: rng.f32(),
        }),
        3 => Message::Wind(Wind {
            valid: true,
            timestamp_ms: rng.f64(),
            speed_mps: rng.f32(),
            direction_deg: rng.f32(),
        }),
        4 => {
            let n = rng.below(60) as usize;
            Message::Log(Box::leak(rng.bytes(n).into_boxed_slice()))
        }
        _ => Message::AeolusInfo(AeolusInfo {
            model: 83,
            firmware: [3, 8, 0],
            mac: [rng.byte(); 6],
        }),
    };
    let mut buf = [0u8; max_encoded_len(64)];
    let n = msg.encode(&mut buf, CrcMode::Compute).unwrap();
    buf[..n].to_vec()
}

#[test]
fn a_thousand_random_messages_in_random_garbage_all_arrive_in_order() {
    let mut rng = Rng(0x5EED_A301);
    let mut stream = Vec::new();
    let mut sent = Vec::new();
    for _ in 0..1000 {
        stream.extend(garbage(&mut rng, 40));
        let frame = random_message(&mut rng);
        let mut d = Decoder::<256>::strict();
        let raw = events(&mut d, &frame).pop().unwrap().unwrap().1;
        sent.push(raw);
        stream.extend(frame);
    }
    stream.extend(garbage(&mut rng, 40));

    let mut d = Decoder::<256>::strict();
    let got: Vec<Vec<u8>> = events(&mut d, &stream)
        .into_iter()
        .filter_map(|e| e.ok().map(|f| f.1))
        .collect();
    assert_eq!(
        got.len(),
        sent.len(),
        "every message delivered, nothing spurious"
    );
    assert_eq!(got, sent, "intact and in order");
    check_accounting(&d, stream.len());
    assert!(
        d.stats().frames_dropped() > 0,
        "the garbage produced rejected frames"
    );

    // The same stream split at every 97th boundary (every boundary over 60 kB is slow in debug).
    for cut in (0..stream.len()).step_by(97) {
        let mut d2 = Decoder::<256>::strict();
        let mut got2 = events(&mut d2, &stream[..cut]);
        got2.extend(events(&mut d2, &stream[cut..]));
        assert_eq!(
            got2.into_iter().filter_map(|e| e.ok().map(|f| f.1)).count(),
            1000,
            "cut {cut}"
        );
        assert_eq!(d2.stats(), d.stats());
    }
}

#[test]
fn a_mebibyte_of_random_bytes_never_panics_and_the_counters_add_up() {
    let mut rng = Rng(0xDEAD_BEEF);
    let noise = rng.bytes(1 << 20);
    for strict in [false, true] {
        let mut d = if strict {
            Decoder::<64>::strict()
        } else {
            Decoder::<64>::new()
        };
        let mut events_seen = 0u32;
        let mut delivered = 0u32;
        for &b in &noise {
            d.feed(&[b], |ev| {
                events_seen += 1;
                if let Ok(frame) = ev {
                    delivered += 1;
                    let _ = frame.message();
                }
            });
        }
        let s = d.stats();
        check_accounting(&d, noise.len());
        assert_eq!(s.frames_delivered(), delivered);
        assert_eq!(s.frames_delivered() + s.frames_dropped(), events_seen);
        assert!(
            s.flags > 3000,
            "about 1 in 256 bytes is a flag: {}",
            s.flags
        );
        // Random frames are short on average, so most die on CRC or as too short.
        assert!(
            s.checksum_errors > 0 && s.too_short > 0 && s.bad_escapes > 0 && s.overflows > 0,
            "{s:?}"
        );
        if strict {
            assert_eq!(s.frames_no_crc, 0);
        }
    }
    // And as datagrams of random sizes.
    let mut buf = noise.clone();
    let mut off = 0;
    while off < buf.len() {
        let n = (rng.below(1500) as usize + 1).min(buf.len() - off);
        for f in decode_datagram(&mut buf[off..off + n], false).flatten() {
            let _ = f.message();
        }
        off += n;
    }
}

/// `feed` copies runs in bulk; it must give exactly what pushing byte by byte gives,
/// events and counters, on noise and on frames, for a capacity that overflows often.
#[test]
fn push_slice_is_exactly_push_byte_by_byte() {
    let mut rng = Rng(0xB01D);
    let mut stream = rng.bytes(200_000);
    for _ in 0..2000 {
        stream.extend(garbage(&mut rng, 30));
        stream.extend(random_message(&mut rng));
    }
    fn by_byte<const N: usize>(bytes: &[u8]) -> (Events, Stats) {
        let mut d = Decoder::<N>::new();
        let mut ev = Vec::new();
        for &b in bytes {
            d.feed(&[b], |e| {
                ev.push(e.map(|f| (f.id(), f.raw().to_vec())));
            });
        }
        (ev, d.stats())
    }
    fn sliced<const N: usize>(bytes: &[u8], chunk: usize) -> (Events, Stats) {
        let mut d = Decoder::<N>::new();
        let mut ev = Vec::new();
        for c in bytes.chunks(chunk) {
            ev.extend(events(&mut d, c));
        }
        (ev, d.stats())
    }
    for chunk in [1, 7, 64, 4096, stream.len()] {
        assert_eq!(
            sliced::<24>(&stream, chunk),
            by_byte::<24>(&stream),
            "capacity 24, chunk {chunk}"
        );
        assert_eq!(
            sliced::<256>(&stream, chunk),
            by_byte::<256>(&stream),
            "capacity 256, chunk {chunk}"
        );
    }
}
