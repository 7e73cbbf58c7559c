//! The two decoders, named after what they read, and what they share.
//!
//! - [`CommandDecoder`] (`command/`) runs on the device and reads the PC's commands.
//! - [`MessageDecoder`] (`message/`) runs on the PC and reads the device's messages, knowing
//!   which request is pending.
//!
//! Each implements [`frame_io::Decode`], the contract of every decoder in this workspace:
//! `feed(bytes, |event| ..)` for every slice of the stream, `finish(|event| ..)` when it ends
//! (AOK's quiet line), and the pull form (`decode`, `end`, `item`) underneath. In each folder,
//! `step.rs` holds the rules (one step over a window of bytes) and what the paths written
//! once in `byte.rs` need of the decoder (`Rules`), and `bulk.rs` the `Decode`
//! implementation. `byte.rs` runs the step over the decoder's buffer byte by byte (the byte
//! path) and over the input itself while nothing is held (the slice fast path of `feed` and
//! `decode`), and records where each event of the pull form lies (`Decode::span`).
//! [`Stats`] counts for both.

mod byte;
mod command;
#[cfg(test)]
mod liveness;
mod message;
mod stats;

use frame_io::{Event, Span};

pub(crate) use byte::Rules;
pub use command::CommandDecoder;
pub use message::MessageDecoder;
pub use stats::Stats;

use crate::Error;
use crate::command::MAX_COMMAND_LEN;
use crate::shift_left;

/// What the rules of a decoder made of the bytes at the front of a window: the decoder's own
/// buffer (the byte-by-byte path and the end of the stream) or, on the slice path, the input
/// itself. An event the bytes gave has already been handed to the step's `on_event`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Step {
    /// Undecided until the window holds this many bytes.
    Need(usize),
    /// The front's bytes up to this count are decided on (a frame found, a byte that starts
    /// none, or on `feed`'s paths a condemned candidate's first byte: [`Step::condemned`]):
    /// drop them.
    Used(usize),
    /// The front's candidate frame of this many bytes was condemned (its error handed over:
    /// a bad checksum, or an out-of-range field): only its first byte is dropped, the bytes
    /// after it are rescanned.
    Rejected(usize),
}

impl Step {
    /// The front's bytes this step drops: a frame found or a byte that starts none, or a
    /// rejected candidate's first byte (none while undecided). One count for every consumer:
    /// a constant 1 of its own beside the held buffer's shift became a `memmove` call (1.6 KB
    /// of `compiler_builtins` on Cortex-M; see `Rules::drop_front`).
    #[inline(always)]
    pub(crate) const fn dropped(self) -> usize {
        match self {
            Step::Need(_) => 0,
            Step::Used(used) => used,
            Step::Rejected(_) => 1,
        }
    }

    /// What the rules make of a condemned candidate of `len` bytes (its error handed over):
    /// on the pull form (`PULL`), [`Step::Rejected`], whose event is the whole candidate; on
    /// `feed`'s paths, which record no span, `Used(1)` (its first byte), so that their code
    /// is that of a step with two variants, as before spans (a third one there cost `feed`'s
    /// one-byte loop a register on Cortex-M3: 4 % more instructions a byte).
    #[inline(always)]
    pub(crate) const fn condemned<const PULL: bool>(len: usize) -> Step {
        if PULL {
            Step::Rejected(len)
        } else {
            Step::Used(1)
        }
    }

    /// The bytes of the event the step gave, if it gave one: the frame found, or the whole
    /// candidate rejected (none while undecided).
    #[inline(always)]
    pub(crate) const fn event_len(self) -> usize {
        match self {
            Step::Need(_) => 0,
            Step::Used(len) | Step::Rejected(len) => len,
        }
    }
}

/// The bytes a decoder holds between two calls: a frame waiting for the rest of its bytes,
/// and any bytes behind it. Both decoders keep it as their first field, so that on 32-bit
/// targets (`repr(C)`) the buffer's address is the decoder's.
#[derive(Debug, Clone)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(target_pointer_width = "32", repr(C))]
pub(crate) struct Held {
    pub(crate) buf: [u8; MAX_COMMAND_LEN],
    pub(crate) len: usize,
    /// Length of the frame the front byte started, once known (0: not known). Hot-path shortcut.
    pub(crate) need: usize,
    /// Where the event that the pull form (`decode`, `end`) last returned lies: written once
    /// per event by the paths of `byte.rs`, read by `Decode::span`.
    pub(crate) span: Span,
}

impl Held {
    /// Nothing held.
    pub(crate) const EMPTY: Held = Held {
        buf: [0; MAX_COMMAND_LEN],
        len: 0,
        need: 0,
        span: Span { len: 0, after: 0 },
    };

    /// The bytes held.
    #[inline(always)]
    pub(crate) fn window(&self) -> &[u8] {
        self.buf.get(..self.len).unwrap_or(&self.buf)
    }

    /// Appends `byte`; returns false if the buffer was full, which no path lets happen (each
    /// decides on a frame as soon as it is whole, and none is longer than the buffer): then
    /// the caller drops the front first.
    #[inline(always)]
    pub(crate) fn append(&mut self, byte: u8) -> bool {
        // The length read once: the compiler cannot tell that storing the byte leaves it.
        let len = self.len;
        if let Some(slot) = self.buf.get_mut(len) {
            *slot = byte;
            self.len = len.wrapping_add(1);
            true
        } else {
            false
        }
    }

    /// Drops the first `used` bytes held; the length of the new front is not known yet.
    #[inline(always)]
    pub(crate) fn consume(&mut self, used: usize) {
        self.need = 0;
        self.len = shift_left(&mut self.buf, self.len, used);
    }

    /// Keeps `bytes`, which the step left undecided until it holds `need` bytes, for the next
    /// call (the slice path ends with them).
    #[inline]
    pub(crate) fn keep(&mut self, bytes: &[u8], need: usize) {
        if bytes.len() <= self.buf.len() {
            // A byte at a time, not `copy_from_slice`: its length check is only proven away
            // where the compiler sees both lengths, and a panic path must not survive
            // (`checks/panic-never`, the C library's decode).
            for (slot, &byte) in self.buf.iter_mut().zip(bytes) {
                *slot = byte;
            }
            self.len = bytes.len();
            self.need = need;
        }
    }

    /// Forgets every byte held.
    #[inline]
    pub(crate) fn clear(&mut self) {
        self.len = 0;
        self.need = 0;
    }
}

/// The pull form's end of the stream, for either decoder, one call: the next event of the
/// quiet line's step (`quiet_next`), exactly those `finish` gives; a front given up is
/// `Truncated` with the bytes it dropped (what a reader reports as the end inside a frame),
/// `None` when nothing is held any more.
macro_rules! end_of_stream {
    ($self:ident, $quiet_next:expr) => {{
        let held = $self.held.len;
        Some(match $quiet_next? {
            Ok(item) => Event::Found(item),
            Err(Error::Truncated) => Event::Truncated(held.saturating_sub($self.held.len)),
            Err(e) => Event::Error(e),
        })
    }};
}
pub(crate) use end_of_stream;

/// An event of the byte-by-byte path as the pull form reports it.
#[inline]
pub(crate) fn event<T>(found: Option<Result<T, Error>>) -> Option<Event<T, Error>> {
    Some(match found? {
        Ok(item) => Event::Found(item),
        Err(e) => Event::Error(e),
    })
}
