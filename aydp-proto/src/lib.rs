//! `aydp-proto`: a zero-allocation, `no_std`, panic-free encoder and decoder for AYDP, the
//! Autonomous Yacht Development Project's binary protocol.
//!
//! AYDP exists in two conventions ([`Profile`]): the 2016 document (`Spec`, the default) and
//! the project's released software (`Reference`). They differ in what the length field
//! counts, in the header's sub-second unit, and in which message types are typed. See the
//! crate README and `docs/protocol-notes.md` for the decisions (Y1..Y9) this crate follows.
//!
//! # Decoding a stream
//!
//! Every decoder of this workspace follows one contract, [`Decode`] (from `frame-io`): feed
//! every slice of the stream, of any length (one byte included), then finish when the stream
//! ends. Each event is `Ok(frame)` or `Err(error)`; the events do not depend on how the stream
//! was cut into slices.
//!
//! ```
//! use aydp_proto::{Decode, Decoder, Encoder, Error, Message, Position, Profile, Timestamp};
//!
//! // Noise, a position report, then a message cut short by the end of the stream.
//! let pos = Position { latitude: 50.5, longitude: -1.25, altitude: 12.5 };
//! let mut bytes = vec![0x13, 0x37];
//! let mut buf = [0u8; 64];
//! let n = Encoder::new(Profile::Spec)
//!     .encode_normal(&pos, Timestamp::new(1_700_000_000, 250), &mut buf)
//!     .unwrap();
//! bytes.extend_from_slice(&buf[..n]);
//! bytes.extend_from_slice(&[0xFF, 0x89, 0x08]);
//!
//! let mut decoder = Decoder::<128>::new(Profile::Spec);
//! let (mut positions, mut errors) = (Vec::new(), Vec::new());
//! decoder.feed(&bytes, |event| match event {
//!     Ok(frame) => {
//!         assert_eq!(frame.timestamp(), Some(Timestamp::new(1_700_000_000, 250)));
//!         if let Ok(Message::Position(p)) = frame.message() {
//!             positions.push(p);
//!         }
//!     }
//!     Err(error) => errors.push(error), // counted; the decoder resynchronised
//! });
//! decoder.finish(|event| errors.extend(event.err())); // the end of the stream
//! assert_eq!(positions, [pos]);
//! assert_eq!(errors, [Error::Truncated]);
//! assert_eq!(decoder.stats().bytes_discarded, 5); // every byte outside the frame
//! ```
//!
//! The pull form underneath ([`Decode::decode`], [`Decode::end`], [`Decode::item`]) returns one
//! event a call, for a caller that must act between two messages; the readers of the
//! `embedded-io` features are built on it.
//!
//! # Contents
//!
//! - at the root: the [`Decoder`] (with lossless resynchronisation) and its [`Stats`]; the
//!   [`Encoder`] (into a buffer or as a byte iterator, [`Bytes`]) and the [`Payload`] trait
//!   ([`Raw`] for any type); [`Frame`], a checked whole message; the typed messages and the
//!   [`Message`] enum; [`Profile`] and the header [`Timestamp`];
//! - [`decoder`]: how the [`Decoder`] resynchronises, and its pull form;
//! - [`profile`]: the profiles' constants (start byte, header lengths);
//! - [`message`]: the type numbers of the special and user-defined messages;
//! - [`checksum`]: the XOR checksum;
//! - [`uflt16`]: the binary16 conversions;
//! - [`registry`]: the system-value registry for devices;
//! - `embedded_io` / `embedded_io_async` (features `embedded-io`, `embedded-io-async`): a
//!   `FrameReader` that returns the next message from a `Read` (`frame-io`'s reader over a
//!   [`Decoder`]) and a `FrameWriter` that encodes into a `Write`, blocking or async, with the
//!   error type `IoError`.
//!
//! Each typed message gives its bytes as a table, `FIELDS` (name, wire type, offset) and
//! `LEN` ([`Position::FIELDS`], [`Frame::HEADER_FIELDS`] for the header), for tools that
//! describe the wire format.
#![no_std]
#![forbid(unsafe_code)]
#![deny(missing_docs)]

pub mod checksum;
pub mod decoder;
#[cfg(feature = "embedded-io")]
pub mod embedded_io;
#[cfg(feature = "embedded-io-async")]
pub mod embedded_io_async;
mod encode;
mod error;
mod frame;
mod header;
#[cfg(any(feature = "embedded-io", feature = "embedded-io-async"))]
mod io;
mod layout;
pub mod message;
pub mod profile;
pub mod registry;
pub mod uflt16;

pub use decoder::{Decoder, Stats};
pub use encode::{Bytes, Encoder, Payload, Raw};
pub use error::{EncodeError, Error, Result};
pub use frame::Frame;
pub use frame_io::{Decode, Event};
#[cfg(any(feature = "embedded-io", feature = "embedded-io-async"))]
pub use io::{IoError, WriteError};
pub use message::{
    DirectOutput, DirectOutputBuilder, Entries, FixDetail, FixDetailBuilder, FixQuality, Message,
    OutputEntry, Position, Satellite, SatelliteList, Satellites, SystemControl, SystemValueUpdate,
    UpdateMode, VesselData, WindDirection, WindSpeed,
};
pub use profile::{Profile, Timestamp};

/// The README's examples, compiled and run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
