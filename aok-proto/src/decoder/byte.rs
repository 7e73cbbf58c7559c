//! The byte path, written once for both decoders: a byte is kept in the buffer, and the step
//! runs over the buffer only when the bytes held may decide the front. Each decoder gives its
//! buffer, its counters and its rules through [`Rules`]; `step.rs` of each folder has the
//! rules themselves. The slice path's handling of a decided front ([`past_front`], and
//! [`past_event`] at the event the pull form stops at) is here too, so that both decoders'
//! slice loops keep the same bytes and record the same spans.
//!
//! # Where an event lies
//!
//! The pull form (`decode`, `end`) records the [`Span`] of each event it returns, once per
//! event and never per byte (`feed`, which reports no span, records nothing):
//!
//! - an item: its frame (`Step::Used`);
//! - an error of the rules: the whole candidate frame it condemns (`Step::Rejected`), though
//!   only its first byte is dropped;
//! - the end of the stream inside a frame: every byte of the frame cut short, all that is
//!   held (none is held after it);
//!
//! and `after` is the bytes held after the event's last byte: every byte held has been used.
//! On the slice path an event ends the bytes used (`after` 0): a rejected candidate's bytes
//! after its first are then kept in the buffer for the rescan, as the byte path holds them.

use frame_io::Span;

use super::{Held, Stats, Step};
use crate::Error;

/// What the byte path needs of a decoder. Implemented by [`CommandDecoder`] and
/// [`MessageDecoder`]; the provided methods are the byte path itself.
///
/// [`CommandDecoder`]: super::CommandDecoder
/// [`MessageDecoder`]: super::MessageDecoder
pub(crate) trait Rules {
    /// What the decoder finds: a command or a message.
    type Item;

    /// The bytes held.
    fn held(&self) -> &Held;

    /// The bytes held, to change.
    fn held_mut(&mut self) -> &mut Held;

    /// The counters.
    fn stats_mut(&mut self) -> &mut Stats;

    /// The rules (`judge` of the decoder's `step.rs`) over the bytes held; `PULL`: for the
    /// pull form, a condemned candidate is [`Step::Rejected`] (see [`Step::condemned`]).
    fn judge_held<const PULL: bool, F: FnMut(Result<Self::Item, Error>)>(
        &mut self,
        on_event: &mut F,
    ) -> Step;

    /// How many bytes the step waits for when `first` is the only byte held, as the rules
    /// decide (asked without running them); 1 or less: the step decides on it now.
    fn lone_need(&self, first: u8) -> usize;

    /// The front was decided on (used or dropped): forget what was known of it.
    fn front_gone(&mut self);

    /// The pull form handed out an event from the bytes held: more may follow it there.
    fn held_event_out(&mut self);

    /// The slice path: runs the rules over `bytes` itself while nothing is held, handing
    /// every event to `on_event` until it returns true (stop after that event), and keeps an
    /// undecided tail. Returns the bytes used. `MANY` (`feed`, which takes every event): the
    /// fields the rules update are copied into locals for the loop (registers) and stored
    /// once at the end; without it (the pull form, one event a call) they are updated in
    /// place, which costs less than the copies for a frame or two.
    fn judge_in_place<const MANY: bool, F: FnMut(Result<Self::Item, Error>) -> bool>(
        &mut self,
        bytes: &[u8],
        on_event: F,
    ) -> usize;

    /// Keeps `byte`; true when the step must run on the bytes held. False, with no call,
    /// inside a frame of known length (most bytes) and on the first byte of a frame that
    /// cannot be decided on alone.
    #[inline(always)]
    fn store(&mut self, byte: u8) -> bool {
        if !self.held_mut().append(byte) {
            self.overflow(byte);
        }
        let held = self.held();
        if held.len < held.need {
            return false;
        }
        !self.lone_first_byte()
    }

    /// The buffer was full (see [`Held::append`]): the front goes first.
    #[cold]
    #[inline(never)]
    fn overflow(&mut self, byte: u8) {
        self.drop_front();
        self.held_mut().append(byte);
    }

    /// One byte is held and the rules wait for more: then `need` is set. The rule `judge`
    /// applies, asked here without the call.
    #[inline(always)]
    fn lone_first_byte(&mut self) -> bool {
        let held = self.held();
        if held.len != 1 {
            return false;
        }
        let need = self.lone_need(held.buf[0]);
        let waits = need > 1;
        if waits {
            self.held_mut().need = need;
        }
        waits
    }

