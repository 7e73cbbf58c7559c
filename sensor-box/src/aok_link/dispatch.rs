//! Decode and dispatch: received bytes through the [`DeviceDecoder`](aok_proto::DeviceDecoder)
//! (with back-pressure and the idle timeout), then one `match` over the commands that hands
//! each family to its room (`params`, `waypoints`, `control`, `debug`).

use super::{AokLink, IDLE_MS, MAX_REPLY, RX_BUDGET, flying};
use crate::Shared;
use crate::port::{Receive, receive_slices};
use aok_proto::{Ack, Command, Error as AokError};

impl AokLink {
    /// Decodes received bytes while the TX queue has room for the longest reply (otherwise
    /// the bytes wait in the port: back-pressure instead of lost replies). The port lends its
    /// bytes a slice at a time (at most [`RX_BUDGET`] a poll); the decoder takes them byte by
    /// byte (`push`), because the link's TX queue holds one longest reply (a bulk read's 112
    /// bytes from a 2-byte command), so the room must be checked after every byte, which the
    /// slice path (`feed`) cannot do. AOK runs at 38 400 Bd: 3 840 bytes a second at most.
    pub(super) fn receive<P: Receive>(&mut self, now_ms: u64, port: &mut P, shared: &mut Shared) {
        let taken = receive_slices(port, RX_BUDGET, |bytes| self.decode(bytes, now_ms, shared));
        self.rx_more = matches!(taken, Ok(n) if n >= RX_BUDGET);
        let port_empty = match taken {
            Ok(n) => n < RX_BUDGET && self.tx_free() >= MAX_REPLY,
            Err(_) => {
                self.counters.port_errors = self.counters.port_errors.wrapping_add(1);
                false
            }
        };
        // Silence only counts when the port has nothing more: bytes held back in it
        // (back-pressure, budget) may be the rest of the partial frame.
        if port_empty
            && self.decoder.held_bytes() > 0
            && now_ms.saturating_sub(self.last_rx_ms) >= IDLE_MS
        {
            while let Some(item) = self.decoder.idle_next() {
                self.handle(item, now_ms, shared);
            }
        }
    }

    /// Pushes `bytes` into the decoder one at a time while one longest reply still fits, and
    /// handles every event; the count decoded.
    fn decode(&mut self, bytes: &[u8], now_ms: u64, shared: &mut Shared) -> usize {
        let mut done = 0;
        for &byte in bytes {
            if self.tx_free() < MAX_REPLY {
                break;
            }
            done += 1;
            self.last_rx_ms = now_ms;
            let mut event = self.decoder.push(byte);
            while let Some(item) = event {
                self.handle(item, now_ms, shared);
                event = self.decoder.poll();
            }
        }
        done
    }

    pub(super) fn handle(
        &mut self,
        item: Result<Command, AokError>,
        now_ms: u64,
        shared: &mut Shared,
    ) {
        if item.is_err() {
            self.counters.rx_errors = self.counters.rx_errors.wrapping_add(1);
        }
        let command = match item {
            Ok(c) => c,
            // A frame cut by a quiet line: counted by the decoder, nothing to answer.
            Err(AokError::Truncated) => return,
            Err(AokError::ChecksumMismatch { .. }) | Err(AokError::InvalidSlot(_)) => {
                // A faulty `73`/`77` is answered 'E' (the spec); the decoder cannot say which
                // command a bad checksum belonged to, so every one is answered.
                self.ack(Ack::Error);
                return;
            }
            Err(_) => {
                // Stick values beyond ±200: external control has no ack; counted by the decoder.
                crate::warn!("AOK: command with an out-of-range field ignored");
                return;
            }
        };
        let flying = flying(shared);
        match command {
            Command::DebugOff | Command::DebugOn => self.switch_debug(command, now_ms),
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
