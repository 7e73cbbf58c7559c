//! Prints the corruption figures: 100,000 random valid frames per protocol through each noisy
//! channel, the crate's decoder beside a naive one on the same bytes.
//!
//! `cargo run --release -p protolink-tests --example corruption [FRAMES]`

use protolink_tests::protocols::*;

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(100_000);
    let protocols: Vec<Box<dyn Protocol>> = vec![
        Box::new(Aeolus { strict: false }),
        Box::new(Aeolus { strict: true }),
        Box::new(Aydp {
            profile: aydp_proto::Profile::Spec,
        }),
        Box::new(Aydp {
            profile: aydp_proto::Profile::Reference,
        }),
        Box::new(Aok),
    ];
    println!(
        "| protocol | channel | intact sent | delivered (crate) | wrongly accepted (crate) | delivered (naive) | wrongly accepted (naive) |"
    );
    println!("| --- | --- | ---: | ---: | ---: | ---: | ---: |");
    for p in &protocols {
        for (i, ch) in channels().into_iter().enumerate() {
            let (real, naive) = run(p.as_ref(), ch, n, 100 + i as u64);
            println!(
                "| {} | {} | {} | {} ({:.3} %) | {} | {} ({:.3} %) | {} |",
                p.name(),
                ch,
                real.intact_sent,
                real.intact_delivered,
                real.delivered_percent(),
                real.wrongly_accepted,
                naive.intact_delivered,
                naive.delivered_percent(),
                naive.wrongly_accepted
            );
        }
    }
}
