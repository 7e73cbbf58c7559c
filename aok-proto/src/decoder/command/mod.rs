//! The device (flight controller) side's decoder: it reads every command the PC sends.

mod bulk;
mod step;

use super::{Held, Stats};
use crate::Error;
use crate::command::Command;

/// The decoder of the PC's commands, run on the device.
///
/// It implements [`Decode`](crate::Decode), the contract of every decoder in this workspace:
/// [`feed`](crate::Decode::feed) every slice the UART gives (one byte included), and
/// [`finish`](crate::Decode::finish) when the line goes quiet (a command cut short is given
/// up as `Err(Error::Truncated)` and the bytes after its first are read again). Each event is
/// `Ok(command)` or `Err(error)`. Checksums are verified. An unknown byte is counted and
/// skipped; a checksum failure is counted, reported as `Err(Error::ChecksumMismatch { .. })`
/// (the device may answer 'E') and the bytes after the false start are rescanned, so a
/// command hidden behind garbage is still found. A frame with a good checksum but an
/// out-of-range field (waypoint slot, stick value) is reported as that error and rescanned the
/// same way (a false candidate passes the 8-bit checksum one time in 256).
///
/// The buffer is fixed at the longest command (19 bytes, the waypoint frame), so no capacity
/// parameter is needed: every command fits.
///
/// ```
/// use aok_proto::{Command, CommandDecoder, Decode, Error};
/// let mut dec = CommandDecoder::new();
/// let mut got = Vec::new();
/// // A stray motor-test start whose "checksum" fails, then a real read of parameter 12, byte
/// // by byte as an interrupt handler gets them.
/// for b in [0x31, 0x67, 0x0c] {
///     dec.feed(&[b], |event| got.push(event));
/// }
/// dec.finish(|event| got.push(event)); // the line went quiet
/// let mismatch = Error::ChecksumMismatch { id: 0x31, computed: 0x56, received: 0x0c };
/// assert_eq!(got, [Err(mismatch), Ok(Command::ReadParameter(12))]);
/// ```
#[derive(Debug, Clone)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
// On 32-bit targets `repr(C)` puts the buffer first: its address is the decoder's, so a byte
// is stored with one `strb` (`scripts/cm3-bench.sh`, issue 29). Not on 64-bit hosts, where
// it made the byte path slower (x86-64 callgrind, PC side: +5.7 %).
#[doc = include_str!("../../../PERFORMANCE.md")]
#[cfg_attr(target_pointer_width = "32", repr(C))]
pub struct CommandDecoder {
    held: Held,
    stats: Stats,
}

impl Default for CommandDecoder {
    fn default() -> Self {
        Self::new()
    }
}

impl CommandDecoder {
    /// An empty decoder.
    ///
    /// ```
    /// assert_eq!(aok_proto::CommandDecoder::new().held_bytes(), 0);
    /// ```
    pub const fn new() -> Self {
        Self {
            held: Held::EMPTY,
            stats: Stats::ZERO,
        }
    }

    /// Forget any buffered bytes (counters stay).
    ///
    /// ```
    /// use aok_proto::{CommandDecoder, Decode};
    /// let mut dec = CommandDecoder::new();
    /// dec.feed(&[0x73], |_| {});
    /// dec.reset();
    /// assert_eq!(dec.held_bytes(), 0);
    /// ```
    pub fn reset(&mut self) {
        self.held.clear();
    }

    /// Bytes held: received, and not yet decoded nor dropped (a frame waiting for the rest of
    /// its bytes, and any bytes behind it).
    ///
    /// ```
    /// use aok_proto::{CommandDecoder, Decode};
    /// let mut dec = CommandDecoder::new();
    /// dec.feed(&[0x53], |_| {});
    /// assert_eq!(dec.held_bytes(), 1);
    /// ```
    pub const fn held_bytes(&self) -> usize {
        self.held.len
    }

    /// The counters.
    ///
    /// ```
    /// assert_eq!(aok_proto::CommandDecoder::new().stats().frames_ok, 0);
    /// ```
    pub const fn stats(&self) -> Stats {
        self.stats
    }
}
