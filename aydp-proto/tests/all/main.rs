//! `aydp-proto`'s integration tests, one test binary with a module per subject: run one module
//! with `cargo test -p aydp-proto --test all stream::`. A module that needs a feature is left
//! out without it (the readers and writers need both `embedded-io` features). The shared
//! helpers are declared once here; `tests/support/` stays where `protolink-tests` includes its
//! files too, and the transports are `aeolus-proto`'s.

#[path = "../support/naive.rs"]
mod naive;
#[path = "../support/streamgen.rs"]
mod streamgen;
#[path = "../../../aeolus-proto/tests/support/transport.rs"]
mod transport;

mod bulk;
mod decoder_state;
mod direct_output;
mod error_messages;
mod fix_detail;
mod frame_len;
#[cfg(all(feature = "embedded-io", feature = "embedded-io-async"))]
mod io;
#[cfg(all(feature = "embedded-io", feature = "embedded-io-async"))]
mod io_parts;
mod kept;
mod place;
mod profile_rules;
#[cfg(all(feature = "embedded-io", feature = "embedded-io-async"))]
mod reader_unread;
mod registry_set;
mod rescan_events;
mod roundtrip;
mod satellite;
mod stream;
mod typed;
mod vectors;
#[cfg(all(feature = "embedded-io", feature = "embedded-io-async"))]
mod writer_flush;
#[cfg(all(feature = "embedded-io", feature = "embedded-io-async"))]
mod writer_forms;
