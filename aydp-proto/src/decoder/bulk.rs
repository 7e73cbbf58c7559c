//! The slice path: [`Decoder::feed`] finds and checks messages in the input itself.

use super::*;

impl<const N: usize> Decoder<N> {
    /// Feed a slice, handing every event (frames and failures) to `on_event` in order.
    ///
    /// This is the bulk path. It behaves exactly like pushing the bytes one at a time with
    /// [`Decoder::push`] and draining [`Decoder::poll`] after each (same events in the same
    /// order, same counters, same rescans), but it is several times faster:
    ///
    /// - while the decoder holds nothing, messages are found and checked **in `bytes` itself**
    ///   (no copy): the 0xFF start is searched a machine word at a time, and once the header
    ///   gives the length the whole message is XORed a word at a time. Frames found this way
    ///   borrow `bytes`;
    /// - a message cut by the end of the slice is copied into the decoder's buffer; the next
    ///   call copies the rest of its body in one go, once its length is known.
    ///
    /// Feed it whole DMA buffers, UART FIFOs or datagrams.
    ///
    /// ```
    /// use aydp_proto::{Decoder, Profile};
    /// let mut dec = Decoder::<32>::new(Profile::Spec);
    /// let mut n = 0;
    /// dec.feed(&[0x00, 0xFF, 0xFF, 0x80, 0x07, 0, 0, 0, 0x78], |ev| n += ev.is_ok() as u32);
    /// assert_eq!(n, 1);
    /// assert_eq!(dec.stats().bytes_discarded, 2);
    ///
    /// // A message split across two calls is delivered by the call that completes it.
    /// dec.feed(&[0xFF, 0x89, 0x08], |_| unreachable!());
    /// dec.feed(&[0, 0, 0, 0x02, 0x7C], |ev| n += ev.is_ok() as u32);
    /// assert_eq!(n, 2);
    /// ```
    pub fn feed<F: FnMut(Result<Frame<'_>>)>(&mut self, bytes: &[u8], mut on_event: F) {
        if N < EXPEDITED_HEADER_LEN {
            // A decoder too small for a header: keep to the byte-at-a-time rules.
            for &b in bytes {
                let mut ev = self.push(b);
                while let Some(e) = ev {
                    on_event(e);
                    ev = self.poll();
                }
            }
            return;
        }
        if bytes.is_empty() {
            // Pushing nothing does nothing, not even hand out events still queued.
            return;
        }
        let mut rest = bytes;
        loop {
            // Events a rescan left queued come first: those bytes precede `rest`.
            while let Some(e) = self.poll() {
                on_event(e);
            }
            if self.len == 0 {
                self.scan_in_place(rest, &mut on_event);
                return;
            }
            let Some((&byte, after)) = rest.split_first() else {
                return;
            };
            if self.need == 0 {
                // The header is still incomplete (at most five bytes): byte by byte.
                rest = after;
                let outcome = self.step(byte);
                if let Some(e) = self.event(outcome) {
                    on_event(e);
                }
                continue;
            }
            // The length is known: copy the rest of the body in one go.
            let want = self.need.saturating_sub(self.len);
            let (body, after) = rest.split_at_checked(want).unwrap_or((rest, &[]));
            rest = after;
            let room = self.buf.get_mut(self.len..).unwrap_or(&mut []);
            if let Some(dst) = room.get_mut(..body.len()) {
                dst.copy_from_slice(body);
                self.xor ^= xor(body);
                self.len += body.len();
            }
            if self.len >= self.need {
                let outcome = self.complete();
                if let Some(e) = self.event(outcome) {
                    on_event(e);
                }
            }
        }
    }

    /// The decoder holds nothing: find and check messages in `bytes` itself, hand every event
    /// to `on_event`, and keep an incomplete last candidate in the buffer. Exactly what
    /// pushing the bytes one by one does: a failed candidate's rescan starts at the byte after
    /// its start, which here is simply the next position in `bytes`.
    pub(super) fn scan_in_place<F: FnMut(Result<Frame<'_>>)>(
        &mut self,
        mut bytes: &[u8],
        on_event: &mut F,
    ) {
        loop {
            // Noise before a start is discarded.
            let noise = if bytes.first() == Some(&START) {
                0
            } else {
                find_ff(bytes)
            };
            let from = bytes.get(noise..).unwrap_or(&[]);
            if from.is_empty() {
                self.discard(noise);
                return;
            }
            // Y5: in a run of 0xFF only the last is the start; the others are discarded.
            let run = if from.get(1) == Some(&START) {
                ff_run(from)
            } else {
                1
            };
            let start = run.saturating_sub(1);
            self.discard(noise.saturating_add(start));
            let candidate = from.get(start..).unwrap_or(&[]);
            let Some(header) = candidate.first_chunk::<EXPEDITED_HEADER_LEN>() else {
                self.hold(candidate, 0);
                return;
            };
            let field = u32::from_le_bytes([header[2], header[3], header[4], header[5]]);
            let expedited = header[1] & EXPEDITED != 0;
            match self.profile.frame_len(field, expedited) {
                Some(total) if total <= N => {
                    let Some(frame) = candidate.get(..total) else {
                        self.hold(candidate, total);
                        return;
                    };
                    if xor(frame) == 0 {
                        self.stats.frames_ok = self.stats.frames_ok.wrapping_add(1);
                        on_event(Ok(Frame::new_unchecked(frame, self.profile)));
                        bytes = candidate.get(total..).unwrap_or(&[]);
                        continue;
                    }
                    self.stats.checksum_errors = self.stats.checksum_errors.wrapping_add(1);
                    on_event(Err(Error::ChecksumMismatch));
                }
                _ => {
                    self.stats.length_errors = self.stats.length_errors.wrapping_add(1);
                    on_event(Err(Error::BadLength(field)));
                }
            }
            // The false start is dropped; scanning resumes at the byte after it.
            self.discard(1);
            bytes = candidate.get(1..).unwrap_or(&[]);
        }
    }

    /// Keep an incomplete candidate (start byte first; `need` = its length once known, else 0).
    pub(super) fn hold(&mut self, candidate: &[u8], need: usize) {
        if let Some(dst) = self.buf.get_mut(..candidate.len()) {
            dst.copy_from_slice(candidate);
            self.len = candidate.len();
            self.xor = xor(candidate);
            self.need = need;
        }
    }

    #[inline]
    pub(super) fn discard(&mut self, count: usize) {
        // Counting `count` at once wraps exactly like counting one at a time.
        self.stats.bytes_discarded = self.stats.bytes_discarded.wrapping_add(count as u32);
    }
}
