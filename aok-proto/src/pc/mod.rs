//! The PC (ground tool) side: encoders for every command, and a decoder of the device's stream that
//! knows which request is pending.

mod slice;
mod step;

pub use crate::command::Expect;
use crate::command::{Command, MAX_COMMAND_LEN, ParameterValue, WAYPOINT};
use crate::message::{
    DEBUG, DEBUG_LEN, HEADED_REPLY_LEN, HEADERLESS_REPLY_LEN, Message, PARAMETER_REPLY,
    WAYPOINT_LEN,
};
use crate::stats::Stats;
use crate::values::{FirmwareVersion, ReplyForm};
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

/// Byte-at-a-time decoder of the device's stream.
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
/// [`PcDecoder::push`] returns at most one event; call [`PcDecoder::poll`] until `None` for any
/// further events a rescan uncovered. [`PcDecoder::feed`] does both for a slice.
///
/// ```
/// use aok_proto::{pc::{Expect, PcDecoder}, FirmwareVersion, Message, ParameterValue};
/// let mut dec = PcDecoder::new(FirmwareVersion::new(0, 30));
/// dec.expect(Expect::Parameter(12));
/// let mut got = None;
/// for b in [0x00, 0x00, 0x05, 0xdc, 0xd9] {
///     let mut event = dec.push(b);
///     while let Some(ev) = event {
///         got = Some(ev);
///         event = dec.poll(); // a rescan can hold more than one event: drain them
///     }
/// }
/// assert_eq!(got, Some(Ok(Message::Parameter(ParameterValue { number: 12, value: 1500 }))));
/// assert_eq!(dec.expecting(), Expect::Nothing);
/// ```
#[derive(Debug, Clone)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
// On 32-bit targets `repr(C)` puts the buffer first: its address is the decoder's, so `push`
// stores a byte with one `strb` (`scripts/cm3-bench.sh`, issue 29). Not on 64-bit hosts, where
// it made `push` slower (x86-64 callgrind, PC side: +5.7 %).
#[cfg_attr(target_pointer_width = "32", repr(C))]
pub struct PcDecoder {
    buf: [u8; MAX_COMMAND_LEN],
    len: usize,
    /// Length of the frame the front byte started, once known (0: not known). Hot-path shortcut.
    need: usize,
    form: ReplyForm,
    expect: Expect,
    /// The byte at the front already failed as a headerless reply; read it as a debug start.
    front_not_reply: bool,
    /// `feed_until` handed out an event from the buffer: the events after it in the buffer
    /// come first in its next call (as `poll` after `push`).
    unpolled: bool,
    stats: Stats,
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
            unpolled: false,
            stats: Stats::ZERO,
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
    /// assert_eq!(dec.push(b'O'), Some(Ok(aok_proto::Message::Ack(aok_proto::Ack::Ok))));
    /// assert_eq!(dec.push(b'O'), None); // no longer expected: an unknown byte
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

    /// Feed one byte. Returns the first event it causes (usually the only one); call
    /// [`PcDecoder::poll`] until `None` to take any further events a rescan uncovered. Events
    /// not taken stay buffered as bytes, ahead of new input.
    ///
    /// ```
    /// use aok_proto::{pc::PcDecoder, FirmwareVersion, Message, DebugValue};
    /// let mut dec = PcDecoder::new(FirmwareVersion::LATEST);
    /// let mut last = None;
    /// for b in [0x1c, 0x56, 0xff, 0xff, 0xff, 0xfe, 0x57] {
    ///     if let Some(ev) = dec.push(b) { last = Some(ev); }
    /// }
    /// assert_eq!(last, Some(Ok(Message::Debug(DebugValue { number: 86, value: -2 }))));
    /// ```
    #[inline]
    pub fn push(&mut self, byte: u8) -> Option<Result<Message, Error>> {
        if self.len >= MAX_COMMAND_LEN {
            // Only reachable when earlier events were not polled.
            self.drop_front();
        }
        if let Some(slot) = self.buf.get_mut(self.len) {
            *slot = byte;
            self.len = self.len.wrapping_add(1);
        }
        self.step(false)
    }

