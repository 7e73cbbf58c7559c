//! The device (flight controller) side: a byte-at-a-time decoder for every command the PC sends, and
//! encoders for everything the device sends.

mod slice;
mod step;

use crate::command::{Command, Len, MAX_COMMAND_LEN, ParameterValue, Waypoint, command_len};
use crate::message::{DebugValue, HEADED_REPLY_LEN, Message};
use crate::stats::Stats;
use crate::values::{Ack, ReplyForm};
use crate::{Error, shift_left};

/// Byte-at-a-time decoder of the PC's commands.
///
/// Feed it one byte at a time with [`DeviceDecoder::push`], which returns at most one event, then
/// call [`DeviceDecoder::poll`] until `None` for any further events a rescan uncovered; or a slice
/// at a time with [`DeviceDecoder::feed`]. Checksums are verified. An unknown byte is counted and
/// skipped; a checksum failure is counted, reported as `Err(Error::ChecksumMismatch { .. })` (the device
/// may answer 'E') and the bytes after the false start are rescanned, so a command hidden behind
/// garbage is still found. A frame with a good checksum but an out-of-range field (waypoint slot,
/// stick value) is reported as that error and rescanned the same way (a false candidate
/// passes the 8-bit checksum one time in 256).
///
/// The buffer is fixed at the longest command (19 bytes, the waypoint frame), so no capacity parameter
/// is needed: every command fits.
///
/// ```
/// use aok_proto::{DeviceDecoder, Command, Error};
/// let mut dec = DeviceDecoder::new();
/// let mut got = Vec::new();
/// // A stray motor-test start whose "checksum" fails, then a real read of parameter 12.
/// for b in [0x31, 0x67, 0x0c] {
///     let mut event = dec.push(b);
///     while let Some(ev) = event {
///         got.push(ev);
///         event = dec.poll(); // a rescan can hold more than one event: drain them
///     }
/// }
/// let mismatch = Error::ChecksumMismatch { id: 0x31, computed: 0x56, received: 0x0c };
/// assert_eq!(got, [Err(mismatch), Ok(Command::ReadParameter(12))]);
/// ```
#[derive(Debug, Clone)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
// On 32-bit targets `repr(C)` puts the buffer first: its address is the decoder's, so `push`
// stores a byte with one `strb` (`scripts/cm3-bench.sh`, issue 29). Not on 64-bit hosts, where
// it made `push` slower (x86-64 callgrind, PC side: +5.7 %).
#[cfg_attr(target_pointer_width = "32", repr(C))]
pub struct DeviceDecoder {
    buf: [u8; MAX_COMMAND_LEN],
    len: usize,
    /// Length of the frame the front byte started, once known (0: not known). Hot-path shortcut.
    need: usize,
    stats: Stats,
}

impl Default for DeviceDecoder {
    fn default() -> Self {
        Self::new()
    }
}

impl DeviceDecoder {
    /// An empty decoder.
    ///
    /// ```
    /// assert_eq!(aok_proto::DeviceDecoder::new().held_bytes(), 0);
    /// ```
    pub const fn new() -> Self {
        Self {
            buf: [0; MAX_COMMAND_LEN],
            len: 0,
            need: 0,
            stats: Stats::ZERO,
        }
    }

