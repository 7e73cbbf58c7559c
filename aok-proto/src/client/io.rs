//! The wire side: loading frames to send, writing them, reading and handling what arrives.

use super::*;
use crate::decoder::Rules;

impl<S: Read<u8> + Write<u8>> Client<S> {
    pub(super) fn load(&mut self, bytes: &[u8]) {
        let n = bytes.len().min(MAX_COMMAND_LEN);
        if let (Some(dst), Some(src)) = (self.tx.get_mut(..n), bytes.get(..n)) {
            dst.copy_from_slice(src);
        }
        self.tx_len = n;
        self.tx_pos = 0;
        self.flushed = false;
    }

    pub(super) fn load_command(&mut self) {
        let (frame, n) = self.command.wire();
        self.load(frame.get(..n).unwrap_or(&[]));
    }

    /// Write what is left of `tx`; `Ok(true)` once it is all out and flushed.
    pub(super) fn transmit(&mut self) -> Result<bool, ClientError> {
        while let Some(&b) = self
            .tx
            .get(self.tx_pos)
            .filter(|_| self.tx_pos < self.tx_len)
        {
            match self.serial.write(b) {
                Ok(()) => self.tx_pos = self.tx_pos.wrapping_add(1),
                Err(nb::Error::WouldBlock) => return Ok(false),
                Err(nb::Error::Other(e)) => {
                    return Err(ClientError::Serial(SerialError::from_hal(&e)));
                }
            }
        }
        if !self.flushed {
            match self.serial.flush() {
                Ok(()) => self.flushed = true,
                Err(nb::Error::WouldBlock) => return Ok(false),
                Err(nb::Error::Other(e)) => {
                    return Err(ClientError::Serial(SerialError::from_hal(&e)));
                }
            }
        }
        Ok(true)
    }

    pub(super) fn receive(&mut self, now_ms: u32) {
        for _ in 0..MAX_READS_PER_POLL {
            match self.serial.read() {
                Ok(b) => {
                    self.last_rx = now_ms;
                    // Failures (checksums, out-of-range fields) are counted by the decoder; the
                    // client only acts on messages.
                    let mut event = self.decoder.push(b);
                    while let Some(ev) = event {
                        if let Ok(m) = ev {
                            self.handle(m);
                        }
                        event = self.decoder.poll();
                    }
                }
                Err(nb::Error::WouldBlock) => break,
                Err(nb::Error::Other(_)) => {
                    self.stats.read_errors = self.stats.read_errors.wrapping_add(1);
                }
            }
        }
    }

    pub(super) fn flush_decoder(&mut self, now_ms: u32) {
        while let Some(ev) = self.decoder.quiet_next() {
            if let Ok(m) = ev {
                self.handle(m);
            }
        }
        self.last_rx = now_ms;
    }

    pub(super) fn handle(&mut self, message: Message) {
        let waiting = matches!(self.phase, Phase::Send | Phase::Await) && self.result.is_none();
        let result = match (message, waiting, self.expect) {
            (Message::Debug(d), _, _) => {
                self.queue_debug(d);
                return;
            }
            (Message::Ack(a), true, Expect::Ack) => Some(match a {
                Ack::Ok => Ok(Outcome::Acked),
                Ack::Error => Err(ClientError::Rejected),
                Ack::InFlight => Err(ClientError::RefusedInFlight),
            }),
            (Message::Parameter(p), true, Expect::Parameter(n)) if p.number == n => {
                Some(Ok(Outcome::Parameter(p)))
            }
            (Message::Parameter(p), true, Expect::Bulk(first)) => {
                let index = p.number.wrapping_sub(first);
                if let Some(slot) = self.bulk.get_mut(usize::from(index)) {
                    *slot = p.value;
                    self.bulk_seen |= 1u16.wrapping_shl(u32::from(index));
                    if self.bulk_seen == u16::MAX {
                        Some(Ok(Outcome::Bulk(BulkValues {
                            first,
                            values: self.bulk,
                        })))
                    } else {
                        return;
                    }
                } else {
                    None
                }
            }
            (Message::Waypoint(w), true, Expect::Waypoint(s)) if w.slot == s => {
                Some(Ok(Outcome::Waypoint(w)))
            }
            _ => None,
        };
        match result {
            Some(r) => self.result = Some(r),
            None => self.stats.stray = self.stats.stray.wrapping_add(1),
        }
    }

    pub(super) fn queue_debug(&mut self, value: DebugValue) {
        self.stats.debug_values = self.stats.debug_values.wrapping_add(1);
        if self.debug_count >= DEBUG_QUEUE {
            self.debug_head = (self.debug_head.wrapping_add(1)) % DEBUG_QUEUE;
            self.debug_count = DEBUG_QUEUE - 1;
            self.stats.debug_dropped = self.stats.debug_dropped.wrapping_add(1);
        }
        let tail = (self.debug_head.wrapping_add(self.debug_count)) % DEBUG_QUEUE;
        if let Some(slot) = self.debug.get_mut(tail) {
            *slot = value;
            self.debug_count = self.debug_count.wrapping_add(1);
        }
    }

    /// Record the result and move on: restore debug output if the client turned it off, else stop.
    pub(super) fn conclude(&mut self, result: Result<Outcome, ClientError>) {
        self.result = Some(result);
        self.conclude_pending();
    }

    pub(super) fn conclude_pending(&mut self) {
        self.decoder.expect(Expect::Nothing);
        if self.restore {
            self.restore = false;
            self.load(&DEBUG_ON);
            self.phase = Phase::Restore;
        } else {
            self.phase = Phase::Idle;
        }
    }

    pub(super) fn finish(
        &mut self,
        restore_error: Option<ClientError>,
    ) -> nb::Result<Outcome, ClientError> {
        self.phase = Phase::Idle;
        match (self.result.take(), restore_error) {
            (Some(Ok(o)), None) => Ok(o),
            (Some(Err(e)), _) | (_, Some(e)) => Err(nb::Error::Other(e)),
            (None, None) => Err(nb::Error::Other(ClientError::Timeout)),
        }
    }
}
