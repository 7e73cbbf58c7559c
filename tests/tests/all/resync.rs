//! The resynchronisation contract, pinned (figures and reasons in docs/RELIABILITY.md; `cargo
//! run --release -p protolink-tests --example resync` prints them). After any single-byte
//! fault in one frame of a stream:
//! - AEOLUS loses no other frame. A fault can make a frame's CRC read `00 00`, which the spec
//!   accepts as "no CRC" (A3); strict mode refuses those. What strict mode still delivers is
//!   one phantom per stream: a 0x00 inserted right after the opening flag, which the CRC
//!   cannot see (it starts at 0, and a leading zero byte leaves it 0), so the frame arrives
//!   as ID 0 with the real ID as its first data byte.
//! - AYDP loses at most one other frame, in either profile: a false candidate that a fault
//!   creates passes the 8-bit XOR checksum one time in 256 and takes the next frame's bytes.
//! - AOK loses at most two: its frames have no start byte and no length field.

use protolink_tests::protocols::{Aeolus, Aok, Aydp, Protocol};
use protolink_tests::resync::{CONTRACT_STREAM, Contract, Fault, NeverResync, run};

const SEEDS: u64 = 20;

/// Each bound below must hold with room to fail: more intact frames follow the corrupted one
/// than any bound allows to be lost.
const _: () = assert!(CONTRACT_STREAM.after >= 8);

fn contract(p: &dyn Protocol, start: u8) -> Contract {
    run(p, start, SEEDS, CONTRACT_STREAM)
}

#[test]
fn faults_are_what_they_say() {
    let f = [0x7E, 0x52, 0x41, 0x7E];
    assert_eq!(Fault::Flip(0).apply(&f, 2), [0x7E, 0x52, 0x40, 0x7E]);
    assert_eq!(Fault::Drop.apply(&f, 1), [0x7E, 0x41, 0x7E]);
    assert_eq!(
        Fault::Insert(0xA5).apply(&f, 1),
        [0x7E, 0xA5, 0x52, 0x41, 0x7E]
    );
    assert_eq!(Fault::Replace(0x7E).apply(&f, 2), [0x7E, 0x52, 0x7E, 0x7E]);
    assert_eq!(Fault::all(0x7E).len(), 13);
}

#[test]
fn aeolus_loses_no_intact_frame_and_strict_mode_no_phantom() {
    let c = contract(&Aeolus { strict: false }, 0x7E);
    assert!(c.cases > 5_000, "{} cases", c.cases);
    assert_eq!(c.worst_lost(), 0, "{c:?}");
    let strict = contract(&Aeolus { strict: true }, 0x7E);
    assert_eq!(strict.worst_lost(), 0, "{strict:?}");
    assert_eq!(strict.phantoms, SEEDS as usize, "{strict:?}");
    assert!(
        matches!(strict.first_phantom, Some((Fault::Insert(0), 1, _))),
        "{strict:?}"
    );
}

#[test]
fn aydp_loses_at_most_one_intact_frame_in_either_profile() {
    for profile in [aydp_proto::Profile::Spec, aydp_proto::Profile::Reference] {
        let c = contract(&Aydp { profile }, 0xFF);
        assert!(c.cases > 5_000, "{profile:?}: {} cases", c.cases);
        assert!(c.worst_lost() <= 1, "{profile:?}: {c:?}");
        // Losing a frame needs a phantom: a false candidate that passed the checksum.
        let losing: usize = c.lost.range(1..).map(|(_, n)| n).sum();
        assert!(losing <= c.phantoms, "{profile:?}: {c:?}");
    }
}

#[test]
fn aok_loses_at_most_two_intact_frames() {
    let c = contract(&Aok, 0x73);
    assert!(c.cases > 1_000, "{} cases", c.cases);
    assert!(c.worst_lost() <= 2, "{c:?}");
}

/// The bounds above can fail: a decoder that stops at its first error and never
/// resynchronises loses every frame after the corrupted one, far past each bound.
#[test]
fn a_decoder_that_never_resynchronises_breaks_every_bound() {
    let aydp_spec = Aydp {
        profile: aydp_proto::Profile::Spec,
    };
    let aydp_reference = Aydp {
        profile: aydp_proto::Profile::Reference,
    };
    let cases: [(&dyn Protocol, u8, usize); 5] = [
        (&Aeolus { strict: false }, 0x7E, 0),
        (&Aeolus { strict: true }, 0x7E, 0),
        (&aydp_spec, 0xFF, 1),
        (&aydp_reference, 0xFF, 1),
        (&Aok, 0x73, 2),
    ];
    for (p, start, bound) in cases {
        let c = contract(&NeverResync(p), start);
        assert_eq!(c.worst_lost(), CONTRACT_STREAM.after, "{}: {c:?}", p.name());
        assert!(c.worst_lost() > bound, "{}: {c:?}", p.name());
    }
}
