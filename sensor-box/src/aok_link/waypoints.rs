//! Waypoints: the RAM slots (0..=30, the RAM POI 254, the FBC target 255), the flash
//! waypoints with the mission POI (31), reading and setting one, and moving them between
//! flash and RAM.

use super::params::store_ack;
use super::{AokLink, MISSION_POI};
use crate::Shared;
use crate::state::StoredWaypoint;
use aok_proto::{Ack, ActionWord, Message, ReplyForm, Waypoint, WaypointSlot};

impl AokLink {
    /// The RAM value of a waypoint slot; the mission POI (31) is read from the flash record.
    pub fn waypoint(&self, slot: WaypointSlot, shared: &Shared) -> StoredWaypoint {
        match slot {
            WaypointSlot::Waypoint(n) => self
                .waypoints
                .get(usize::from(n.wire()))
                .copied()
                .unwrap_or_default(),
            WaypointSlot::MissionPoi => shared
                .persisted
                .aok
                .waypoints
                .get(MISSION_POI)
                .copied()
                .unwrap_or_default(),
            WaypointSlot::RamPoi => self.ram_poi,
            WaypointSlot::FbcTarget => self.fbc_target,
        }
    }

    /// `63 09` (and boot): flash slots 0..=30 into RAM, flash slot 31 into the RAM POI.
    pub(super) fn load_waypoints(&mut self, shared: &Shared) {
        let flash = &shared.persisted.aok.waypoints;
        for (r, f) in self.waypoints.iter_mut().zip(flash.iter()) {
            *r = *f;
        }
        self.ram_poi = flash.get(MISSION_POI).copied().unwrap_or_default();
    }

    /// `63 08`: RAM slots 0..=30 and the RAM POI into the flash record (when the [store
    /// policy](crate::store_policy) allows).
    pub(super) fn save_waypoints(&mut self, flying: bool, now_ms: u64, shared: &mut Shared) {
        let ack = store_ack(shared.request_store(now_ms, flying));
        if ack == Ack::Ok {
            crate::info!("AOK waypoints saved to flash");
            let flash = &mut shared.persisted.aok.waypoints;
            for (f, r) in flash.iter_mut().zip(self.waypoints.iter()) {
                *f = *r;
            }
            if let Some(poi) = flash.get_mut(MISSION_POI) {
                *poi = self.ram_poi;
            }
        }
        self.ack(ack);
    }

    /// `77`: one slot (the mission POI goes to flash, when the store policy allows).
    pub(super) fn set_waypoint(
        &mut self,
        w: &Waypoint,
        flying: bool,
        now_ms: u64,
        shared: &mut Shared,
    ) {
        let stored = StoredWaypoint {
            lon: w.longitude,
            lat: w.latitude,
            action1: w.action1.raw(),
            action2: w.action2.raw(),
        };
        let slot = match w.slot {
            WaypointSlot::Waypoint(n) => self.waypoints.get_mut(usize::from(n.wire())),
            WaypointSlot::MissionPoi => match store_ack(shared.request_store(now_ms, flying)) {
                Ack::Ok => shared.persisted.aok.waypoints.get_mut(MISSION_POI),
                refused => return self.ack(refused),
            },
            WaypointSlot::RamPoi => Some(&mut self.ram_poi),
            WaypointSlot::FbcTarget => Some(&mut self.fbc_target),
        };
        let ack = match slot {
            Some(slot) => {
                *slot = stored;
                Ack::Ok
            }
            None => Ack::Error,
        };
        self.ack(ack);
    }

    /// `78`: one slot, answered with its `77` frame.
    pub(super) fn read_waypoint(&mut self, slot: WaypointSlot, shared: &Shared) {
        let s = self.waypoint(slot, shared);
        let w = Waypoint {
            slot,
            longitude: s.lon,
            latitude: s.lat,
            action1: ActionWord(s.action1),
            action2: ActionWord(s.action2),
        };
        let mut buf = [0u8; 19];
        if let Ok(n) = Message::Waypoint(w).emit(&mut buf, ReplyForm::Headed) {
            self.queue(buf.get(..n).unwrap_or_default());
        }
    }
}