    /// Drops the front's first byte, counted as discarded. Out of line: its callers are cold,
    /// and put in line where the buffer is known full, its shift became a `memmove` call
    /// (1.6 KB of `compiler_builtins` on Cortex-M).
    #[inline(never)]
    fn drop_front(&mut self) {
        let stats = self.stats_mut();
        stats.bytes_discarded = stats.bytes_discarded.wrapping_add(1);
        self.held_mut().consume(1);
        self.front_gone();
    }

    /// One byte: the first event it causes; [`Rules::poll`] takes any further events a
    /// rescan uncovered.
    #[inline]
    fn push(&mut self, byte: u8) -> Option<Result<Self::Item, Error>> {
        if self.store(byte) {
            self.step_slow(false)
        } else {
            None
        }
    }

    /// The next event from bytes already held (after a rescan), or `None`.
    #[inline]
    fn poll(&mut self) -> Option<Result<Self::Item, Error>> {
        self.step(false)
    }

    /// The next event of the quiet line (the end of the stream), or `None` once nothing is
    /// held: the partial frame at the front is given up as [`Error::Truncated`].
    fn quiet_next(&mut self) -> Option<Result<Self::Item, Error>> {
        self.step(true)
    }

    /// The next event from the bytes held, or `None` when they decide nothing more. With
    /// `quiet` (the line went quiet: the end of the stream), an undecided front is given up:
    /// its first byte is dropped and reported as [`Error::Truncated`].
    #[inline]
    fn step(&mut self, quiet: bool) -> Option<Result<Self::Item, Error>> {
        let held = self.held();
        if held.len == 0 {
            // Nothing held: nothing to decide (the usual last call after an event).
            return None;
        }
        if !quiet {
            // The step's last answer: a frame still short of its known length stays
            // undecided until the line goes quiet.
            if held.len < held.need {
                return None;
            }
            if self.lone_first_byte() {
                return None;
            }
        }
        self.step_slow(quiet)
    }

    /// [`Rules::run`] up to the first event, which it returns (the pull form's byte path).
    fn step_slow(&mut self, quiet: bool) -> Option<Result<Self::Item, Error>> {
        let mut event = None;
        self.run::<true, _>(quiet, &mut |e| {
            event = Some(e);
            true
        });
        event
    }

    /// [`Rules::run`] handing every event to `on_event` (`feed`'s byte path): the events are
    /// handed over in place, none returned through memory.
    #[inline]
    fn deliver<F: FnMut(Result<Self::Item, Error>)>(&mut self, on_event: &mut F) {
        self.run::<false, _>(false, &mut |e| {
            on_event(e);
            false
        });
    }

    /// Runs the step over the buffer, which holds a byte or more, handing each event to
    /// `on_event` until it returns true (stop after that event), the front needs more bytes
    /// or nothing is held any more; with `quiet`, each undecided front is given up as
    /// [`Error::Truncated`] instead.
    ///
    /// `PULL` (the pull form): the event it stops at is the pull form's, and its span is
    /// recorded (see the module's documentation). Without it (`feed`, whose `on_event` never
    /// stops) nothing of the spans is computed: the rules give a condemned candidate as its
    /// first byte used ([`Step::condemned`]), and the loop is the byte path's of before spans.
    #[inline]
    fn run<const PULL: bool, F: FnMut(Result<Self::Item, Error>) -> bool>(
        &mut self,
        quiet: bool,
        on_event: &mut F,
    ) {
        loop {
            let held = self.held().len;
            let mut stop = false;
            // The bytes of the front's event, if it gave one.
            let len = match self.judge_held::<PULL, _>(&mut |e| stop = on_event(e)) {
                Step::Need(need) => {
                    if !quiet {
                        self.held_mut().need = need;
                        return;
                    }
                    let stats = self.stats_mut();
                    stats.abandoned = stats.abandoned.wrapping_add(1);
                    self.drop_front();
                    stop = on_event(Err(Error::Truncated));
                    // The frame cut short: every byte held (it waited for more).
                    held
                }
                step => {
                    // One count for every step (see `Step::dropped`).
                    self.front_gone();
                    self.held_mut().consume(step.dropped());
                    step.event_len()
                }
            };
            if stop {
                if PULL {
                    let after = held.saturating_sub(len);
                    self.held_mut().span = Span { len, after };
                }
                return;
            }
            if self.held().len == 0 {
                return;
            }
        }
    }

