//! Stream tests: random valid messages behind adversarial garbage, split streams, corrupted
//! streams and pure noise.

use crate::naive;
use crate::streamgen;

use aydp_proto::{Decode, Decoder, Error, Event, Profile};
use naive::NaiveDecoder;
use streamgen::{Rng, garbage, random_message};

const CAP: usize = 128;

/// Build `count` messages, each behind 0..=64 bytes of garbage.
fn build_stream(
    seed: u64,
    count: usize,
    profile: Profile,
    mix: (u64, u64),
) -> (Vec<u8>, Vec<Vec<u8>>) {
    let mut rng = Rng(seed);
    let mut stream = Vec::new();
    let mut msgs = Vec::with_capacity(count);
    for _ in 0..count {
        garbage(&mut rng, profile, CAP, mix, &mut stream);
        let m = random_message(&mut rng, profile);
        assert!(m.len() <= CAP, "generator made a {}-byte message", m.len());
        stream.extend_from_slice(&m);
        msgs.push(m);
    }
    (stream, msgs)
}

/// Events of the library decoder, fed one byte at a time: frames as byte vectors, errors as
/// errors.
fn run_lib(stream: &[u8], profile: Profile) -> (Vec<Result<Vec<u8>, Error>>, aydp_proto::Stats) {
    let mut dec = Decoder::<CAP>::new(profile);
    let mut out = Vec::new();
    for b in stream {
        dec.feed(core::slice::from_ref(b), |e| {
            out.push(e.map(|f| f.as_bytes().to_vec()))
        });
    }
    dec.finish(|e| out.push(e.map(|f| f.as_bytes().to_vec())));
    (out, dec.stats())
}

/// The events of one byte, each as `Err` or `Ok(())`.
fn byte_events<const N: usize>(dec: &mut Decoder<N>, b: u8) -> Vec<Result<(), Error>> {
    let mut out = Vec::new();
    dec.feed(&[b], |e| out.push(e.map(|_| ())));
    out
}

fn frames(events: &[Result<Vec<u8>, Error>]) -> Vec<Vec<u8>> {
    events
        .iter()
        .filter_map(|e| e.as_ref().ok().cloned())
        .collect()
}

/// How many of `expected` come out intact and in order (greedy in-order matching).
fn in_order(expected: &[Vec<u8>], got: &[Vec<u8>]) -> usize {
    let mut hits = 0;
    let mut j = 0;
    for g in got {
        if let Some(k) = expected[j..].iter().position(|e| e == g) {
            hits += 1;
            j += k + 1;
        }
    }
    hits
}

fn stream_figures(profile: Profile, seed: u64, mix: (u64, u64)) -> (f64, f64) {
    let (stream, msgs) = build_stream(seed, 10_000, profile, mix);
    let (events, stats) = run_lib(&stream, profile);
    let got = frames(&events);
    let ok = in_order(&msgs, &got);

    let mut naive = NaiveDecoder::new(profile, CAP);
    let naive_got: Vec<Vec<u8>> = stream.iter().filter_map(|&b| naive.push(b)).collect();
    let naive_ok = in_order(&msgs, &naive_got);

    let pct = |n: usize| n as f64 * 100.0 / msgs.len() as f64;
    println!(
        "{profile:?}: {} bytes, {} messages: rescanning decoder {} intact in order ({:.2} %), \
         {} frames delivered in all, stats {:?}; naive decoder {} ({:.2} %)",
        stream.len(),
        msgs.len(),
        ok,
        pct(ok),
        got.len(),
        stats,
        naive_ok,
        pct(naive_ok),
    );
    assert_eq!(stats.frames_ok as usize, got.len());
    (pct(ok), pct(naive_ok))
}

/// Garbage mix of the main test: a quarter of the bytes are 0xFF, one start in 64 carries a
/// plausible type and length.
const MIX: (u64, u64) = (1, 64);

#[test]
fn ten_thousand_messages_behind_garbage_spec() {
    let (ok, naive) = stream_figures(Profile::Spec, 0x5EED_0001, MIX);
    assert!(ok >= 99.9, "only {ok:.2} % intact");
    assert!(naive < ok - 10.0);
}

