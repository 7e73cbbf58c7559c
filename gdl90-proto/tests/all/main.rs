//! `gdl90-proto`'s integration tests, one test binary with a module per subject: run one
//! module with `cargo test -p gdl90-proto --test all vectors::`.

mod place;
mod roundtrip;
mod stream;
mod vectors;
