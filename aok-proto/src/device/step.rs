//! The per-byte state machine: a command's length from its first bytes, the checksum, rescans.

use super::*;

impl DeviceDecoder {
    #[inline]
    pub(super) fn step(&mut self, flush: bool) -> Option<Result<Command, Error>> {
        // Nothing buffered gives nothing (the usual last call to `poll`); a frame still
        // short of its known length gives nothing until the line goes quiet.
        if self.len == 0 || (self.len < self.need && !flush) {
            return None;
        }
        // The first byte of a command only tells its length (every command has two or more).
        if self.len == 1 && !flush {
            let need = match self.buf.first().map(|&b| command_len(b, None)) {
                Some(Len::Is(n)) if n > 1 => n,
                Some(Len::More) => 2,
                _ => 0,
            };
            if need != 0 {
                self.need = need;
                return None;
            }
        }
        self.step_slow(flush)
    }

    pub(super) fn step_slow(&mut self, flush: bool) -> Option<Result<Command, Error>> {
        loop {
            let len = if self.len < MAX_COMMAND_LEN {
                self.len
            } else {
                MAX_COMMAND_LEN
            };
            let bytes = self.buf.get(..len)?;
            let (&first, rest) = bytes.split_first()?;
            let need = match command_len(first, rest.first().copied()) {
                Len::Is(n) => n,
                Len::More => 2,
                Len::Unknown => {
                    self.stats.unknown_bytes = self.stats.unknown_bytes.wrapping_add(1);
                    self.drop_front();
                    continue;
                }
            };
            if len < need {
                if flush {
                    self.stats.abandoned = self.stats.abandoned.wrapping_add(1);
                    self.drop_front();
                    return Some(Err(Error::Truncated));
                }
                self.need = need;
                return None;
            }
            let parsed = Command::parse_known(first, bytes);
            return Some(match parsed {
                Ok(cmd) => {
                    self.stats.frames_ok = self.stats.frames_ok.wrapping_add(1);
                    self.need = 0;
                    self.len = shift_left(&mut self.buf, self.len, need);
                    Ok(cmd)
                }
                Err(Error::ChecksumMismatch) => {
                    self.stats.checksum_errors = self.stats.checksum_errors.wrapping_add(1);
                    self.drop_front();
                    Err(Error::ChecksumMismatch)
                }
                Err(e) => {
                    self.stats.invalid = self.stats.invalid.wrapping_add(1);
                    self.need = 0;
                    self.len = shift_left(&mut self.buf, self.len, need);
                    Err(e)
                }
            });
        }
    }

    pub(super) fn drop_front(&mut self) {
        self.need = 0;
        self.stats.bytes_discarded = self.stats.bytes_discarded.wrapping_add(1);
        self.len = shift_left(&mut self.buf, self.len, 1);
    }
}
