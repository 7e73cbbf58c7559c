//! The candidate's state machine: one byte step, completion, rescans, end of stream.

use super::*;

impl<const N: usize> Decoder<N> {
    /// End of stream: fail the incomplete candidate (if any), rescan what it held, and hand
    /// every resulting event to `on_event`. Afterwards the decoder is empty. An incomplete
    /// candidate is reported as [`Error::Truncated`] and is not counted as a checksum or
    /// length error.
    ///
    /// ```
    /// use aydp_proto::{Decoder, Error, Profile};
    /// let mut dec = Decoder::<32>::new(Profile::Spec);
    /// let mut evs = Vec::new();
    /// dec.feed(&[0xFF, 0x80, 0x07], |e| evs.push(e.map(|_| ())));
    /// dec.flush(|e| evs.push(e.map(|_| ())));
    /// assert_eq!(evs, vec![Err(Error::Truncated)]);
    /// ```
    pub fn flush<F: FnMut(Result<Frame<'_>>)>(&mut self, mut on_event: F) {
        while let Some(e) = self.flush_next() {
            on_event(e);
        }
    }

    /// End of stream, one event at a time: the next event [`Decoder::flush`] would hand over,
    /// or `None` once the decoder is empty (it is then reset). Between calls the caller may
    /// read [`Decoder::unscanned_bytes`] to place each event in the input.
    ///
    /// ```
    /// use aydp_proto::{Decoder, Error, Profile};
    /// let mut dec = Decoder::<32>::new(Profile::Spec);
    /// dec.feed(&[0xFF, 0x80, 0x07], |_| {});
    /// assert!(matches!(dec.flush_next(), Some(Err(Error::Truncated))));
    /// assert!(dec.flush_next().is_none());
    /// ```
    pub fn flush_next(&mut self) -> Option<Result<Frame<'_>>> {
        self.release();
        let outcome = self.rescan_queued();
        if outcome != Outcome::More {
            return self.event(outcome);
        }
        if self.len == 0 {
            self.reset();
            return None;
        }
        self.rescan();
        Some(Err(Error::Truncated))
    }

    /// Drop a frame handed out on the previous call. Queued bytes stay where they are.
    #[inline]
    pub(super) fn release(&mut self) {
        if self.delivered {
            self.delivered = false;
            self.len = 0;
            self.need = 0;
            self.xor = 0;
        }
    }

    /// Copy `count` bytes from `buf[from..]` to `buf[to..]` (`to <= from`).
    pub(super) fn move_down(&mut self, from: usize, to: usize, count: usize) {
        let mut i = 0;
        while i < count {
            let v = self.buf.get(from.wrapping_add(i)).copied().unwrap_or(0);
            if let Some(d) = self.buf.get_mut(to.wrapping_add(i)) {
                *d = v;
            }
            i += 1;
        }
    }

    /// Close the gap of consumed bytes between the candidate and the queued bytes.
    pub(super) fn compact(&mut self) {
        if self.head != self.len {
            self.move_down(self.head, self.len, self.pending);
            self.head = self.len;
        }
    }

    /// The current candidate failed: drop its start byte and queue the rest for a rescan,
    /// ahead of the bytes already queued.
    pub(super) fn rescan(&mut self) {
        self.stats.bytes_discarded = self.stats.bytes_discarded.wrapping_add(1);
        self.compact();
        let count = self.len.saturating_sub(1).saturating_add(self.pending);
        self.move_down(1, 0, count);
        self.pending = count;
        self.head = 0;
        self.len = 0;
        self.need = 0;
        self.xor = 0;
    }

    /// Queue a byte behind bytes waiting for a rescan.
    pub(super) fn enqueue(&mut self, byte: u8) {
        if self.pending == 0 {
            self.head = self.len;
        }
        if self.head.saturating_add(self.pending) >= N {
            self.compact();
        }
        let at = self.head.saturating_add(self.pending);
        if let Some(slot) = self.buf.get_mut(at) {
            *slot = byte;
            self.pending += 1;
        } else {
            // Unreachable by construction (a failure or a delivery always frees a byte);
            // count it rather than panic.
            self.stats.bytes_discarded = self.stats.bytes_discarded.wrapping_add(1);
        }
    }

    /// The candidate holds all its announced bytes: the checksum decides.
    pub(super) fn complete(&mut self) -> Outcome {
        if self.xor == 0 {
            self.stats.frames_ok = self.stats.frames_ok.wrapping_add(1);
            self.delivered = true;
            return Outcome::Frame;
        }
        self.stats.checksum_errors = self.stats.checksum_errors.wrapping_add(1);
        self.rescan();
        Outcome::ChecksumMismatch
    }

    #[inline]
    pub(super) fn event(&self, outcome: Outcome) -> Option<Result<Frame<'_>>> {
        match outcome {
            Outcome::More => None,
            Outcome::Frame => Some(Ok(Frame::new_unchecked(
                self.buf.get(..self.len).unwrap_or(&[]),
                self.profile,
            ))),
            Outcome::BadLength(field) => Some(Err(Error::BadLength(field))),
            Outcome::ChecksumMismatch => Some(Err(Error::ChecksumMismatch)),
        }
    }

    /// Process the byte that belongs at `buf[len]`.
    #[inline]
    pub(super) fn step(&mut self, byte: u8) -> Outcome {
        let len = self.len;
        if self.need != 0 {
            if let Some(slot) = self.buf.get_mut(len) {
                *slot = byte;
            }
            let len = len.wrapping_add(1);
            self.len = len;
            self.xor ^= byte;
            if len < self.need {
                return Outcome::More;
            }
            return self.complete();
        }
        match len {
            0 => {
                match self.buf.get_mut(0) {
                    Some(slot) if byte == START => {
                        *slot = START;
                        self.len = 1;
                        self.xor = START;
                    }
                    // Noise, or a start that a decoder of capacity 0 cannot hold: either
                    // way the byte is dropped, and counted.
                    _ => self.stats.bytes_discarded = self.stats.bytes_discarded.wrapping_add(1),
                }
                Outcome::More
            }
            1 if byte == START => {
                // Y5: FF FF - the first start is dropped, the second becomes the start.
                self.stats.bytes_discarded = self.stats.bytes_discarded.wrapping_add(1);
                Outcome::More
            }
            _ => {
                if let Some(slot) = self.buf.get_mut(len) {
                    *slot = byte;
                }
                let len = len.wrapping_add(1);
                self.len = len;
                self.xor ^= byte;
                if len < EXPEDITED_HEADER_LEN {
                    return Outcome::More;
                }
                let field = u32::from_le_bytes(array_at(&self.buf, 2));
                let expedited = self.buf.get(1).copied().unwrap_or(0) & EXPEDITED != 0;
                match self.profile.frame_len(field, expedited) {
                    Some(total) if total <= N => {
                        self.need = total;
                        Outcome::More
                    }
                    _ => {
                        self.stats.length_errors = self.stats.length_errors.wrapping_add(1);
                        self.rescan();
                        Outcome::BadLength(field)
                    }
                }
            }
        }
    }
}
