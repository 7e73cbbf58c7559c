//! The slice path: [`DeviceDecoder::feed`], and the readers' feed-until-the-first-event.

use super::*;
use crate::checked_value;
use crate::command::{MotorTest, ParameterValue, SET_PARAMETER};
use crate::layout::{motor_test as motor, set_parameter as set};
use crate::values::Motor;

impl DeviceDecoder {
    /// Feed a slice and hand every item to `on_event`, in order.
    ///
    /// This is the bulk path: it behaves exactly like pushing the bytes one at a time with
    /// [`DeviceDecoder::push`] and draining [`DeviceDecoder::poll`] after each (same items in the same order, same
    /// counters, same bytes left buffered), but while the decoder holds nothing, commands are
    /// parsed straight from `bytes` without being copied, and a false start's rescan is simply
    /// the next position in `bytes`. Bytes held from an earlier call, and a command cut by the
    /// end of the slice (at most 18 bytes), go through [`DeviceDecoder::push`].
    ///
    /// ```
    /// use aok_proto::{Command, DeviceDecoder, Error};
    /// let mut dec = DeviceDecoder::new();
    /// let mut got = Vec::new();
    /// // Noise, a motor-test start whose checksum fails, a read, and half a read.
    /// dec.feed(&[0x00, 0x31, 0x67, 0x0c, 0x67], |item| got.push(item));
    /// assert_eq!(got, [Err(Error::ChecksumMismatch), Ok(Command::ReadParameter(12))]);
    /// assert_eq!(dec.buffered(), 1);
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
        // Nothing held: parse in place.
        loop {
            let Some((&first, tail)) = rest.split_first() else {
                return;
            };
            // The common commands first: an intact parameter set or motor test is exactly
            // what `Command::parse_known` makes of it.
            if let Some(motor) = Motor::from_command_byte(first) {
                if let Some((f, after)) = rest.split_first_chunk::<{ motor::LEN }>() {
                    // The checksum covers the start byte and the value (`motor::CHECKED`).
                    if first ^ f[motor::VALUE] == f[motor::CHECKSUM] {
                        self.stats.frames_ok = self.stats.frames_ok.wrapping_add(1);
                        rest = after;
                        let value = f[motor::VALUE];
                        on_event(Ok(Command::MotorTest(MotorTest { motor, value })));
                        continue;
                    }
                }
            } else if first == SET_PARAMETER {
                if let Some((frame, after)) = rest.split_first_chunk::<{ set::LEN }>() {
                    if let Some((number, value)) = checked_value(frame) {
                        self.stats.frames_ok = self.stats.frames_ok.wrapping_add(1);
                        rest = after;
                        on_event(Ok(Command::SetParameter(ParameterValue { number, value })));
                        continue;
                    }
                }
            }
            let need = match command_len(first, tail.first().copied()) {
                Len::Is(n) => n,
                Len::More => break,
                Len::Unknown => {
                    self.stats.unknown_bytes = self.stats.unknown_bytes.wrapping_add(1);
                    self.stats.bytes_discarded = self.stats.bytes_discarded.wrapping_add(1);
                    rest = tail;
                    continue;
                }
            };
            let Some((frame, after)) = rest.split_at_checked(need) else {
                break;
            };
            match Command::parse_known(first, frame) {
                Ok(cmd) => {
                    self.stats.frames_ok = self.stats.frames_ok.wrapping_add(1);
                    rest = after;
                    on_event(Ok(cmd));
                }
                Err(Error::ChecksumMismatch) => {
                    // The false start is dropped; the rescan starts at the next byte.
                    self.stats.checksum_errors = self.stats.checksum_errors.wrapping_add(1);
                    self.stats.bytes_discarded = self.stats.bytes_discarded.wrapping_add(1);
                    rest = tail;
                    on_event(Err(Error::ChecksumMismatch));
                }
                Err(e) => {
                    self.stats.invalid = self.stats.invalid.wrapping_add(1);
                    rest = after;
                    on_event(Err(e));
                }
            }
        }
        // A command cut by the end of the slice: keep it, exactly as pushing would.
        for &byte in rest {
            let mut event = self.push(byte);
            while let Some(item) = event {
                on_event(item);
                event = self.poll();
            }
        }
    }

    /// Feed `bytes` up to and including the first item, with the bulk path of
    /// [`DeviceDecoder::feed`] (commands parsed in place while nothing is held); items an
    /// earlier call left unpolled come first. Returns how many bytes were consumed and the
    /// item. Calling it until it finds nothing in an empty slice gives exactly the items of
    /// [`DeviceDecoder::push`] and [`DeviceDecoder::poll`].
    #[cfg(any(feature = "embedded-io", feature = "embedded-io-async"))]
    pub(crate) fn feed_until(&mut self, bytes: &[u8]) -> (usize, Option<Result<Command, Error>>) {
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
        // Nothing held: parse in place (the rules of `feed`).
        loop {
            let Some((&first, tail)) = rest.split_first() else {
                return (total, None);
            };
            let need = match command_len(first, tail.first().copied()) {
                Len::Is(n) => n,
                Len::More => break,
                Len::Unknown => {
                    self.stats.unknown_bytes = self.stats.unknown_bytes.wrapping_add(1);
                    self.stats.bytes_discarded = self.stats.bytes_discarded.wrapping_add(1);
                    rest = tail;
                    continue;
                }
            };
            let Some((frame, after)) = rest.split_at_checked(need) else {
                break;
            };
            let (item, rest) = match Command::parse_known(first, frame) {
                Ok(cmd) => {
                    self.stats.frames_ok = self.stats.frames_ok.wrapping_add(1);
                    (Ok(cmd), after)
                }
                Err(Error::ChecksumMismatch) => {
                    // The false start is dropped; the rescan starts at the next byte.
                    self.stats.checksum_errors = self.stats.checksum_errors.wrapping_add(1);
                    self.stats.bytes_discarded = self.stats.bytes_discarded.wrapping_add(1);
                    (Err(Error::ChecksumMismatch), tail)
                }
                Err(e) => {
                    self.stats.invalid = self.stats.invalid.wrapping_add(1);
                    (Err(e), after)
                }
            };
            return (total.saturating_sub(rest.len()), Some(item));
        }
        // A command cut by the end of the slice: keep it, exactly as pushing would.
        while let Some((&byte, after)) = rest.split_first() {
            rest = after;
            if let Some(item) = self.push(byte) {
                return (total.saturating_sub(rest.len()), Some(item));
            }
        }
        (total, None)
    }
}
