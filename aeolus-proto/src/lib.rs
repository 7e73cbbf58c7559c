//! # aeolus-proto
//!
//! A zero-allocation, `no_std` encoder and decoder for the AEOLUS sensor-box telemetry
//! protocol: GDL90-style framing (`0x7E` flags, `0x7D` escapes, a CRC-16) carrying the 16
//! message types of the AEOLUS communications document. Decoders never panic, whatever the
//! input.
//!
//! ## Decoding a stream: the one loop
//!
//! ```
//! use aeolus_proto::{Decode, Decoder, message::Message};
//!
//! // Two frames from the vectors: TOAST "AEOLUS on", then a TOAST sent without CRC.
//! let stream: &[u8] = &[
//!     0x7e, 0x52, 0x41, 0x45, 0x4f, 0x4c, 0x55, 0x53, 0x20, 0x6f, 0x6e, 0x00, 0x17, 0xd1, 0x7e,
//!     0x7e, 0x52, 0x6e, 0x6f, 0x20, 0x63, 0x72, 0x63, 0x00, 0x00, 0x00, 0x7e,
//! ];
//! let mut decoder = Decoder::<{ aeolus_proto::MAX_FIXED_FRAME }>::new();
//! let mut seen = Vec::new();
//! let mut errors = 0;
//! // Every slice as it comes (a DMA buffer, a read, one byte from an ISR: all the same).
//! for piece in stream.chunks(4) {
//!     decoder.feed(piece, |event| match event {
//!         Ok(frame) => {
//!             if let Ok(Message::Toast(text)) = frame.message() {
//!                 seen.push((text.as_str().unwrap_or("?").to_owned(), frame.has_crc()));
//!             }
//!         }
//!         Err(_) => errors += 1, // counted in `stats()` too; the decoder resynchronised
//!     });
//! }
//! // The end of the stream: a frame cut short would be reported here.
//! decoder.finish(|_| errors += 1);
//! assert_eq!(seen, [("AEOLUS on".to_owned(), true), ("no crc".to_owned(), false)]);
//! assert_eq!(errors, 0);
//! assert_eq!(decoder.stats().frames_ok, 1);
//! assert_eq!(decoder.stats().frames_no_crc, 1);
//! ```
//!
//! ## Contents
//!
//! - [`Decoder`], the stream decoder, and its [`Stats`]. It implements [`Decode`], the
//!   decoder contract every protocol crate of this workspace shares (from `frame-io`).
//! - [`decode_datagram`]: one UDP datagram (several messages) decoded in place.
//! - Encoding, one vocabulary with the other protocol crates: every message has `emit` (its
//!   data into a caller's buffer) and `buffer_len`; [`message::Message::encode`] writes a whole
//!   frame (the buffer first, the [`CrcMode`] after it); [`encode_frame`] frames any ID with raw
//!   data, or [`FrameBytes`] for a buffer-less TX path; [`max_encoded_len`] sizes buffers at
//!   compile time.
//! - [`message`]: typed messages with `parse`, `emit` and `buffer_len`; [`Frame`], a checked
//!   frame; [`crc`]: the frame check exactly as section 4.3 prints it.
//!
//! ## Features
//!
//! - `embedded-io`, `embedded-io-async`: the modules `embedded_io` and `embedded_io_async`,
//!   a `FrameReader` from a `Read` and a `FrameWriter` into a `Write`, blocking or async,
//!   with the error type `IoError`.
//! - `defmt`, `serde`: `defmt::Format` and serde's traits derived on the public types.
#![no_std]
#![forbid(unsafe_code)]
#![deny(missing_docs)]

pub mod crc;
mod datagram;
mod decoder;
#[cfg(feature = "embedded-io")]
pub mod embedded_io;
#[cfg(feature = "embedded-io-async")]
pub mod embedded_io_async;
mod encode;
mod error;
mod frame;
#[cfg(any(feature = "embedded-io", feature = "embedded-io-async"))]
mod io;
#[cfg(test)]
mod liveness;
pub mod message;
mod scan;

pub use datagram::{DatagramFrames, decode_datagram};
pub use decoder::{Decoder, Stats};
pub use encode::{CrcMode, FrameBytes, encode_frame, max_encoded_len};
pub use error::{EncodeError, Error};
pub use frame::Frame;
pub use frame_io::{Decode, Event, Place, Span, Stream};
#[cfg(any(feature = "embedded-io", feature = "embedded-io-async"))]
pub use io::{IoError, WriteError};
pub use scan::find_flag;

/// The flag byte that opens and closes every frame.
pub const FLAG: u8 = 0x7E;
/// The control-escape byte.
pub const ESCAPE: u8 = 0x7D;
/// The longest TOAST or COMMAND text (without its NUL) this crate holds.
pub const TEXT_CAPACITY: usize = 120;
/// The unescaped length (ID + data + CRC) of the longest fixed-size message, DEBUGINFO:
/// a [`Decoder`] of this capacity receives every message but long LOG or text messages.
pub const MAX_FIXED_FRAME: usize = 1 + message::DEBUGINFO_LEN + 2;

/// The README's examples, compiled and run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
