//! What a decoder tells of itself: its profile and capacity, the bytes waiting for a rescan,
//! counters that `reset_stats` zeroes without touching the frame in progress, and `reset`,
//! which forgets that frame and keeps the counters.

use aydp_proto::{Decoder, Error, Profile, Stats};

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
    for &b in &[0xFF, 0x80, 0x07, 0, 0, 0] {
        assert!(d.push(b).is_none());
    }
    assert_eq!(
        d.push(0xFF).map(|e| e.map(|f| f.data().to_vec())),
        Some(Err(Error::ChecksumMismatch {
            id: 0x80,
            computed: 0x78,
            received: 0xFF
        }))
    );
    assert_eq!(d.held_bytes(), 6);
    // The rescan drops the five bytes before the last 0xFF, which waits for its type byte.
    while d.poll().is_some() {}
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
