//! The AYDP slice path (`feed` on chunks, and the pull form `next_event` called on the rest
//! until it finds nothing) against `feed` one byte a call: on any byte stream, in chunks the
//! input chooses, all give the same events and the same counters after every chunk, and the
//! same `finish`.
#![no_main]
use aeolus_proto::Decode as _;
use aydp_proto::{Decoder, Error, Frame, Profile};
use libfuzzer_sys::fuzz_target;

type Event = Result<Vec<u8>, Error>;

fn record(out: &mut Vec<Event>) -> impl FnMut(Result<Frame<'_>, Error>) + '_ {
    |e| out.push(e.map(|f| f.as_bytes().to_vec()))
}

fn run<const N: usize>(profile: Profile, cuts: &[u8], data: &[u8]) {
    let mut slow = Decoder::<N>::new(profile);
    let mut fast = Decoder::<N>::new(profile);
    let mut until = Decoder::<N>::new(profile);
    let (mut want, mut got) = (Vec::new(), Vec::new());
    let mut rest = data;
    let mut i = 0;
    while !rest.is_empty() {
        // 0..=95 bytes a chunk (an empty feed now and then); every fourth chunk has one or more.
        let cut = cuts.get(i % cuts.len().max(1)).copied().unwrap_or(0x3F) as usize % 96;
        let n = if i % 4 == 3 { cut.max(1) } else { cut }.min(rest.len());
        i += 1;
        let (chunk, tail) = rest.split_at(n);
        rest = tail;
        want.clear();
        got.clear();
        for &b in chunk {
            slow.feed(&[b], |e| {
                want.push(e.map(|f| f.as_bytes().to_vec()));
            });
        }
        fast.feed(chunk, record(&mut got));
        assert_eq!(got, want);
        assert_eq!(fast.stats(), slow.stats());
        assert_eq!(fast.held_bytes(), slow.held_bytes());
        // next_event on what each call left, until it finds nothing in what is left.
        got.clear();
        let mut part = chunk;
        loop {
            let (n, ev) = until.next_event(part);
            assert!(n <= part.len());
            let found = ev.is_some();
            assert!(found || n == part.len());
            got.extend(ev.map(|e| e.map(|f| f.as_bytes().to_vec())));
            part = &part[n..];
            if !found && part.is_empty() {
                break;
            }
        }
        assert_eq!(got, want);
        assert_eq!(until.stats(), slow.stats());
        assert_eq!(until.held_bytes(), slow.held_bytes());
    }
    want.clear();
    got.clear();
    slow.finish(record(&mut want));
    fast.finish(record(&mut got));
    assert_eq!(got, want);
    assert_eq!(fast.stats(), slow.stats());
}

fuzz_target!(|input: &[u8]| {
    // First byte: profile, capacity and how many chunk sizes follow; then the sizes; then data.
    let Some((&cfg, rest)) = input.split_first() else {
        return;
    };
    let (cuts, data) = rest.split_at((cfg as usize & 7).min(rest.len()));
    let profile = if cfg & 0x80 == 0 {
        Profile::Spec
    } else {
        Profile::Reference
    };
    match (cfg >> 4) & 3 {
        0 => run::<128>(profile, cuts, data),
        1 => run::<40>(profile, cuts, data),
        2 => run::<7>(profile, cuts, data),
        _ => run::<3>(profile, cuts, data),
    }
});
