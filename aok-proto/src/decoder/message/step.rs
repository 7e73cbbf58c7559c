//! The step: every rule of the message decoder, once (a frame's length from its first byte, the
//! headerless reply, acks, the checksum, what is dropped after a failure), applied to a window
//! of bytes; and `Rules`, what the paths of `../byte.rs` need of the decoder.

use super::*;
use crate::checked_value;
use crate::command::ParameterValue;
use crate::decoder::Step;
use crate::decoder::byte::{Rules, past_event, past_front};
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
///   are rescanned), and so does a good checksum with an out-of-range field: either error
///   condemns the whole candidate (`Step::Rejected`, its span, on the pull form: `PULL`;
///   see `Step::condemned`). A message that matches the pending request clears it.
///
/// Each decision depends on a fixed prefix of the window only, so it is the same whether the
/// window holds more bytes or not.
#[inline(always)]
pub(super) fn judge<const PULL: bool, F: FnMut(Result<Message, Error>)>(
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
                Err(e) => {
                    return checksum_failed::<PULL, _>(stats, e, HEADERLESS_REPLY_LEN, on_event);
                }
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
        Err(e @ Error::ChecksumMismatch { .. }) => {
            checksum_failed::<PULL, _>(stats, e, need, on_event)
        }
        Err(e) => {
            // A good checksum but a value out of range (a waypoint reply with a bad slot): as
            // a checksum failure, only the first byte goes and the rest is rescanned.
            stats.invalid = stats.invalid.wrapping_add(1);
            stats.bytes_discarded = stats.bytes_discarded.wrapping_add(1);
            on_event(Err(e));
            Step::condemned::<PULL>(need)
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

/// The checksum of a candidate of `len` bytes failed: the false start is dropped, the rescan
/// starts at the next byte.
fn checksum_failed<const PULL: bool, F: FnMut(Result<Message, Error>)>(
    stats: &mut Stats,
    error: Error,
    len: usize,
    on_event: &mut F,
) -> Step {
    stats.checksum_errors = stats.checksum_errors.wrapping_add(1);
    stats.bytes_discarded = stats.bytes_discarded.wrapping_add(1);
    on_event(Err(error));
    Step::condemned::<PULL>(len)
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

impl Rules for MessageDecoder {
    type Item = Message;

    #[inline(always)]
    fn held(&self) -> &Held {
        &self.held
    }

    #[inline(always)]
    fn held_mut(&mut self) -> &mut Held {
        &mut self.held
    }

    #[inline(always)]
    fn stats_mut(&mut self) -> &mut Stats {
        &mut self.stats
    }

    #[inline(always)]
    fn judge_held<const PULL: bool, F: FnMut(Result<Message, Error>)>(
        &mut self,
        on_event: &mut F,
    ) -> Step {
        judge::<PULL, _>(
            &mut self.stats,
            &mut self.expect,
            &mut self.front_not_reply,
            self.form,
            self.held.window(),
            on_event,
        )
    }

    /// The length of a self-describing frame from its first byte. Not while a headerless
    /// (<= 0.30) reply is pending: then any byte may start one, decided on its own rule.
    #[inline(always)]
    fn lone_need(&self, first: u8) -> usize {
        let headerless =
            matches!(self.expect, Expect::Parameter(_)) && self.form == ReplyForm::Headerless;
        if headerless {
            return 0;
        }
        frame_len(first, self.expect).unwrap_or(0)
    }

    /// The front's failed reply check goes with it.
    #[inline(always)]
    fn front_gone(&mut self) {
        self.front_not_reply = false;
    }

    /// `decode` takes the events after it from the buffer first (see `unpolled`).
    #[inline(always)]
    fn held_event_out(&mut self) {
        self.unpolled = true;
    }

    #[inline(always)]
    fn judge_in_place<const MANY: bool, F: FnMut(Result<Message, Error>) -> bool>(
        &mut self,
        bytes: &[u8],
        on_event: F,
    ) -> usize {
        let form = self.form;
        if MANY {
            // `on_event` cannot reach the decoder: the fields the rules update can live in
            // copies meanwhile.
            let (mut stats, mut expect, mut front_not_reply) =
                (self.stats, self.expect, self.front_not_reply);
            let used = in_place::<false, _>(
                &mut self.held,
                &mut stats,
                &mut expect,
                &mut front_not_reply,
                form,
                bytes,
                on_event,
            );
            self.stats = stats;
            self.expect = expect;
            self.front_not_reply = front_not_reply;
            used
        } else {
            in_place::<true, _>(
                &mut self.held,
                &mut self.stats,
                &mut self.expect,
                &mut self.front_not_reply,
                form,
                bytes,
                on_event,
            )
        }
    }
}

/// The slice path's loop: the rules over `bytes` itself (nothing is held), every event handed
/// to `on_event` until it returns true (stop after that event), an undecided tail kept in
/// `held` (and, at the event it stops at, its span: `past_event`). Returns the bytes used.
/// The fields the rules update come apart from the decoder, so that they may be copies.
/// `PULL`: the pull form's (`decode`), as `Rules::run`'s.
#[inline(always)]
fn in_place<const PULL: bool, F: FnMut(Result<Message, Error>) -> bool>(
    held: &mut Held,
    stats: &mut Stats,
    expect: &mut Expect,
    front_not_reply: &mut bool,
    form: ReplyForm,
    bytes: &[u8],
    mut on_event: F,
) -> usize {
    let mut rest = bytes;
    while !rest.is_empty() {
        let mut stop = false;
        let step = judge::<PULL, _>(stats, expect, front_not_reply, form, rest, &mut |e| {
            stop = on_event(e)
        });
        if stop {
            *front_not_reply = false;
            rest = past_event(held, rest, step);
            break;
        }
        match past_front(held, rest, step) {
            Some(after) => {
                // The front was decided on: its failed reply check goes with it.
                *front_not_reply = false;
                rest = after;
            }
            // An undecided tail kept: every byte is used.
            None => return bytes.len(),
        }
    }
    bytes.len().saturating_sub(rest.len())
}
