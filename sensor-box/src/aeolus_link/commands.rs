//! What UART0 receives: the decoder, COMMAND (`a pause`, `a resume`, `a reboot`, anything
//! else answered as unknown) and SETTIME. `a reboot` is refused in flight (answered with the
//! TOAST [`REBOOT_REFUSED`](super::REBOOT_REFUSED), counted in
//! [`LinkCounters::refused_in_flight`](super::LinkCounters::refused_in_flight)): a COMMAND is
//! checked by a 16-bit CRC, but AEOLUS lets a frame go unchecked (a CRC of `00 00`, A3), and
//! nothing in flight needs a reboot.

use super::{AeolusLink, FRAME_BUF, REBOOT_REFUSED, RX_BUDGET, TX_QUEUE, UNKNOWN_PREFIX, bump};
use crate::Shared;
use crate::port::{Receive, receive_slices};
use aeolus_proto::message::{SetTime, Text, id};
use aeolus_proto::{Frame, TEXT_CAPACITY};

/// What a received frame asks for, copied out of the decoder's buffer.
pub(super) enum Incoming {
    Command(Text),
    SetTime(SetTime),
    Ignored,
    /// A good frame whose data does not parse as its type.
    Malformed,
    /// A frame the decoder dropped.
    Error,
}

impl AeolusLink {
    /// Decodes what the port has received (at most [`RX_BUDGET`] bytes, in the slices the
    /// port lends) and acts on every frame it completes.
    pub(super) fn receive<P: Receive>(&mut self, now_ms: u64, port: &mut P, shared: &mut Shared) {
        let taken = receive_slices(port, RX_BUDGET, |bytes| self.decode(bytes, now_ms, shared));
        self.rx_more = matches!(taken, Ok(n) if n >= RX_BUDGET);
        if taken.is_err() {
            bump(&mut self.counters.port_errors);
        }
    }

    /// Decodes a slice event by event through the contract's adapter, in its pull form
    /// (`Stream::next_event` stops
    /// after each frame or error): only a frame queues an answer, so the room is checked again before every
    /// frame's last byte, exactly as if the bytes came one at a time. A byte is decoded only
    /// while the longest answer it could complete still fits: when the host reads slowly and
    /// TX backs up, received bytes wait in the port instead of their answers being dropped.
    /// The count decoded.
    fn decode(&mut self, bytes: &[u8], now_ms: u64, shared: &mut Shared) -> usize {
        let mut done = 0;
        while let Some(rest) = bytes.get(done..).filter(|r| !r.is_empty()) {
            if TX_QUEUE - self.tx.len() < FRAME_BUF {
                break;
            }
            let (len, event) = self.decoder.next_event(rest);
            let incoming_frame = event.map(|(_, ev)| match ev {
                Ok(frame) => incoming(&frame),
                Err(_) => Incoming::Error,
            });
            done += len;
            if let Some(frame) = incoming_frame {
                self.handle(frame, now_ms, shared);
            }
        }
        done
    }

    pub(super) fn handle(&mut self, incoming: Incoming, now_ms: u64, shared: &mut Shared) {
        match incoming {
            Incoming::Command(text) => self.command(&text, shared),
            Incoming::SetTime(time) => self.set_time(time, now_ms, shared),
            Incoming::Ignored => bump(&mut self.counters.ignored),
            Incoming::Malformed => bump(&mut self.counters.malformed),
            Incoming::Error => bump(&mut self.counters.rx_errors),
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
            b"a reboot" if crate::aok_link::flying(shared) => {
                crate::warn!("AEOLUS: a reboot refused: flying");
                self.toast(REBOOT_REFUSED);
                bump(&mut self.counters.refused_in_flight);
                return;
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
    parsed.unwrap_or(Incoming::Malformed)
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
