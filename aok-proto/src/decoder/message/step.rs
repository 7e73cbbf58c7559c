//! The step: every rule of the message decoder, once (a frame's length from its first byte, the
//! headerless reply, acks, the checksum, what is dropped after a failure), applied to a window
//! of bytes.

use super::*;
use crate::checked_value;
use crate::command::ParameterValue;
use crate::decoder::Step;
use crate::message::{DebugValue, HEADERLESS_REPLY_LEN};

/// The rules, applied to the bytes at the front of `window` (the first byte not decided on
/// yet comes first). The byte-by-byte path and the end of the stream run it over the buffer,
/// the slice path over the input itself: every path decides through this function. The decoder's fields it reads and
/// updates are passed apart from its buffer, which may be the window.
///
/// - While a headerless (<= 0.30) reply is pending, any byte may start one; a `1C` whose
///   reply check fails is read as a debug frame (`front_not_reply` remembers that).
/// - Otherwise a frame's length follows from its first byte; 'O'/'E'/'I' are acks only while
///   one is expected; any other byte is unknown: counted and dropped.
/// - A whole frame is checked: a bad checksum drops only its first byte (the bytes after it
///   are rescanned), and so does a good checksum with an out-of-range field. A message
///   that matches the pending request clears it.
///
/// Each decision depends on a fixed prefix of the window only, so it is the same whether the
/// window holds more bytes or not.
#[inline(always)]
pub(super) fn judge<F: FnMut(Result<Message, Error>)>(
    stats: &mut Stats,
    expect: &mut Expect,
    front_not_reply: &mut bool,
    form: ReplyForm,
    window: &[u8],
    on_event: &mut F,
) -> Step {
    let Some(&first) = window.first() else {
        return Step::Need(1);
    };
    let headerless = match *expect {
        Expect::Parameter(n) if form == ReplyForm::Headerless => Some(n),
        _ => None,
    };
    match headerless {
        None => {
            // The common frame first, without `Message::parse`: an intact debug frame is
            // exactly what it makes of it, and settles nothing.
            if first == DEBUG {
                if let Some(frame) = window.first_chunk::<DEBUG_LEN>() {
                    if let Some((number, value)) = checked_value(frame) {
                        stats.frames_ok = stats.frames_ok.wrapping_add(1);
                        on_event(Ok(Message::Debug(DebugValue { number, value })));
                        return Step::Used(DEBUG_LEN);
                    }
                }
            }
        }
        // The headerless reply candidate comes first: any byte may start it.
        Some(number) if !*front_not_reply => {
            let Some(reply) = window.get(..HEADERLESS_REPLY_LEN) else {
                return Step::Need(HEADERLESS_REPLY_LEN);
            };
            match ParameterValue::parse_headerless(reply, number) {
                Ok(p) => {
                    let m = Message::Parameter(p);
                    return accept(stats, expect, HEADERLESS_REPLY_LEN, m, on_event);
                }
                // Not a reply; maybe a debug frame (the rules below).
                Err(_) if first == DEBUG => *front_not_reply = true,
                Err(e) => return checksum_failed(stats, e, on_event),
            }
        }
        Some(_) => {}
    }
    let Some(need) = frame_len(first, *expect) else {
        stats.unknown_bytes = stats.unknown_bytes.wrapping_add(1);
        stats.bytes_discarded = stats.bytes_discarded.wrapping_add(1);
        return Step::Used(1);
    };
    let Some(frame) = window.get(..need) else {
        return Step::Need(need);
    };
    match Message::parse(frame) {
        Ok((m, n)) => accept(stats, expect, n, m, on_event),
        Err(e @ Error::ChecksumMismatch { .. }) => checksum_failed(stats, e, on_event),
        Err(e) => {
            // A good checksum but a value out of range (a waypoint reply with a bad slot): as
            // a checksum failure, only the first byte goes and the rest is rescanned.
            stats.invalid = stats.invalid.wrapping_add(1);
            stats.bytes_discarded = stats.bytes_discarded.wrapping_add(1);
            on_event(Err(e));
            Step::Used(1)
        }
    }
}

/// A message decoded: counted, the pending request settled, handed over.
#[inline]
fn accept<F: FnMut(Result<Message, Error>)>(
    stats: &mut Stats,
    expect: &mut Expect,
    used: usize,
    m: Message,
    on_event: &mut F,
) -> Step {
    stats.frames_ok = stats.frames_ok.wrapping_add(1);
    settle(expect, &m);
    on_event(Ok(m));
    Step::Used(used)
}

