//! `flight-sim`'s integration tests, one test binary with a module per subject: run one module
//! with `cargo test -p flight-sim --test all attitude::`. The climbing flight's module needs
//! the `climb` feature and is left out without it.

mod attitude;
#[cfg(feature = "climb")]
mod climb;
mod flight;
mod reference;
