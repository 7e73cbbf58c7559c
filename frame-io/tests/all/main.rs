//! `frame-io`'s integration tests, one test binary with a module per subject: run one module
//! with `cargo test -p frame-io --all-features --test all io::`. A module that needs a feature
//! is left out without it.

#[cfg(all(feature = "embedded-io", feature = "embedded-io-async"))]
mod io;
mod stream;
