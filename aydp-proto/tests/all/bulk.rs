//! The slice path (`feed` of a whole chunk) against the byte-at-a-time path (`feed` of
//! one-byte slices): on any byte stream, split at any chunk boundaries, in both profiles and
//! at several capacities, both give the same events in the same order, the same counters
//! after every chunk, and the same end state (what `finish` reports); and so does the pull
//! form (`decode`, called again and again on what each call left, and `item`).

use crate::streamgen;

use aydp_proto::{Decode, Decoder, Error, Event as Pulled, Frame, Profile, Stats};
use proptest::prelude::*;
use streamgen::{Rng, garbage, random_message};

type Event = Result<Vec<u8>, Error>;

fn record(out: &mut Vec<Event>) -> impl FnMut(Result<Frame<'_>, Error>) + '_ {
    |e| out.push(e.map(|f| f.as_bytes().to_vec()))
}

/// The reference: every byte fed on its own.
fn bytewise<const N: usize>(dec: &mut Decoder<N>, bytes: &[u8], out: &mut Vec<Event>) {
    for b in bytes {
        dec.feed(core::slice::from_ref(b), record(out));
    }
}

/// The event of the pull form as the loop hands it out.
fn pulled<const N: usize>(
    dec: &Decoder<N>,
    input: &[u8],
    event: Pulled<(Option<usize>, usize), Error>,
) -> Event {
    match event {
        Pulled::Found(found) => Ok(dec.item(input, found).as_bytes().to_vec()),
        Pulled::Error(e) => Err(e),
        Pulled::Truncated(_) => Err(Error::Truncated),
    }
}

/// `decode` again and again on what each call left, until it finds nothing in what is left;
/// every call uses a byte or more, or hands out an event.
fn decode_all<const N: usize>(dec: &mut Decoder<N>, bytes: &[u8], out: &mut Vec<Event>) {
    let mut rest = bytes;
    loop {
        let (n, ev) = dec.decode(rest);
        assert!(n <= rest.len());
        let found = ev.is_some();
        if let Some(e) = ev {
            out.push(pulled(dec, rest, e));
        }
        assert!(found || n == rest.len(), "stopped without an event");
        assert!(
            found || n > 0 || rest.is_empty(),
            "neither consumed nor found"
        );
        rest = &rest[n..];
        if !found && rest.is_empty() {
            return;
        }
    }
}

/// `end` until `None`: the events of the end of the stream.
fn end_all<const N: usize>(dec: &mut Decoder<N>, out: &mut Vec<Event>) {
    while let Some(e) = dec.end() {
        out.push(pulled(dec, &[], e));
    }
}

/// Feed `stream` in chunks of the given sizes (cycled; 0 is an empty call) both ways and
/// compare after every chunk and after the end of the stream.
fn check_chunks<const N: usize>(profile: Profile, stream: &[u8], sizes: &[usize]) {
    let mut slow = Decoder::<N>::new(profile);
    let mut fast = Decoder::<N>::new(profile);
    let mut pull = Decoder::<N>::new(profile);
    let mut rest = stream;
    // The extra 1 makes every round of `sizes` consume a byte, so the loop ends.
    let mut sizes = sizes.iter().chain(&[1]).cycle();
    let mut at = 0;
    let mut all = Vec::new();
    loop {
        let n = (*sizes.next().unwrap()).min(rest.len());
        let (chunk, tail) = rest.split_at(n);
        let (mut want, mut got) = (Vec::new(), Vec::new());
        bytewise(&mut slow, chunk, &mut want);
        fast.feed(chunk, record(&mut got));
        let mut one_by_one = Vec::new();
        decode_all(&mut pull, chunk, &mut one_by_one);
        assert_eq!(
            one_by_one,
            want,
            "N={N} {profile:?}: decode, chunk ending at {}",
            at + n
        );
        assert_eq!(
            pull.stats(),
            slow.stats(),
            "N={N} {profile:?}: decode's stats"
        );
        assert_eq!(pull.held_bytes(), slow.held_bytes());
        at += n;
        assert_eq!(
            got, want,
            "N={N} {profile:?}: events of the chunk ending at {at}"
        );
        assert_eq!(
            fast.stats(),
            slow.stats(),
            "N={N} {profile:?}: stats at {at}"
        );
        assert_eq!(fast.held_bytes(), slow.held_bytes());
        all.extend(got);
        rest = tail;
        if rest.is_empty() {
            break;
        }
    }
    let (mut want, mut got, mut ended) = (Vec::new(), Vec::new(), Vec::new());
    slow.finish(record(&mut want));
    fast.finish(record(&mut got));
    end_all(&mut pull, &mut ended);
    assert_eq!(got, want, "N={N} {profile:?}: finish");
    assert_eq!(ended, want, "N={N} {profile:?}: end");
    assert_eq!(
        fast.stats(),
        slow.stats(),
        "N={N} {profile:?}: stats after finish"
    );
    assert_eq!(pull.stats(), slow.stats(), "N={N} {profile:?}: end's stats");
    assert_eq!((fast.held_bytes(), pull.held_bytes()), (0, 0));
    all.extend(got);
    conserved(stream, &fast.stats(), &all);
}

/// After `finish` every byte fed is either in a delivered frame or discarded (D3).
fn conserved(stream: &[u8], stats: &Stats, events: &[Event]) {
    let delivered: usize = events.iter().flatten().map(Vec::len).sum();
    assert_eq!(delivered + stats.bytes_discarded as usize, stream.len());
}

fn check_all(profile: Profile, stream: &[u8], sizes: &[usize]) {
    check_chunks::<128>(profile, stream, sizes);
    check_chunks::<40>(profile, stream, sizes);
    check_chunks::<23>(profile, stream, sizes);
    check_chunks::<7>(profile, stream, sizes);
    check_chunks::<6>(profile, stream, sizes);
    check_chunks::<3>(profile, stream, sizes);
}

/// How far a piece of a test stream reaches: `Long` in the bulk and reader streams, `Short` in
/// streams short enough to be cut at every split point (`place.rs`).
#[derive(Debug, Clone, Copy)]
pub(crate) enum Reach {
    Long,
    Short,
}

/// One piece of a test stream.
pub(crate) fn piece(profile: Profile, reach: Reach) -> impl Strategy<Value = Vec<u8>> {
    // The garbage's capacity (the longest false candidate), how often it writes a plausible
    // header, the longest run of 0xFF, the longest run of random bytes.
    let (capacity, headers, ff, random) = match reach {
        Reach::Long => (128, (1, 4), 12, 24),
        Reach::Short => (48, (1, 3), 6, 12),
    };
    prop_oneof![
        // A valid message (both header forms, as the generator picks).
        3 => any::<u64>().prop_map(move |seed| random_message(&mut Rng(seed), profile)),
        // A message with one byte changed (checksum failure, or a changed length).
        1 => (any::<u64>(), any::<prop::sample::Index>(), any::<u8>()).prop_map(
            move |(seed, i, v)| {
                let mut m = random_message(&mut Rng(seed), profile);
                let i = i.index(m.len());
                m[i] = v;
                m
            }
        ),
        // A message cut short.
        1 => (any::<u64>(), any::<prop::sample::Index>()).prop_map(move |(seed, i)| {
            let m = random_message(&mut Rng(seed), profile);
            m[..i.index(m.len())].to_vec()
        }),
        // Garbage rich in 0xFF and plausible headers.
        2 => any::<u64>().prop_map(move |seed| {
            let mut out = Vec::new();
            garbage(&mut Rng(seed), profile, capacity, headers, &mut out);
            out
        }),
        // A run of 0xFF.
        1 => (1usize..ff).prop_map(|n| vec![0xFF; n]),
        // Plain random bytes.
        1 => prop::collection::vec(any::<u8>(), 0..random),
    ]
}

/// Either profile.
pub(crate) fn profile() -> impl Strategy<Value = Profile> {
    prop_oneof![Just(Profile::Spec), Just(Profile::Reference)]
}

fn framed_stream() -> impl Strategy<Value = (Profile, Vec<u8>)> {
    profile().prop_flat_map(|p| {
        prop::collection::vec(piece(p, Reach::Long), 0..24)
            .prop_map(move |pieces| (p, pieces.concat()))
    })
}

/// Bytes that make false starts likely: 0xFF, type bytes, small length fields.
fn biased_stream() -> impl Strategy<Value = Vec<u8>> {
    biased_stream_of(400)
}

/// [`biased_stream`]'s streams of fewer than `len` bytes.
pub(crate) fn biased_stream_of(len: usize) -> impl Strategy<Value = Vec<u8>> {
    prop::collection::vec(
        prop_oneof![
            3 => Just(0xFFu8),
            1 => Just(0x80u8),
            3 => Just(0u8),
            2 => 0u8..48,
            2 => any::<u8>(),
        ],
        0..len,
    )
}

fn chunk_sizes() -> impl Strategy<Value = Vec<usize>> {
    prop::collection::vec(
        prop_oneof![3 => 0usize..8, 2 => 0usize..64, 1 => 0usize..600],
        1..16,
    )
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 512, ..ProptestConfig::default() })]

    #[test]
    fn random_bytes_bulk_equals_bytewise(
        p in profile(),
        stream in prop::collection::vec(any::<u8>(), 0..600),
        sizes in chunk_sizes(),
    ) {
        check_all(p, &stream, &sizes);
    }

    #[test]
    fn biased_bytes_bulk_equals_bytewise(
        p in profile(),
        stream in biased_stream(),
        sizes in chunk_sizes(),
    ) {
        check_all(p, &stream, &sizes);
    }

    #[test]
    fn frames_garbage_and_ff_runs_bulk_equals_bytewise(
        (p, stream) in framed_stream(),
        sizes in chunk_sizes(),
    ) {
        check_all(p, &stream, &sizes);
    }

    /// `feed` after pull-form calls that left events queued (a rescan found several, and the
    /// caller took one a call), or that lent a frame out, continues exactly as the pull form
    /// would, and `finish` as one-byte feeds would: no event is lost or reordered.
    #[test]
    fn feed_after_pull_form_calls_equals_bytewise(
        (p, stream) in framed_stream(),
        ops in prop::collection::vec((0usize..3, 0usize..80), 0..40),
    ) {
        let mut slow = Decoder::<64>::new(p);
        let mut fast = Decoder::<64>::new(p);
        let (mut want, mut got) = (Vec::new(), Vec::new());
        let mut rest = &stream[..];
        // Every round of `ops` uses at least one byte, so this ends.
        let ops = ops.into_iter().chain([(2, 1)]).collect::<Vec<_>>();
        for (op, n) in ops.into_iter().cycle() {
            if rest.is_empty() {
                break;
            }
            if op == 1 {
                // One pull-form call each on no input: an event left queued, if any.
                for (dec, out) in [(&mut slow, &mut want), (&mut fast, &mut got)] {
                    let (used, e) = dec.decode(&[]);
                    prop_assert_eq!(used, 0);
                    out.extend(e.map(|e| pulled(dec, &[], e)));
                }
                continue;
            }
            let n = n.min(rest.len());
            let (chunk, tail) = rest.split_at(n);
            rest = tail;
            if op == 0 {
                // One event a call, byte by byte: a byte is given again while the call takes
                // an event a rescan left queued (none of it used), and the events behind the
                // last one stay queued.
                for (dec, out) in [(&mut slow, &mut want), (&mut fast, &mut got)] {
                    for b in chunk {
                        loop {
                            let (used, e) = dec.decode(core::slice::from_ref(b));
                            out.extend(e.map(|e| pulled(dec, core::slice::from_ref(b), e)));
                            if used == 1 {
                                break;
                            }
                        }
                    }
                }
            } else {
                // `feed` against the loop the contract builds on the pull form: on an empty
                // chunk too, both hand out what a rescan left queued.
                decode_all(&mut slow, chunk, &mut want);
                fast.feed(chunk, record(&mut got));
            }
            prop_assert_eq!(&got, &want);
            prop_assert_eq!(fast.stats(), slow.stats());
        }
        slow.finish(record(&mut want));
        fast.finish(record(&mut got));
        prop_assert_eq!(&got, &want);
        prop_assert_eq!(fast.stats(), slow.stats());
    }
}

/// A long stream of valid messages behind garbage, fed in 4 KiB blocks (what a DMA ring
/// hands over), is decoded exactly as byte by byte.
#[test]
fn long_stream_in_dma_blocks() {
    for profile in [Profile::Spec, Profile::Reference] {
        let mut rng = Rng(0xB0B);
        let mut stream = Vec::new();
        for _ in 0..3000 {
            garbage(&mut rng, profile, 128, (1, 64), &mut stream);
            stream.extend(random_message(&mut rng, profile));
        }
        check_chunks::<128>(profile, &stream, &[4096]);
        check_chunks::<128>(profile, &stream, &[4093, 1, 0, 17]);
    }
}
