//! The subcommands, one module each: its arguments (a clap `Args` struct) and its `run`.
//! [`crate::cli`] routes to them. A subcommand builds on the shared modules below it (and
//! `wireshark` on the generator in [`crate::wireshark`]), never on another subcommand.
//!
//! | module | subcommand |
//! | --- | --- |
//! | [`decode`] | `decode`: one line per message (text or JSON), live streams and captures |
//! | [`watch`] | `watch`: the live telemetry view in the terminal |
//! | [`web`] | `web`: the glass cockpit in the browser (server-sent events, `/api/state`) |
//! | [`record`] | `record`: an endpoint into a pcapng file |
//! | [`replay`] | `replay`: a capture's payloads to an endpoint with their timing |
//! | [`bridge`] | `bridge`: AEOLUS UART frames to UDP datagrams and back |
//! | [`sim`] | `sim`: a virtual AEOLUS-SENSE box on UDP, running the firmware's own AEOLUS link |
//! | [`aeolus`] | `aeolus`: COMMAND and SETTIME to a box, its TOAST as the answer |
//! | [`aydp`] | `aydp`: system values, store, direct outputs |
//! | [`aok`] | `aok`: the `aok-proto` client over an endpoint |
//! | [`gdl90`] | `gdl90`: the box's telemetry as GDL90, ForeFlight and Stratux AHRS for EFB apps |
//! | [`nmea`] | `nmea`: the box's telemetry as NMEA 0183 for gliding and moving-map apps |
//! | [`wireshark`] | `wireshark`: prints the generated Lua dissector |

#[cfg(feature = "cli")]
pub(crate) mod aeolus;
pub mod aok;
#[cfg(feature = "cli")]
pub(crate) mod aydp;
#[cfg(feature = "cli")]
pub(crate) mod bridge;
pub mod decode;
#[cfg(feature = "servers")]
pub mod gdl90;
#[cfg(feature = "servers")]
pub mod nmea;
#[cfg(feature = "cli")]
pub(crate) mod record;
#[cfg(feature = "cli")]
pub(crate) mod replay;
#[cfg(feature = "sim")]
pub(crate) mod sim;
#[cfg(feature = "cli")]
pub mod watch;
#[cfg(feature = "servers")]
pub mod web;
#[cfg(feature = "cli")]
pub(crate) mod wireshark;
