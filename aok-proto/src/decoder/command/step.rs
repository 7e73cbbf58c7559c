//! The step: every rule of the command decoder, once (a command's length from its first
//! bytes, the checksum, what is dropped after a failure), applied to a window of bytes; and
//! `Rules`, what the paths of `../byte.rs` need of the decoder.

use super::*;
use crate::checked_value;
use crate::command::{Len, MotorTest, ParameterValue, SET_PARAMETER, command_len};
use crate::decoder::Step;
use crate::decoder::byte::{Rules, past_event, past_front};
use crate::layout::{motor_test as motor, set_parameter as set};
use crate::values::Motor;

impl CommandDecoder {
    /// The rules, applied to the bytes at the front of `window` (the first byte not decided on
    /// yet comes first). The byte-by-byte path and the end of the stream run it over the
    /// buffer, the slice path over the input itself: every path decides through this
    /// function.
    ///
    /// - A byte that starts no command is unknown: counted and dropped.
    /// - A command's length follows from its first byte (its first two for `63`).
    /// - A whole command is checked: a bad checksum drops only its first byte (the bytes after
    ///   it are rescanned), and so does a good checksum with an out-of-range field: either
    ///   error condemns the whole candidate (`Step::Rejected`, its span, on the pull form:
    ///   `PULL`; see `Step::condemned`).
    ///
    /// Each decision depends on a fixed prefix of the window only, so it is the same whether
    /// the window holds more bytes or not.
    #[inline(always)]
    pub(super) fn judge<const PULL: bool, F: FnMut(Result<Command, Error>)>(
        stats: &mut Stats,
        window: &[u8],
        on_event: &mut F,
    ) -> Step {
        let Some((&first, tail)) = window.split_first() else {
            return Step::Need(1);
        };
        // The common commands first, without `Command::parse_known`: an intact motor test or
        // parameter set is exactly what it makes of them (a failed check falls through to it).
        if let Some(motor) = Motor::from_command_byte(first) {
            if let Some(f) = window.first_chunk::<{ motor::LEN }>() {
                // The checksum covers the start byte and the value (`motor::CHECKED`).
                if first ^ f[motor::VALUE] == f[motor::CHECKSUM] {
                    let value = f[motor::VALUE];
                    stats.frames_ok = stats.frames_ok.wrapping_add(1);
                    on_event(Ok(Command::MotorTest(MotorTest { motor, value })));
                    return Step::Used(motor::LEN);
                }
            }
        } else if first == SET_PARAMETER {
            if let Some(frame) = window.first_chunk::<{ set::LEN }>() {
                if let Some((number, value)) = checked_value(frame) {
                    stats.frames_ok = stats.frames_ok.wrapping_add(1);
                    on_event(Ok(Command::SetParameter(ParameterValue { number, value })));
                    return Step::Used(set::LEN);
                }
            }
        }
        let need = match command_len(first, tail.first().copied()) {
            Len::Is(n) => n,
            Len::More => return Step::Need(2),
            Len::Unknown => {
                stats.unknown_bytes = stats.unknown_bytes.wrapping_add(1);
                stats.bytes_discarded = stats.bytes_discarded.wrapping_add(1);
                return Step::Used(1);
            }
        };
        let Some(frame) = window.get(..need) else {
            return Step::Need(need);
        };
        match Command::parse_known(first, frame) {
            Ok(cmd) => {
                stats.frames_ok = stats.frames_ok.wrapping_add(1);
                on_event(Ok(cmd));
                Step::Used(need)
            }
            Err(e @ Error::ChecksumMismatch { .. }) => {
                // The false start is dropped; the rescan starts at the next byte.
                stats.checksum_errors = stats.checksum_errors.wrapping_add(1);
                stats.bytes_discarded = stats.bytes_discarded.wrapping_add(1);
                on_event(Err(e));
                Step::condemned::<PULL>(need)
            }
            Err(e) => {
                // As a checksum failure: only the first byte goes. A false candidate passes
                // the 8-bit checksum one time in 256; dropped whole, it would take the
                // intact frames inside it along (`tests/tests/all/resync.rs`).
                stats.invalid = stats.invalid.wrapping_add(1);
                stats.bytes_discarded = stats.bytes_discarded.wrapping_add(1);
                on_event(Err(e));
                Step::condemned::<PULL>(need)
            }
        }
    }
}

impl Rules for CommandDecoder {
    type Item = Command;

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
    fn judge_held<const PULL: bool, F: FnMut(Result<Command, Error>)>(
        &mut self,
        on_event: &mut F,
    ) -> Step {
        Self::judge::<PULL, _>(&mut self.stats, self.held.window(), on_event)
    }

    /// A command's length from its first byte (2 for `63`, whose second byte tells).
    #[inline(always)]
    fn lone_need(&self, first: u8) -> usize {
        match command_len(first, None) {
            Len::Is(n) => n,
            Len::More => 2,
            Len::Unknown => 0,
        }
    }

    /// Nothing is kept about the front.
    #[inline(always)]
    fn front_gone(&mut self) {}

    /// Nothing to note: `decode` asks the buffer first on every call.
    #[inline(always)]
    fn held_event_out(&mut self) {}

    #[inline(always)]
    fn judge_in_place<const MANY: bool, F: FnMut(Result<Command, Error>) -> bool>(
        &mut self,
        bytes: &[u8],
        on_event: F,
    ) -> usize {
        if MANY {
            // `on_event` cannot reach the decoder: its counters can live in a copy meanwhile.
            let mut stats = self.stats;
            let used = in_place::<false, _>(&mut self.held, &mut stats, bytes, on_event);
            self.stats = stats;
            used
        } else {
            in_place::<true, _>(&mut self.held, &mut self.stats, bytes, on_event)
        }
    }
}

/// The slice path's loop: the rules over `bytes` itself (nothing is held), every event handed
/// to `on_event` until it returns true (stop after that event), an undecided tail kept in
/// `held` (and, at the event it stops at, its span: `past_event`). Returns the bytes used.
/// The counters come apart from the decoder, so that they may be a copy. `PULL`: the pull
/// form's (`decode`), as `Rules::run`'s.
#[inline(always)]
fn in_place<const PULL: bool, F: FnMut(Result<Command, Error>) -> bool>(
    held: &mut Held,
    stats: &mut Stats,
    bytes: &[u8],
    mut on_event: F,
) -> usize {
    let mut rest = bytes;
    while !rest.is_empty() {
        let mut stop = false;
        let step = CommandDecoder::judge::<PULL, _>(stats, rest, &mut |e| stop = on_event(e));
        if stop {
            rest = past_event(held, rest, step);
            break;
        }
        match past_front(held, rest, step) {
            Some(after) => rest = after,
            // An undecided tail kept: every byte is used.
            None => return bytes.len(),
        }
    }
    bytes.len().saturating_sub(rest.len())
}
