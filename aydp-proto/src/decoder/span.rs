//! Where each event lies ([`Decode::span`](crate::Decode::span)): recorded when the pull form
//! returns an event, never per byte.

use super::*;

impl<const N: usize> Decoder<N> {
    /// Records the span of a frame of `len` bytes just delivered: the bytes held follow it.
    #[inline]
    pub(super) fn frame_span(&mut self, len: usize) {
        self.span = Span {
            len,
            after: self.held_bytes(),
        };
    }

    /// Records the span of a candidate of `len` bytes that just failed: its start byte was
    /// dropped, and its other `len - 1` bytes are the first of those held (the rescan's).
    #[inline]
    pub(super) fn failed_span(&mut self, len: usize) {
        self.span = Span {
            len,
            after: self.held_bytes().saturating_sub(len.saturating_sub(1)),
        };
    }

    /// The slice path of `decode` (nothing held) found that `candidate`, at the front of what
    /// is left of the input, failed: its start byte is dropped (counted by the step), and its
    /// other bytes are used and held for the rescan, as the per-byte path holds them, so that
    /// the error's bytes lie within the bytes used. A failure costs this copy (at most `N - 1`
    /// bytes) and a rescan over the bytes held rather than in the input; a byte costs nothing
    /// more.
    pub(super) fn hold_failed(&mut self, candidate: &[u8]) {
        self.append(candidate.get(1..).unwrap_or(&[]));
        self.decide_at = 0;
        self.span = Span {
            len: candidate.len(),
            after: 0,
        };
    }
}
