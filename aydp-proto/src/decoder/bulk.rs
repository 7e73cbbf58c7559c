//! The slice path: [`Decoder::feed`] runs the step over the input itself while nothing is
//! held, and copies the input behind the bytes held in runs otherwise.

use super::*;

impl<const N: usize> Decoder<N> {
    /// Feed a slice, handing every event (frames and failures) to `on_event` in order.
    ///
    /// This is the bulk path. It behaves exactly like pushing the bytes one at a time with
    /// [`Decoder::push`] and draining [`Decoder::poll`] after each (same events in the same
    /// order, same counters, same rescans: the same step decides), but it is several times
    /// faster:
    ///
    /// - while the decoder holds nothing, the step runs **on `bytes` itself** (no copy): the
    ///   0xFF start is searched a machine word at a time, and once the header gives the length
    ///   the whole message is XORed a word at a time. Frames found this way borrow `bytes`;
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
            // A decoder too small for a header: keep to the byte-at-a-time path.
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
            while let Some(e) = self.poll_held() {
                on_event(e);
            }
            if self.len == self.start {
                break;
            }
            // The bytes held are one undecided candidate: copy the input behind them up to
            // the point where the step can decide.
            if rest.is_empty() {
                return;
            }
            rest = self.take_needed(rest);
        }
        // Nothing held: the step runs on the input itself; a failed candidate's rescan is
        // simply the next position.
        let profile = self.profile;
        loop {
            if rest.is_empty() {
                return;
            }
            match Self::step(profile, &mut self.stats, rest) {
                Step::Need(n) => return self.hold(rest, n),
                Step::Noise(n) => rest = rest.get(n..).unwrap_or(&[]),
                Step::Frame(n) => {
                    let (frame, after) = rest.split_at_checked(n).unwrap_or((rest, &[]));
                    on_event(Ok(Frame::new_unchecked(frame, profile)));
                    rest = after;
                }
                Step::Mismatch(total) => {
                    let e = Error::mismatch(rest.get(..total).unwrap_or(&[]));
                    rest = rest.get(1..).unwrap_or(&[]);
                    on_event(Err(e));
                }
                Step::Failed(e) => {
                    rest = rest.get(1..).unwrap_or(&[]);
                    on_event(Err(e));
                }
            }
        }
    }

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
}
