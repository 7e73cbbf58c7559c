//! The slice path: [`PcDecoder::feed`], and the readers' feed-until-the-first-event.

use super::*;
use crate::checked_value;
use crate::message::DebugValue;

impl PcDecoder {
    /// Feed a slice and hand every event (messages and failures) to `on_event`, in order.
    ///
    /// This is the bulk path: it behaves exactly like pushing the bytes one at a time with
    /// [`PcDecoder::push`] and draining [`PcDecoder::poll`] after each (same events in the same order, same
    /// counters, same pending request, same bytes left buffered), but while the decoder holds
    /// nothing, frames are parsed straight from `bytes` without being copied, and a false
    /// start's rescan is simply the next position in `bytes`. Bytes held from an earlier call,
    /// and a frame cut by the end of the slice (at most 18 bytes), go through
    /// [`PcDecoder::push`].
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
    /// assert_eq!(dec.buffered(), 2);
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
        // Nothing held: parse in place.
        loop {
            let Some((&first, tail)) = rest.split_first() else {
                return;
            };
            let headerless = match self.expect {
                Expect::Parameter(n) if self.form == ReplyForm::Headerless => Some(n),
                _ => None,
            };
            // The common frame first: an intact debug frame, where no headerless reply is
            // pending, is exactly what `Message::parse` makes of it, and settles nothing.
            if first == DEBUG && headerless.is_none() {
                if let Some((frame, after)) = rest.split_first_chunk::<DEBUG_LEN>() {
                    if let Some((number, value)) = checked_value(frame) {
                        self.stats.frames_ok = self.stats.frames_ok.wrapping_add(1);
                        rest = after;
                        on_event(Ok(Message::Debug(DebugValue { number, value })));
                        continue;
                    }
                }
            }
            if let Some(number) = headerless {
                let Some(reply) = rest.get(..HEADERLESS_REPLY_LEN) else {
                    break;
                };
                match ParameterValue::parse_headerless(reply, number) {
                    Ok(p) => {
                        self.stats.frames_ok = self.stats.frames_ok.wrapping_add(1);
                        rest = rest.get(HEADERLESS_REPLY_LEN..).unwrap_or(&[]);
                        let m = Message::Parameter(p);
                        self.settle(&m);
                        on_event(Ok(m));
                        continue;
                    }
                    // Not a reply; maybe a debug frame (the rules below).
                    Err(_) if first == DEBUG => {}
                    Err(_) => {
                        self.stats.checksum_errors = self.stats.checksum_errors.wrapping_add(1);
                        self.stats.bytes_discarded = self.stats.bytes_discarded.wrapping_add(1);
                        rest = tail;
                        on_event(Err(Error::ChecksumMismatch));
                        continue;
                    }
                }
            }
            let Some(need) = frame_len(first, self.expect) else {
                self.stats.unknown_bytes = self.stats.unknown_bytes.wrapping_add(1);
                self.stats.bytes_discarded = self.stats.bytes_discarded.wrapping_add(1);
                rest = tail;
                continue;
            };
            let Some((frame, after)) = rest.split_at_checked(need) else {
                break;
            };
            match Message::parse(frame) {
                Ok((m, _)) => {
                    self.stats.frames_ok = self.stats.frames_ok.wrapping_add(1);
                    rest = after;
                    self.settle(&m);
                    on_event(Ok(m));
                }
                Err(Error::ChecksumMismatch) => {
                    // The false start is dropped; the rescan starts at the next byte.
                    self.stats.checksum_errors = self.stats.checksum_errors.wrapping_add(1);
                    self.stats.bytes_discarded = self.stats.bytes_discarded.wrapping_add(1);
                    rest = tail;
                    on_event(Err(Error::ChecksumMismatch));
                }
                Err(e) => {
                    // Intact but out of range (a waypoint reply with a bad slot): dropped whole.
                    self.stats.invalid = self.stats.invalid.wrapping_add(1);
                    rest = after;
                    on_event(Err(e));
                }
            }
        }
        // A frame cut by the end of the slice: keep it, exactly as pushing would.
        for &byte in rest {
            let mut event = self.push(byte);
            while let Some(ev) = event {
                on_event(ev);
                event = self.poll();
            }
        }
    }

    /// Feed `bytes` up to and including the first event, with the bulk path of
    /// [`PcDecoder::feed`] (frames parsed in place while nothing is held); events an
    /// earlier call left unpolled come first. Returns how many bytes were consumed and the
    /// event. Calling it until it finds nothing in an empty slice gives exactly the
    /// events of [`PcDecoder::push`] and [`PcDecoder::poll`].
    #[cfg(any(feature = "embedded-io", feature = "embedded-io-async"))]
    pub(crate) fn feed_until(&mut self, bytes: &[u8]) -> (usize, Option<Result<Message, Error>>) {
        let total = bytes.len();
        if let Some(ev) = self.poll() {
            return (0, Some(ev));
        }
        let mut rest = bytes;
        // Bytes held from an earlier call: byte by byte until the buffer is empty.
        while self.len != 0 {
            let Some((&byte, after)) = rest.split_first() else {
                return (total, None);
            };
            rest = after;
            if let Some(ev) = self.push(byte) {
                return (total.saturating_sub(rest.len()), Some(ev));
            }
        }
        // Nothing held: parse in place (the rules of `feed`).
        loop {
            let Some((&first, tail)) = rest.split_first() else {
                return (total, None);
            };
            let headerless = match self.expect {
                Expect::Parameter(n) if self.form == ReplyForm::Headerless => Some(n),
                _ => None,
            };
            if let Some(number) = headerless {
                let Some(reply) = rest.get(..HEADERLESS_REPLY_LEN) else {
                    break;
                };
                match ParameterValue::parse_headerless(reply, number) {
                    Ok(p) => {
                        self.stats.frames_ok = self.stats.frames_ok.wrapping_add(1);
                        rest = rest.get(HEADERLESS_REPLY_LEN..).unwrap_or(&[]);
                        let m = Message::Parameter(p);
                        self.settle(&m);
                        return (total.saturating_sub(rest.len()), Some(Ok(m)));
                    }
                    Err(_) if first == DEBUG => {}
                    Err(_) => {
                        self.stats.checksum_errors = self.stats.checksum_errors.wrapping_add(1);
                        self.stats.bytes_discarded = self.stats.bytes_discarded.wrapping_add(1);
                        let used = total.saturating_sub(tail.len());
                        return (used, Some(Err(Error::ChecksumMismatch)));
                    }
                }
            }
            let Some(need) = frame_len(first, self.expect) else {
                self.stats.unknown_bytes = self.stats.unknown_bytes.wrapping_add(1);
                self.stats.bytes_discarded = self.stats.bytes_discarded.wrapping_add(1);
                rest = tail;
                continue;
            };
            let Some((frame, after)) = rest.split_at_checked(need) else {
                break;
            };
            match Message::parse(frame) {
                Ok((m, _)) => {
                    self.stats.frames_ok = self.stats.frames_ok.wrapping_add(1);
                    self.settle(&m);
                    return (total.saturating_sub(after.len()), Some(Ok(m)));
                }
                Err(Error::ChecksumMismatch) => {
                    // The false start is dropped; the rescan starts at the next byte.
                    self.stats.checksum_errors = self.stats.checksum_errors.wrapping_add(1);
                    self.stats.bytes_discarded = self.stats.bytes_discarded.wrapping_add(1);
                    let used = total.saturating_sub(tail.len());
                    return (used, Some(Err(Error::ChecksumMismatch)));
                }
                Err(e) => {
                    self.stats.invalid = self.stats.invalid.wrapping_add(1);
                    return (total.saturating_sub(after.len()), Some(Err(e)));
                }
            }
        }
        // A frame cut by the end of the slice: keep it, exactly as pushing would.
        while let Some((&byte, after)) = rest.split_first() {
            rest = after;
            if let Some(ev) = self.push(byte) {
                return (total.saturating_sub(rest.len()), Some(ev));
            }
        }
        (total, None)
    }
}
