//! The step: every rule of the command decoder, once (a command's length from its first
//! bytes, the checksum, what is dropped after a failure), applied to a window of bytes.

use super::*;
use crate::checked_value;
use crate::command::{Len, MotorTest, ParameterValue, SET_PARAMETER, command_len};
use crate::decoder::Step;
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
    ///   it are rescanned), and so does a good checksum with an out-of-range field.
    ///
    /// Each decision depends on a fixed prefix of the window only, so it is the same whether
    /// the window holds more bytes or not.
    #[inline(always)]
    pub(super) fn judge<F: FnMut(Result<Command, Error>)>(
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
                Step::Used(1)
            }
            Err(e) => {
                // As a checksum failure: only the first byte goes. A false candidate passes
                // the 8-bit checksum one time in 256; dropped whole, it would take the
                // intact frames inside it along (`tests/tests/resync.rs`).
                stats.invalid = stats.invalid.wrapping_add(1);
                stats.bytes_discarded = stats.bytes_discarded.wrapping_add(1);
                on_event(Err(e));
                Step::Used(1)
            }
        }
    }

    /// Runs the step over the buffer until it gives an event or needs more bytes. With
    /// `quiet` (the line went quiet: the end of the stream), an undecided front is given up:
    /// its first byte is dropped and reported as [`Error::Truncated`].
    #[inline]
    pub(super) fn step(&mut self, quiet: bool) -> Option<Result<Command, Error>> {
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
            if self.lone_first_byte() {
                return None;
            }
        }
        self.step_slow(quiet)
    }

    /// A lone first byte: only its length is known (the rule `judge` applies, asked here
    /// without the call). True if it waits for more bytes (then `need` is set).
    #[inline(always)]
    fn lone_first_byte(&mut self) -> bool {
        if self.held.len != 1 {
            return false;
        }
        let need = match self.held.buf.first().map(|&b| command_len(b, None)) {
            Some(Len::Is(n)) if n > 1 => n,
            Some(Len::More) => 2,
            _ => 0,
        };
        if need != 0 {
            self.held.need = need;
        }
        need != 0
    }

    fn step_slow(&mut self, quiet: bool) -> Option<Result<Command, Error>> {
        loop {
            let mut event = None;
            let window = self.held.window();
            if window.is_empty() {
                return None;
            }
            match Self::judge(&mut self.stats, window, &mut |e| event = Some(e)) {
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
    }
}
