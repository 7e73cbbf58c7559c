//! The per-byte path: what [`Decode::feed`](crate::Decode::feed) does with a slice of one byte
//! (an interrupt handler's call), and what the pull form does in a decoder too small for a
//! header. It stores the byte and runs the step; a byte the step already knows it cannot
//! decide on is only stored.

use super::*;

impl<const N: usize> Decoder<N> {
    /// One byte, every event it gives handed to `on_event` in order (a rescan can give several).
    #[inline]
    pub(super) fn feed_byte<F: FnMut(Result<Frame<'_>>)>(&mut self, byte: u8, mut on_event: F) {
        let mut event = self.push(byte);
        while let Some(e) = event {
            on_event(e);
            event = self.poll();
        }
    }

    /// Stores one byte and returns the first event it gives; [`Decoder::poll`] gives the rest.
    #[inline]
    pub(super) fn push(&mut self, byte: u8) -> Option<Result<Frame<'_>>> {
        // The common case, inlined: the step said it cannot decide before more than one
        // further byte is held, so this byte is only stored.
        let len = self.len;
        if len.wrapping_add(1) < self.decide_at {
            if let Some(slot) = self.buf.get_mut(len) {
                *slot = byte;
                self.len = len + 1;
                return None;
            }
        }
        self.advance(Some(byte))
    }

    /// Stores `byte` (if any) behind the bytes held, then runs the step over them: the one
    /// out-of-line function of `push` and `poll`, so that a byte the fast path of `push` does
    /// not take costs one call.
    #[inline(never)]
    fn advance(&mut self, byte: Option<u8>) -> Option<Result<Frame<'_>>> {
        if let Some(byte) = byte {
            if self.start == self.len {
                self.start = 0;
                self.len = 0;
            } else if self.len >= N {
                self.compact();
            }
            if let Some(slot) = self.buf.get_mut(self.len) {
                *slot = byte;
                self.len += 1;
            } else {
                // Unreachable by construction, as in `append`.
                discard(&mut self.stats, 1);
            }
        }
        let step = self.examine();
        self.event(step)
    }

    /// The next event a rescan left queued in the bytes held, or `None`.
    #[inline]
    pub(super) fn poll(&mut self) -> Option<Result<Frame<'_>>> {
        if self.start == self.len {
            // Nothing held (the usual call after an event): nothing to decide.
            return None;
        }
        self.poll_held()
    }

    /// [`Decoder::poll`] when bytes are held: the step runs over them.
    #[inline]
    pub(super) fn poll_held(&mut self) -> Option<Result<Frame<'_>>> {
        self.advance(None)
    }
}