    /// The pull form (`decode`) for two bytes or more, once the events left queued are
    /// taken: up to the first event, the bytes held from an earlier call completed byte by
    /// byte, then the slice path over the rest. Returns the bytes used and the event.
    #[inline]
    fn decode_slice(&mut self, bytes: &[u8]) -> (usize, Option<Result<Self::Item, Error>>) {
        let total = bytes.len();
        let mut rest = bytes;
        while self.held().len != 0 {
            let Some((&byte, after)) = rest.split_first() else {
                return (total, None);
            };
            rest = after;
            if let Some(item) = self.push(byte) {
                self.held_event_out();
                return (total.saturating_sub(rest.len()), Some(item));
            }
        }
        let mut found = None;
        let used = self.judge_in_place::<false, _>(rest, |item| {
            found = Some(item);
            true
        });
        if found.is_some() && self.held().len != 0 {
            // A rejected candidate's bytes after its first, kept for the rescan.
            self.held_event_out();
        }
        (total.saturating_sub(rest.len()).saturating_add(used), found)
    }

    /// `feed` for one byte: kept, and the events it causes handed to `on_event`.
    #[inline(always)]
    fn feed_byte<F: FnMut(Result<Self::Item, Error>)>(&mut self, byte: u8, on_event: &mut F) {
        // Most bytes end here, with no call.
        if self.store(byte) {
            self.deliver(on_event);
        }
    }

    /// `feed` for a slice of any length: the bytes held from an earlier call completed byte
    /// by byte, then the slice path over the rest.
    fn feed_slice<F: FnMut(Result<Self::Item, Error>)>(&mut self, bytes: &[u8], mut on_event: F) {
        let rest = self.feed_held(bytes, &mut on_event);
        self.judge_in_place::<true, _>(rest, |item| {
            on_event(item);
            false
        });
    }

    /// `feed` while bytes from an earlier call are held: byte by byte until the buffer is
    /// empty. Returns the bytes left for the slice path (none if the buffer still holds some).
    #[inline]
    fn feed_held<'a, F: FnMut(Result<Self::Item, Error>)>(
        &mut self,
        bytes: &'a [u8],
        on_event: &mut F,
    ) -> &'a [u8] {
        let mut rest = bytes;
        while self.held().len != 0 {
            let Some((&byte, after)) = rest.split_first() else {
                break;
            };
            rest = after;
            self.feed_byte(byte, on_event);
        }
        rest
    }
}

/// The slice path (the rules over the input itself, nothing held) once the rules decided on
/// the front of `rest` without an event the pull form stops at, for both decoders' loops: the
/// rest of `rest` to go on with, or `None` when every byte is used (an undecided tail is kept
/// in `held`, which then waits for `need` bytes; or the step counted past the end, which no
/// rule does). A rejected candidate passes only its first byte: the rescan is the next
/// position.
#[inline(always)]
pub(crate) fn past_front<'a>(held: &mut Held, rest: &'a [u8], step: Step) -> Option<&'a [u8]> {
    match step {
        Step::Need(need) => {
            held.keep(rest, need);
            None
        }
        step => rest.get(step.dropped()..),
    }
}

/// The slice path at the event the pull form stops at (`step` handed it over), once a
/// `decode`, after its loop: records the event's span, which ends the bytes used, and returns
/// the rest of `rest` after it. A rejected candidate is used whole, its bytes after the first
/// kept in `held` for the rescan, as the byte path holds them (the next `decode` reads them
/// first).
#[inline]
pub(crate) fn past_event<'a>(held: &mut Held, rest: &'a [u8], step: Step) -> &'a [u8] {
    let len = step.event_len();
    held.span = Span { len, after: 0 };
    match step {
        Step::Used(used) => rest.get(used..).unwrap_or(&[]),
        Step::Rejected(len) => {
            let (candidate, after) = rest.split_at_checked(len).unwrap_or((rest, &[]));
            held.keep(candidate.get(1..).unwrap_or(&[]), 0);
            after
        }
        // No event leaves the front undecided.
        Step::Need(need) => {
            held.keep(rest, need);
            &[]
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Rules;
    use crate::CommandDecoder;

    /// A full buffer gives up its front byte for the next one. Neither path fills it (each
    /// decides on a frame as soon as it is whole, and none is longer than the buffer), so only
    /// this test reaches the fallback.
    #[test]
    fn a_full_buffer_drops_its_front_for_the_next_byte() {
        let mut d = CommandDecoder::new();
        let mut full = [0x77; 19];
        full[1] = 0x00;
        d.held_mut().keep(&full, 19);
        assert_eq!(d.held().len, 19);
        assert!(d.store(0x42));
        let held = d.held();
        assert_eq!((held.len, held.buf[0], held.buf[18]), (19, 0x00, 0x42));
        assert_eq!(d.stats().bytes_discarded, 1);
    }
}
