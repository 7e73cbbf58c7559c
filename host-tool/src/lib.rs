//! # protolink
//!
//! The host-side companion of the AEOLUS, AYDP and AOK protocol crates: a `std` command-line
//! tool (the `protolink` binary) and the library it is built from.
//!
//! The library's public face is what the Python package (`python/`) and this crate's
//! integration tests build on: [`cli::main_with`], the stream [`decoders`], [`proto`], the
//! [`endpoint`] syntax, [`capture`] reading and writing, [`render`], and the few items of
//! [`commands`], [`nmea`], [`telemetry`] and [`wireshark`] the tests check. Everything else
//! is crate-private; `cargo doc -p protolink --document-private-items` documents it all.
//!
//! Cargo features (all on by default; the crate's README.md, "Features"): `cli` (the command
//! line and its subcommands), `serial` (`serial:` endpoints), `servers` (`web`, `nmea`,
//! `gdl90`), `parquet` (Parquet and Arrow IPC files) and `sim`. Without any, the library keeps
//! the decoders, captures, columns, air data and endpoints over files and sockets.
//!
//! The modules stand on four floors, and a module uses only modules on floors below its own
//! (`tests/tests/all/module_layers.rs` checks it, and that there is no import cycle):
//!
//! | floor | module | holds |
//! | --- | --- | --- |
//! | top | [`cli`] | the command line (clap): routes each subcommand to its module in [`commands`] |
//! | subcommands | [`commands`] | one module per subcommand (`decode`, `watch`, `web`, `record`, `replay`, `bridge`, `sim`, `aeolus`, `aydp`, `aok`, `gdl90`, `nmea`, `wireshark`), never using one another |
//! | generators | [`wireshark`] | the Wireshark Lua dissector, generated from the protocol crates' layout tables |
//! | shared | [`endpoint`] | `serial:`, `tcp:`, `udp:`, `file:` and `-`: the address syntax and the byte streams they open |
//! | shared | [`nb_serial`] | an endpoint behind the `embedded-hal-nb` serial traits |
//! | shared | [`datagrams`] | the UDP side of an AEOLUS box: frames packed into datagrams, the in-port |
//! | shared | [`capture`] | pcapng/pcap captures: link types and ports, reading and writing |
//! | shared | [`civil`] | calendar dates and days since 1970, both ways |
//! | shared | [`proto`] | what a stream carries: protocol, AYDP profile, AOK side |
//! | shared | [`decoders`] | the stream decoder of the four protocols: typed items placed in the input, their rendering as events, counters |
//! | shared | [`telemetry`] | the live AEOLUS telemetry model that `watch` and `web` show |
//! | shared | [`air_data`] | the one air-data truth: IAS, TAS, pressure altitude, vertical speed (PL39) |
//! | shared | [`fresh`] | how long a telemetry value stays current for what the faces send |
//! | shared | [`nmea`] | NMEA 0183 sentences and their bounded fan-out to TCP clients or UDP |
//! | shared | [`render`] | output lines, text escaping, JSON and `key=value` rendering |
//! | shared | [`args`], [`units`], [`value_type`] | durations and range-checked numbers, display units, AYDP value types such as `f32[3]` |
//! | shared | [`progress`], [`stop`] | the progress spinner; Ctrl-C and `--seconds` |
//! | shared | [`error`] | the crate's one error type |
//!
//! ```
//! use protolink::decoders::Decoder;
//! use protolink::proto::Proto;
//! // A TOAST "hi" frame, then one with a flipped bit.
//! let stream = [0x7E, 0x52, b'h', b'i', 0, 0x73, 0xEC, 0x7E, 0x7E, 0x52, b'h', b'j', 0, 0x73, 0xEC, 0x7E];
//! let mut decoder = Decoder::new(Proto::Aeolus, Default::default(), Default::default());
//! let events = decoder.events(&stream, 0, false);
//! assert_eq!(events[0].to_text(), "@0 TOAST id=82 len=8 crc=ok text=hi");
//! assert!(events[1].to_text().starts_with("@8 error: CRC mismatch on message 82"));
//! ```
// One call is `unsafe`: `nmea::window` asks Linux for a client's receive window.
#![deny(unsafe_code)]
#![deny(missing_docs)]
#![warn(unreachable_pub)]
// The table above and the modules' docs name crate-private modules too: they resolve in the
// maintainers' build (`--document-private-items`, checked by scripts/test.sh).
#![allow(rustdoc::private_intra_doc_links)]
// Without every subcommand, crate-private helpers that only some subcommands call (output
// lines, the live telemetry's staleness, display units, time windows) have no caller left; the
// full build (clippy with every feature) still finds dead code.
#![cfg_attr(
    not(all(feature = "cli", feature = "servers", feature = "sim")),
    allow(dead_code)
)]

#[cfg(feature = "cli")]
pub mod cli;
pub mod commands;
#[cfg(feature = "cli")]
pub mod wireshark;

pub(crate) mod air_data;
#[cfg(feature = "cli")]
pub(crate) mod args;
pub mod capture;
pub(crate) mod civil;
pub mod columns;
#[cfg(feature = "cli")]
pub(crate) mod datagrams;
pub mod decoders;
pub mod endpoint;
pub(crate) mod error;
pub(crate) mod fresh;
#[cfg(feature = "cli")]
pub(crate) mod nb_serial;
#[cfg(feature = "servers")]
pub mod nmea;
#[cfg(feature = "cli")]
pub(crate) mod progress;
pub mod proto;
pub mod render;
#[cfg(feature = "cli")]
pub(crate) mod stop;
pub mod telemetry;
pub(crate) mod units;
#[cfg(feature = "cli")]
pub(crate) mod value_type;

pub use error::{Error, Result};
