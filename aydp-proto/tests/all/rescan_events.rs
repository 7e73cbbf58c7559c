//! A rescan can find several events among the bytes held, so one byte can give several: none
//! is lost, whichever way the caller takes them. The pull form hands out one event a call,
//! those a rescan left queued first with no byte used; a caller that takes one event a call,
//! byte by byte, gets the events of `feed` (which hands them all out) in the same order, with
//! the same counters.

use crate::streamgen;

use aydp_proto::{Decode, Decoder, Error, Event as Pulled, Frame, Profile, Stats};
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

/// The one loop, a byte at a time: every event of each byte handed out.
fn fed<const N: usize>(profile: Profile, stream: &[u8]) -> (Vec<Event>, Stats) {
    let mut d = Decoder::<N>::new(profile);
    let mut out = Vec::new();
    for b in stream {
        d.feed(core::slice::from_ref(b), |e| out.push(copy(e)));
    }
    d.finish(|e| out.push(copy(e)));
    (out, d.stats())
}

/// The pull form, one event a call, a byte at a time: the byte is given again while a call
/// takes an event a rescan left queued (none of it used); what is still queued after the last
/// byte comes from `decode` on nothing, then `end`. Also returns how many calls gave a queued
/// event (used no byte).
fn pulled<const N: usize>(profile: Profile, stream: &[u8]) -> (Vec<Event>, Stats, usize) {
    let mut d = Decoder::<N>::new(profile);
    let mut out = Vec::new();
    let mut queued = 0;
    let take = |d: &Decoder<N>, input: &[u8], e: Pulled<_, Error>| match e {
        Pulled::Found(found) => copy(Ok(d.item(input, found))),
        Pulled::Error(e) => Err(e),
        Pulled::Truncated(_) => Err(Error::Truncated),
    };
    for b in stream {
        let input = core::slice::from_ref(b);
        loop {
            match d.decode(input) {
                (1, e) => {
                    out.extend(e.map(|e| take(&d, input, e)));
                    break;
                }
                (_, Some(e)) => {
                    queued += 1;
                    out.push(take(&d, input, e));
                }
                (_, None) => panic!("a call that used nothing found nothing"),
            }
        }
    }
    while let (0, Some(e)) = d.decode(&[]) {
        queued += 1;
        out.push(take(&d, &[], e));
    }
    while let Some(e) = d.end() {
        out.push(take(&d, &[], e));
    }
    (out, d.stats(), queued)
}

fn check<const N: usize>(profile: Profile) {
    let mut with_queued_events = 0;
    for seed in 1..=60 {
        let stream = hostile_stream(seed, profile, N);
        let want = fed::<N>(profile, &stream);
        let (events, stats, queued) = pulled::<N>(profile, &stream);
        assert_eq!((events, stats), want, "N={N} {profile:?} seed {seed}");
        // The streams do make a rescan find several events for one byte.
        with_queued_events += usize::from(queued > 0);
    }
    assert!(
        with_queued_events > 30,
        "{with_queued_events} streams where one byte gave several events"
    );
}

#[test]
fn one_event_a_call_gives_every_event_of_feed_in_order() {
    for profile in [Profile::Spec, Profile::Reference] {
        check::<64>(profile);
        check::<256>(profile);
    }
}
