//! Feed until the first event: [`Decoder::feed_until`], and the readers' form of it
//! (`embedded-io` features).

use super::*;

impl<const N: usize> Decoder<N> {
    /// Feed `bytes` up to and including the first event (a frame or a failure), with the
    /// bulk path of [`Decoder::feed`]; events an earlier call left queued come first. Returns
    /// how many bytes were consumed and the event, if any (`None` when every byte was
    /// consumed without one). A frame borrows `bytes` (found in place) or the decoder (held
    /// across calls). Calling it again on the rest gives exactly the events of
    /// [`Decoder::push`] and [`Decoder::poll`]: a caller that must act between two messages
    /// does so without deframing the bytes itself.
    ///
    /// ```
    /// use aydp_proto::{Decoder, Profile};
    /// let mut dec = Decoder::<32>::new(Profile::Spec);
    /// let two = [0xFF, 0x80, 0x07, 0, 0, 0, 0x78, 0xFF, 0x89, 0x08, 0, 0, 0, 0x02, 0x7C];
    /// let (n, ev) = dec.feed_until(&two);
    /// assert_eq!((n, ev.map(|r| r.map(|f| f.base_type()))), (7, Some(Ok(0))));
    /// let (m, ev) = dec.feed_until(&two[n..]);
    /// assert_eq!((m, ev.map(|r| r.map(|f| f.base_type()))), (8, Some(Ok(9))));
    /// assert_eq!(dec.feed_until(&[0x00]).0, 1);
    /// ```
    pub fn feed_until<'a>(&'a mut self, bytes: &'a [u8]) -> (usize, Option<Result<Frame<'a>>>) {
        let (n, found) = self.find_until(bytes);
        let event = match found {
            Found::Nothing | Found::Truncated(_) => None,
            Found::Error(e) => Some(Err(e)),
            Found::InPlace { at, len } => Some(Ok(Frame::new_unchecked(
                bytes.get(at..at.saturating_add(len)).unwrap_or(&[]),
                self.profile,
            ))),
            Found::Held(len) => Some(Ok(self.held_frame(len))),
        };
        (n, event)
    }

    /// Feed `bytes` up to and including the first event, with the bulk path of
    /// [`Decoder::feed`] (the step run on `bytes` itself, bodies copied in one go), events
    /// still queued by a rescan first. Returns how many bytes were consumed and what the
    /// event was, as a [`Found`] that borrows nothing, so a reader can loop over reads and
    /// build the frame afterwards. Calling it until it finds nothing in an empty slice gives
    /// exactly the events of [`Decoder::push`] and [`Decoder::poll`].
    pub(crate) fn find_until(&mut self, bytes: &[u8]) -> (usize, Found) {
        let total = bytes.len();
        if let Some(found) = self.poll_found() {
            return (0, found);
        }
        if N < EXPEDITED_HEADER_LEN {
            // A decoder too small for a header: keep to the byte-at-a-time path.
            for (i, &b) in bytes.iter().enumerate() {
                let found = match self.push(b) {
                    None => continue,
                    Some(Ok(frame)) => Found::Held(frame.as_bytes().len()),
                    Some(Err(e)) => Found::Error(e),
                };
                return (i.saturating_add(1), found);
            }
            return (total, Found::Nothing);
        }
        let mut rest = bytes;
        loop {
            let used = total.saturating_sub(rest.len());
            if let Some(found) = self.poll_found() {
                return (used, found);
            }
            if self.len == self.start {
                let (n, step) = self.scan_in_place(rest);
                let end = used.saturating_add(n);
                let found = match step {
                    Step::Frame(len) => Found::InPlace {
                        at: end.saturating_sub(len),
                        len,
                    },
                    Step::Failed(e) => Found::Error(e),
                    Step::Mismatch(total) => {
                        let at = used.saturating_add(n).saturating_sub(1);
                        let end = at.saturating_add(total);
                        Found::Error(Error::mismatch(bytes.get(at..end).unwrap_or(&[])))
                    }
                    Step::Need(_) | Step::Noise(_) => Found::Nothing,
                };
                return (end, found);
            }
            if rest.is_empty() {
                return (total, Found::Nothing);
            }
            rest = self.take_needed(rest);
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

    /// [`Decoder::poll`], as a [`Found`].
    pub(super) fn poll_found(&mut self) -> Option<Found> {
        match self.examine() {
            Step::Frame(total) => Some(Found::Held(total)),
            Step::Failed(e) => Some(Found::Error(e)),
            Step::Mismatch(total) => Some(Found::Error(self.mismatch_held(total))),
            Step::Need(_) | Step::Noise(_) => None,
        }
    }

    /// The end of the stream, one event at a time: what [`Decoder::flush`] hands out, in the
    /// same order, with each incomplete candidate as [`Found::Truncated`] (with its length).
    /// `None` once the decoder is empty.
    #[cfg_attr(
        not(any(feature = "embedded-io", feature = "embedded-io-async")),
        allow(dead_code)
    )]
    pub(crate) fn flush_until(&mut self) -> Option<Found> {
        if let Some(found) = self.poll_found() {
            return Some(found);
        }
        let pending = self.len.saturating_sub(self.start);
        self.give_up()?;
        Some(Found::Truncated(pending))
    }

    /// The frame of `len` bytes a [`Found::Held`] stands for (until the next call).
    pub(crate) fn held_frame(&self, len: usize) -> Frame<'_> {
        let at = self.start.saturating_sub(len);
        Frame::new_unchecked(self.buf.get(at..self.start).unwrap_or(&[]), self.profile)
    }
}

/// What [`Decoder::find_until`] or [`Decoder::flush_until`] found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Found {
    /// Every byte was consumed without an event.
    Nothing,
    /// A frame of this many bytes held in the decoder's buffer ([`Decoder::held_frame`]).
    Held(usize),
    /// A frame at `bytes[at..at + len]` of the slice fed.
    InPlace { at: usize, len: usize },
    /// A failed candidate.
    Error(Error),
    /// End of stream: an incomplete candidate of this many bytes was given up.
    Truncated(usize),
}