/// A checksum failed: the false start is dropped, the rescan starts at the next byte.
fn checksum_failed<F: FnMut(Result<Message, Error>)>(
    stats: &mut Stats,
    error: Error,
    on_event: &mut F,
) -> Step {
    stats.checksum_errors = stats.checksum_errors.wrapping_add(1);
    stats.bytes_discarded = stats.bytes_discarded.wrapping_add(1);
    on_event(Err(error));
    Step::Used(1)
}

/// The pending request is over when its reply or ack arrives.
fn settle(expect: &mut Expect, message: &Message) {
    *expect = match (*expect, message) {
        (Expect::Ack, Message::Ack(_)) => Expect::Nothing,
        (Expect::Parameter(n), Message::Parameter(p)) if p.number == n => Expect::Nothing,
        (Expect::Bulk(first), Message::Parameter(p)) if p.number == first.wrapping_add(15) => {
            Expect::Nothing
        }
        (Expect::Waypoint(s), Message::Waypoint(w)) if w.slot == s => Expect::Nothing,
        (e, _) => e,
    };
}

impl MessageDecoder {
    /// Runs the step over the buffer until it gives an event or needs more bytes. With
    /// `quiet` (the line went quiet: the end of the stream), an undecided front is given up:
    /// its first byte is dropped and reported as [`Error::Truncated`].
    #[inline]
    pub(super) fn step(&mut self, quiet: bool) -> Option<Result<Message, Error>> {
        if self.held.len == 0 {
            // Nothing held: nothing to decide (the usual last call to `poll`).
            return None;
        }
        if !quiet {
            // The step's last answer: a frame still short of its known length stays
            // undecided until the line goes quiet.
            if self.held.len < self.held.need {
                return None;
            }
            // A lone first byte of a self-describing frame: only its length is known (the
            // rule `judge` applies, asked here without the call). Not while a headerless
            // reply is pending: then any byte may start one.
            if self.held.len == 1 && !self.headerless_pending() {
                let first = self.held.buf.first().copied().unwrap_or(0);
                let need = frame_len(first, self.expect).unwrap_or(0);
                if need > 1 {
                    self.held.need = need;
                    return None;
                }
            }
        }
        self.step_slow(quiet)
    }

    /// Whether a headerless (<= 0.30) parameter reply is pending: then any byte may start one.
    #[inline]
    fn headerless_pending(&self) -> bool {
        matches!(self.expect, Expect::Parameter(_)) && self.form == ReplyForm::Headerless
    }

    fn step_slow(&mut self, quiet: bool) -> Option<Result<Message, Error>> {
        loop {
            let mut event = None;
            let window = self.held.window();
            if window.is_empty() {
                return None;
            }
            let step = judge(
                &mut self.stats,
                &mut self.expect,
                &mut self.front_not_reply,
                self.form,
                window,
                &mut |e| event = Some(e),
            );
            match step {
                Step::Need(need) => {
                    if quiet {
                        self.stats.abandoned = self.stats.abandoned.wrapping_add(1);
                        self.drop_front();
                        return Some(Err(Error::Truncated));
                    }
                    self.held.need = need;
                    return None;
                }
                Step::Used(used) => {
                    self.front_not_reply = false;
                    self.held.consume(used);
                    if event.is_some() {
                        return event;
                    }
                }
            }
        }
    }

    pub(super) fn drop_front(&mut self) {
        self.stats.bytes_discarded = self.stats.bytes_discarded.wrapping_add(1);
        self.held.consume(1);
        self.front_not_reply = false;
    }

    /// Runs the step over `bytes` itself (nothing is held), handing every event to
    /// `on_event`, until `stop` says so after an event; keeps an undecided tail. Returns the
    /// bytes consumed.
    #[inline(always)]
    pub(super) fn judge_in_place<F: FnMut(Result<Message, Error>) -> bool>(
        &mut self,
        bytes: &[u8],
        mut on_event: F,
    ) -> usize {
        let mut rest = bytes;
        let mut stop = false;
        while !rest.is_empty() && !stop {
            let step = judge(
                &mut self.stats,
                &mut self.expect,
                &mut self.front_not_reply,
                self.form,
                rest,
                &mut |e| stop = on_event(e),
            );
            match step {
                Step::Need(need) => {
                    self.held.keep(rest, need);
                    return bytes.len();
                }
                Step::Used(used) => {
                    self.front_not_reply = false;
                    rest = rest.get(used..).unwrap_or(&[]);
                }
            }
        }
        bytes.len().saturating_sub(rest.len())
    }
}
