//! The PC (ground tool) side: encoders for every command, and a decoder of the device's stream that
//! knows which request is pending.

use crate::command::{Command, MAX_COMMAND_LEN, ParameterValue, WAYPOINT};
use crate::message::{
    DEBUG, DEBUG_LEN, HEADED_REPLY_LEN, HEADERLESS_REPLY_LEN, Message, PARAMETER_REPLY,
    WAYPOINT_LEN,
};
use crate::stats::DecoderStats;
use crate::values::{FirmwareVersion, ReplyForm, WaypointSlot};
use crate::{Error, shift_left};

/// `63 01`, debug off, ready to send.
pub const DEBUG_OFF: [u8; 2] = [0x63, 0x01];
/// `63 02`, debug on, ready to send.
pub const DEBUG_ON: [u8; 2] = [0x63, 0x02];

/// Encode any command (the same as [`Command::emit`]).
///
/// ```
/// use aok_proto::{pc, Command, ParameterValue};
/// let mut buf = [0u8; 19];
/// let n = pc::encode(&Command::SetParameter(ParameterValue { number: 12, value: 1500 }), &mut buf)?;
/// assert_eq!(&buf[..n], &[0x73, 0x0c, 0x00, 0x00, 0x05, 0xdc, 0xd5]);
/// # Ok::<(), aok_proto::Error>(())
/// ```
pub fn encode(command: &Command, buf: &mut [u8]) -> Result<usize, Error> {
    command.emit(buf)
}

/// What the PC is waiting for. It tells the decoder how to read headerless parameter replies and
/// whether single bytes 'O'/'E'/'I' are acks.
///
/// ```
/// use aok_proto::pc::Expect;
/// assert_eq!(Expect::default(), Expect::Nothing);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Expect {
    /// No request pending: only debug frames and self-describing replies are decoded.
    #[default]
    Nothing,
    /// An ack ('O', 'E' or 'I') after `73` or `77`.
    Ack,
    /// The reply to `67 NUM`.
    Parameter(u8),
    /// The 16 replies to `47 NUM`; pending until the reply for NUM+15 arrives.
    Bulk(u8),
    /// The reply to `78 NUM`.
    Waypoint(WaypointSlot),
}

/// Byte-at-a-time decoder of the device's stream.
///
/// * Debug frames (`1C`), headed parameter replies (`FF`, firmware >= 0.31) and waypoint replies (`77`)
///   are decoded at any time; they describe themselves and carry a checksum.
/// * 'O'/'E'/'I' are acks only while [`Expect::Ack`] is pending; otherwise they are unknown bytes.
/// * A headerless (<= 0.30) parameter reply is read only while [`Expect::Parameter`] is pending and the
///   firmware is <= 0.30. Then every byte may start a reply: a `1C` is first tried as a reply (5 bytes,
///   checksum over B1..B4) and, if that checksum fails, as a debug frame.
/// * A byte inside a frame is never an ack; a failed checksum rescans from the byte after the false
///   start, so an ack or frame hidden there is still found.
///
/// ```
/// use aok_proto::{pc::{Expect, PcDecoder}, FirmwareVersion, Message, ParameterValue};
/// let mut dec = PcDecoder::new(FirmwareVersion::new(0, 30));
/// dec.expect(Expect::Parameter(12));
/// let mut got = None;
/// for b in [0x00, 0x00, 0x05, 0xdc, 0xd9] {
///     if let Some(m) = dec.push(b).next() { got = Some(m); }
/// }
/// assert_eq!(got, Some(Message::Parameter(ParameterValue { number: 12, value: 1500 })));
/// assert_eq!(dec.expecting(), Expect::Nothing);
/// ```
#[derive(Debug, Clone)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PcDecoder {
    buf: [u8; MAX_COMMAND_LEN],
    len: usize,
    /// Length of the frame the front byte started, once known (0: not known). Hot-path shortcut.
    need: usize,
    form: ReplyForm,
    expect: Expect,
    /// The byte at the front already failed as a headerless reply; read it as a debug start.
    front_not_reply: bool,
    stats: DecoderStats,
}

impl PcDecoder {
    /// A decoder for a device with this firmware (it picks the parameter-reply form, K4).
    ///
    /// ```
    /// let dec = aok_proto::pc::PcDecoder::new(aok_proto::FirmwareVersion::LATEST);
    /// assert_eq!(dec.reply_form(), aok_proto::ReplyForm::Headed);
    /// ```
    pub const fn new(firmware: FirmwareVersion) -> Self {
        Self {
            buf: [0; MAX_COMMAND_LEN],
            len: 0,
            need: 0,
            form: firmware.reply_form(),
            expect: Expect::Nothing,
            front_not_reply: false,
            stats: DecoderStats {
                ok: 0,
                checksum_errors: 0,
                unknown_bytes: 0,
                invalid: 0,
                abandoned: 0,
                discarded: 0,
            },
        }
    }

