//! The PC (ground tool) side's decoder: it reads the device's stream of debug frames, acks and
//! replies, knowing which request is pending.

mod bulk;
mod step;

use super::{Held, Stats};
use crate::Error;
use crate::command::{Expect, WAYPOINT};
use crate::message::{DEBUG, DEBUG_LEN, HEADED_REPLY_LEN, Message, PARAMETER_REPLY, WAYPOINT_LEN};
use crate::values::{FirmwareVersion, ReplyForm};

/// The decoder of the device's messages, run on the PC.
///
/// It implements [`Decode`](crate::Decode), the contract of every decoder in this workspace:
/// [`feed`](crate::Decode::feed) every slice read from the port, and
/// [`finish`](crate::Decode::finish) when the line goes quiet. Each event is `Ok(message)` or
/// `Err(error)`.
///
/// * Debug frames (`1C`), headed parameter replies (`FF`, firmware >= 0.31) and waypoint replies (`77`)
///   are decoded at any time; they describe themselves and carry a checksum.
/// * 'O'/'E'/'I' are acks only while [`Expect::Ack`] is pending; otherwise they are unknown bytes.
/// * A headerless (<= 0.30) parameter reply is read only while [`Expect::Parameter`] is pending and the
///   firmware is <= 0.30. Then every byte may start a reply: a `1C` is first tried as a reply (5 bytes,
///   checksum over B1..B4) and, if that checksum fails, as a debug frame.
/// * A byte inside a frame is never an ack; a failed checksum is reported as
///   [`Error::ChecksumMismatch`] and rescans from the byte after the false start, so an ack or
///   frame hidden there is still found. A frame with a good checksum but an out-of-range field (a
///   waypoint reply with a bad slot) is reported as that error and rescanned the same way.
///
/// ```
/// use aok_proto::{Decode, Expect, FirmwareVersion, Message, MessageDecoder, ParameterValue};
/// let mut dec = MessageDecoder::new(FirmwareVersion::new(0, 30));
/// dec.expect(Expect::Parameter(12));
/// let mut got = Vec::new();
/// dec.feed(&[0x00, 0x00, 0x05, 0xdc, 0xd9], |event| got.push(event));
/// dec.finish(|event| got.push(event)); // the line went quiet
/// assert_eq!(got, [Ok(Message::Parameter(ParameterValue { number: 12, value: 1500 }))]);
/// assert_eq!(dec.expecting(), Expect::Nothing);
/// ```
#[derive(Debug, Clone)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
// On 32-bit targets `repr(C)` puts the buffer first: its address is the decoder's, so a byte
// is stored with one `strb` (`scripts/cm3-bench.sh`, issue 29). Not on 64-bit hosts, where
// it made the byte path slower (x86-64 callgrind, PC side: +5.7 %).
#[doc = include_str!("../../../PERFORMANCE.md")]
#[cfg_attr(target_pointer_width = "32", repr(C))]
pub struct MessageDecoder {
    held: Held,
    form: ReplyForm,
    expect: Expect,
    /// The byte at the front already failed as a headerless reply; read it as a debug start.
    front_not_reply: bool,
    /// `decode` handed out an event from the buffer: the events after it in the buffer come
    /// first in its next call (as `poll` after `push`).
    unpolled: bool,
    stats: Stats,
}

impl MessageDecoder {
    /// A decoder for a device with this firmware (it picks the parameter-reply form, K4).
    ///
    /// ```
    /// let dec = aok_proto::MessageDecoder::new(aok_proto::FirmwareVersion::LATEST);
    /// assert_eq!(dec.reply_form(), aok_proto::ReplyForm::Headed);
    /// ```
    pub const fn new(firmware: FirmwareVersion) -> Self {
        Self {
            held: Held::EMPTY,
            form: firmware.reply_form(),
            expect: Expect::Nothing,
            front_not_reply: false,
            unpolled: false,
            stats: Stats::ZERO,
        }
    }