    /// Take the next event from bytes already buffered (after a rescan), or `None`.
    ///
    /// ```
    /// use aok_proto::{pc::{Expect, PcDecoder}, Ack, Error, FirmwareVersion, Message};
    /// let mut dec = PcDecoder::new(FirmwareVersion::LATEST);
    /// dec.expect(Expect::Ack);
    /// // A debug start whose checksum fails holds the ack: the rescan finds it.
    /// for b in [0x1c, b'O', 0, 0, 0, 0] {
    ///     assert_eq!(dec.push(b), None);
    /// }
    /// let mismatch = Error::ChecksumMismatch { id: 0x1c, computed: u16::from(b'O'), received: 0 };
    /// assert_eq!(dec.push(0), Some(Err(mismatch)));
    /// assert_eq!(dec.poll(), Some(Ok(Message::Ack(Ack::Ok))));
    /// assert_eq!(dec.poll(), None);
    /// ```
    #[inline]
    pub fn poll(&mut self) -> Option<Result<Message, Error>> {
        self.step(false)
    }

    /// The line went quiet: abandon the partial frame at the front (its first byte is dropped,
    /// counted as abandoned and reported as [`Error::Truncated`]) and rescan what followed it,
    /// handing every event to `on_event` until nothing is buffered. AOK's end of a stream.
    ///
    /// ```
    /// use aok_proto::{pc::{Expect, PcDecoder}, Ack, Error, FirmwareVersion, Message};
    /// let mut dec = PcDecoder::new(FirmwareVersion::LATEST);
    /// dec.expect(Expect::Ack);
    /// // A debug frame cut short, then the ack: the ack is inside the debug candidate...
    /// for b in [0x1c, 0x56, b'O'] { assert_eq!(dec.push(b), None); }
    /// // ...until the line goes quiet.
    /// let mut got = Vec::new();
    /// dec.idle(|ev| got.push(ev));
    /// assert_eq!(got, [Err(Error::Truncated), Ok(Message::Ack(Ack::Ok))]);
    /// ```
    pub fn idle<F: FnMut(Result<Message, Error>)>(&mut self, mut on_event: F) {
        while let Some(ev) = self.idle_next() {
            on_event(ev);
        }
    }

    /// [`PcDecoder::idle`] one event at a time: the next event, or `None` once nothing is
    /// buffered.
    ///
    /// ```
    /// let mut dec = aok_proto::pc::PcDecoder::new(aok_proto::FirmwareVersion::LATEST);
    /// dec.push(0x1c);
    /// assert_eq!(dec.idle_next(), Some(Err(aok_proto::Error::Truncated)));
    /// assert_eq!(dec.idle_next(), None);
    /// ```
    pub fn idle_next(&mut self) -> Option<Result<Message, Error>> {
        self.step(true)
    }

    /// Forget buffered bytes (the pending request and the counters stay).
    ///
    /// ```
    /// let mut dec = aok_proto::pc::PcDecoder::new(aok_proto::FirmwareVersion::LATEST);
    /// dec.push(0x1c);
    /// dec.reset();
    /// assert_eq!(dec.held_bytes(), 0);
    /// ```
    pub fn reset(&mut self) {
        self.len = 0;
        self.need = 0;
        self.front_not_reply = false;
        self.unpolled = false;
    }

    /// Bytes held: received, and not yet decoded nor dropped (a frame waiting for the rest of
    /// its bytes, and any bytes behind it).
    ///
    /// ```
    /// let mut dec = aok_proto::pc::PcDecoder::new(aok_proto::FirmwareVersion::LATEST);
    /// dec.push(0xff);
    /// assert_eq!(dec.held_bytes(), 1);
    /// ```
    pub const fn held_bytes(&self) -> usize {
        self.len
    }

    /// The counters.
    ///
    /// ```
    /// let mut dec = aok_proto::pc::PcDecoder::new(aok_proto::FirmwareVersion::LATEST);
    /// dec.push(0x00);
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
