//! A mission ends at a waypoint whose coordinates are both 0 or both -1 (K8), and nowhere
//! else: one coordinate alone never ends it.

use aok_proto::{ActionWord, Waypoint, WaypointSlot};

fn at(longitude: i32, latitude: i32) -> bool {
    Waypoint {
        slot: WaypointSlot::MissionPoi,
        longitude,
        latitude,
        action1: ActionWord::NONE,
        action2: ActionWord::NONE,
    }
    .ends_mission()
}

#[test]
fn only_0_0_and_minus1_minus1_end_a_mission() {
    let coords = [0, -1, 1, i32::MIN];
    let mut ends = Vec::new();
    for lon in coords {
        for lat in coords {
            if at(lon, lat) {
                ends.push((lon, lat));
            }
        }
    }
    assert_eq!(ends, [(0, 0), (-1, -1)]);
}
