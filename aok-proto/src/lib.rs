//! Both ends of the AOK serial protocol (38400 8N1) for `no_std` firmware and host tools.
//!
//! * [`device`]: the flight controller's side. [`DeviceDecoder`] reads every command the PC sends,
//!   byte at a time; encoders write debug values, acks, parameter replies (both firmware forms),
//!   bulk replies and waypoint replies.
//! * [`pc`]: the ground tool's side. Command encoders and [`pc::PcDecoder`], which reads the device's
//!   stream of debug frames, acks and replies, knowing which request is pending.
//! * [`client`]: a non-blocking PC-side state machine over `embedded-hal-nb` serial traits: debug off,
//!   drain, request, wait (with timeout), debug back on.
//! * `embedded_io` / `embedded_io_async` (features `embedded-io`, `embedded-io-async`): readers
//!   that return the next message (PC side) or command (device side) from a `Read`
//!   (`frame-io`'s reader over [`pc::PcDecoder`] or [`DeviceDecoder`], which implement
//!   `frame_io::Decode`), a writer
//!   into a `Write`, blocking or async, with the error type `IoError`; and `AsyncClient`, the
//!   client's async form.
//! * [`layout`]: every frame's bytes in one table (start byte, length, field offsets, checksum).
//! * [`values`]: motor numbers, stick values, waypoint slots, action words, acks, firmware versions.
//!
//! The wire formats follow `DECISIONS.md` K1..K9; the crate README lists the extra decisions.
//!
//! ```
//! use aok_proto::{pc::{Expect, PcDecoder}, Command, DeviceDecoder, FirmwareVersion, Message,
//!                 ParameterValue};
//! // PC: read parameter 12.
//! let mut wire = [0u8; 19];
//! let n = Command::ReadParameter(12).emit(&mut wire)?;
//! // Device: decode it and answer.
//! let mut device = DeviceDecoder::new();
//! let mut reply = [0u8; 7];
//! let mut reply_len = 0;
//! for &b in &wire[..n] {
//!     if let Some(Ok(Command::ReadParameter(num))) = device.push(b) {
//!         let m = Message::Parameter(ParameterValue { number: num, value: 1500 });
//!         reply_len = m.emit(FirmwareVersion::LATEST.reply_form(), &mut reply)?;
//!     }
//! }
//! // PC: decode the reply.
//! let mut pc = PcDecoder::new(FirmwareVersion::LATEST);
//! pc.expect(Expect::Parameter(12));
//! let got = reply[..reply_len].iter().find_map(|&b| pc.push(b));
//! assert_eq!(got, Some(Ok(Message::Parameter(ParameterValue { number: 12, value: 1500 }))));
//! # Ok::<(), aok_proto::Error>(())
//! ```
#![no_std]
#![forbid(unsafe_code)]
#![deny(missing_docs)]

pub mod client;
pub mod command;
pub mod device;
#[cfg(feature = "embedded-io")]
pub mod embedded_io;
#[cfg(feature = "embedded-io-async")]
pub mod embedded_io_async;
mod error;
#[cfg(any(feature = "embedded-io", feature = "embedded-io-async"))]
mod io;
pub mod layout;
#[cfg(test)]
mod liveness;
pub mod message;
pub mod pc;
pub mod stats;
mod step;
pub mod values;

pub use client::{Client, Config, Outcome};
pub use command::{Command, ExternalControl, MotorTest, ParameterValue, Waypoint};
pub use device::DeviceDecoder;
pub use error::{Error, SerialError};
#[cfg(any(feature = "embedded-io", feature = "embedded-io-async"))]
pub use io::IoError;
pub use message::{DebugValue, Message};
pub use pc::PcDecoder;
pub use stats::Stats;
pub use values::{
    Ack, Action, ActionWord, FirmwareVersion, Motor, ReplyForm, Stick, WaypointNumber, WaypointSlot,
};

/// The README's example, compiled and run as a doctest.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;

/// XOR of all bytes: the checksum of every AOK frame that has one.
#[inline]
pub(crate) fn xor(bytes: &[u8]) -> u8 {
    bytes.iter().fold(0, |a, &b| a ^ b)
}

/// The value of a `HEAD NUM B1..B4 CRC` frame (a debug value, a parameter set) whose checksum
/// covers `NUM..B4`, if the checksum is right: [`xor`] of those bytes, the four value bytes
/// folded as one word (a few instructions instead of a loop; the frames are 7 bytes, so the
/// check weighs on every byte). `number`, `value` and `checksum` at the offsets of
/// [`layout::debug`], which [`layout::set_parameter`] shares.
#[inline(always)]
pub(crate) fn checked_value(frame: &[u8; layout::debug::LEN]) -> Option<(u8, i32)> {
    use layout::debug::{CHECKSUM, NUMBER, VALUE};
    let value = u32::from_be_bytes(layout::bytes!(frame, VALUE, 4));
    let folded = value ^ (value >> 16);
    let folded = (folded ^ (folded >> 8)) as u8;
    if folded ^ frame[NUMBER] == frame[CHECKSUM] {
        Some((frame[NUMBER], value as i32))
    } else {
        None
    }
}

// `checked_value` reads a parameter set with the debug frame's offsets: they must agree.
const _: () = {
    use layout::{debug, set_parameter as set};
    assert!(debug::LEN == set::LEN && debug::NUMBER == set::NUMBER);
    assert!(debug::VALUE == set::VALUE && debug::CHECKSUM == set::CHECKSUM);
    assert!(debug::CHECKED.start == set::CHECKED.start && debug::CHECKED.end == set::CHECKED.end);
};

/// Drop the first `n` of the `len` buffered bytes; returns the new length.
#[inline]
pub(crate) fn shift_left<const N: usize>(buf: &mut [u8; N], len: usize, n: usize) -> usize {
    let len = if len < N { len } else { N };
    if n >= len {
        return 0;
    }
    // A byte loop rather than `copy_within`: at most 18 bytes, and no bounds-check panic path
    // left for the optimiser to prove away (at `opt-level = "z"` it does not always).
    let mut i = 0;
    while i + n < len {
        let v = buf.get(i + n).copied().unwrap_or(0);
        if let Some(d) = buf.get_mut(i) {
            *d = v;
        }
        i += 1;
    }
    len - n
}