    /// The parameter-reply form in use.
    ///
    /// ```
    /// let dec = aok_proto::pc::PcDecoder::new(aok_proto::FirmwareVersion::new(0, 20));
    /// assert_eq!(dec.reply_form(), aok_proto::ReplyForm::Headerless);
    /// ```
    pub const fn reply_form(&self) -> ReplyForm {
        self.form
    }

    /// Change the firmware version (and with it the reply form).
    ///
    /// ```
    /// let mut dec = aok_proto::pc::PcDecoder::new(aok_proto::FirmwareVersion::new(0, 20));
    /// dec.set_firmware(aok_proto::FirmwareVersion::new(0, 31));
    /// assert_eq!(dec.reply_form(), aok_proto::ReplyForm::Headed);
    /// ```
    pub fn set_firmware(&mut self, firmware: FirmwareVersion) {
        self.form = firmware.reply_form();
        self.need = 0;
    }

    /// Set what the PC waits for; call it just before sending the request. The decoder clears it
    /// when the matching reply or ack arrives.
    ///
    /// ```
    /// use aok_proto::pc::{Expect, PcDecoder};
    /// let mut dec = PcDecoder::new(aok_proto::FirmwareVersion::LATEST);
    /// dec.expect(Expect::Ack);
    /// assert_eq!(dec.push(b'O').next(), Some(aok_proto::Message::Ack(aok_proto::Ack::Ok)));
    /// assert_eq!(dec.push(b'O').next(), None); // no longer expected: an unknown byte
    /// ```
    pub fn expect(&mut self, expect: Expect) {
        self.expect = expect;
        self.need = 0;
    }

    /// What the decoder is waiting for.
    ///
    /// ```
    /// let dec = aok_proto::pc::PcDecoder::new(aok_proto::FirmwareVersion::LATEST);
    /// assert_eq!(dec.expecting(), aok_proto::pc::Expect::Nothing);
    /// ```
    pub const fn expecting(&self) -> Expect {
        self.expect
    }

