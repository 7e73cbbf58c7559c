//! `aeolus-proto`'s integration tests, one test binary with a module per subject: run one
//! module with `cargo test -p aeolus-proto --test all roundtrip::`. A module that needs a
//! feature is left out without it (the readers and writers need both `embedded-io` features).
//! The shared helpers are declared once here; `tests/support/transport.rs` stays where
//! `aydp-proto`'s and `aok-proto`'s tests include it too.

#[path = "../common/mod.rs"]
mod common;
#[path = "../support/transport.rs"]
mod transport;

mod calibration_status;
mod crc;
mod decoder_state;
mod encoded_len;
mod error_messages;
mod every_kind;
mod fast_path;
mod fixed_frame_capacity;
#[cfg(all(feature = "embedded-io", feature = "embedded-io-async"))]
mod io;
mod place;
#[cfg(all(feature = "embedded-io", feature = "embedded-io-async"))]
mod reader_unread;
mod roundtrip;
mod stats_totals;
mod stream;
mod timestamp;
mod vectors;
#[cfg(all(feature = "embedded-io", feature = "embedded-io-async"))]
mod writer_flush;
#[cfg(all(feature = "embedded-io", feature = "embedded-io-async"))]
mod writer_long_text;
