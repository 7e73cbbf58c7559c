//! What a decoder tells of itself: its profile and capacity, the bytes waiting for a rescan,
//! counters that `reset_stats` zeroes without touching the frame in progress, `reset`, which
//! forgets that frame and keeps the counters, and the counters of `Decoder<0>`, which can hold
//! no byte.

use aydp_proto::{Decode, Decoder, Error, Event, Profile, Stats};

/// A frame of type 0x09 (flag 0x80) with one data byte, 0x02.
const FRAME: [u8; 8] = [0xFF, 0x89, 0x08, 0, 0, 0, 0x02, 0x7C];

fn datas<const N: usize>(d: &mut Decoder<N>, bytes: &[u8]) -> Vec<Result<Vec<u8>, Error>> {
    let mut out = Vec::new();
    d.feed(bytes, |ev| out.push(ev.map(|f| f.data().to_vec())));
    out
}

#[test]
fn profile_and_capacity_are_what_it_was_built_with() {
    let d = Decoder::<48>::new(Profile::Reference);
    assert_eq!((d.profile(), d.capacity()), (Profile::Reference, 48));
    let d = Decoder::<16>::new(Profile::Spec);
    assert_eq!((d.profile(), d.capacity()), (Profile::Spec, 16));
    assert_eq!(Decoder::<8>::default().profile(), Profile::default());
}

#[test]
fn bytes_behind_a_failed_candidate_wait_for_the_rescan() {
    let mut d = Decoder::<64>::new(Profile::Spec);
    assert_eq!(d.held_bytes(), 0);
    // A false start whose length (7) takes in the real frame's first bytes.
    assert_eq!(d.decode(&[0xFF, 0x80, 0x07, 0, 0, 0]), (6, None));
    assert_eq!(
        d.decode(&[0xFF]),
        (
            1,
            Some(Event::Error(Error::ChecksumMismatch {
                id: 0x80,
                computed: 0x78,
                received: 0xFF
            }))
        )
    );
    assert_eq!(d.held_bytes(), 6);
    // The rescan drops the five bytes before the last 0xFF, which waits for its type byte.
    while d.decode(&[]) != (0, None) {}
    assert_eq!(d.held_bytes(), 1);
    assert_eq!(d.stats().bytes_discarded, 6);
}

#[test]
fn reset_stats_zeroes_the_counters_and_keeps_the_frame_in_progress() {
    let mut d = Decoder::<32>::new(Profile::Spec);
    assert_eq!(datas(&mut d, &[0x00, 0x01]), []);
    assert_eq!(datas(&mut d, &FRAME), [Ok(vec![0x02])]);
    assert_eq!(
        d.stats(),
        Stats {
            frames_ok: 1,
            bytes_discarded: 2,
            ..Stats::default()
        }
    );
    assert_eq!(datas(&mut d, &FRAME[..4]), []);
    d.reset_stats();
    assert_eq!(d.stats(), Stats::default());
    assert_eq!(datas(&mut d, &FRAME[4..]), [Ok(vec![0x02])]);
    assert_eq!(
        d.stats(),
        Stats {
            frames_ok: 1,
            ..Stats::default()
        }
    );
}

#[test]
fn reset_forgets_the_frame_in_progress_and_keeps_the_counters() {
    let mut d = Decoder::<32>::new(Profile::Spec);
    assert_eq!(datas(&mut d, &FRAME), [Ok(vec![0x02])]);
    assert_eq!(datas(&mut d, &FRAME[..4]), []);
    d.reset();
    assert_eq!(d.stats().frames_ok, 1);
    // The rest of the frame is noise now; the next frame arrives whole.
    assert_eq!(datas(&mut d, &FRAME[4..]), []);
    assert_eq!(datas(&mut d, &FRAME), [Ok(vec![0x02])]);
    assert_eq!(
        d.stats(),
        Stats {
            frames_ok: 2,
            bytes_discarded: 4,
            ..Stats::default()
        }
    );
}

/// A decoder of capacity 0 holds nothing: every byte is discarded, the start bytes too, and
/// it never reports an event, byte by byte or a slice at a time.
#[test]
fn a_decoder_of_capacity_zero_discards_every_byte() {
    let stream = [0xFF, 0xFF, 0x80, 0x07, 0, 0, 0, 0x78, 0x00, 0xFF];
    for profile in [Profile::Spec, Profile::Reference] {
        let mut by_byte = Decoder::<0>::new(profile);
        let mut whole = Decoder::<0>::new(profile);
        let mut events = 0;
        for b in &stream {
            by_byte.feed(core::slice::from_ref(b), |_| events += 1);
        }
        whole.feed(&stream, |_| events += 1);
        assert_eq!(events, 0, "{profile:?}");
        for d in [&mut by_byte, &mut whole] {
            d.finish(|_| events += 1);
            assert_eq!(events, 0);
            let s = d.stats();
            assert_eq!(s.bytes_discarded, stream.len() as u32, "{profile:?}: {s:?}");
            assert_eq!((s.frames_ok, s.checksum_errors, s.length_errors), (0, 0, 0));
        }
    }
}
