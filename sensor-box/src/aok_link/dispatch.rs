//! Receive, gate and dispatch: received bytes through the
//! [`CommandDecoder`](aok_proto::CommandDecoder) into the burst being received; at a silence of
//! [`GAP_MS`] the burst is obeyed whole or discarded whole (the framing policy: [`AokLink`],
//! "Framing"); then one `match` over the commands that hands each family to its room
//! (`params`, `waypoints`, `control`, `debug`).

use super::{AokLink, GAP_MS, MAX_REPLY, RX_BUDGET, flying};
use crate::Shared;
use crate::port::Receive;
use aok_proto::{Ack, Command, CommandDecoder, Error as AokError, Stream};

impl AokLink {
    /// Obeys what is left of an accepted burst, then decodes received bytes (at most
    /// [`RX_BUDGET`] a poll, lent by the port a slice at a time) into the open burst, and ends
    /// the burst when this poll observes silence: the port empty after receiving and nothing
    /// taken for [`GAP_MS`]. While an accepted burst is still being obeyed (its replies wait
    /// for room in the TX queue), new bytes wait in the port: back-pressure, no lost reply.
    /// AOK runs at 38 400 Bd: 3 840 bytes a second at most.
    pub(super) fn receive<P: Receive>(&mut self, now_ms: u64, port: &mut P, shared: &mut Shared) {
        if self.obey_next.is_some() {
            self.obey(now_ms, shared);
            if self.obey_next.is_some() {
                return;
            }
        }
        // A fault counted before these bytes were taken may sit in any burst of them.
        let faulted = port.receive_faults() != self.faults_seen;
        let taken = self.take(now_ms, port, shared, faulted);
        // Read after the bytes: a fault counted while they arrived is seen with them.
        self.check_line(port.receive_faults(), now_ms);
        let port_empty = match taken {
            Ok(n) => n < RX_BUDGET,
            Err(_) => {
                self.counters.port_errors = self.counters.port_errors.wrapping_add(1);
                false
            }
        };
        if self.obey_next.is_some() {
            // A burst the receive side framed waits to be obeyed: the rest waits in the port.
            return;
        }
        self.rx_more = matches!(taken, Ok(n) if n >= RX_BUDGET);
        // Silence only counts when the port has nothing more: bytes left in it (the budget, a
        // port error) may be the rest of the burst.
        if port_empty && self.burst_open && now_ms.saturating_sub(self.last_rx_ms) >= GAP_MS {
            self.end_burst(now_ms, shared);
        }
    }

    /// Takes received bytes from the port into the open burst, a slice at a time and at most
    /// [`RX_BUDGET`], and ends the open burst where the port says the receive side saw silence
    /// before the next byte ([`Receive::burst_starts`]: the commands that waited in the ring
    /// while the main loop stalled); stops when a burst so ended waits to be obeyed (its
    /// replies need room in the TX queue). `faulted`: the port counted a line fault that this
    /// poll has not seen yet, which may sit in any of the bursts taken now: each is discarded.
    /// The count taken, or the port's error.
    fn take<P: Receive>(
        &mut self,
        now_ms: u64,
        port: &mut P,
        shared: &mut Shared,
        faulted: bool,
    ) -> Result<usize, P::Error> {
        let mut total = 0;
        while total < RX_BUDGET {
            if self.burst_open && port.burst_starts() {
                if faulted {
                    self.burst_clean = false;
                }
                self.end_burst(now_ms, shared);
                if self.obey_next.is_some() {
                    break;
                }
            }
            let budget = RX_BUDGET - total;
            let n = port.receive(|bytes| {
                let piece = bytes.get(..budget).unwrap_or(bytes);
                self.decode(piece, now_ms)
            })?;
            if n == 0 {
                break;
            }
            total += n;
        }
        Ok(total)
    }

    /// A change of the port's fault count since the last poll is line activity now: it opens
    /// a burst if none is open and spoils it (discarded at the next silence).
    fn check_line(&mut self, faults: u32, now_ms: u64) {
        let new = faults.wrapping_sub(self.faults_seen);
        if new == 0 {
            return;
        }
        crate::debug!("AOK: {=u32} line fault(s): the burst is spoilt", new);
        self.faults_seen = faults;
        self.counters.line_faults = self.counters.line_faults.wrapping_add(new);
        self.last_rx_ms = now_ms;
        self.burst_open = true;
        self.burst_clean = false;
    }

    /// Decodes `bytes` through the contract's adapter in its pull form (`Stream::next_event`), a
    /// byte at a time
    /// (the byte path alone: the firmware links no slice path for AOK's short frames), and
    /// collects every event into the open burst; the count decoded: all of them.
    fn decode(&mut self, bytes: &[u8], now_ms: u64) -> usize {
        if !bytes.is_empty() {
            self.last_rx_ms = now_ms;
            self.burst_open = true;
        }
        for byte in bytes {
            // Every event of the byte before it was taken, so the byte is used at once; the
            // events a rescan left queued come with nothing (`&[]`).
            let (_, mut event) = self.decoder.next_event(core::slice::from_ref(byte));
            while let Some((_, item)) = event {
                self.collect(item);
                event = self.decoder.next_event(&[]).1;
            }
        }
        bytes.len()
    }

