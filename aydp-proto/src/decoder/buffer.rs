//! The bytes held between calls: a candidate cut by the end of a slice, and any bytes behind
//! a failed candidate waiting for the rescan, kept in order at `buf[start..len]`.

use super::*;

impl<const N: usize> Decoder<N> {
    /// Nothing is held: keep `bytes`, which the step left undecided until it holds `need`.
    #[inline]
    pub(super) fn hold(&mut self, bytes: &[u8], need: usize) {
        self.append(bytes);
        self.decide_at = self.start.wrapping_add(need);
    }

    /// The bytes held are one undecided candidate: append the part of `bytes` the step needs
    /// before it can decide (or all of `bytes` if that is fewer) and return the rest.
    #[inline]
    pub(super) fn take_needed<'b>(&mut self, bytes: &'b [u8]) -> &'b [u8] {
        let want = self.decide_at.saturating_sub(self.len);
        let (part, rest) = bytes.split_at_checked(want).unwrap_or((bytes, &[]));
        self.append(part);
        rest
    }

    /// Moves the bytes held to the front of the buffer.
    pub(super) fn compact(&mut self) {
        if self.start == 0 {
            return;
        }
        let held = self.len.saturating_sub(self.start);
        let mut i = 0;
        while i < held {
            let v = self
                .buf
                .get(self.start.wrapping_add(i))
                .copied()
                .unwrap_or(0);
            if let Some(d) = self.buf.get_mut(i) {
                *d = v;
            }
            i += 1;
        }
        if self.decide_at != 0 {
            self.decide_at = self.decide_at.wrapping_sub(self.start);
        }
        self.len = held;
        self.start = 0;
    }

    /// Stores `bytes` behind the bytes held, moving those to the front of the buffer first
    /// if there is no room behind them. Only the step decides what the bytes are.
    pub(super) fn append(&mut self, bytes: &[u8]) {
        if self.start == self.len {
            self.start = 0;
            self.len = 0;
        }
        if self.len.saturating_add(bytes.len()) > N {
            self.compact();
        }
        let room = self.buf.get_mut(self.len..).unwrap_or(&mut []);
        if let Some(dst) = room.get_mut(..bytes.len()) {
            dst.copy_from_slice(bytes);
            self.len = self.len.wrapping_add(bytes.len());
        } else {
            // Unreachable by construction (the bytes held never exceed one candidate of at
            // most `N` bytes, and callers append at most what the step still needs); count
            // the bytes rather than panic.
            discard(&mut self.stats, bytes.len());
        }
    }
}
