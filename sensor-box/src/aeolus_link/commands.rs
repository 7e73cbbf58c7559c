//! What UART0 receives: the deframer, COMMAND (`a pause`, `a resume`, `a reboot`, anything
//! else answered as unknown) and SETTIME.

use super::{AeolusLink, FRAME_BUF, RX_BUDGET, TX_QUEUE, UNKNOWN_PREFIX, bump};
use crate::Shared;
use aeolus_proto::message::{SetTime, Text, id};
use aeolus_proto::{Frame, TEXT_CAPACITY};
use embedded_hal_nb::serial::Read;

/// What a received frame asks for, copied out of the deframer's buffer.
pub(super) enum Incoming {
    Command(Text),
    SetTime(SetTime),
    Ignored,
    Error,
}

impl AeolusLink {
    pub(super) fn receive<P: Read<u8>>(&mut self, now_ms: u64, port: &mut P, shared: &mut Shared) {
        for _ in 0..RX_BUDGET {
            // A byte is read only while the longest answer it could complete still fits: when
            // the host reads slowly and TX backs up, received bytes wait in the port (and the
            // UART) instead of their answers being dropped.
            if TX_QUEUE - self.tx.len() < FRAME_BUF {
                break;
            }
            match port.read() {
                Ok(byte) => {
                    let incoming = self.deframe(byte);
                    self.handle(incoming, now_ms, shared);
                }
                Err(nb::Error::WouldBlock) => break,
                Err(nb::Error::Other(_)) => bump(&mut self.counters.port_errors),
            }
        }
    }

    /// Feeds one byte to the deframer; what a completed frame asks for, if any. Only the two
    /// messages the box acts on are parsed (the others' parsers stay out of the firmware).
    fn deframe(&mut self, byte: u8) -> Option<Incoming> {
        let Ok(frame) = self.deframer.push(byte)? else {
            return Some(Incoming::Error);
        };
        Some(incoming(&frame))
    }

    pub(super) fn handle(&mut self, incoming: Option<Incoming>, now_ms: u64, shared: &mut Shared) {
        match incoming {
            None => {}
            Some(Incoming::Command(text)) => self.command(&text, shared),
            Some(Incoming::SetTime(time)) => self.set_time(time, now_ms, shared),
            Some(Incoming::Ignored) => bump(&mut self.counters.ignored),
            Some(Incoming::Error) => bump(&mut self.counters.rx_errors),
        }
    }

    fn command(&mut self, text: &Text, shared: &mut Shared) {
        match text.as_bytes().trim_ascii() {
            b"a pause" => {
                crate::info!("AEOLUS: a pause");
                shared.paused = true;
                self.toast(b"AEOLUS paused");
            }
            b"a resume" => {
                crate::info!("AEOLUS: a resume");
                shared.paused = false;
                self.toast(b"AEOLUS resumed");
            }
            b"a reboot" => {
                crate::info!("AEOLUS: a reboot");
                self.toast(b"AEOLUS rebooting");
                shared.requests.reboot = true;
            }
            other => {
                crate::warn!("AEOLUS: unknown command ({=usize} bytes)", other.len());
                bump(&mut self.counters.unknown_commands);
                let mut answer = [0u8; TEXT_CAPACITY];
                let n = join(&mut answer, UNKNOWN_PREFIX, other);
                self.toast(answer.get(..n).unwrap_or(&[]));
                return;
            }
        }
        bump(&mut self.counters.commands);
    }

    fn set_time(&mut self, time: SetTime, now_ms: u64, shared: &mut Shared) {
        if !settime_in_range(&time) {
            crate::warn!("AEOLUS: SETTIME out of range, ignored");
            bump(&mut self.counters.settime_rejected);
            return;
        }
        crate::info!(
            "AEOLUS: SETTIME {=u16}-{=u8}-{=u8} {=u8}:{=u8}:{=u8} at {=u64} ms",
            1900 + u16::from(time.year_since_1900),
            time.month0 + 1,
            time.day,
            time.hour,
            time.minute,
            time.second,
            now_ms
        );
        shared.wall_clock = Some((time, now_ms));
        bump(&mut self.counters.settime);
    }
}

/// What a good frame asks for. Only the two messages the box acts on are parsed.
pub(super) fn incoming(frame: &Frame<'_>) -> Incoming {
    let parsed = match frame.id() {
        id::COMMAND => Text::parse(id::COMMAND, frame.data()).map(Incoming::Command),
        id::SETTIME => SetTime::parse(frame.data()).map(Incoming::SetTime),
        _ => Ok(Incoming::Ignored),
    };
    parsed.unwrap_or(Incoming::Error)
}

/// Writes `a` then as much of `b` as fits into `out`; returns the length written.
fn join(out: &mut [u8], a: &[u8], b: &[u8]) -> usize {
    let mut n = 0;
    for (slot, &byte) in out.iter_mut().zip(a.iter().chain(b)) {
        *slot = byte;
        n += 1;
    }
    n
}

/// SETTIME fields within the ranges of section 7.16 (DECISIONS.md A8).
fn settime_in_range(t: &SetTime) -> bool {
    t.month0 <= 11 && (1..=31).contains(&t.day) && t.hour <= 23 && t.minute <= 59 && t.second <= 59
}