    /// The parameter-reply form in use.
    ///
    /// ```
    /// let dec = aok_proto::MessageDecoder::new(aok_proto::FirmwareVersion::new(0, 20));
    /// assert_eq!(dec.reply_form(), aok_proto::ReplyForm::Headerless);
    /// ```
    pub const fn reply_form(&self) -> ReplyForm {
        self.form
    }

    /// Change the firmware version (and with it the reply form).
    ///
    /// ```
    /// let mut dec = aok_proto::MessageDecoder::new(aok_proto::FirmwareVersion::new(0, 20));
    /// dec.set_firmware(aok_proto::FirmwareVersion::new(0, 31));
    /// assert_eq!(dec.reply_form(), aok_proto::ReplyForm::Headed);
    /// ```
    pub fn set_firmware(&mut self, firmware: FirmwareVersion) {
        self.form = firmware.reply_form();
        self.held.need = 0;
    }

    /// Set what the PC waits for; call it just before sending the request. The decoder clears it
    /// when the matching reply or ack arrives.
    ///
    /// ```
    /// use aok_proto::{Ack, Decode, Expect, FirmwareVersion, Message, MessageDecoder};
    /// let mut dec = MessageDecoder::new(FirmwareVersion::LATEST);
    /// dec.expect(Expect::Ack);
    /// let mut got = Vec::new();
    /// dec.feed(b"O", |event| got.push(event));
    /// dec.feed(b"O", |event| got.push(event)); // no longer expected: an unknown byte
    /// assert_eq!(got, [Ok(Message::Ack(Ack::Ok))]);
    /// assert_eq!(dec.stats().unknown_bytes, 1);
    /// ```
    pub fn expect(&mut self, expect: Expect) {
        self.expect = expect;
        self.held.need = 0;
    }

    /// What the decoder is waiting for.
    ///
    /// ```
    /// let dec = aok_proto::MessageDecoder::new(aok_proto::FirmwareVersion::LATEST);
    /// assert_eq!(dec.expecting(), aok_proto::Expect::Nothing);
    /// ```
    pub const fn expecting(&self) -> Expect {
        self.expect
    }

    /// Forget buffered bytes (the pending request and the counters stay).
    ///
    /// ```
    /// use aok_proto::{Decode, FirmwareVersion, MessageDecoder};
    /// let mut dec = MessageDecoder::new(FirmwareVersion::LATEST);
    /// dec.feed(&[0x1c], |_| {});
    /// dec.reset();
    /// assert_eq!(dec.held_bytes(), 0);
    /// ```
    pub fn reset(&mut self) {
        self.held.clear();
        self.front_not_reply = false;
        self.unpolled = false;
    }

    /// Bytes held: received, and not yet decoded nor dropped (a frame waiting for the rest of
    /// its bytes, and any bytes behind it).
    ///
    /// ```
    /// use aok_proto::{Decode, FirmwareVersion, MessageDecoder};
    /// let mut dec = MessageDecoder::new(FirmwareVersion::LATEST);
    /// dec.feed(&[0xff], |_| {});
    /// assert_eq!(dec.held_bytes(), 1);
    /// ```
    pub const fn held_bytes(&self) -> usize {
        self.held.len
    }

    /// The counters.
    ///
    /// ```
    /// use aok_proto::{Decode, FirmwareVersion, MessageDecoder};
    /// let mut dec = MessageDecoder::new(FirmwareVersion::LATEST);
    /// dec.feed(&[0x00], |_| {});
    /// assert_eq!(dec.stats().unknown_bytes, 1);
    /// ```
    pub const fn stats(&self) -> Stats {
        self.stats
    }
}

/// The length of the frame that `first` starts while `expect` is pending (with a header: the
/// headerless reply is read before this), or `None` for a byte that starts no frame.
#[inline(always)]
const fn frame_len(first: u8, expect: Expect) -> Option<usize> {
    match first {
        DEBUG => Some(DEBUG_LEN),
        PARAMETER_REPLY => Some(HEADED_REPLY_LEN),
        WAYPOINT => Some(WAYPOINT_LEN),
        b'O' | b'E' | b'I' if matches!(expect, Expect::Ack) => Some(1),
        _ => None,
    }
}
