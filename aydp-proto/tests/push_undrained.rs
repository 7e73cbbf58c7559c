//! `push` without draining `poll`: a byte pushed while a rescan still holds queued bytes goes
//! behind them, so the decoder reports the same events in the same order as one whose caller
//! drains every event, only later (each `push` returns the next one). And the smallest
//! decoder, `Decoder<0>`, which can hold no byte.

#[path = "support/streamgen.rs"]
mod streamgen;

use aydp_proto::{Decoder, Error, Frame, Profile};
use streamgen::{Rng, garbage, random_message};

type Event = Result<Vec<u8>, Error>;

fn copy(e: Result<Frame<'_>, Error>) -> Event {
    e.map(|f| f.as_bytes().to_vec())
}

/// Messages behind garbage rich in false starts, one in four with a byte changed.
fn hostile_stream(seed: u64, profile: Profile, capacity: usize) -> Vec<u8> {
    let mut rng = Rng(seed);
    let mut out = Vec::new();
    for _ in 0..40 {
        garbage(&mut rng, profile, capacity, (1, 3), &mut out);
        let mut m = random_message(&mut rng, profile);
        if rng.chance(1, 4) {
            let i = rng.below(m.len() as u64) as usize;
            m[i] ^= 1 << rng.below(8);
        }
        out.extend(m);
    }
    out
}

fn drained<const N: usize>(profile: Profile, stream: &[u8]) -> (Vec<Event>, aydp_proto::Stats) {
    let mut d = Decoder::<N>::new(profile);
    let mut out = Vec::new();
    for &b in stream {
        let mut ev = d.push(b);
        while let Some(e) = ev {
            out.push(copy(e));
            ev = d.poll();
        }
    }
    d.flush(|e| out.push(copy(e)));
    (out, d.stats())
}

/// Only the first event of each `push` is taken; `poll` is called only after the last byte.
fn undrained<const N: usize>(profile: Profile, stream: &[u8]) -> (Vec<Event>, aydp_proto::Stats) {
    let mut d = Decoder::<N>::new(profile);
    let mut out = Vec::new();
    for &b in stream {
        if let Some(e) = d.push(b) {
            out.push(copy(e));
        }
    }
    while let Some(e) = d.poll() {
        out.push(copy(e));
    }
    d.flush(|e| out.push(copy(e)));
    (out, d.stats())
}

fn check<const N: usize>(profile: Profile) {
    let mut queued_pushes = 0;
    for seed in 1..=60 {
        let stream = hostile_stream(seed, profile, N);
        let want = drained::<N>(profile, &stream);
        let got = undrained::<N>(profile, &stream);
        assert_eq!(got, want, "N={N} {profile:?} seed {seed}");
        // The streams do make `push` meet queued bytes (events that came later than drained).
        queued_pushes += usize::from(want.0.iter().filter(|e| e.is_err()).count() > 0);
    }
    assert!(
        queued_pushes > 30,
        "{queued_pushes} streams with a failed candidate"
    );
}

#[test]
fn undrained_pushes_give_the_drained_events_in_order() {
    for profile in [Profile::Spec, Profile::Reference] {
        check::<64>(profile);
        check::<256>(profile);
    }
}

/// A decoder of capacity 0 holds nothing: every byte is discarded, the start bytes too, and
/// it never reports an event.
#[test]
fn a_decoder_of_capacity_zero_discards_every_byte() {
    for profile in [Profile::Spec, Profile::Reference] {
        let mut d = Decoder::<0>::new(profile);
        let stream = [0xFF, 0xFF, 0x80, 0x07, 0, 0, 0, 0x78, 0x00, 0xFF];
        for &b in &stream {
            assert!(d.push(b).is_none(), "{profile:?}: byte {b:#04x}");
            assert!(d.poll().is_none());
        }
        let mut events = 0;
        d.flush(|_| events += 1);
        assert_eq!(events, 0);
        let s = d.stats();
        assert_eq!(s.bytes_discarded, stream.len() as u32, "{profile:?}: {s:?}");
        assert_eq!((s.frames_ok, s.checksum_errors, s.length_errors), (0, 0, 0));
    }
}
