//! The `AIR` table of an export: the air data derived from each AEOLUS PRESSURE by the one
//! air-data module ([`crate::air_data`], what `gdl90`, `nmea`, `watch` and `web` show), a row
//! per PRESSURE at its place and time.
//!
//! | column | unit | from |
//! | --- | --- | --- |
//! | `timestamp_ms` | ms | the PRESSURE's box time |
//! | `static_hpa`, `dynamic_pa` | hPa, Pa | its static and pitot (differential) pressure |
//! | `celsius` | °C | the flow's latest TEMP within 2.5 s of box time (the live faces' `FRESH_SLOW`) |
//! | `ias_mps`, `tas_mps` | m/s | indicated and true airspeed (true needs the temperature) |
//! | `pressure_altitude_m` | m | ISA, 1013.25 hPa datum |
//! | `vertical_speed_mps` | m/s | the pressure altitude's change over the last second of box time |
//!
//! A value is null where the module gives none (a PRESSURE the box marked invalid, no recent
//! TEMP, less than half a second of altitudes). Each flow of a capture (each byte file) keeps
//! its own latest TEMP and altitudes; at most [`MAX_FLOWS`] flows are followed at once.

use aeolus_proto::message::{Pressure, Temp};

use crate::air_data::{AirData, VerticalSpeed};
use crate::fresh::FRESH_SLOW;

/// The flows whose TEMP and altitudes are kept at once; a new one past them replaces the one
/// least recently seen.
pub(crate) const MAX_FLOWS: usize = 64;

/// What one flow's next AIR row needs of its past.
#[derive(Debug, Default)]
struct Flow {
    temp: Option<Temp>,
    vertical: VerticalSpeed,
}

/// The flows' latest TEMP and pressure altitudes.
#[derive(Debug, Default)]
pub(crate) struct AirState {
    /// (the flow's name, or none for a byte file; its state), the most recently seen last.
    flows: Vec<(Option<String>, Flow)>,
}

impl AirState {
    /// Forgets every flow (a new source begins).
    pub(crate) fn clear(&mut self) {
        self.flows.clear();
    }

    /// The state of `flow`, made when new.
    fn flow(&mut self, flow: Option<&str>) -> &mut Flow {
        let at = match self.flows.iter().rposition(|(f, _)| f.as_deref() == flow) {
            Some(i) => i,
            None => {
                if self.flows.len() == MAX_FLOWS {
                    self.flows.remove(0);
                }
                self.flows.push((flow.map(str::to_owned), Flow::default()));
                self.flows.len() - 1
            }
        };
        // The most recently seen last: the search finds it first next time, and the first
        // is the one least recently seen.
        let seen = self.flows.remove(at);
        self.flows.push(seen);
        let last = self.flows.len() - 1;
        &mut self.flows[last].1
    }

    /// Takes a TEMP of `flow`.
    pub(crate) fn temp(&mut self, flow: Option<&str>, t: &Temp) {
        self.flow(flow).temp = Some(*t);
    }

    /// Takes a PRESSURE of `flow`: the air data of its moment.
    pub(crate) fn pressure(&mut self, flow: Option<&str>, p: &Pressure) -> AirData {
        let state = self.flow(flow);
        state.vertical.take_valid(p);
        let window = FRESH_SLOW.as_secs_f64() * 1000.0;
        let temp = state
            .temp
            .filter(|t| (p.timestamp_ms - t.timestamp_ms).abs() <= window);
        AirData::of(Some(p), temp.as_ref(), state.vertical.mps())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pressure(ms: f64, static_mbar: f32) -> Pressure {
        Pressure {
            valid: true,
            timestamp_ms: ms,
            static_mbar,
            pitot_mbar: 5.0,
            airspeed_mps: 0.0,
        }
    }

    #[test]
    fn each_flow_keeps_its_own_temperature_and_climb() {
        let mut air = AirState::default();
        let t = Temp {
            valid: true,
            timestamp_ms: 0.0,
            celsius: 15.0,
        };
        air.temp(Some("a"), &t);
        // Flow a climbs (the static pressure falls), flow b has no temperature.
        for i in 0..=10 {
            let ms = f64::from(i) * 100.0;
            let a = air.pressure(Some("a"), &pressure(ms, 1000.0 - i as f32));
            let b = air.pressure(Some("b"), &pressure(ms, 1000.0));
            assert!(a.tas_mps.is_some() && b.tas_mps.is_none() && b.ias_mps.is_some());
            if i == 10 {
                assert!(a.vertical_speed_mps.unwrap() > 50.0, "{a:?}");
                assert_eq!(b.vertical_speed_mps, Some(0.0));
            }
        }
        // A TEMP older than 2.5 s of box time is not used.
        assert!(
            air.pressure(Some("a"), &pressure(2600.0, 990.0))
                .tas_mps
                .is_none()
        );
        air.clear();
        assert_eq!(
            air.pressure(Some("a"), &pressure(0.0, 990.0))
                .vertical_speed_mps,
            None
        );
    }

    #[test]
    fn the_flows_followed_are_bounded() {
        let mut air = AirState::default();
        for i in 0..1000 {
            air.pressure(Some(&i.to_string()), &pressure(0.0, 1000.0));
        }
        assert_eq!(air.flows.len(), MAX_FLOWS);
    }
}
