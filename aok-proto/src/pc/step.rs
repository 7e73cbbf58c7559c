//! The per-byte state machine: a frame's length from its first byte, the checksum, rescans.

use super::*;

impl PcDecoder {
    pub(super) fn drop_front(&mut self) {
        self.need = 0;
        self.stats.bytes_discarded = self.stats.bytes_discarded.wrapping_add(1);
        self.len = shift_left(&mut self.buf, self.len, 1);
        self.front_not_reply = false;
    }

    pub(super) fn consume(&mut self, n: usize) {
        self.need = 0;
        self.stats.frames_ok = self.stats.frames_ok.wrapping_add(1);
        self.len = shift_left(&mut self.buf, self.len, n);
        self.front_not_reply = false;
    }

    pub(super) fn checksum_failed(&mut self) {
        self.stats.checksum_errors = self.stats.checksum_errors.wrapping_add(1);
        self.drop_front();
    }

    pub(super) fn settle(&mut self, message: &Message) {
        self.expect = match (self.expect, message) {
            (Expect::Ack, Message::Ack(_)) => Expect::Nothing,
            (Expect::Parameter(n), Message::Parameter(p)) if p.number == n => Expect::Nothing,
            (Expect::Bulk(first), Message::Parameter(p)) if p.number == first.wrapping_add(15) => {
                Expect::Nothing
            }
            (Expect::Waypoint(s), Message::Waypoint(w)) if w.slot == s => Expect::Nothing,
            (e, _) => e,
        };
    }

    #[inline]
    pub(super) fn step(&mut self, flush: bool) -> Option<Result<Message, Error>> {
        // Nothing buffered gives nothing (the usual last call to `poll`); a frame still
        // short of its known length gives nothing until the line goes quiet.
        if self.len == 0 || (self.len < self.need && !flush) {
            return None;
        }
        // The first byte of a self-describing frame only tells its length (unless a headerless
        // reply is pending: then any byte may start one, and the slow path decides).
        if self.len == 1 && !flush && !self.headerless_pending() {
            let need = match self.buf.first() {
                Some(&DEBUG) => DEBUG_LEN,
                Some(&PARAMETER_REPLY) => HEADED_REPLY_LEN,
                Some(&WAYPOINT) => WAYPOINT_LEN,
                _ => 0,
            };
            if need != 0 {
                self.need = need;
                return None;
            }
        }
        self.step_slow(flush)
    }

    /// Whether a headerless (<= 0.30) parameter reply is pending: then any byte may start one.
    #[inline]
    pub(super) fn headerless_pending(&self) -> bool {
        matches!(self.expect, Expect::Parameter(_)) && self.form == ReplyForm::Headerless
    }

    pub(super) fn step_slow(&mut self, flush: bool) -> Option<Result<Message, Error>> {
        loop {
            let len = if self.len < MAX_COMMAND_LEN {
                self.len
            } else {
                MAX_COMMAND_LEN
            };
            let bytes = self.buf.get(..len)?;
            let first = *bytes.first()?;
            let headerless_pending = match self.expect {
                Expect::Parameter(n) if self.form == ReplyForm::Headerless => Some(n),
                _ => None,
            };
            // The headerless reply candidate comes first: any byte may start it.
            if let (Some(number), false) = (headerless_pending, self.front_not_reply) {
                if len < HEADERLESS_REPLY_LEN {
                    if flush {
                        self.abandon();
                        return Some(Err(Error::Truncated));
                    }
                    self.need = HEADERLESS_REPLY_LEN;
                    return None;
                }
                match ParameterValue::parse_headerless(bytes, number) {
                    Ok(p) => {
                        self.consume(HEADERLESS_REPLY_LEN);
                        let m = Message::Parameter(p);
                        self.settle(&m);
                        return Some(Ok(m));
                    }
                    Err(_) if first == DEBUG => {
                        // Not a reply; maybe a debug frame.
                        self.front_not_reply = true;
                        continue;
                    }
                    Err(_) => {
                        self.checksum_failed();
                        return Some(Err(Error::ChecksumMismatch));
                    }
                }
            }
            let Some(need) = frame_len(first, self.expect) else {
                self.stats.unknown_bytes = self.stats.unknown_bytes.wrapping_add(1);
                self.drop_front();
                continue;
            };
            if len < need {
                if flush {
                    self.abandon();
                    return Some(Err(Error::Truncated));
                }
                self.need = need;
                return None;
            }
            match Message::parse(bytes) {
                Ok((m, n)) => {
                    self.consume(n);
                    self.settle(&m);
                    return Some(Ok(m));
                }
                Err(Error::ChecksumMismatch) => {
                    self.checksum_failed();
                    return Some(Err(Error::ChecksumMismatch));
                }
                Err(e) => {
                    // Intact but out of range (a waypoint reply with a bad slot): drop it whole.
                    self.stats.invalid = self.stats.invalid.wrapping_add(1);
                    self.need = 0;
                    self.len = shift_left(&mut self.buf, self.len, need);
                    self.front_not_reply = false;
                    return Some(Err(e));
                }
            }
        }
    }

    pub(super) fn abandon(&mut self) {
        self.stats.abandoned = self.stats.abandoned.wrapping_add(1);
        self.drop_front();
    }
}
