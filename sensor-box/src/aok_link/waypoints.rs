//! Waypoints: the RAM slots (0..=30, the RAM POI 254, the FBC target 255), the flash
//! waypoints with the mission POI (31), and loading them from flash into RAM.

use super::{AokLink, MISSION_POI};
use crate::Shared;
use crate::state::StoredWaypoint;
use aok_proto::WaypointSlot;

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
}
