//! `aydp-proto`: a zero-allocation, `no_std`, panic-free encoder and decoder for AYDP, the
//! Autonomous Yacht Development Project's binary protocol.
//!
//! AYDP exists in two conventions ([`Profile`]): the 2016 document (`Spec`, the default) and
//! the project's released software (`Reference`). They differ in what the length field
//! counts, in the header's sub-second unit, and in which message types are typed. See the
//! crate README and `docs/protocol-notes.md` for the decisions (Y1..Y9) this crate follows.
//!
//! Modules:
//! - [`profile`]: the two profiles and the header [`Timestamp`];
//! - [`layout`]: every message's bytes in one table (field offsets, lengths);
//! - [`header`]: the header view [`Header`] and [`HeaderRepr`];
//! - [`frame`]: [`Frame`], a checked whole message;
//! - [`checksum`]: the XOR checksum;
//! - [`encoder`]: [`Encoder`] (into a buffer or as a byte iterator) and the [`Payload`] trait;
//! - [`decoder`]: the [`Decoder`] with lossless resynchronisation, byte at a time or a slice
//!   at a time;
//! - [`messages`]: typed messages and the [`Message`] enum;
//! - [`uflt16`]: the binary16 conversions;
//! - [`registry`]: the system-value registry for devices;
//! - `embedded_io` / `embedded_io_async` (features `embedded-io`, `embedded-io-async`): a
//!   `FrameReader` that returns the next message from a `Read` (`frame-io`'s reader over a
//!   [`Decoder`], which implements `frame_io::Decode`) and a `FrameWriter` that
//!   encodes into a `Write`, blocking or async, with the error type `IoError`.
//!
//! ```
//! use aydp_proto::{Decoder, Encoder, Message, Position, Profile, Timestamp};
//!
//! let enc = Encoder::new(Profile::Spec);
//! let pos = Position { latitude: 50.5, longitude: -1.25, altitude: 12.5 };
//! let mut buf = [0u8; 64];
//! let n = enc.encode_normal(&pos, Timestamp::new(1_700_000_000, 250), &mut buf).unwrap();
//!
//! let mut dec = Decoder::<128>::new(Profile::Spec);
//! let mut seen = 0;
//! dec.feed(&buf[..n], |ev| {
//!     let frame = ev.unwrap();
//!     assert_eq!(frame.timestamp(), Some(Timestamp::new(1_700_000_000, 250)));
//!     assert_eq!(frame.message(), Ok(Message::Position(pos)));
//!     seen += 1;
//! });
//! assert_eq!(seen, 1);
//! ```
#![no_std]
#![forbid(unsafe_code)]
#![deny(missing_docs)]

pub mod checksum;
pub mod decoder;
#[cfg(feature = "embedded-io")]
pub mod embedded_io;
#[cfg(feature = "embedded-io-async")]
pub mod embedded_io_async;
pub mod encoder;
mod error;
pub mod frame;
pub mod header;
#[cfg(any(feature = "embedded-io", feature = "embedded-io-async"))]
mod io;
pub mod layout;
pub mod messages;
pub mod profile;
pub mod registry;
pub mod uflt16;

pub use decoder::{Decoder, Stats};
pub use encoder::{Bytes, Encoder, Payload, Raw};
pub use error::{Error, Result};
pub use frame::Frame;
pub use header::{Header, HeaderRepr};
#[cfg(any(feature = "embedded-io", feature = "embedded-io-async"))]
pub use io::IoError;
pub use messages::{
    DirectOutput, DirectOutputBuilder, Entries, FixDetail, FixDetailBuilder, FixQuality, Message,
    OutputEntry, Position, Satellite, SatelliteList, Satellites, SystemControl, SystemValueUpdate,
    UpdateMode, VesselData, WindDirection, WindSpeed,
};
pub use profile::{Profile, Timestamp};

/// The README's examples, compiled and run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
