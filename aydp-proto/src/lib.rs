//! `aydp-proto`: a zero-allocation, `no_std`, panic-free encoder and decoder for AYDP, the
//! Autonomous Yacht Development Project's binary protocol, in both of its conventions
//! ([`Profile`]): the 2016 document (`Spec`, the default) and the project's released software
//! (`Reference`). The decisions it follows (Y1..Y9) are in the crate README and
//! `docs/protocol-notes.md`.
//!
//! # Decoding a stream: the one loop
//!
//! ```
//! use aydp_proto::{Decode, Decoder, Encoder, Error, Message, Position, Profile, Timestamp};
//!
//! // Noise, a position report, then a message cut short by the end of the stream.
//! let pos = Position { latitude: 50.5, longitude: -1.25, altitude: 12.5 };
//! let mut bytes = vec![0x13, 0x37];
//! let mut buf = [0u8; 64];
//! let n = Encoder::new(Profile::Spec)
//!     .encode(&pos, Some(Timestamp::new(1_700_000_000, 250)), &mut buf)
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
//! # Contents
//!
//! - [`Decoder`] and its [`Stats`]: the stream decoder. It implements [`Decode`], the decoder
//!   contract of every protocol crate of this workspace (from `frame-io`); [`decoder`]: how it
//!   resynchronises, and its pull form. [`Stream`] gives every event its [`Place`] in the
//!   stream (from [`Decode::span`]: where each event lies, on [`Decoder`]'s `Decode`).
//! - Encoding, one vocabulary with the other protocol crates: every payload has `emit` (its
//!   data into a caller's buffer) and `buffer_len` ([`Payload`], [`Raw`] for any type);
//!   [`Encoder::encode`] writes the whole message, normal with `Some(timestamp)`, expedited
//!   with `None` (or [`Encoder::iter`], a byte iterator, [`Bytes`]).
//! - [`Frame`], a checked whole message; the typed messages and the [`Message`] enum
//!   ([`message`]: the type numbers).
//! - [`Profile`] and the header [`Timestamp`] ([`profile`]: the start byte, header lengths).
//! - [`checksum`]: the XOR checksum; [`uflt16`]: the binary16 conversions; [`registry`]: the
//!   system-value registry for devices.
//!
//! # Features
//!
//! - `embedded-io`, `embedded-io-async`: the modules `embedded_io` and `embedded_io_async`,
//!   a `FrameReader` that returns the next message from a `Read` and a `FrameWriter` that
//!   encodes into a `Write`, blocking or async, with the error type `IoError`.
//! - `defmt`, `serde`: `defmt::Format` and serde's traits derived on the public types.
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
pub use frame_io::{Decode, Event, Place, Span, Stream};
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
