//! The slice path: [`DeviceDecoder::feed`], and the readers' feed-until-the-first-event. Both
//! run the step over the input itself while nothing is held.

use super::*;
use crate::step::Step;

impl DeviceDecoder {
    /// Feed a slice and hand every item to `on_event`, in order.
    ///
    /// This is the bulk path: it behaves exactly like pushing the bytes one at a time with
    /// [`DeviceDecoder::push`] and draining [`DeviceDecoder::poll`] after each (same items in
    /// the same order, same counters, same bytes left buffered: the same step decides), but
    /// while the decoder holds nothing the step runs on `bytes` itself, without copying, and
    /// a false start's rescan is simply the next position in `bytes`. Bytes held from an
    /// earlier call go through [`DeviceDecoder::push`]; a command cut by the end of the slice
    /// (at most 18 bytes) is copied into the buffer.
    ///
    /// ```
    /// use aok_proto::{Command, DeviceDecoder, Error};
    /// let mut dec = DeviceDecoder::new();
    /// let mut got = Vec::new();
    /// // Noise, a motor-test start whose checksum fails, a read, and half a read.
    /// dec.feed(&[0x00, 0x31, 0x67, 0x0c, 0x67], |item| got.push(item));
    /// let mismatch = Error::ChecksumMismatch { id: 0x31, computed: 0x56, received: 0x0c };
    /// assert_eq!(got, [Err(mismatch), Ok(Command::ReadParameter(12))]);
    /// assert_eq!(dec.held_bytes(), 1);
    /// dec.feed(&[0x0d], |item| got.push(item));
    /// assert_eq!(got[2], Ok(Command::ReadParameter(13)));
    /// assert_eq!(dec.stats().unknown_bytes, 1);
    /// ```
    pub fn feed<F: FnMut(Result<Command, Error>)>(&mut self, bytes: &[u8], mut on_event: F) {
        let mut rest = bytes;
        // Bytes held from an earlier call: byte by byte until the buffer is empty.
        while self.len != 0 {
            let Some((&byte, after)) = rest.split_first() else {
                return;
            };
            rest = after;
            let mut event = self.push(byte);
            while let Some(item) = event {
                on_event(item);
                event = self.poll();
            }
        }
        // Nothing held: the step runs on the input itself.
        while !rest.is_empty() {
            match Self::judge(&mut self.stats, rest, &mut on_event) {
                Step::Need(need) => return self.hold(rest, need),
                Step::Used(used) => rest = rest.get(used..).unwrap_or(&[]),
            }
        }
    }

    /// Feed `bytes` up to and including the first item, with the bulk path of
    /// [`DeviceDecoder::feed`]; items an earlier call left unpolled come first. Returns how
    /// many bytes were consumed and the item. Calling it until it finds nothing in an empty
    /// slice gives exactly the items of [`DeviceDecoder::push`] and [`DeviceDecoder::poll`]: a
    /// caller that must act between two commands does so without deframing the bytes itself.
    ///
    /// ```
    /// use aok_proto::{Command, DeviceDecoder};
    /// let mut dec = DeviceDecoder::new();
    /// // Two reads of parameters 12 and 13.
    /// let (n, item) = dec.feed_until(&[0x67, 0x0c, 0x67, 0x0d]);
    /// assert_eq!((n, item), (2, Some(Ok(Command::ReadParameter(12)))));
    /// let (m, item) = dec.feed_until(&[0x67, 0x0d]);
    /// assert_eq!((m, item), (2, Some(Ok(Command::ReadParameter(13)))));
    /// assert_eq!(dec.feed_until(&[]), (0, None));
    /// ```
    pub fn feed_until(&mut self, bytes: &[u8]) -> (usize, Option<Result<Command, Error>>) {
        let total = bytes.len();
        if let Some(item) = self.poll() {
            return (0, Some(item));
        }
        let mut rest = bytes;
        // Bytes held from an earlier call: byte by byte until the buffer is empty.
        while self.len != 0 {
            let Some((&byte, after)) = rest.split_first() else {
                return (total, None);
            };
            rest = after;
            if let Some(item) = self.push(byte) {
                return (total.saturating_sub(rest.len()), Some(item));
            }
        }
        // Nothing held: the step runs on the input itself.
        let mut event = None;
        while !rest.is_empty() {
            match Self::judge(&mut self.stats, rest, &mut |e| event = Some(e)) {
                Step::Need(need) => {
                    self.hold(rest, need);
                    break;
                }
                Step::Used(used) => rest = rest.get(used..).unwrap_or(&[]),
            }
            if event.is_some() {
                return (total.saturating_sub(rest.len()), event);
            }
        }
        (total, None)
    }
}
