//! Frame readers and writers over [`embedded-io`](https://docs.rs/embedded-io) and
//! [`embedded-io-async`](https://docs.rs/embedded-io-async), written once for every protocol
//! of this workspace: `no_std`, no allocation, no panic.
//!
//! - [`Decode`]: **the decoder contract** of every protocol crate of this workspace, stated
//!   once: the one loop (`feed` every slice, `finish` at the end of the stream), the pull form
//!   (`next_event`), and the three methods an implementation writes (`decode`, `end`, `item`).
//!   `aeolus-proto`'s, `aydp-proto`'s and `gdl90-proto`'s `Decoder<N>` and `aok-proto`'s
//!   `MessageDecoder` and `CommandDecoder` implement it.
//! - `embedded_io::Reader` / `embedded_io_async::Reader` (features `embedded-io`,
//!   `embedded-io-async`): a decoder plus an `R`-byte read buffer; `read()` returns the next
//!   item, decoding every read with the decoder's fast path, so the items and errors are
//!   exactly those of the decoder's `feed` over the same bytes.
//! - `write_all` and `write_iter` in the same modules: the write loops the protocol crates'
//!   writers are built on (a slice, or an encoder's byte iterator a chunk of 32 bytes at a time).
//! - [`IoError`]: the transport's error and the protocol's, kept apart, and the end of the
//!   stream (inside a frame, or between frames).
//!
//! **Blocking and async from one source.** Everything but the calls to `read` and `write` is in
//! one shared core (the read buffer and its bookkeeping, the decode step, the end-of-stream
//! state, turning an event into an item or an error, the chunking of the writers), plain
//! synchronous code tested once. Each feature module adds only the loops around it, a few
//! lines each, identical but for `.await`. This was chosen over one macro body expanded
//! twice: the public items keep ordinary source, documentation and compiler messages, and each
//! async loop keeps exactly one `.await` (on the transport), which keeps its state machine
//! small enough for LLVM to prove panic-free (`checks/panic-never`).
//!
//! ```
//! use frame_io::{Decode, Event, IoError, embedded_io::Reader};
//!
//! /// Lines of up to 8 bytes, each ended by `\n`; a longer line is an error.
//! struct Lines {
//!     buf: [u8; 8],
//!     len: usize,
//! }
//!
//! impl Decode for Lines {
//!     type Error = &'static str;
//!     type Found = usize;
//!     type Item<'a> = &'a [u8];
//!     const TRUNCATED: &'static str = "line cut short";
//!
//!     fn decode(&mut self, bytes: &[u8]) -> (usize, Option<Event<usize, &'static str>>) {
//!         for (i, &b) in bytes.iter().enumerate() {
//!             if b == b'\n' {
//!                 return (i + 1, Some(Event::Found(core::mem::take(&mut self.len))));
//!             }
//!             let Some(slot) = self.buf.get_mut(self.len) else {
//!                 self.len = 0;
//!                 return (i + 1, Some(Event::Error("line too long")));
//!             };
//!             *slot = b;
//!             self.len += 1;
//!         }
//!         (bytes.len(), None)
//!     }
//!
//!     fn end(&mut self) -> Option<Event<usize, &'static str>> {
//!         let pending = core::mem::take(&mut self.len);
//!         (pending > 0).then_some(Event::Truncated(pending))
//!     }
//!
//!     fn item<'a>(&'a self, _input: &'a [u8], len: usize) -> &'a [u8] {
//!         self.buf.get(..len).unwrap_or(&[])
//!     }
//! }
//!
//! // A line, a line too long (its ninth byte is the error), a line, half a line.
//! let wire: &[u8] = b"hi\n123456789ok\nhal";
//! let mut reader = Reader::<_, _, 4>::new(wire, Lines { buf: [0; 8], len: 0 });
//! assert_eq!(reader.read(), Ok(&b"hi"[..]));
//! assert_eq!(reader.read(), Err(IoError::Protocol("line too long")));
//! assert_eq!(reader.read(), Ok(&b"ok"[..]));
//! assert_eq!(reader.read(), Err(IoError::UnexpectedEof { pending: 3 }));
//! assert_eq!(reader.read(), Err(IoError::Eof));
//! ```
#![no_std]
#![forbid(unsafe_code)]
#![deny(missing_docs)]

mod decode;
#[cfg(feature = "embedded-io")]
pub mod embedded_io;
#[cfg(feature = "embedded-io-async")]
pub mod embedded_io_async;
mod error;
#[cfg(any(feature = "embedded-io", feature = "embedded-io-async"))]
mod shared;

pub use decode::{Decode, Event};
pub use error::IoError;

/// The README's example, compiled and run as a doctest.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
