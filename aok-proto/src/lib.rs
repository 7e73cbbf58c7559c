//! Both ends of the AOK serial protocol (38400 8N1) for `no_std` firmware and host tools. The
//! wire formats follow `DECISIONS.md` K1..K9; the crate README lists the extra decisions.
//!
//! # The one loop
//!
//! ```
//! use aok_proto::{Command, CommandDecoder, Decode, Expect, FirmwareVersion, Message,
//!                 MessageDecoder, ParameterValue};
//! // PC: read parameter 12.
//! let mut wire = [0u8; 19];
//! let n = Command::ReadParameter(12).emit(&mut wire)?;
//! // Device: decode it (every slice the UART gives, one byte included) and answer.
//! let mut device = CommandDecoder::new();
//! let mut asked = Vec::new();
//! device.feed(&wire[..n], |event| match event {
//!     Ok(Command::ReadParameter(number)) => asked.push(number),
//!     Ok(_) => {}
//!     Err(_) => { /* counted; the decoder resynchronised */ }
//! });
//! device.finish(|_| { /* the line went quiet: nothing was left */ });
//! assert_eq!(asked, [12]);
//! let m = Message::Parameter(ParameterValue { number: 12, value: 1500 });
//! let mut reply = [0u8; 7];
//! let reply_len = m.emit(&mut reply, FirmwareVersion::LATEST.reply_form())?;
//! // PC: decode the reply, knowing what it waits for.
//! let mut pc = MessageDecoder::new(FirmwareVersion::LATEST);
//! pc.expect(Expect::Parameter(12));
//! let mut got = Vec::new();
//! pc.feed(&reply[..reply_len], |event| got.push(event));
//! pc.finish(|event| got.push(event));
//! assert_eq!(got, [Ok(Message::Parameter(ParameterValue { number: 12, value: 1500 }))]);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # Contents
//!
//! - The decoders, named after what they read, both implementing [`Decode`], the one decoder
//!   contract of this workspace: [`CommandDecoder`] runs on the flight controller and reads the
//!   PC's commands; [`MessageDecoder`] runs on the ground tool and reads the device's debug
//!   frames, acks and replies, knowing which request is pending ([`Expect`]).
//!   [`Stream`] gives each of their events its [`Place`] in the stream (from the decoder's
//!   [`Span`]).
//! - Encoding, one vocabulary with the other protocol crates: every value that goes on the
//!   wire has `emit(out)` (its whole frame into a caller's buffer; AOK frames have no framing
//!   beyond it) and `buffer_len()`: [`Command::emit`] (the PC's side, also the ready-made
//!   [`DEBUG_OFF`] and [`DEBUG_ON`]), the device's [`Message::emit`] (`emit(out, form)` and
//!   `buffer_len(form)`: the [`ReplyForm`] of a parameter reply) and
//!   [`BulkReply::emit`](message::BulkReply::emit) (the 16 replies to a bulk read).
//! - [`client`]: the PC-side client: [`Client`], a non-blocking state machine over
//!   `embedded-hal-nb` serial traits, and its async form `client::AsyncClient` (feature
//!   `embedded-io-async`).
//! - [`FrameLayout`]: every frame's bytes as a table ([`Command::FRAMES`], [`Message::FRAMES`]).
//! - [`values`]: motor numbers, sticks, waypoint slots, action words, acks, firmware versions.
//!
//! # Features
//!
//! - `embedded-io`, `embedded-io-async`: `embedded_io` and `embedded_io_async`, readers of the
//!   next message (PC side) or command (device side) from a `Read`, a writer into a `Write`,
//!   and (async) `client::AsyncClient`; a reader fails with `IoError`, a writer with `WriteError`.
//! - `defmt`, `serde`: `defmt::Format` and serde's traits derived on the public types.
#![no_std]
#![forbid(unsafe_code)]
#![deny(missing_docs)]

pub mod client;
pub mod command;
mod decoder;
#[cfg(feature = "embedded-io")]
pub mod embedded_io;
#[cfg(feature = "embedded-io-async")]
pub mod embedded_io_async;
mod error;
#[cfg(any(feature = "embedded-io", feature = "embedded-io-async"))]
mod io;
mod layout;
pub mod message;
pub mod values;

pub use client::{Client, Config, Outcome};
pub use command::{
    Command, DEBUG_OFF, DEBUG_ON, Expect, ExternalControl, MotorTest, ParameterValue, Waypoint,
};
pub use decoder::{CommandDecoder, MessageDecoder, Stats};
pub use error::{ClientError, EncodeError, Error, SerialError};
pub use frame_io::{Decode, Event, Place, Span, Stream};
#[cfg(any(feature = "embedded-io", feature = "embedded-io-async"))]
pub use io::{IoError, WriteError};
pub use layout::FrameLayout;
pub use message::{BulkReply, DebugValue, Message};
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
