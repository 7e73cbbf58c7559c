//! The slice fast path of [`Decode::feed`](crate::Decode::feed) (and of the pull form): while
//! the decoder holds nothing, the step runs on the input itself; otherwise the input is copied
//! behind the bytes held in runs, as many bytes as the step needs before it can decide.

use super::*;

impl<const N: usize> Decoder<N> {
    /// Every event of `bytes` (of any length) handed to `on_event` in order, with exactly the
    /// events, counters and rescans of feeding the bytes one at a time (the same step
    /// decides), several times faster:
    ///
    /// - while the decoder holds nothing, the step runs **on `bytes` itself** (no copy): the
    ///   0xFF start is searched a machine word at a time, and once the header gives the length
    ///   the whole message is XORed a word at a time. Frames found this way borrow `bytes`;
    /// - a message cut by the end of the slice is copied into the decoder's buffer; the next
    ///   call copies the rest of its body in one go, once its length is known.
    pub(super) fn feed_bulk<F: FnMut(Result<Frame<'_>>)>(&mut self, bytes: &[u8], mut on_event: F) {
        if N < EXPEDITED_HEADER_LEN {
            // A decoder too small for a header: keep to the byte-at-a-time path, events a
            // pull-form caller left queued first.
            while let Some(e) = self.poll() {
                on_event(e);
            }
            for &b in bytes {
                self.feed_byte(b, &mut on_event);
            }
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

    /// The decoder holds nothing: runs the step over `bytes` itself up to and including the
    /// first frame or failure, and returns how many bytes that took with the step's report (a
    /// frame reported ends there). Reaching the end undecided, it holds the undecided bytes
    /// and reports `Need`. A failed candidate's rescan is simply the next position in `bytes`.
    #[inline(always)]
    pub(super) fn scan_in_place(&mut self, bytes: &[u8]) -> (usize, Step) {
        let mut at = 0;
        loop {
            let window = bytes.get(at..).unwrap_or(&[]);
            if window.is_empty() {
                return (at, Step::Noise(0));
            }
            match Self::step(self.profile, &mut self.stats, window) {
                Step::Need(n) => {
                    self.hold(window, n);
                    return (bytes.len(), Step::Need(n));
                }
                Step::Noise(n) => at = at.saturating_add(n),
                Step::Frame(n) => return (at.saturating_add(n), Step::Frame(n)),
                Step::Failed(e) => return (at.saturating_add(1), Step::Failed(e)),
                Step::Mismatch(total) => return (at.saturating_add(1), Step::Mismatch(total)),
            }
        }
    }
}
