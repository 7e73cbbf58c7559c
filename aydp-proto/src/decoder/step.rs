//! The step: every rule of the decoder, once, applied to a window of bytes (the decoder's
//! buffer, or on the slice path the input itself); and its reports turned into events.

use super::*;

impl<const N: usize> Decoder<N> {
    /// The rules, applied to the bytes at the front of `window` (the next byte not yet decided
    /// on comes first). Every path (`feed` a byte or a slice at a time, the pull form
    /// `decode` and `end`, so the readers too) decides through this function; they differ
    /// only in where the window lies.
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
    // Inlined into `advance` (the per-byte path) on 64-bit hosts, where the call's register saving
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

    /// The stream ended inside the candidate held (if any): its start byte is dropped and the
    /// rest waits for the rescan, as after any failure. Returns how many bytes the candidate
    /// held, or `None` if nothing was held.
    pub(super) fn give_up(&mut self) -> Option<usize> {
        let pending = self.held_bytes();
        if pending == 0 {
            return None;
        }
        discard(&mut self.stats, 1);
        self.start = self.start.wrapping_add(1);
        self.decide_at = 0;
        Some(pending)
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