#[test]
fn ten_thousand_messages_behind_garbage_reference() {
    let (ok, naive) = stream_figures(Profile::Reference, 0x5EED_0002, MIX);
    assert!(ok >= 99.9, "only {ok:.2} % intact");
    assert!(naive < ok - 10.0);
}

/// Harsher garbage: more plausible false headers. Each false candidate that overlaps a real
/// message passes the 8-bit XOR with probability 1/256, which bounds any decoder; the figures
/// are printed and must stay well above the naive decoder's.
#[test]
fn harsher_garbage_figures() {
    for mix in [(1, 16), (1, 4), (1, 2)] {
        for (profile, seed) in [
            (Profile::Spec, 0x5EED_0003),
            (Profile::Reference, 0x5EED_0004),
        ] {
            print!("mix {mix:?} ");
            let (ok, naive) = stream_figures(profile, seed, mix);
            assert!(ok >= 98.5, "{ok:.2} % at mix {mix:?}");
            assert!(naive < ok - 40.0);
        }
    }
}

/// Every input byte ends up in exactly one delivered frame or in `bytes_discarded`.
fn assert_conserved(stream: &[u8], events: &[Result<Vec<u8>, Error>], stats: aydp_proto::Stats) {
    let delivered: usize = frames(events).iter().map(Vec::len).sum();
    assert_eq!(delivered + stats.bytes_discarded as usize, stream.len());
}

#[test]
fn small_stream_split_at_every_byte_boundary() {
    for (profile, seed) in [(Profile::Spec, 11), (Profile::Reference, 12)] {
        let (stream, msgs) = build_stream(seed, 120, profile, (1, 2));
        let (whole, stats) = run_lib(&stream, profile);
        assert_conserved(&stream, &whole, stats);
        assert!(in_order(&msgs, &frames(&whole)) >= 115);
        for cut in 0..=stream.len() {
            let mut dec = Decoder::<CAP>::new(profile);
            let mut out = Vec::new();
            let mut sink = |e: Result<aydp_proto::Frame<'_>, Error>| {
                out.push(e.map(|f| f.as_bytes().to_vec()))
            };
            dec.feed(&stream[..cut], &mut sink);
            dec.feed(&stream[cut..], &mut sink);
            dec.finish(&mut sink);
            assert_eq!(out, whole, "{profile:?} split at {cut}");
        }
    }
}

#[test]
fn big_stream_in_random_chunks_matches_byte_at_a_time() {
    let (stream, _) = build_stream(0x5EED_0001, 10_000, Profile::Spec, MIX);
    let (whole, stats) = run_lib(&stream, Profile::Spec);
    assert_conserved(&stream, &whole, stats);
    let mut rng = Rng(99);
    let mut dec = Decoder::<CAP>::new(Profile::Spec);
    let mut out = Vec::new();
    let mut rest = &stream[..];
    while !rest.is_empty() {
        let n = (1 + rng.below(200) as usize).min(rest.len());
        let (chunk, tail) = rest.split_at(n);
        dec.feed(chunk, |e| out.push(e.map(|f| f.as_bytes().to_vec())));
        rest = tail;
    }
    dec.finish(|e| out.push(e.map(|f| f.as_bytes().to_vec())));
    assert_eq!(out, whole);
}

/// Taking one event a call loses nothing: the pull form over the whole stream, each call on
/// what the last one left, events a rescan left queued first (no byte used), then the end.
#[test]
fn one_event_a_call_only_delays_events() {
    let (stream, _) = build_stream(5, 500, Profile::Spec, (1, 2));
    let (whole, _) = run_lib(&stream, Profile::Spec);
    let mut dec = Decoder::<CAP>::new(Profile::Spec);
    let mut out = Vec::new();
    let mut take = |dec: &Decoder<CAP>, input: &[u8], e| {
        out.push(match e {
            Event::Found(found) => Ok(dec.item(input, found).as_bytes().to_vec()),
            Event::Error(e) => Err(e),
            Event::Truncated(_) => Err(Error::Truncated),
        })
    };
    let mut rest = &stream[..];
    loop {
        let (used, e) = dec.decode(rest);
        let Some(e) = e else { break };
        take(&dec, rest, e);
        rest = &rest[used..];
    }
    while let Some(e) = dec.end() {
        take(&dec, &[], e);
    }
    assert_eq!(out, whole);
}

