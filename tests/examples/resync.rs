//! Prints the resynchronisation contract (see `protolink_tests::resync`) for every protocol
//! and profile, as Markdown: the share of cases losing 0, 1, 2... intact frames, the worst
//! case, and the cases that delivered a frame nobody sent.

use protolink_tests::protocols::{Aeolus, Aok, Aydp, Protocol};
use protolink_tests::resync::{CONTRACT_STREAM, run};

fn main() {
    let rows: [(&dyn Protocol, u8); 5] = [
        (&Aeolus { strict: false }, 0x7E),
        (&Aeolus { strict: true }, 0x7E),
        (
            &Aydp {
                profile: aydp_proto::Profile::Spec,
            },
            0xFF,
        ),
        (
            &Aydp {
                profile: aydp_proto::Profile::Reference,
            },
            0xFF,
        ),
        (&Aok, 0x73),
    ];
    println!(
        "| protocol | cases | intact frames lost: cases | worst | first worst case (fault, position, frame length) | phantom frames |"
    );
    println!("| --- | ---: | --- | ---: | --- | ---: |");
    for (p, start) in rows {
        let c = run(p, start, 20, CONTRACT_STREAM);
        let dist = c
            .lost
            .iter()
            .map(|(lost, n)| format!("{lost}: {n}"))
            .collect::<Vec<_>>()
            .join(", ");
        println!(
            "| {} | {} | {dist} | {} | {:?} | {} |",
            p.name(),
            c.cases,
            c.worst_lost(),
            c.worst
                .map(|(f, at, len)| format!("{f:?} at {at} of {len}"))
                .unwrap_or_default(),
            c.phantoms
        );
    }
}