    /// Feed one byte. Returns the first event it causes (usually the only one); call
    /// [`DeviceDecoder::poll`] until `None` to take any further events a rescan uncovered.
    /// Events not taken stay buffered as bytes, ahead of new input.
    ///
    /// ```
    /// use aok_proto::{DeviceDecoder, Command};
    /// let mut dec = DeviceDecoder::new();
    /// assert_eq!(dec.push(0x63), None);
    /// assert_eq!(dec.push(0x01), Some(Ok(Command::DebugOff)));
    /// assert_eq!(dec.poll(), None);
    /// ```
    #[inline]
    pub fn push(&mut self, byte: u8) -> Option<Result<Command, Error>> {
        if self.len >= MAX_COMMAND_LEN {
            // Only reachable when earlier events were not polled.
            self.len = shift_left(&mut self.buf, self.len, 1);
            self.stats.bytes_discarded = self.stats.bytes_discarded.wrapping_add(1);
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
    /// use aok_proto::{Command, DeviceDecoder, Error};
    /// let mut dec = DeviceDecoder::new();
    /// // A `73` start swallows a read; its checksum fails when the frame is complete, and the
    /// // rescan finds the read among the bytes held.
    /// for b in [0x73, 0x67, 0x0c, 0x00, 0x00, 0x00] {
    ///     assert_eq!(dec.push(b), None);
    /// }
    /// let mismatch = Error::ChecksumMismatch { id: 0x73, computed: 0x67 ^ 0x0c, received: 0 };
    /// assert_eq!(dec.push(0x00), Some(Err(mismatch)));
    /// assert_eq!(dec.poll(), Some(Ok(Command::ReadParameter(12))));
    /// assert_eq!(dec.poll(), None);
    /// ```
    #[inline]
    pub fn poll(&mut self) -> Option<Result<Command, Error>> {
        self.step(false)
    }

    /// The line went quiet: give up on the partial frame at the front (its first byte is dropped,
    /// counted as abandoned and reported as [`Error::Truncated`]) and rescan what followed it,
    /// handing every event to `on_event` until nothing is buffered. AOK's end of a stream.
    ///
    /// ```
    /// use aok_proto::{DeviceDecoder, Command, Error};
    /// let mut dec = DeviceDecoder::new();
    /// dec.feed(&[0x73, 0x63, 0x02], |_| {}); // 73 waits for 4 more bytes
    /// let mut got = Vec::new();
    /// dec.idle(|ev| got.push(ev));
    /// assert_eq!(got, [Err(Error::Truncated), Ok(Command::DebugOn)]);
    /// assert_eq!(dec.stats().abandoned, 1);
    /// ```
    pub fn idle<F: FnMut(Result<Command, Error>)>(&mut self, mut on_event: F) {
        while let Some(item) = self.idle_next() {
            on_event(item);
        }
    }

    /// [`DeviceDecoder::idle`] one event at a time: the next event, or `None` once nothing is
    /// buffered.
    ///
    /// ```
    /// let mut dec = aok_proto::DeviceDecoder::new();
    /// dec.feed(&[0x73], |_| {});
    /// assert_eq!(dec.idle_next(), Some(Err(aok_proto::Error::Truncated)));
    /// assert_eq!(dec.idle_next(), None);
    /// ```
    pub fn idle_next(&mut self) -> Option<Result<Command, Error>> {
        self.step(true)
    }

    /// Forget any buffered bytes (counters stay).
    ///
    /// ```
    /// let mut dec = aok_proto::DeviceDecoder::new();
    /// dec.push(0x73);
    /// dec.reset();
    /// assert_eq!(dec.held_bytes(), 0);
    /// ```
    pub fn reset(&mut self) {
        self.len = 0;
        self.need = 0;
    }

    /// Bytes held: received, and not yet decoded nor dropped (a frame waiting for the rest of
    /// its bytes, and any bytes behind it).
    ///
    /// ```
    /// let mut dec = aok_proto::DeviceDecoder::new();
    /// dec.push(0x53);
    /// assert_eq!(dec.held_bytes(), 1);
    /// ```
    pub const fn held_bytes(&self) -> usize {
        self.len
    }

    /// The counters.
    ///
    /// ```
    /// assert_eq!(aok_proto::DeviceDecoder::new().stats().frames_ok, 0);
    /// ```
    pub const fn stats(&self) -> Stats {
        self.stats
    }
}

/// Encode a debug value frame `1C NUM B1..B4 CRC`.
///
/// ```
/// use aok_proto::{device, DebugValue};
/// let mut buf = [0u8; 7];
/// device::encode_debug(DebugValue { number: 3, value: 305419896 }, &mut buf)?;
/// assert_eq!(buf, [0x1c, 0x03, 0x12, 0x34, 0x56, 0x78, 0x0b]);
/// # Ok::<(), aok_proto::Error>(())
/// ```
pub fn encode_debug(value: DebugValue, buf: &mut [u8]) -> Result<usize, Error> {
    Message::Debug(value).emit(ReplyForm::Headed, buf)
}

/// Encode a single-byte ack.
///
/// ```
/// let mut buf = [0u8; 1];
/// aok_proto::device::encode_ack(aok_proto::Ack::Ok, &mut buf)?;
/// assert_eq!(buf, [b'O']);
/// # Ok::<(), aok_proto::Error>(())
/// ```
pub fn encode_ack(ack: Ack, buf: &mut [u8]) -> Result<usize, Error> {
    Message::Ack(ack).emit(ReplyForm::Headed, buf)
}

/// Encode a parameter reply in the given firmware form (K4).
///
/// ```
/// use aok_proto::{device, ParameterValue, ReplyForm};
/// let mut buf = [0u8; 7];
/// let p = ParameterValue { number: 12, value: 1500 };
/// assert_eq!(device::encode_parameter(p, ReplyForm::Headed, &mut buf)?, 7);
/// assert_eq!(buf, [0xff, 0x0c, 0x00, 0x00, 0x05, 0xdc, 0xd9]);
/// # Ok::<(), aok_proto::Error>(())
/// ```
pub fn encode_parameter(
    value: ParameterValue,
    form: ReplyForm,
    buf: &mut [u8],
) -> Result<usize, Error> {
    Message::Parameter(value).emit(form, buf)
}

/// Encode the 16 replies to a bulk read `47 NUM`: parameters NUM..NUM+15 (numbers wrap at 255), in the
/// headed form (bulk read exists only from 0.35). Needs 112 bytes.
///
/// ```
/// let mut buf = [0u8; 112];
/// let n = aok_proto::device::encode_bulk(10, &[7; 16], &mut buf)?;
/// assert_eq!(n, 112);
/// assert_eq!(&buf[..7], &[0xff, 10, 0, 0, 0, 7, 7]);
/// assert_eq!(buf[105], 0xff);
/// assert_eq!(buf[106], 25);
/// # Ok::<(), aok_proto::Error>(())
/// ```
pub fn encode_bulk(first: u8, values: &[i32; 16], buf: &mut [u8]) -> Result<usize, Error> {
    let out = buf
        .get_mut(..HEADED_REPLY_LEN * 16)
        .ok_or(Error::BufferTooSmall {
            needed: HEADED_REPLY_LEN * 16,
        })?;
    let mut number = first;
    for (chunk, &value) in out.chunks_exact_mut(HEADED_REPLY_LEN).zip(values) {
        Message::Parameter(ParameterValue { number, value }).emit(ReplyForm::Headed, chunk)?;
        number = number.wrapping_add(1);
    }
    Ok(HEADED_REPLY_LEN * 16)
}

/// Encode the waypoint reply (the same `77` frame the PC sends to set one).
///
/// ```
/// use aok_proto::{device, ActionWord, Waypoint, WaypointSlot};
/// let w = Waypoint { slot: WaypointSlot::FbcTarget, longitude: 1, latitude: 2,
///                    action1: ActionWord::NONE, action2: ActionWord::NONE };
/// let mut buf = [0u8; 19];
/// assert_eq!(device::encode_waypoint(&w, &mut buf)?, 19);
/// assert_eq!(&buf[..2], &[0x77, 0xff]);
/// # Ok::<(), aok_proto::Error>(())
/// ```
pub fn encode_waypoint(waypoint: &Waypoint, buf: &mut [u8]) -> Result<usize, Error> {
    Message::Waypoint(*waypoint).emit(ReplyForm::Headed, buf)
}
