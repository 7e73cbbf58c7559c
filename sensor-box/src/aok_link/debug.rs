//! The debug value stream: the values the box sends, one per frame, on a fixed grid.

use super::{AokLink, ControlSource, flying};
use crate::Shared;
use aok_proto::message::DEBUG_LEN;
use aok_proto::{Command, DebugValue};

/// The debug values the box sends, with their numbers on the wire. One value per frame,
/// cycling through [`DebugId::CYCLE`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(all(feature = "defmt", target_os = "none"), derive(defmt::Format))]
#[repr(u8)]
pub enum DebugId {
    /// Roll angle, 0.01°.
    Roll = 1,
    /// Pitch angle, 0.01°.
    Pitch = 2,
    /// True heading, 0.01° in 0..36000.
    Heading = 3,
    /// True airspeed, cm/s.
    Airspeed = 4,
    /// Altitude, cm.
    Altitude = 5,
    /// Static pressure, Pa.
    StaticPressure = 6,
    /// Pitot (dynamic) pressure, Pa.
    PitotPressure = 7,
    /// Outside air temperature, 0.01 °C.
    Temperature = 8,
    /// Latitude, 1e-7°.
    Latitude = 9,
    /// Longitude, 1e-7°.
    Longitude = 10,
    /// Ground speed, cm/s.
    GroundSpeed = 11,
    /// Turn rate, 0.01°/s (positive: right).
    TurnRate = 12,
    /// Who steers: 0 = RC, 1 = external control (`53`).
    ControlSource = 13,
    /// Motor test: bit `n - 1` set while motor `n` has a non-zero test value.
    MotorTestMask = 14,
    /// Flight status, always in the cycle (K2): bit 0 flying, bit 1 external control,
    /// bit 2 motor test running.
    FlightStatus = 86,
}

impl DebugId {
    /// The order the values are sent in.
    pub const CYCLE: [DebugId; 15] = [
        DebugId::Roll,
        DebugId::Pitch,
        DebugId::Heading,
        DebugId::Airspeed,
        DebugId::Altitude,
        DebugId::StaticPressure,
        DebugId::PitotPressure,
        DebugId::Temperature,
        DebugId::Latitude,
        DebugId::Longitude,
        DebugId::GroundSpeed,
        DebugId::TurnRate,
        DebugId::ControlSource,
        DebugId::MotorTestMask,
        DebugId::FlightStatus,
    ];
}

impl DebugId {
    /// Whether the value changes with the flight's time (attitude, heading, altitude,
    /// position, ground speed): it is read from the flight's state at the frame's instant.
    /// The others are the flight's steady values (airspeed, pressures, temperature, turn rate:
    /// read from the last state computed, as AEOLUS PRESSURE is, see
    /// [`Shared::steady_state`]) or the box's own (control source, motor test, status), which
    /// need no flight state at all.
    ///
    /// ```
    /// use sensor_box::aok_link::DebugId;
    /// assert!(DebugId::Heading.moves_with_time());
    /// assert!(!DebugId::Airspeed.moves_with_time());
    /// ```
    pub const fn moves_with_time(self) -> bool {
        matches!(
            self,
            DebugId::Roll
                | DebugId::Pitch
                | DebugId::Heading
                | DebugId::Altitude
                | DebugId::Latitude
                | DebugId::Longitude
                | DebugId::GroundSpeed
        )
    }
}

/// Flight status (debug value 86) bit: the box is flying (see [`flying`]).
pub const STATUS_FLYING: i32 = 1;
/// Flight status bit: external control has the sticks.
pub const STATUS_EXTERNAL: i32 = 2;
/// Flight status bit: a motor-test value is active.
pub const STATUS_MOTOR_TEST: i32 = 4;

impl AokLink {
    /// `63 01` (off) and `63 02` (on: the next value goes out at once).
    pub(super) fn switch_debug(&mut self, command: Command, now_ms: u64) {
        if command == Command::DebugOn {
            crate::info!("AOK debug on");
            self.debug_on = true;
            self.next_debug_ms = now_ms;
        } else {
            crate::info!("AOK debug off");
            self.debug_on = false;
        }
    }