#[test]
fn one_mib_of_random_bytes_never_panics() {
    for (profile, seed) in [(Profile::Spec, 0xA11CE), (Profile::Reference, 0xB0B)] {
        let mut rng = Rng(seed);
        let stream: Vec<u8> = (0..1 << 20).map(|_| rng.byte()).collect();
        let (events, stats) = run_lib(&stream, profile);
        assert_conserved(&stream, &events, stats);
        // Also through a tiny decoder, where almost every length fails.
        let mut small = Decoder::<8>::new(profile);
        small.feed(&stream, |_| {});
        small.finish(|_| {});
        println!(
            "{profile:?}: 1 MiB noise: {stats:?}; 8-byte decoder {:?}",
            small.stats()
        );
    }
}

/// Messages back to back, a fifth of them with one corrupted byte: every intact one survives.
#[test]
fn corrupted_messages_do_not_take_their_neighbours() {
    for (profile, seed) in [(Profile::Spec, 21), (Profile::Reference, 22)] {
        let mut rng = Rng(seed);
        let mut stream = Vec::new();
        let mut intact = Vec::new();
        for _ in 0..5_000 {
            let mut m = random_message(&mut rng, profile);
            if rng.chance(1, 5) {
                let i = rng.below(m.len() as u64) as usize;
                m[i] ^= 1 << rng.below(8);
            } else {
                intact.push(m.clone());
            }
            stream.extend(m);
        }
        let (events, stats) = run_lib(&stream, profile);
        assert_conserved(&stream, &events, stats);
        let ok = in_order(&intact, &frames(&events));
        println!(
            "{profile:?}: corrupted stream: {ok} of {} intact messages delivered",
            intact.len()
        );
        assert!(ok * 1000 >= intact.len() * 998, "{ok} of {}", intact.len());
    }
}

#[test]
fn a_false_start_hides_a_good_message_and_the_rescan_finds_it() {
    // FF 03 with length 30 (Spec): the claimed 30 bytes cover the heartbeat and run on.
    let mut stream = vec![0xFF, 0x03, 30, 0, 0, 0];
    let hb = [0xFF, 0x80, 0x07, 0, 0, 0, 0x78];
    stream.extend_from_slice(&hb);
    stream.extend(std::iter::repeat_n(0x55, 17));
    let (events, stats) = run_lib(&stream, Profile::Spec);
    // The false candidate's 30 bytes: its header, the heartbeat (XOR 0) and sixteen 0x55 (XOR
    // 0) before the seventeenth, read as its checksum.
    let mismatch = Error::ChecksumMismatch {
        id: 0x03,
        computed: 0xFF ^ 0x03 ^ 30,
        received: 0x55,
    };
    assert_eq!(events, vec![Err(mismatch), Ok(hb.to_vec())]);
    assert_eq!(stats.checksum_errors, 1);
    assert_eq!(stats.bytes_discarded as usize, stream.len() - hb.len());
    // The naive decoder loses it.
    let mut naive = NaiveDecoder::new(Profile::Spec, CAP);
    assert!(stream.iter().all(|&b| naive.push(b).is_none()));
}

#[test]
fn length_is_checked_as_soon_as_the_field_is_complete() {
    let mut dec = Decoder::<32>::new(Profile::Spec);
    // Below the Spec minimum for a normal message (23).
    for b in [0xFF, 0x03, 22, 0, 0] {
        assert_eq!(byte_events(&mut dec, b), []);
    }
    assert_eq!(byte_events(&mut dec, 0), [Err(Error::BadLength(22))]);
    // Beyond the capacity.
    let mut dec = Decoder::<32>::new(Profile::Reference);
    dec.feed(&[0xFF, 0x81, 26, 0, 0], |_| panic!("too early"));
    assert_eq!(byte_events(&mut dec, 0), [Err(Error::BadLength(26))]);
    assert_eq!(dec.stats().length_errors, 1);
    // 25 data bytes + 7 = 32 fits exactly.
    let mut dec = Decoder::<32>::new(Profile::Reference);
    dec.feed(&[0xFF, 0x81, 25, 0, 0, 0], |_| panic!("no event yet"));
    assert_eq!(dec.stats().length_errors, 0);
}
