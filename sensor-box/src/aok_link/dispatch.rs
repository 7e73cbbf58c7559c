//! Decode and dispatch: received bytes through the [`DeviceDecoder`](aok_proto::DeviceDecoder)
//! (with back-pressure and the idle timeout), then one `match` over the commands: the short
//! answers (parameter reads, set and waypoint moves) inline, the rest in their rooms.

use super::MISSION_POI;
use super::{AokLink, External, FIRMWARE, IDLE_MS, MAX_REPLY, RX_BUDGET, flying};
use crate::Shared;
use crate::state::StoredWaypoint;
use aok_proto::message::HEADED_REPLY_LEN;
use aok_proto::{
    Ack, ActionWord, Command, Error as AokError, ParameterValue, Waypoint, WaypointSlot, device,
};
use embedded_io::{Read, ReadReady};

impl AokLink {
    /// Decodes received bytes while the TX queue has room for the longest reply (otherwise
    /// the bytes wait in the port's RX queue, and the rest of a read in `self.rx`:
    /// back-pressure instead of lost replies). The port is read a slice at a time (at most
    /// [`RX_BUDGET`] bytes a poll); the decoder is fed byte by byte (`push`), because the
    /// link's TX queue holds one longest reply (a bulk read's 112 bytes from a 2-byte command),
    /// so the room must be checked after every byte, which the slice path (`feed`) cannot do.
    pub(super) fn receive<P: Read + ReadReady>(
        &mut self,
        now_ms: u64,
        port: &mut P,
        shared: &mut Shared,
    ) {
        let mut budget = RX_BUDGET;
        let mut port_empty = false;
        while self.tx_free() >= MAX_REPLY {
            match self.rx.refill(port, budget) {
                Ok(n) => budget = budget.saturating_sub(n),
                Err(_) => {
                    self.counters.rx_errors = self.counters.rx_errors.wrapping_add(1);
                    break;
                }
            }
            let Some(&byte) = self.rx.pending().first() else {
                port_empty = budget > 0;
                break;
            };
            self.rx.consume(1);
            self.last_rx_ms = now_ms;
            let mut event = self.decoder.push(byte);
            while let Some(item) = event {
                self.handle(item, now_ms, shared);
                event = self.decoder.poll();
            }
        }
        // Silence only counts when the port has nothing more: bytes held back in its RX queue
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

    pub(super) fn handle(
        &mut self,
        item: Result<Command, AokError>,
        now_ms: u64,
        shared: &mut Shared,
    ) {
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
            Command::DebugOff => {
                crate::info!("AOK debug off");
                self.debug_on = false;
            }
            Command::DebugOn => {
                crate::info!("AOK debug on");
                self.debug_on = true;
                self.next_debug_ms = now_ms;
            }
            Command::Reset => {
                crate::info!("AOK reset requested");
                shared.requests.reboot = true;
            }
            Command::SetParameter(p) => self.set_parameter(p, flying),
            Command::ReadParameter(number) => {
                let value = self.parameter(number);
                let mut buf = [0u8; HEADED_REPLY_LEN];
                let reply = ParameterValue { number, value };
                if let Ok(n) = device::encode_parameter(reply, FIRMWARE.reply_form(), &mut buf) {
                    self.queue(buf.get(..n).unwrap_or_default());
                }
            }
            Command::BulkRead(first) => {
                let mut values = [0i32; 16];
                let mut number = first;
                for v in values.iter_mut() {
                    *v = self.parameter(number);
                    number = number.wrapping_add(1);
                }
                let mut buf = [0u8; MAX_REPLY];
                if let Ok(n) = device::encode_bulk(first, &values, &mut buf) {
                    self.queue(buf.get(..n).unwrap_or_default());
                }
            }
            Command::LoadSet(n) => {
                let ack = match shared.persisted.aok.sets.get(usize::from(n)) {
                    None => Ack::Error,
                    Some(_) if flying => Ack::InFlight,
                    Some(set) => {
                        crate::info!("AOK parameters loaded from set {=u8}", n);
                        self.params = *set;
                        Ack::Ok
                    }
                };
                self.ack(ack);
            }
            Command::SaveSet(n) => {
                let params = self.params;
                let ack = match shared.persisted.aok.sets.get_mut(usize::from(n)) {
                    None => Ack::Error,
                    Some(_) if flying => Ack::InFlight,
                    Some(set) => {
                        crate::info!("AOK parameters saved to set {=u8}", n);
                        *set = params;
                        shared.requests.store = true;
                        Ack::Ok
                    }
                };
                self.ack(ack);
            }
            Command::StartSet(n) => {
                let ack = if usize::from(n) >= shared.persisted.aok.sets.len() {
                    Ack::Error
                } else if flying {
                    Ack::InFlight
                } else {
                    crate::info!("AOK start set {=u8}", n);
                    shared.persisted.aok.start_set = n;
                    shared.requests.store = true;
                    Ack::Ok
                };
                self.ack(ack);
            }
            Command::SaveWaypoints => {
                let ack = if flying {
                    Ack::InFlight
                } else {
                    crate::info!("AOK waypoints saved to flash");
                    let flash = &mut shared.persisted.aok.waypoints;
                    for (f, r) in flash.iter_mut().zip(self.waypoints.iter()) {
                        *f = *r;
                    }
                    if let Some(poi) = flash.get_mut(MISSION_POI) {
                        *poi = self.ram_poi;
                    }
                    shared.requests.store = true;
                    Ack::Ok
                };
                self.ack(ack);
            }
            Command::LoadWaypoints => {
                crate::info!("AOK waypoints loaded from flash");
                self.load_waypoints(shared);
                self.ack(Ack::Ok);
            }
            Command::SetWaypoint(w) => {
                let stored = StoredWaypoint {
                    lon: w.longitude,
                    lat: w.latitude,
                    action1: w.action1.raw(),
                    action2: w.action2.raw(),
                };
                let ack = match w.slot {
                    WaypointSlot::Waypoint(n) => {
                        match self.waypoints.get_mut(usize::from(n.wire())) {
                            Some(slot) => {
                                *slot = stored;
                                Ack::Ok
                            }
                            None => Ack::Error,
                        }
                    }
                    WaypointSlot::MissionPoi if flying => Ack::InFlight,
                    WaypointSlot::MissionPoi => {
                        match shared.persisted.aok.waypoints.get_mut(MISSION_POI) {
                            Some(slot) => {
                                *slot = stored;
                                shared.requests.store = true;
                                Ack::Ok
                            }
                            None => Ack::Error,
                        }
                    }
                    WaypointSlot::RamPoi => {
                        self.ram_poi = stored;
                        Ack::Ok
                    }
                    WaypointSlot::FbcTarget => {
                        self.fbc_target = stored;
                        Ack::Ok
                    }
                };
                self.ack(ack);
            }
            Command::ReadWaypoint(slot) => {
                let s = self.waypoint(slot, shared);
                let w = Waypoint {
                    slot,
                    longitude: s.lon,
                    latitude: s.lat,
                    action1: ActionWord(s.action1),
                    action2: ActionWord(s.action2),
                };
                let mut buf = [0u8; 19];
                if let Ok(n) = device::encode_waypoint(&w, &mut buf) {
                    self.queue(buf.get(..n).unwrap_or_default());
                }
            }
            Command::MotorTest(m) => self.motor_test(m, now_ms, flying),
            Command::ExternalControl(e) => {
                if self.external.is_none() {
                    crate::info!("AOK external control takes over from RC");
                }
                self.external = Some(External {
                    control: e,
                    until_ms: now_ms.saturating_add(u64::from(e.expiry_ms)),
                });
            }
        }
    }
}