    pub(super) fn send_debug(&mut self, now_ms: u64, shared: &Shared) {
        let id = DebugId::CYCLE
            .get(self.debug_index)
            .copied()
            .unwrap_or(DebugId::FlightStatus);
        self.debug_index = self.debug_index.wrapping_add(1);
        if self.debug_index >= DebugId::CYCLE.len() {
            self.debug_index = 0;
        }
        let value = DebugValue {
            number: id as u8,
            value: self.debug_value(id, now_ms, shared),
        };
        let mut buf = [0u8; DEBUG_LEN];
        if let Ok(n) = value.emit(&mut buf) {
            self.queue(buf.get(..n).unwrap_or_default());
            self.counters.debug_frames = self.counters.debug_frames.wrapping_add(1);
        }
        let period = u64::from(shared.settings().aok_debug_period_ms);
        let next = self.next_debug_ms.saturating_add(period);
        // On time: keep the grid. Late (slow polls, a full port): restart from now, no burst.
        self.next_debug_ms = if next <= now_ms {
            now_ms.saturating_add(period)
        } else {
            next
        };
    }

    /// The value of one debug id at `now_ms`, scaled to i32 (see [`DebugId`]). A flight state
    /// is computed only for the ids that move with time ([`DebugId::moves_with_time`]); the
    /// others take the last one ([`Shared::steady_state`]).
    pub fn debug_value(&self, id: DebugId, now_ms: u64, shared: &Shared) -> i32 {
        let s = if id.moves_with_time() {
            shared.flight_state(now_ms)
        } else {
            shared.steady_state(now_ms)
        };
        match id {
            DebugId::Roll => scaled(s.euler.roll.to_degrees(), 100.0),
            DebugId::Pitch => scaled(s.euler.pitch.to_degrees(), 100.0),
            DebugId::Heading => scaled(s.heading_deg, 100.0),
            DebugId::Airspeed => scaled(s.airspeed_mps, 100.0),
            DebugId::Altitude => scaled(s.gps_altitude_m, 100.0),
            DebugId::StaticPressure => scaled(s.static_pressure_mbar, 100.0),
            DebugId::PitotPressure => scaled(s.pitot_pressure_mbar, 100.0),
            DebugId::Temperature => scaled(s.oat_celsius, 100.0),
            DebugId::Latitude => scaled64(s.latitude_deg, 1e7),
            DebugId::Longitude => scaled64(s.longitude_deg, 1e7),
            DebugId::GroundSpeed => scaled(s.ground_speed_mps, 100.0),
            DebugId::TurnRate => scaled(s.turn_rate_rad_s.to_degrees(), 100.0),
            DebugId::ControlSource => match self.control_source() {
                ControlSource::Rc => 0,
                ControlSource::External => 1,
            },
            DebugId::MotorTestMask => self.motor_mask(),
            DebugId::FlightStatus => {
                let mut status = 0;
                if flying(shared) {
                    status |= STATUS_FLYING;
                }
                if self.external.is_some() {
                    status |= STATUS_EXTERNAL;
                }
                if self.motor_mask() != 0 {
                    status |= STATUS_MOTOR_TEST;
                }
                status
            }
        }
    }

    pub(super) fn motor_mask(&self) -> i32 {
        self.motors
            .iter()
            .rev()
            .fold(0, |mask, m| (mask << 1) | i32::from(m.value != 0))
    }
}

/// `x * scale` rounded to the nearest integer; saturates, NaN gives 0 (`as` from float).
fn scaled(x: f32, scale: f32) -> i32 {
    let v = x * scale;
    (if v >= 0.0 { v + 0.5 } else { v - 0.5 }) as i32
}

fn scaled64(x: f64, scale: f64) -> i32 {
    let v = x * scale;
    (if v >= 0.0 { v + 0.5 } else { v - 0.5 }) as i32
}
