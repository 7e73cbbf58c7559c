//! The corruption assertions of the proof issue, on 100,000 frames each.

use protolink_tests::{channel::Channel, protocols::*};

const N: usize = 100_000;

#[test]
fn aeolus_delivers_every_intact_frame_through_garbage() {
    for strict in [false, true] {
        let (real, naive) = run(&Aeolus { strict }, Channel::Garbage { max: 64 }, N, 1);
        println!("strict {strict}: real {real:?}\n naive {naive:?}");
        assert_eq!(real.intact_sent, N);
        assert_eq!(real.intact_delivered, N, "strict {strict}");
        assert!(
            naive.intact_delivered < N,
            "the naive decoder loses frames: {naive:?}"
        );
    }
}

#[test]
fn aeolus_delivers_every_intact_frame_through_byte_drops() {
    let (real, _) = run(
        &Aeolus { strict: true },
        Channel::Drops { rate: 1e-3 },
        N,
        2,
    );
    println!("{real:?}");
    assert!(real.intact_sent < N, "the channel dropped something");
    assert_eq!(real.intact_delivered, real.intact_sent);
    assert_eq!(real.wrongly_accepted, 0);
}

#[test]
fn aeolus_strict_accepts_no_corrupted_frame_at_ber_1e_4() {
    let (real, _) = run(
        &Aeolus { strict: true },
        Channel::BitFlips { ber: 1e-4 },
        N,
        3,
    );
    println!("{real:?}");
    assert!(
        real.intact_sent < N - 1000,
        "the channel corrupted frames: {real:?}"
    );
    assert_eq!(real.wrongly_accepted, 0);
    assert_eq!(real.intact_delivered, real.intact_sent);
}

#[test]
fn aydp_delivers_at_least_99_9_percent_through_garbage() {
    for profile in [aydp_proto::Profile::Spec, aydp_proto::Profile::Reference] {
        let (real, naive) = run(&Aydp { profile }, Channel::Garbage { max: 64 }, N, 4);
        println!("{profile:?}: real {real:?}\n naive {naive:?}");
        assert!(real.delivered_percent() >= 99.9, "{profile:?}: {real:?}");
        assert!(naive.delivered_percent() < real.delivered_percent());
    }
}
