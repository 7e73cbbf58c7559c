//! The step: every rule of the decoder, once, applied to a window of bytes (the decoder's
//! buffer, or on the slice path the input itself); and the buffer it keeps between calls.

use super::*;

impl<const N: usize> Decoder<N> {
    /// The rules, applied to the bytes at the front of `window` (the next byte not yet decided
    /// on comes first). Every path (`push`, `poll`, `feed`, `flush`, the readers) decides
    /// through this function; they differ only in where the window lies.
    ///
    /// - Bytes before a 0xFF start are noise, dropped and counted.
    /// - Y5: a 0xFF followed by 0xFF is dropped; the last of a run is the start.
    /// - The length field is checked the moment it is complete, against the profile's minimum
    ///   and the capacity `N` (Y5).
    /// - Once the announced number of bytes is there, the XOR checksum decides (Y4).
    /// - After a failure only the start byte is dropped: the caller resumes at the byte after
    ///   it (the rescan), so a message hidden behind a false start is still found.
    ///
    /// Each decision depends on a fixed prefix of the window only (one byte, two, six, the
    /// announced length), so it is the same whether the window holds more bytes or not.
    #[inline(always)]
    pub(super) fn step(profile: Profile, stats: &mut Stats, window: &[u8]) -> Step {
        let Some(&first) = window.first() else {
            return Step::Need(1);
        };
        if first != START {
            // `find_ff` only skips work: it counts the bytes before the next start a word
            // at a time.
            let noise = find_ff(window);
            discard(stats, noise);
            return Step::Noise(noise);
        }
        let Some(&second) = window.get(1) else {
            return Step::Need(2);
        };
        if second == START {
            // Y5: in a run of 0xFF only the last can be a start.
            let dropped = ff_run(window).saturating_sub(1);
            discard(stats, dropped);
            return Step::Noise(dropped);
        }
        let Some(header) = window.first_chunk::<EXPEDITED_HEADER_LEN>() else {
            return Step::Need(EXPEDITED_HEADER_LEN);
        };
        let field = u32::from_le_bytes([header[2], header[3], header[4], header[5]]);
        let total = match profile.frame_len(field, second & EXPEDITED != 0) {
            Some(total) if total <= N => total,
            _ => {
                stats.length_errors = stats.length_errors.wrapping_add(1);
                discard(stats, 1);
                return Step::Failed(Error::BadLength(field));
            }
        };
        let Some(frame) = window.get(..total) else {
            return Step::Need(total);
        };
        if xor(frame) == 0 {
            stats.frames_ok = stats.frames_ok.wrapping_add(1);
            Step::Frame(total)
        } else {
            stats.checksum_errors = stats.checksum_errors.wrapping_add(1);
            discard(stats, 1);
            Step::Mismatch(total)
        }
    }

    /// Runs the step over the bytes held until it reports a frame or a failure, or needs more
    /// bytes (`Need`; also when nothing is held). A frame reported is at
    /// `buf[start - total..start]` until the next call.
    // Inlined into `push_slow` and `poll` on 64-bit hosts, where the call's register saving
    // costs more than the code it spares; a call on 32-bit targets, where inlining it costs
    // more (both measured with the x86 callgrind bench and `scripts/cm3-bench.sh`).
    #[cfg_attr(target_pointer_width = "64", inline(always))]
    pub(super) fn examine(&mut self) -> Step {
        loop {
            let held = self.buf.get(self.start..self.len).unwrap_or(&[]);
            if held.is_empty() {
                self.reset();
                return Step::Need(1);
            }
            if self.len < self.decide_at {
                // Already examined: undecided until `decide_at` is reached.
                return Step::Need(self.decide_at.wrapping_sub(self.start));
            }
            let step = Self::step(self.profile, &mut self.stats, held);
            self.decide_at = 0;
            match step {
                Step::Need(n) => {
                    self.decide_at = self.start.wrapping_add(n);
                    return step;
                }
                Step::Noise(n) => self.start = self.start.wrapping_add(n),
                Step::Frame(n) => {
                    self.start = self.start.wrapping_add(n);
                    return step;
                }
                Step::Failed(_) | Step::Mismatch(_) => {
                    self.start = self.start.wrapping_add(1);
                    return step;
                }
            }
        }
    }

    /// The event of a step's report on the bytes held (see [`Decoder::examine`]).
    #[inline]
    pub(super) fn event(&self, step: Step) -> Option<Result<Frame<'_>>> {
        match step {
            Step::Frame(total) => {
                let at = self.start.wrapping_sub(total);
                let frame = self.buf.get(at..self.start).unwrap_or(&[]);
                Some(Ok(Frame::new_unchecked(frame, self.profile)))
            }
            Step::Failed(e) => Some(Err(e)),
            Step::Mismatch(total) => Some(Err(self.mismatch_held(total))),
            Step::Need(_) | Step::Noise(_) => None,
        }
    }

    /// The [`Error::ChecksumMismatch`] of the candidate of `total` bytes that started one byte
    /// before the bytes held (its start byte was just dropped).
    pub(super) fn mismatch_held(&self, total: usize) -> Error {
        let at = self.start.wrapping_sub(1);
        let end = at.saturating_add(total);
        Error::mismatch(self.buf.get(at..end).unwrap_or(&[]))
    }

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
    /// read [`Decoder::held_bytes`] to place each event in the input.
    ///
    /// ```
    /// use aydp_proto::{Decoder, Error, Profile};
    /// let mut dec = Decoder::<32>::new(Profile::Spec);
    /// dec.feed(&[0xFF, 0x80, 0x07], |_| {});
    /// assert!(matches!(dec.flush_next(), Some(Err(Error::Truncated))));
    /// assert!(dec.flush_next().is_none());
    /// ```
    pub fn flush_next(&mut self) -> Option<Result<Frame<'_>>> {
        let step = self.examine();
        if let Step::Need(_) = step {
            return self.give_up().map(Err);
        }
        self.event(step)
    }

    /// The stream ended inside the candidate held (if any): its start byte is dropped and the
    /// rest waits for the rescan, as after any failure.
    pub(super) fn give_up(&mut self) -> Option<Error> {
        if self.start == self.len {
            return None;
        }
        discard(&mut self.stats, 1);
        self.start = self.start.wrapping_add(1);
        self.decide_at = 0;
        Some(Error::Truncated)
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

/// Counts `count` bytes as discarded (at once: it wraps exactly like counting one at a time).
// Out of line: inlined, the optimiser keeps every counter in a register across the loop of
// `examine`, and loads and spills them on each call of `poll_held` (issue 29: `push` 36.8 ->
// 36.4, `feed` 8.8 -> 8.7 instructions per byte on Cortex-M3).
#[inline(never)]
pub(super) fn discard(stats: &mut Stats, count: usize) {
    stats.bytes_discarded = stats.bytes_discarded.wrapping_add(count as u32);
}
