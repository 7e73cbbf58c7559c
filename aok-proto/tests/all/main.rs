//! `aok-proto`'s integration tests, one test binary with a module per subject: run one module
//! with `cargo test -p aok-proto --test all client::`. A module that needs a feature is left
//! out without it (the readers and writers need both `embedded-io` features, the async client
//! `embedded-io-async`). The shared helpers are declared once here; the transports are
//! `aeolus-proto`'s.

#[path = "../support/events.rs"]
mod events;
#[path = "../../../aeolus-proto/tests/support/transport.rs"]
mod transport;
#[path = "../support/watchdog.rs"]
mod watchdog;

#[cfg(feature = "embedded-io-async")]
mod async_client;
mod bulk;
mod bulk_reply;
mod checksums;
mod client;
mod debug_frame;
mod decoder_state;
mod error_messages;
mod fuzz;
#[cfg(all(feature = "embedded-io", feature = "embedded-io-async"))]
mod io;
mod mission_end;
mod parameter_reply;
mod place;
#[cfg(all(feature = "embedded-io", feature = "embedded-io-async"))]
mod reader_unread;
mod roundtrip;
mod side_helpers;
mod streams;
mod values;
mod vectors;
#[cfg(all(feature = "embedded-io", feature = "embedded-io-async"))]
mod writer_flush;
