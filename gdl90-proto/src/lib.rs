//! # gdl90-proto
//!
//! A zero-allocation, `no_std` encoder and decoder for GDL90 (FAA GDL 90 Public ICD Rev A)
//! and ForeFlight's GDL 90 extensions: Heartbeat, Ownship and Traffic Reports, Ownship
//! Geometric Altitude, ForeFlight ID, ForeFlight AHRS and the Stratux AHRS report (0x4C),
//! typed with physical units; every other ID delivered raw. GDL90 framing is AEOLUS framing
//! (`0x7E` flags, `0x7D` escapes, the same CRC-16 sent LSB first), so this crate reuses
//! `aeolus-proto`'s decoder, frame encoder and CRC. Decoders never panic, whatever the input.
//!
//! ## Decoding a stream: the one loop
//!
//! ```
//! use gdl90_proto::{Decode, Decoder, message::Message};
//!
//! // The ICD's heartbeat example, a frame with a corrupted CRC, then the heartbeat again.
//! let heartbeat = [0x7E, 0x00, 0x81, 0x41, 0xDB, 0xD0, 0x08, 0x02, 0xB3, 0x8B, 0x7E];
//! let mut stream = heartbeat.to_vec();
//! stream.extend_from_slice(&[0x7E, 0x0B, 0x01, 0x2C, 0x00, 0x0A, 0x12, 0x34, 0x7E]);
//! stream.extend_from_slice(&heartbeat);
//!
//! let mut decoder = Decoder::<{ gdl90_proto::TYPED_FRAME }>::new();
//! let (mut heartbeats, mut errors) = (0, 0);
//! // Every slice as it comes: a datagram, a read, one byte from an ISR.
//! for piece in stream.chunks(5) {
//!     decoder.feed(piece, |event| match event {
//!         Ok(Message::Heartbeat(hb)) => {
//!             assert!(hb.gps_position_valid && hb.utc_ok);
//!             heartbeats += 1;
//!         }
//!         Ok(_) => {}
//!         Err(_) => errors += 1, // counted in `stats()` too; the decoder resynchronised
//!     });
//! }
//! decoder.finish(|_| errors += 1); // a frame cut short by the end of the stream
//! assert_eq!((heartbeats, errors), (2, 1));
//! assert_eq!(decoder.stats().checksum_errors, 1);
//! ```
//!
//! ## Contents
//!
//! - [`Decoder`] and its [`Stats`]: the stream decoder. It implements [`Decode`], the decoder
//!   contract every protocol crate of this workspace shares.
//! - Encoding, one vocabulary with the other protocol crates: every typed message has `emit`
//!   (its data into a `&mut [u8]`) and `buffer_len`; [`message::Message::encode`] puts any
//!   message on the wire as a whole frame (flags, escapes, CRC), returning its length
//!   ([`MAX_ENCODED_LEN`] bytes always do); [`encode_frame`] frames any ID with raw data.
//! - [`message`]: the typed messages; [`crc`]: the frame check.
//!
//! ## Features
//!
//! - `defmt`: `defmt::Format` derived on the public types.
//! - `serde`: `serde::Serialize` derived on the public types (for host tools).
#![no_std]
#![forbid(unsafe_code)]
#![deny(missing_docs)]

mod decode;
mod encode;
mod error;
pub mod message;

pub use aeolus_proto::crc;
pub use aeolus_proto::{Decode, Event, Place, Span, Stream};
pub use decode::{Decoder, Stats};
pub use encode::{MAX_ENCODED_LEN, encode_frame, max_encoded_len};
pub use error::{EncodeError, Error};

/// The flag byte that opens and closes every frame.
pub const FLAG: u8 = aeolus_proto::FLAG;
/// The control-escape byte.
pub const ESCAPE: u8 = aeolus_proto::ESCAPE;
/// The unescaped length (ID + data + CRC) of the longest typed message, the ForeFlight ID:
/// a [`Decoder`] of this capacity receives every typed message (longer ones give
/// [`Error::Overflow`]).
pub const TYPED_FRAME: usize = 1 + message::ForeFlightId::LEN + 2;
/// The unescaped length of the longest ICD message, the UAT uplink (ID 7: 3 bytes of time
/// of reception and a 432-byte payload): a [`Decoder`] of this capacity receives them all.
pub const MAX_FRAME: usize = 1 + 3 + 432 + 2;

/// The README's example, compiled and run as a doc test.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeDoctest;
