//! The slice path: [`PcDecoder::feed`], and the readers' feed-until-the-first-event. Both run
//! the step over the input itself while nothing is held.

use super::*;

impl PcDecoder {
    /// Feed a slice and hand every event (messages and failures) to `on_event`, in order.
    ///
    /// This is the bulk path: it behaves exactly like pushing the bytes one at a time with
    /// [`PcDecoder::push`] and draining [`PcDecoder::poll`] after each (same events in the same
    /// order, same counters, same pending request, same bytes left buffered: the same step
    /// decides), but while the decoder holds nothing the step runs on `bytes` itself, without
    /// copying, and a false start's rescan is simply the next position in `bytes`. Bytes held
    /// from an earlier call go through [`PcDecoder::push`]; a frame cut by the end of the slice
    /// (at most 18 bytes) is copied into the buffer.
    ///
    /// ```
    /// use aok_proto::{pc::{Expect, PcDecoder}, Ack, DebugValue, FirmwareVersion, Message};
    /// let mut dec = PcDecoder::new(FirmwareVersion::LATEST);
    /// dec.expect(Expect::Ack);
    /// let mut got = Vec::new();
    /// // A debug frame, the ack, and the first half of the next debug frame.
    /// dec.feed(&[0x1c, 0x56, 0xff, 0xff, 0xff, 0xfe, 0x57, b'O', 0x1c, 0x56], |ev| got.push(ev));
    /// assert_eq!(got, [
    ///     Ok(Message::Debug(DebugValue { number: 86, value: -2 })),
    ///     Ok(Message::Ack(Ack::Ok)),
    /// ]);
    /// assert_eq!(dec.expecting(), Expect::Nothing);
    /// assert_eq!(dec.held_bytes(), 2);
    /// dec.feed(&[0, 0, 0, 1, 0x57], |ev| got.push(ev));
    /// assert_eq!(got[2], Ok(Message::Debug(DebugValue { number: 86, value: 1 })));
    /// ```
    pub fn feed<F: FnMut(Result<Message, Error>)>(&mut self, bytes: &[u8], mut on_event: F) {
        let mut rest = bytes;
        // Bytes held from an earlier call: byte by byte until the buffer is empty.
        while self.len != 0 {
            let Some((&byte, after)) = rest.split_first() else {
                return;
            };
            rest = after;
            let mut event = self.push(byte);
            while let Some(ev) = event {
                on_event(ev);
                event = self.poll();
            }
        }
        // Nothing held: the step runs on the input itself.
        self.judge_in_place(rest, |ev| {
            on_event(ev);
            false
        });
    }

    /// Feed `bytes` up to and including the first event, with the bulk path of
    /// [`PcDecoder::feed`]; events an earlier call left unpolled come first. Returns how many
    /// bytes were consumed and the event. Calling it until it finds nothing in an empty slice
    /// gives exactly the events of [`PcDecoder::push`] and [`PcDecoder::poll`]: a caller that
    /// must act between two messages does so without deframing the bytes itself.
    ///
    /// ```
    /// use aok_proto::{pc::PcDecoder, DebugValue, FirmwareVersion, Message};
    /// let mut dec = PcDecoder::new(FirmwareVersion::LATEST);
    /// let two = [0x1c, 0x56, 0xff, 0xff, 0xff, 0xfe, 0x57, 0x1c, 0x56, 0, 0, 0, 1, 0x57];
    /// let (n, ev) = dec.feed_until(&two);
    /// assert_eq!((n, ev), (7, Some(Ok(Message::Debug(DebugValue { number: 86, value: -2 })))));
    /// let (m, ev) = dec.feed_until(&two[n..]);
    /// assert_eq!((m, ev), (7, Some(Ok(Message::Debug(DebugValue { number: 86, value: 1 })))));
    /// assert_eq!(dec.feed_until(&[]), (0, None));
    /// ```
    pub fn feed_until(&mut self, bytes: &[u8]) -> (usize, Option<Result<Message, Error>>) {
        let total = bytes.len();
        // Only after an event out of the buffer: a drained decoder is not asked again, since
        // a pending request changed since (`expect`) could decide its held bytes otherwise
        // than the next `push` will.
        if self.unpolled {
            if let Some(ev) = self.poll() {
                return (0, Some(ev));
            }
            self.unpolled = false;
        }
        let mut rest = bytes;
        // Bytes held from an earlier call: byte by byte until the buffer is empty.
        while self.len != 0 {
            let Some((&byte, after)) = rest.split_first() else {
                return (total, None);
            };
            rest = after;
            if let Some(ev) = self.push(byte) {
                self.unpolled = true;
                return (total.saturating_sub(rest.len()), Some(ev));
            }
        }
        let mut event = None;
        let used = self.judge_in_place(rest, |ev| {
            event = Some(ev);
            true
        });
        (total.saturating_sub(rest.len()).saturating_add(used), event)
    }
}
