//! The readers' slice path (`embedded-io` features): feed until the first event.

use super::*;

impl<const N: usize> Decoder<N> {
    /// Feed `bytes` up to and including the first event, with the bulk path of
    /// [`Decoder::feed`] (messages found in place in `bytes`, bodies copied in one go), events
    /// still queued by a rescan first. Returns how many bytes were consumed and what the
    /// event was, as a [`Found`] that borrows nothing, so a reader can loop over reads and
    /// build the frame afterwards. Calling it until it finds nothing in an empty slice gives
    /// exactly the events of [`Decoder::push`] and [`Decoder::poll`].
    #[cfg(any(feature = "embedded-io", feature = "embedded-io-async"))]
    pub(crate) fn feed_until(&mut self, bytes: &[u8]) -> (usize, Found) {
        let total = bytes.len();
        if let Some(found) = self.poll_found() {
            return (0, found);
        }
        if N < EXPEDITED_HEADER_LEN {
            // A decoder too small for a header: keep to the byte-at-a-time rules.
            for (i, &b) in bytes.iter().enumerate() {
                let found = match self.push(b) {
                    None => continue,
                    Some(Ok(_)) => Found::Held,
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
            if self.len == 0 {
                let (n, found) = self.scan_until(rest);
                let found = match found {
                    Found::InPlace { at, len } => Found::InPlace {
                        at: at.saturating_add(used),
                        len,
                    },
                    other => other,
                };
                return (used.saturating_add(n), found);
            }
            let Some((&byte, after)) = rest.split_first() else {
                return (total, Found::Nothing);
            };
            let outcome = if self.need == 0 {
                // The header is still incomplete (at most five bytes): byte by byte.
                rest = after;
                self.step(byte)
            } else {
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
                if self.len < self.need {
                    continue;
                }
                self.complete()
            };
            if let Some(found) = Found::of(outcome) {
                return (total.saturating_sub(rest.len()), found);
            }
        }
    }

    /// [`Decoder::poll`], as a [`Found`].
    #[cfg(any(feature = "embedded-io", feature = "embedded-io-async"))]
    pub(super) fn poll_found(&mut self) -> Option<Found> {
        match self.poll()? {
            Ok(_) => Some(Found::Held),
            Err(e) => Some(Found::Error(e)),
        }
    }

    /// [`Decoder::scan_in_place`] up to the first event: returns the bytes consumed and the
    /// event; a frame found is at `bytes[at..at + len]`.
    #[cfg(any(feature = "embedded-io", feature = "embedded-io-async"))]
    pub(super) fn scan_until(&mut self, bytes: &[u8]) -> (usize, Found) {
        let total = bytes.len();
        let noise = if bytes.first() == Some(&START) {
            0
        } else {
            find_ff(bytes)
        };
        let from = bytes.get(noise..).unwrap_or(&[]);
        if from.is_empty() {
            self.discard(noise);
            return (total, Found::Nothing);
        }
        let run = if from.get(1) == Some(&START) {
            ff_run(from)
        } else {
            1
        };
        let start = run.saturating_sub(1);
        self.discard(noise.saturating_add(start));
        let candidate = from.get(start..).unwrap_or(&[]);
        let at = total.saturating_sub(candidate.len());
        let Some(header) = candidate.first_chunk::<EXPEDITED_HEADER_LEN>() else {
            self.hold(candidate, 0);
            return (total, Found::Nothing);
        };
        let field = u32::from_le_bytes([header[2], header[3], header[4], header[5]]);
        let expedited = header[1] & EXPEDITED != 0;
        let found = match self.profile.frame_len(field, expedited) {
            Some(len) if len <= N => {
                let Some(frame) = candidate.get(..len) else {
                    self.hold(candidate, len);
                    return (total, Found::Nothing);
                };
                if xor(frame) == 0 {
                    self.stats.frames_ok = self.stats.frames_ok.wrapping_add(1);
                    return (at.saturating_add(len), Found::InPlace { at, len });
                }
                self.stats.checksum_errors = self.stats.checksum_errors.wrapping_add(1);
                Found::Error(Error::ChecksumMismatch)
            }
            _ => {
                self.stats.length_errors = self.stats.length_errors.wrapping_add(1);
                Found::Error(Error::BadLength(field))
            }
        };
        // The false start is dropped; the next call resumes at the byte after it.
        self.discard(1);
        (at.saturating_add(1), found)
    }

    /// The end of the stream, one event at a time: what [`Decoder::flush`] hands out, in the
    /// same order, with each incomplete candidate as [`Found::Truncated`] (with its length).
    /// `None` once the decoder is empty.
    #[cfg(any(feature = "embedded-io", feature = "embedded-io-async"))]
    pub(crate) fn flush_until(&mut self) -> Option<Found> {
        if let Some(found) = self.poll_found() {
            return Some(found);
        }
        if self.len == 0 {
            self.reset();
            return None;
        }
        let pending = self.len;
        self.rescan();
        Some(Found::Truncated(pending))
    }

    /// The frame a [`Found::Held`] stands for (until the next call).
    #[cfg(any(feature = "embedded-io", feature = "embedded-io-async"))]
    pub(crate) fn held_frame(&self) -> Frame<'_> {
        Frame::new_unchecked(self.buf.get(..self.len).unwrap_or(&[]), self.profile)
    }
}

/// What [`Decoder::feed_until`] or [`Decoder::flush_until`] found.
#[cfg(any(feature = "embedded-io", feature = "embedded-io-async"))]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Found {
    /// Every byte was consumed without an event.
    Nothing,
    /// A frame held in the decoder's buffer ([`Decoder::held_frame`]).
    Held,
    /// A frame at `bytes[at..at + len]` of the slice fed.
    InPlace { at: usize, len: usize },
    /// A failed candidate.
    Error(Error),
    /// End of stream: an incomplete candidate of this many bytes was given up.
    Truncated(usize),
}

#[cfg(any(feature = "embedded-io", feature = "embedded-io-async"))]
impl Found {
    pub(super) fn of(outcome: Outcome) -> Option<Self> {
        match outcome {
            Outcome::More => None,
            Outcome::Frame => Some(Found::Held),
            Outcome::BadLength(field) => Some(Found::Error(Error::BadLength(field))),
            Outcome::ChecksumMismatch => Some(Found::Error(Error::ChecksumMismatch)),
        }
    }
}
