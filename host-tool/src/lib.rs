//! # protolink
//!
//! The host-side companion of the AEOLUS, AYDP and AOK protocol crates: a `std` command-line
//! tool (the `protolink` binary) and the library it is built from.
//!
//! | module | holds |
//! | --- | --- |
//! | [`cli`] | the command line (clap), one subcommand per module below |
//! | [`endpoint`] | `serial:`, `tcp:`, `udp:`, `file:` and `-` endpoints, opened as byte streams |
//! | [`decode`] | `decode`: stream decoders for the three protocols, events, text and JSON lines |
//! | [`bridge`] | `bridge`: AEOLUS UART frames to UDP datagrams and back |
//! | [`aeolus_cmd`] | `aeolus`: COMMAND and SETTIME to a box, its TOAST as the answer |
//! | [`args`] | durations with units and range-checked numbers on the command line |
//! | [`aydp_cmd`] | `aydp`: system values, store, direct outputs |
//! | [`aok_cmd`] | `aok`: the `aok-proto` client over an endpoint |
//! | [`gdl90_cmd`] | `gdl90`: the box's telemetry as GDL90 and ForeFlight AHRS for EFB apps |
//! | [`capture`], [`record`], [`replay`] | pcapng/pcap captures: `record`, `replay`, `decode` of a capture |
//! | [`wireshark`] | `wireshark`: the Lua dissector generated from the layout tables |
//! | [`watch`] | `watch`: the live telemetry view |
//! | [`web`] | `web`: the glass cockpit in the browser (server-sent events, `/api/state`) |
//! | [`sim`] | `sim`: a virtual AEOLUS-SENSE box on UDP, running the firmware's own AEOLUS link |
//! | [`value_type`] | AYDP value types such as `f32[3]` and `char[40]` |
//! | [`nb_serial`] | an endpoint behind the `embedded-hal-nb` serial traits |
//! | [`render`], [`progress`], [`stop`] | output, progress spinner, Ctrl-C and `--seconds` |
//! | [`error`] | the crate's one error type |
//!
//! ```
//! use protolink::decode::{AeolusDecoder, StreamDecoder};
//! // A TOAST "hi" frame, then one with a flipped bit.
//! let stream = [0x7E, 0x52, b'h', b'i', 0, 0x73, 0xEC, 0x7E, 0x7E, 0x52, b'h', b'j', 0, 0x73, 0xEC, 0x7E];
//! let mut decoder = AeolusDecoder::new();
//! let mut events = Vec::new();
//! decoder.feed(&stream, 0, &mut events);
//! assert_eq!(events[0].to_text(), "@0 TOAST id=82 len=8 crc=ok text=hi");
//! assert!(events[1].to_text().starts_with("@8 error: CRC mismatch on message 82"));
//! ```
#![forbid(unsafe_code)]
#![deny(missing_docs)]

pub mod aeolus_cmd;
pub mod aok_cmd;
pub mod args;
pub mod aydp_cmd;
pub mod bridge;
pub mod capture;
pub mod cli;
pub mod decode;
pub mod endpoint;
pub mod error;
pub mod gdl90_cmd;
pub mod nb_serial;
pub mod progress;
pub mod record;
pub mod render;
pub mod replay;
pub mod sim;
pub mod stop;
pub mod units;
pub mod value_type;
pub mod watch;
pub mod web;
pub mod wireshark;
pub mod wireshark_aok;
pub mod wireshark_aydp;

pub use error::{Error, Result};