    /// Feed one byte; the iterator yields every message it completes. Drain it.
    ///
    /// ```
    /// use aok_proto::{pc::PcDecoder, FirmwareVersion, Message, DebugValue};
    /// let mut dec = PcDecoder::new(FirmwareVersion::LATEST);
    /// let mut last = None;
    /// for b in [0x1c, 0x56, 0xff, 0xff, 0xff, 0xfe, 0x57] {
    ///     for m in dec.push(b) { last = Some(m); }
    /// }
    /// assert_eq!(last, Some(Message::Debug(DebugValue { number: 86, value: -2 })));
    /// ```
    pub fn push(&mut self, byte: u8) -> Messages<'_> {
        if self.len >= MAX_COMMAND_LEN {
            // Only reachable when an earlier iterator was not drained.
            self.drop_front();
        }
        if let Some(slot) = self.buf.get_mut(self.len) {
            *slot = byte;
            self.len = self.len.wrapping_add(1);
        }
        Messages {
            dec: self,
            flush: false,
        }
    }

    /// Feed a slice and hand every message to `on_message`, in order.
    ///
    /// This is the bulk path: it behaves exactly like pushing the bytes one at a time with
    /// [`PcDecoder::push`] and draining each iterator (same messages in the same order, same
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
    /// dec.feed(&[0x1c, 0x56, 0xff, 0xff, 0xff, 0xfe, 0x57, b'O', 0x1c, 0x56], |m| got.push(m));
    /// assert_eq!(got, [
    ///     Message::Debug(DebugValue { number: 86, value: -2 }),
    ///     Message::Ack(Ack::Ok),
    /// ]);
    /// assert_eq!(dec.expecting(), Expect::Nothing);
    /// assert_eq!(dec.buffered(), 2);
    /// dec.feed(&[0, 0, 0, 1, 0x57], |m| got.push(m));
    /// assert_eq!(got[2], Message::Debug(DebugValue { number: 86, value: 1 }));
    /// ```
    pub fn feed<F: FnMut(Message)>(&mut self, bytes: &[u8], mut on_message: F) {
        let mut rest = bytes;
        // Bytes held from an earlier call: byte by byte until the buffer is empty.
        while self.len != 0 {
            let Some((&byte, after)) = rest.split_first() else {
                return;
            };
            rest = after;
            for m in self.push(byte) {
                on_message(m);
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
            if let Some(number) = headerless {
                let Some(reply) = rest.get(..HEADERLESS_REPLY_LEN) else {
                    break;
                };
                match ParameterValue::parse_headerless(reply, number) {
                    Ok(p) => {
                        self.stats.ok = self.stats.ok.wrapping_add(1);
                        rest = rest.get(HEADERLESS_REPLY_LEN..).unwrap_or(&[]);
                        let m = Message::Parameter(p);
                        self.settle(&m);
                        on_message(m);
                        continue;
                    }
                    // Not a reply; maybe a debug frame (the rules below).
                    Err(_) if first == DEBUG => {}
                    Err(_) => {
                        self.stats.checksum_errors = self.stats.checksum_errors.wrapping_add(1);
                        self.stats.discarded = self.stats.discarded.wrapping_add(1);
                        rest = tail;
                        continue;
                    }
                }
            }
            let Some(need) = frame_len(first, self.expect) else {
                self.stats.unknown_bytes = self.stats.unknown_bytes.wrapping_add(1);
                self.stats.discarded = self.stats.discarded.wrapping_add(1);
                rest = tail;
                continue;
            };
            let Some((frame, after)) = rest.split_at_checked(need) else {
                break;
            };
            match Message::parse(frame) {
                Ok((m, _)) => {
                    self.stats.ok = self.stats.ok.wrapping_add(1);
                    rest = after;
                    self.settle(&m);
                    on_message(m);
                }
                Err(Error::Checksum) => {
                    // The false start is dropped; the rescan starts at the next byte.
                    self.stats.checksum_errors = self.stats.checksum_errors.wrapping_add(1);
                    self.stats.discarded = self.stats.discarded.wrapping_add(1);
                    rest = tail;
                }
                Err(_) => {
                    // Intact but out of range (a waypoint reply with a bad slot): dropped whole.
                    self.stats.invalid = self.stats.invalid.wrapping_add(1);
                    rest = after;
                }
            }
        }
        // A frame cut by the end of the slice: keep it, exactly as pushing would.
        for &byte in rest {
            for m in self.push(byte) {
                on_message(m);
            }
        }
    }

    /// Feed `bytes` up to and including the first message, with the bulk path of
    /// [`PcDecoder::feed`] (frames parsed in place while nothing is held); messages an
    /// earlier call left undrained come first. Returns how many bytes were consumed and the
    /// message. Calling it until it finds nothing in an empty slice gives exactly the
    /// messages of [`PcDecoder::push`] with every iterator drained.
    #[cfg(any(feature = "embedded-io", feature = "embedded-io-async"))]
    pub(crate) fn feed_until(&mut self, bytes: &[u8]) -> (usize, Option<Message>) {
        let total = bytes.len();
        if let Some(m) = self.drain().next() {
            return (0, Some(m));
        }
        let mut rest = bytes;
        // Bytes held from an earlier call: byte by byte until the buffer is empty.
        while self.len != 0 {
            let Some((&byte, after)) = rest.split_first() else {
                return (total, None);
            };
            rest = after;
            if let Some(m) = self.push(byte).next() {
                return (total.saturating_sub(rest.len()), Some(m));
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
                        self.stats.ok = self.stats.ok.wrapping_add(1);
                        rest = rest.get(HEADERLESS_REPLY_LEN..).unwrap_or(&[]);
                        let m = Message::Parameter(p);
                        self.settle(&m);
                        return (total.saturating_sub(rest.len()), Some(m));
                    }
                    Err(_) if first == DEBUG => {}
                    Err(_) => {
                        self.stats.checksum_errors = self.stats.checksum_errors.wrapping_add(1);
                        self.stats.discarded = self.stats.discarded.wrapping_add(1);
                        rest = tail;
                        continue;
                    }
                }
            }
            let Some(need) = frame_len(first, self.expect) else {
                self.stats.unknown_bytes = self.stats.unknown_bytes.wrapping_add(1);
                self.stats.discarded = self.stats.discarded.wrapping_add(1);
                rest = tail;
                continue;
            };
            let Some((frame, after)) = rest.split_at_checked(need) else {
                break;
            };
            match Message::parse(frame) {
                Ok((m, _)) => {
                    self.stats.ok = self.stats.ok.wrapping_add(1);
                    self.settle(&m);
                    return (total.saturating_sub(after.len()), Some(m));
                }
                Err(Error::Checksum) => {
                    self.stats.checksum_errors = self.stats.checksum_errors.wrapping_add(1);
                    self.stats.discarded = self.stats.discarded.wrapping_add(1);
                    rest = tail;
                }
                Err(_) => {
                    self.stats.invalid = self.stats.invalid.wrapping_add(1);
                    rest = after;
                }
            }
        }
        // A frame cut by the end of the slice: keep it, exactly as pushing would.
        while let Some((&byte, after)) = rest.split_first() {
            rest = after;
            if let Some(m) = self.push(byte).next() {
                return (total.saturating_sub(rest.len()), Some(m));
            }
        }
        (total, None)
    }

    /// Continue on bytes already buffered, without new input: what an undrained iterator left.
    ///
    /// ```
    /// let mut dec = aok_proto::pc::PcDecoder::new(aok_proto::FirmwareVersion::LATEST);
    /// let _ = dec.push(0x00); // iterator dropped unread
    /// assert_eq!(dec.drain().count(), 0);
    /// assert_eq!(dec.buffered(), 0);
    /// ```
    pub fn drain(&mut self) -> Messages<'_> {
        Messages {
            dec: self,
            flush: false,
        }
    }

    /// The line went quiet: abandon the partial frame at the front and rescan what followed it.
    ///
    /// ```
    /// use aok_proto::{pc::{Expect, PcDecoder}, FirmwareVersion, Message, Ack};
    /// let mut dec = PcDecoder::new(FirmwareVersion::LATEST);
    /// dec.expect(Expect::Ack);
    /// // A debug frame cut short, then the ack: the ack is inside the debug candidate...
    /// for b in [0x1c, 0x56, b'O'] { assert_eq!(dec.push(b).next(), None); }
    /// // ...until the line goes quiet.
    /// assert_eq!(dec.idle().next(), Some(Message::Ack(Ack::Ok)));
    /// ```
    pub fn idle(&mut self) -> Messages<'_> {
        Messages {
            dec: self,
            flush: true,
        }
    }

    /// Forget buffered bytes (the pending request and the counters stay).
    ///
    /// ```
    /// let mut dec = aok_proto::pc::PcDecoder::new(aok_proto::FirmwareVersion::LATEST);
    /// for _ in dec.push(0x1c) {}
    /// dec.reset();
    /// assert_eq!(dec.buffered(), 0);
    /// ```
    pub fn reset(&mut self) {
        self.len = 0;
        self.need = 0;
        self.front_not_reply = false;
    }

    /// Bytes waiting for the rest of their frame.
    ///
    /// ```
    /// let mut dec = aok_proto::pc::PcDecoder::new(aok_proto::FirmwareVersion::LATEST);
    /// for _ in dec.push(0xff) {}
    /// assert_eq!(dec.buffered(), 1);
    /// ```
    pub const fn buffered(&self) -> usize {
        self.len
    }

    /// The counters.
    ///
    /// ```
    /// let mut dec = aok_proto::pc::PcDecoder::new(aok_proto::FirmwareVersion::LATEST);
    /// for _ in dec.push(0x00) {}
    /// assert_eq!(dec.stats().unknown_bytes, 1);
    /// ```
    pub const fn stats(&self) -> &DecoderStats {
        &self.stats
    }

    fn drop_front(&mut self) {
        self.need = 0;
        self.stats.discarded = self.stats.discarded.wrapping_add(1);
        self.len = shift_left(&mut self.buf, self.len, 1);
        self.front_not_reply = false;
    }

    fn consume(&mut self, n: usize) {
        self.need = 0;
        self.stats.ok = self.stats.ok.wrapping_add(1);
        self.len = shift_left(&mut self.buf, self.len, n);
        self.front_not_reply = false;
    }

    fn checksum_failed(&mut self) {
        self.stats.checksum_errors = self.stats.checksum_errors.wrapping_add(1);
        self.drop_front();
    }

    fn settle(&mut self, message: &Message) {
        self.expect = match (self.expect, message) {
            (Expect::Ack, Message::Ack(_)) => Expect::Nothing,
            (Expect::Parameter(n), Message::Parameter(p)) if p.number == n => Expect::Nothing,
            (Expect::Bulk(first), Message::Parameter(p)) if p.number == first.wrapping_add(15) => {
                Expect::Nothing
            }
            (Expect::Waypoint(s), Message::Waypoint(w)) if w.slot == s => Expect::Nothing,
            (e, _) => e,
        };
    }

    #[inline]
    fn step(&mut self, flush: bool) -> Option<Message> {
        // Nothing buffered gives nothing (the usual last call on an iterator); a frame still
        // short of its known length gives nothing until the line goes quiet.
        if self.len == 0 || (self.len < self.need && !flush) {
            return None;
        }
        // The first byte of a self-describing frame only tells its length (unless a headerless
        // reply is pending: then any byte may start one, and the slow path decides).
        if self.len == 1 && !flush && !self.headerless_pending() {
            let need = match self.buf.first() {
                Some(&DEBUG) => DEBUG_LEN,
                Some(&PARAMETER_REPLY) => HEADED_REPLY_LEN,
                Some(&WAYPOINT) => WAYPOINT_LEN,
                _ => 0,
            };
            if need != 0 {
                self.need = need;
                return None;
            }
        }
        self.step_slow(flush)
    }

    /// Whether a headerless (<= 0.30) parameter reply is pending: then any byte may start one.
    #[inline]
    fn headerless_pending(&self) -> bool {
        matches!(self.expect, Expect::Parameter(_)) && self.form == ReplyForm::Headerless
    }

    fn step_slow(&mut self, flush: bool) -> Option<Message> {
        loop {
            let len = if self.len < MAX_COMMAND_LEN {
                self.len
            } else {
                MAX_COMMAND_LEN
            };
            let bytes = self.buf.get(..len)?;
            let first = *bytes.first()?;
            let headerless_pending = match self.expect {
                Expect::Parameter(n) if self.form == ReplyForm::Headerless => Some(n),
                _ => None,
            };
            // The headerless reply candidate comes first: any byte may start it.
            if let (Some(number), false) = (headerless_pending, self.front_not_reply) {
                if len < HEADERLESS_REPLY_LEN {
                    if flush {
                        self.abandon();
                        continue;
                    }
                    self.need = HEADERLESS_REPLY_LEN;
                    return None;
                }
                match ParameterValue::parse_headerless(bytes, number) {
                    Ok(p) => {
                        self.consume(HEADERLESS_REPLY_LEN);
                        let m = Message::Parameter(p);
                        self.settle(&m);
                        return Some(m);
                    }
                    Err(_) if first == DEBUG => {
                        // Not a reply; maybe a debug frame.
                        self.front_not_reply = true;
                        continue;
                    }
                    Err(_) => {
                        self.checksum_failed();
                        continue;
                    }
                }
            }
            let Some(need) = frame_len(first, self.expect) else {
                self.stats.unknown_bytes = self.stats.unknown_bytes.wrapping_add(1);
                self.drop_front();
                continue;
            };
            if len < need {
                if flush {
                    self.abandon();
                    continue;
                }
                self.need = need;
                return None;
            }
            match Message::parse(bytes) {
                Ok((m, n)) => {
                    self.consume(n);
                    self.settle(&m);
                    return Some(m);
                }
                Err(Error::Checksum) => self.checksum_failed(),
                Err(_) => {
                    // Intact but out of range (a waypoint reply with a bad slot): drop it whole.
                    self.stats.invalid = self.stats.invalid.wrapping_add(1);
                    self.need = 0;
                    self.len = shift_left(&mut self.buf, self.len, need);
                    self.front_not_reply = false;
                }
            }
        }
    }

    fn abandon(&mut self) {
        self.stats.abandoned = self.stats.abandoned.wrapping_add(1);
        self.drop_front();
    }
}

/// The messages one [`PcDecoder::push`] (or [`PcDecoder::idle`]) completes.
///
/// ```
/// let mut dec = aok_proto::pc::PcDecoder::new(aok_proto::FirmwareVersion::LATEST);
/// assert_eq!(dec.push(0x1c).count(), 0);
/// ```
#[derive(Debug)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Messages<'a> {
    dec: &'a mut PcDecoder,
    flush: bool,
}

impl Iterator for Messages<'_> {
    type Item = Message;

    #[inline]
    fn next(&mut self) -> Option<Message> {
        self.dec.step(self.flush)
    }
}

/// The length of the frame that `first` starts while `expect` is pending (with a header: the
/// headerless reply is read before this), or `None` for a byte that starts no frame.
const fn frame_len(first: u8, expect: Expect) -> Option<usize> {
    match first {
        DEBUG => Some(DEBUG_LEN),
        PARAMETER_REPLY => Some(HEADED_REPLY_LEN),
        WAYPOINT => Some(WAYPOINT_LEN),
        b'O' | b'E' | b'I' if matches!(expect, Expect::Ack) => Some(1),
        _ => None,
    }
}