    /// One decoder event into the open burst: a command is kept (the burst is spoilt when it
    /// already holds [`BURST_COMMANDS`](super::BURST_COMMANDS)), an error spoils it.
    fn collect(&mut self, item: Result<Command, AokError>) {
        match item {
            Ok(command) => {
                if self.burst.push(command).is_err() {
                    self.burst_clean = false;
                }
            }
            Err(e) => {
                self.counters.rx_errors = self.counters.rx_errors.wrapping_add(1);
                self.burst_clean = false;
                // A faulty `73`/`77` is answered 'E' (the spec), once for the burst: the
                // decoder cannot say which command a bad checksum belonged to.
                if matches!(
                    e,
                    AokError::ChecksumMismatch { .. } | AokError::InvalidSlot(_)
                ) {
                    self.burst_bad_check = true;
                }
            }
        }
    }

    /// Silence observed: a frame still held was cut short (abandoned, reported by the decoder
    /// as `Truncated`), and the burst is obeyed if it decoded cleanly, else discarded whole.
    /// Clean: no error event, no more commands than the buffer holds, and not one byte thrown
    /// away by the decoder (its `bytes_discarded`, which counts every byte that is not part of
    /// a command: unknown bytes, which it skips without an event, false starts, abandoned
    /// starts, unchanged since the last burst ended).
    fn end_burst(&mut self, now_ms: u64, shared: &mut Shared) {
        // The end of the stream of the contract (`finish`), with the decoder taken out for the
        // call so that its events can be collected into `self`; it is put back as it is left.
        let mut decoder = core::mem::replace(&mut self.decoder, Stream::new(CommandDecoder::new()));
        decoder.finish(|_, item| self.collect(item));
        self.decoder = decoder;
        let discarded = self.decoder.decoder().stats().bytes_discarded;
        if self.burst_clean && discarded == self.burst_discarded && !self.burst.is_empty() {
            self.bursts_obeyed = self.bursts_obeyed.wrapping_add(1);
            self.obey_next = Some(0);
            self.obey(now_ms, shared);
        } else {
            crate::debug!("AOK: burst discarded");
            self.counters.bursts_discarded = self.counters.bursts_discarded.wrapping_add(1);
            self.burst.clear();
            if self.burst_bad_check {
                self.ack(Ack::Error);
            }
        }
        self.burst_open = false;
        self.burst_discarded = discarded;
        self.burst_clean = true;
        self.burst_bad_check = false;
    }

    /// The commands of the accepted burst, in order, while the TX queue has room for the
    /// longest reply; the rest at the next poll.
    fn obey(&mut self, now_ms: u64, shared: &mut Shared) {
        loop {
            let next = self.obey_next.unwrap_or(0);
            let Some(&command) = self.burst.get(usize::from(next)) else {
                self.burst.clear();
                self.obey_next = None;
                return;
            };
            if self.tx_free() < MAX_REPLY {
                return;
            }
            self.obey_next = Some(next.wrapping_add(1));
            self.handle(command, now_ms, shared);
        }
    }

    fn handle(&mut self, command: Command, now_ms: u64, shared: &mut Shared) {
        let flying = flying(shared);
        match command {
            Command::DebugOff | Command::DebugOn => self.switch_debug(command, now_ms),
            // The `63` family has no check of its own: nothing of it but debug off/on in
            // flight (the sets and the waypoint store answer 'I' through the store policy).
            Command::Reset | Command::LoadWaypoints if flying => {
                crate::warn!("AOK control command refused: flying");
                self.ack(Ack::InFlight);
            }
            Command::Reset => {
                crate::info!("AOK reset requested");
                shared.requests.reboot = true;
            }
            Command::SetParameter(p) => self.set_parameter(p, flying),
            Command::ReadParameter(number) => self.read_parameter(number),
            Command::BulkRead(first) => self.bulk_read(first),
            Command::LoadSet(n) => self.load_set(n, flying, shared),
            Command::SaveSet(n) => self.save_set(n, flying, now_ms, shared),
            Command::StartSet(n) => self.start_set(n, flying, now_ms, shared),
            Command::SaveWaypoints => self.save_waypoints(flying, now_ms, shared),
            Command::LoadWaypoints => {
                crate::info!("AOK waypoints loaded from flash");
                self.load_waypoints(shared);
                self.ack(Ack::Ok);
            }
            Command::SetWaypoint(w) => self.set_waypoint(&w, flying, now_ms, shared),
            Command::ReadWaypoint(slot) => self.read_waypoint(slot, shared),
            Command::MotorTest(m) => self.motor_test(m, now_ms, flying),
            Command::ExternalControl(e) => self.take_external(e, now_ms),
        }
    }
}
