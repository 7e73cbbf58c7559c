//! What a decoder tells of itself between frames: the wire bytes of the frame in progress
//! (escapes included), strict or not, and counters that `reset_stats` zeroes without touching
//! the frame in progress, while `reset` drops that frame as discarded bytes.

use aeolus_proto::{Decode, Decoder, Error, Event, Stats};

const HI: [u8; 8] = [0x7E, 0x52, b'h', b'i', 0x00, 0x73, 0xEC, 0x7E];

#[test]
fn held_bytes_counts_the_wire_bytes_since_the_flag() {
    let mut d = Decoder::<16>::new();
    let mut pending = Vec::new();
    for b in [0x01, 0x7E, 0x52, 0x7D, 0x5E, b'h', 0x7D] {
        d.feed(&[b], |ev| panic!("no event expected, got {:?}", ev.err()));
        pending.push(d.held_bytes());
    }
    // Noise before the flag is not pending; an escape pair is two wire bytes.
    assert_eq!(pending, [0, 0, 1, 2, 3, 4, 5]);
}

#[test]
fn strict_is_only_what_it_was_built_as() {
    assert!(Decoder::<8>::strict().is_strict());
    assert!(!Decoder::<8>::new().is_strict());
}

#[test]
fn reset_stats_zeroes_the_counters_and_keeps_the_frame_in_progress() {
    let mut d = Decoder::<16>::new();
    d.feed(&[0x00, 0x00], |_| {});
    d.feed(&HI, |_| {});
    d.feed(&HI[1..4], |_| {});
    assert_eq!(d.stats().frames_ok, 1);
    assert_eq!(d.stats().bytes_discarded, 2);
    d.reset_stats();
    assert_eq!(d.stats(), Stats::default());
    assert_eq!(d.held_bytes(), 3);
    let mut ids = Vec::new();
    d.feed(&HI[4..], |ev| ids.push(ev.map(|f| f.id())));
    assert_eq!(ids, [Ok(0x52)]);
    assert_eq!(
        (d.stats().frames_ok, d.stats().frame_bytes, d.stats().flags),
        (1, 6, 1)
    );
}

#[test]
fn reset_drops_the_frame_in_progress_as_discarded_bytes() {
    let mut d = Decoder::<16>::new();
    d.feed(&[0x7E, 0x52, 0x7D, 0x5E, b'h'], |_| {});
    d.reset();
    assert_eq!(d.held_bytes(), 0);
    assert_eq!(d.stats().bytes_discarded, 4);
    // It hunts for a flag: the rest of the frame is noise, the next frame arrives whole.
    let mut ids = Vec::new();
    d.feed(&[b'i', 0x00], |ev| ids.push(ev.map(|f| f.id())));
    d.feed(&HI, |ev| ids.push(ev.map(|f| f.id())));
    assert_eq!(ids, [Ok(0x52)]);
    assert_eq!(d.stats().bytes_discarded, 6);
}

#[test]
fn finish_gives_up_a_frame_in_progress_and_nothing_else() {
    let mut d = Decoder::<16>::new();
    let mut events = Vec::new();
    d.finish(|ev| events.push(ev.map(|f| f.id())));
    d.feed(&HI, |ev| events.push(ev.map(|f| f.id())));
    // Between frames (the closing flag may open the next one): nothing to give up.
    d.finish(|ev| events.push(ev.map(|f| f.id())));
    assert_eq!(events, [Ok(0x52)]);
    d.feed(&[0x52, 0x7D, 0x5E], |_| {});
    d.finish(|ev| events.push(ev.map(|f| f.id())));
    assert_eq!(events, [Ok(0x52), Err(Error::Truncated)]);
    assert_eq!((d.held_bytes(), d.stats().bytes_discarded), (0, 3));
    // Only once.
    d.finish(|ev| events.push(ev.map(|f| f.id())));
    assert_eq!(events.len(), 2);
}

/// The IDs (or errors) of feeding `bytes` one at a time.
fn push_all(d: &mut Decoder<8>, bytes: &[u8]) -> Vec<Result<u8, Error>> {
    let mut ids = Vec::new();
    for &b in bytes {
        d.feed(&[b], |ev| {
            ids.push(ev.map(|f| f.id()));
        });
    }
    ids
}

/// A new decoder is all zeros (a `static` one lives in `.bss`): its first hunt lets the fast
/// path store the garbage, and the counters must still see every byte of it, at every byte,
/// whichever call comes next.
#[test]
fn a_new_decoder_counts_every_garbage_byte_at_once_whatever_comes_next() {
    // Past the buffer's 8 bytes, so the stored garbage fills it and goes on.
    let garbage: Vec<u8> = (1..=13).collect();
    let mut d = Decoder::<8>::new();
    for (i, &b) in garbage.iter().enumerate() {
        d.feed(&[b], |ev| panic!("no event expected, got {:?}", ev.err()));
        assert_eq!(
            (d.stats().bytes_discarded, d.held_bytes()),
            (i as u32 + 1, 0)
        );
    }
    let mut ids = Vec::new();
    d.feed(&HI, |ev| ids.push(ev.map(|f| f.id())));
    assert_eq!(ids, [Ok(0x52)]);
    assert_eq!((d.stats().bytes_discarded, d.stats().frames_ok), (13, 1));

    // Garbage pushed, then each of the other calls: the same counts as pushing it all.
    type Next = fn(&mut Decoder<8>) -> Vec<Result<u8, Error>>;
    let nexts: [(&str, Next); 5] = [
        ("one byte a call", |d| push_all(d, &HI)),
        ("feed", |d| {
            let mut ids = Vec::new();
            d.feed(&HI, |ev| ids.push(ev.map(|f| f.id())));
            ids
        }),
        ("decode", |d| {
            let (n, ev) = d.decode(&HI);
            assert_eq!(n, HI.len());
            match ev {
                Some(Event::Found(at)) => vec![Ok(d.item(&HI, at).id())],
                other => panic!("expected a frame, got {other:?}"),
            }
        }),
        ("finish, then one byte a call", |d| {
            d.finish(|_| panic!("nothing to give up in a hunt"));
            push_all(d, &HI)
        }),
        ("a clone", |d| {
            let mut c = d.clone();
            let ids = push_all(&mut c, &HI);
            *d = c;
            ids
        }),
    ];
    for (what, next) in nexts {
        let mut d = Decoder::<8>::new();
        for &b in &garbage[..5] {
            d.feed(&[b], |_| {});
        }
        assert_eq!(next(&mut d), [Ok(0x52)], "{what}");
        assert_eq!(
            (d.stats().bytes_discarded, d.stats().frames_ok),
            (5, 1),
            "{what}"
        );
    }
}

#[test]
fn reset_stats_and_reset_on_a_new_decoder_forget_and_keep_its_garbage() {
    // `reset_stats` forgets the garbage stored so far: none of it counts at the flag.
    let mut d = Decoder::<8>::new();
    push_all(&mut d, &[1, 2, 3, 4, 5]);
    d.reset_stats();
    assert_eq!(d.stats(), Stats::default());
    assert_eq!(push_all(&mut d, &HI), [Ok(0x52)]);
    assert_eq!(d.stats().bytes_discarded, 0);
    // `reset` keeps it counted, once.
    let mut d = Decoder::<8>::new();
    push_all(&mut d, &[6, 7]);
    d.reset();
    assert_eq!((d.stats().bytes_discarded, d.held_bytes()), (2, 0));
    assert_eq!(push_all(&mut d, &HI), [Ok(0x52)]);
    assert_eq!(d.stats().bytes_discarded, 2);
}
