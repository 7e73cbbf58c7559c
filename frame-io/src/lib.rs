//! Frame readers and writers over [`embedded-io`](https://docs.rs/embedded-io) and
//! [`embedded-io-async`](https://docs.rs/embedded-io-async), written once for every protocol
//! of this workspace: `no_std`, no allocation, no panic. It also states, once, [`Decode`]: the
//! decoder contract that `aeolus-proto`'s, `aydp-proto`'s and `gdl90-proto`'s `Decoder<N>`
//! and `aok-proto`'s `MessageDecoder` and `CommandDecoder` implement.
//!
//! # The one loop, and the same decoder behind a reader
//!
//! ```
//! # use frame_io::Event;
//! # /// Lines of up to 8 bytes, each ended by `\n`; a longer line is an error.
//! # #[derive(Default)]
//! # struct Lines {
//! #     buf: [u8; 8],
//! #     len: usize,
//! #     last: usize,
//! # }
//! #
//! # impl Decode for Lines {
//! #     type Error = &'static str;
//! #     type Found = usize;
//! #     type Item<'a> = &'a [u8];
//! #     const TRUNCATED: &'static str = "line cut short";
//! #
//! #     fn decode(&mut self, bytes: &[u8]) -> (usize, Option<Event<usize, &'static str>>) {
//! #         for (i, &b) in bytes.iter().enumerate() {
//! #             if b == b'\n' {
//! #                 self.last = self.len + 1;
//! #                 return (i + 1, Some(Event::Found(core::mem::take(&mut self.len))));
//! #             }
//! #             let Some(slot) = self.buf.get_mut(self.len) else {
//! #                 self.last = core::mem::take(&mut self.len) + 1;
//! #                 return (i + 1, Some(Event::Error("line too long")));
//! #             };
//! #             *slot = b;
//! #             self.len += 1;
//! #         }
//! #         (bytes.len(), None)
//! #     }
//! #
//! #     fn end(&mut self) -> Option<Event<usize, &'static str>> {
//! #         let pending = core::mem::take(&mut self.len);
//! #         self.last = pending;
//! #         (pending > 0).then_some(Event::Truncated(pending))
//! #     }
//! #
//! #     fn item<'a>(&'a self, _input: &'a [u8], len: usize) -> &'a [u8] {
//! #         self.buf.get(..len).unwrap_or(&[])
//! #     }
//! #
//! #     fn span(&self) -> frame_io::Span {
//! #         frame_io::Span { len: self.last, after: 0 }
//! #     }
//! # }
//! use frame_io::{Decode, IoError, embedded_io::Reader};
//!
//! // `Lines` (hidden here, written out in `Decode`'s documentation): lines of up to 8 bytes,
//! // each ended by `\n`. The one loop: every slice of the stream, then its end.
//! let mut lines = Lines::default();
//! let mut seen = Vec::new();
//! for piece in [&b"hi\no"[..], b"k\nhal"] {
//!     lines.feed(piece, |event| seen.push(event.map(|line| line.to_vec())));
//! }
//! lines.finish(|event| seen.push(event.map(|line| line.to_vec())));
//! assert_eq!(seen, [Ok(b"hi".to_vec()), Ok(b"ok".to_vec()), Err("line cut short")]);
//!
//! // A reader of a `Read`: a line, a line too long (its ninth byte is the error), a line,
//! // half a line.
//! let wire: &[u8] = b"hi\n123456789ok\nhal";
//! let mut reader = Reader::<_, _, 4>::new(wire, Lines::default());
//! assert_eq!(reader.read(), Ok(&b"hi"[..]));
//! assert_eq!(reader.read(), Err(IoError::Protocol("line too long")));
//! assert_eq!(reader.read(), Ok(&b"ok"[..]));
//! assert_eq!(reader.read(), Err(IoError::UnexpectedEof { pending: 3 }));
//! assert_eq!(reader.read(), Err(IoError::Eof));
//! ```
//!
//! # Contents
//!
//! - [`Decode`], **the decoder contract**, and its [`Event`]: the one loop (`feed` every slice,
//!   `finish` at the end of the stream), the pull form (`next_event`), and the three methods
//!   an implementation writes (`decode`, `end`, `item`).
//! - [`IoError`]: the transport's error and the protocol's, kept apart, and the end of the
//!   stream (inside a frame, or between frames).
//!
//! # Features
//!
//! - `embedded-io`, `embedded-io-async`: the modules `embedded_io` and `embedded_io_async`,
//!   each with a `Reader` (a decoder plus an `R`-byte read buffer; `read()` returns the next
//!   item) and `write_all` and `write_iter`, the write loops the protocol crates' writers
//!   are built on. Blocking and async come from one source (see `embedded_io_async`).
//! - `defmt`: `defmt::Format` derived on `IoError` and `Event`.
#![no_std]
#![forbid(unsafe_code)]
#![deny(missing_docs)]

mod decode;
#[cfg(feature = "embedded-io")]
pub mod embedded_io;
#[cfg(feature = "embedded-io-async")]
pub mod embedded_io_async;
mod error;
mod place;
#[cfg(any(feature = "embedded-io", feature = "embedded-io-async"))]
mod shared;
mod stream;

pub use decode::{Decode, Event};
pub use error::IoError;
pub use place::{Place, Span};
pub use stream::Stream;

/// The README's example, compiled and run as a doctest.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
