//! The one air-data truth every face of `protolink` shows or sends: `gdl90` (ForeFlight and
//! Stratux AHRS), `nmea` (`$LXWP0`, `$POV`, `$PGRMZ`), `watch`, `web` and the PlotJuggler
//! output of `decode --udp-json` (`docs/protocol-notes.md` PL39).
//!
//! | value | from | rule |
//! | --- | --- | --- |
//! | static pressure | PRESSURE `static_mbar` | finite, above 0 |
//! | dynamic pressure `q` | PRESSURE `pitot_mbar` (the pitot's differential pressure, PL33) | finite; below 0 (sensor offset at rest) reads 0 |
//! | indicated airspeed | `q` | `sqrt(2 q / ρ0)`, ρ0 = 1.225 kg/m³ (ISA sea level) |
//! | true airspeed | `q`, static pressure, TEMP | `sqrt(2 q / ρ)`, ρ = p / (R T) with R = 287.05 J/(kg·K) |
//! | pressure altitude | static pressure | ISA troposphere, 1013.25 hPa datum |
//! | vertical speed | pressure altitude | its change over the last second of the box's clock ([`VerticalSpeed`]) |
//!
//! PRESSURE's own airspeed field is not used: the spec does not say whether it is indicated
//! or true (the firmware and `flight-sim` fill it with the true airspeed), and the pressures
//! are what the box measures. The raw decoders (`decode`, Wireshark, Python, C) show it as the
//! wire field `airspeed_mps`.
//!
//! A value is there only while its message is fresh ([`FRESH`](crate::fresh::FRESH) for PRESSURE, [`FRESH_SLOW`]
//! for TEMP, which the box sends about once a second) and marked valid by the box; anything
//! else is `None`, which each face sends as its format's invalid marker, never as an old
//! value.

use std::collections::VecDeque;
use std::time::Instant;

use aeolus_proto::message::{Message, Pressure, Temp};
use serde::Serialize;

use crate::fresh::{FRESH_SLOW, fresh, fresh_within};

/// Air density of the ISA at sea level, kg/m³: the density indicated airspeed assumes.
pub(crate) const SEA_LEVEL_DENSITY: f64 = 1.225;
/// The specific gas constant of dry air, J/(kg·K).
const R_AIR: f64 = 287.05;

/// Air density, kg/m³, from static pressure in hPa (mbar) and temperature in °C (the ideal
/// gas law).
pub(crate) fn air_density(static_hpa: f64, celsius: f64) -> f64 {
    static_hpa * 100.0 / (R_AIR * (celsius + 273.15))
}

/// Pressure altitude in the ISA, m, from static pressure in hPa (mbar).
pub(crate) fn isa_altitude_m(static_hpa: f32) -> f64 {
    44_330.77 * (1.0 - (f64::from(static_hpa) / 1013.25).powf(0.190_263))
}

/// Indicated airspeed, m/s, from the dynamic pressure in Pa: `sqrt(2 q / ρ0)`. A negative
/// pressure (a sensor's offset at rest) reads 0; `None` when it is not finite.
pub(crate) fn indicated_airspeed_mps(dynamic_pa: f64) -> Option<f64> {
    airspeed(dynamic_pa, SEA_LEVEL_DENSITY)
}

/// True airspeed, m/s, from the dynamic pressure in Pa and the air's static pressure (hPa) and
/// temperature (°C): `sqrt(2 q / ρ)`. `None` when a value is not finite or the density is not
/// positive.
pub(crate) fn true_airspeed_mps(dynamic_pa: f64, static_hpa: f64, celsius: f64) -> Option<f64> {
    airspeed(dynamic_pa, air_density(static_hpa, celsius))
}

fn airspeed(dynamic_pa: f64, density: f64) -> Option<f64> {
    if !(dynamic_pa.is_finite() && density.is_finite() && density > 0.0) {
        return None;
    }
    Some((2.0 * dynamic_pa.max(0.0) / density).sqrt())
}

/// The air data at one moment; each value `None` when its source is stale, invalid or not
/// usable.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub(crate) struct AirData {
    /// Static pressure, hPa.
    pub(crate) static_hpa: Option<f64>,
    /// Dynamic (pitot minus static) pressure, Pa.
    pub(crate) dynamic_pa: Option<f64>,
    /// Outside air temperature, °C.
    pub(crate) celsius: Option<f64>,
    /// Indicated airspeed, m/s.
    pub(crate) ias_mps: Option<f64>,
    /// True airspeed, m/s.
    pub(crate) tas_mps: Option<f64>,
    /// Pressure altitude (ISA, 1013.25 hPa datum), m.
    pub(crate) pressure_altitude_m: Option<f64>,
    /// Vertical speed from the pressure altitude, m/s, positive up.
    pub(crate) vertical_speed_mps: Option<f64>,
}

impl AirData {
    /// The air data of one PRESSURE and TEMP (each already known fresh and valid, or `None`)
    /// and a vertical speed.
    pub(crate) fn of(
        pressure: Option<&Pressure>,
        temp: Option<&Temp>,
        vertical: Option<f64>,
    ) -> Self {
        let pressure = pressure.filter(|p| p.valid);
        let static_hpa = pressure
            .map(|p| f64::from(p.static_mbar))
            .filter(|v| v.is_finite() && *v > 0.0);
        let dynamic_pa = pressure
            .map(|p| f64::from(p.pitot_mbar) * 100.0)
            .filter(|v| v.is_finite());
        let celsius = temp
            .filter(|t| t.valid)
            .map(|t| f64::from(t.celsius))
            .filter(|c| c.is_finite() && *c > -273.15);
        let tas_mps = match (dynamic_pa, static_hpa, celsius) {
            (Some(q), Some(p), Some(c)) => true_airspeed_mps(q, p, c),
            _ => None,
        };
        AirData {
            static_hpa,
            dynamic_pa,
            celsius,
            ias_mps: dynamic_pa.and_then(indicated_airspeed_mps),
            tas_mps,
            pressure_altitude_m: static_hpa
                .map(|hpa| isa_altitude_m(hpa as f32))
                .filter(|m| m.is_finite()),
            vertical_speed_mps: vertical
                .filter(|v| v.is_finite())
                .filter(|_| static_hpa.is_some()),
        }
    }
}

/// The latest PRESSURE and TEMP with when they arrived, and the vertical speed: what every
/// face asks for the [`AirData`] of a moment.
#[derive(Debug, Default, Clone)]
pub(crate) struct AirDataSource {
    pressure: Option<(Pressure, Instant)>,
    temp: Option<(Temp, Instant)>,
    vertical: VerticalSpeed,
}

impl AirDataSource {
    /// Takes a PRESSURE or TEMP that arrived at `at`; other messages are ignored.
    pub(crate) fn take(&mut self, m: &Message<'_>, at: Instant) {
        match m {
            Message::Pressure(p) => self.take_pressure(p, at),
            Message::Temp(t) => self.temp = Some((*t, at)),
            _ => {}
        }
    }

    /// Takes a PRESSURE that arrived at `at`.
    pub(crate) fn take_pressure(&mut self, p: &Pressure, at: Instant) {
        self.pressure = Some((*p, at));
        self.vertical.take_valid(p);
    }

    /// The air data at `now`, from the messages still fresh then.
    pub(crate) fn at(&self, now: Instant) -> AirData {
        AirData::of(
            fresh(&self.pressure, now).as_ref(),
            fresh_within(&self.temp, now, FRESH_SLOW).as_ref(),
            self.vertical.mps(),
        )
    }
}

/// The vertical speed is the change of the pressure altitude over this much of the box's
/// clock (at most; the first estimate needs half of it).
pub(crate) const VERTICAL_SPEED_WINDOW_MS: f64 = 1000.0;
/// Pressure altitudes closer together than this (box clock) are not kept.
const VERTICAL_SPEED_STEP_MS: f64 = 100.0;

/// The vertical speed from the pressure altitude: samples at least
/// `VERTICAL_SPEED_STEP_MS` apart over the last [`VERTICAL_SPEED_WINDOW_MS`], bounded.
#[derive(Debug, Default, Clone)]
pub(crate) struct VerticalSpeed {
    samples: VecDeque<(f64, f64)>,
}

impl VerticalSpeed {
    const SAMPLES: usize = (VERTICAL_SPEED_WINDOW_MS / VERTICAL_SPEED_STEP_MS) as usize + 1;

    /// Takes a PRESSURE message the box marked valid: its ISA pressure altitude at its box
    /// time.
    pub(crate) fn take_valid(&mut self, p: &Pressure) {
        if p.valid && p.static_mbar.is_finite() && p.static_mbar > 0.0 {
            self.take(p.timestamp_ms, isa_altitude_m(p.static_mbar));
        }
    }

    /// Takes a pressure altitude (m) at a box time (ms). A step back in time (a reboot)
    /// starts again; values that are not finite are ignored.
    pub(crate) fn take(&mut self, box_ms: f64, altitude_m: f64) {
        if !(box_ms.is_finite() && altitude_m.is_finite()) {
            return;
        }
        if let Some(&(last, _)) = self.samples.back() {
            if box_ms < last {
                self.samples.clear();
            } else if box_ms - last < VERTICAL_SPEED_STEP_MS {
                return;
            }
        }
        if self.samples.len() == Self::SAMPLES {
            self.samples.pop_front();
        }
        self.samples.push_back((box_ms, altitude_m));
    }

    /// m/s, positive up, once the samples span half the window.
    pub(crate) fn mps(&self) -> Option<f64> {
        let (&(t0, a0), &(t1, a1)) = (self.samples.front()?, self.samples.back()?);
        (t1 - t0 >= VERTICAL_SPEED_WINDOW_MS / 2.0).then(|| (a1 - a0) / (t1 - t0) * 1000.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    fn pressure(static_mbar: f32, pitot_mbar: f32) -> Pressure {
        Pressure {
            valid: true,
            timestamp_ms: 0.0,
            static_mbar,
            pitot_mbar,
            airspeed_mps: 999.0,
        }
    }

    #[test]
    fn the_airspeed_field_is_never_used() {
        let air = AirData::of(Some(&pressure(1013.25, 0.0)), None, None);
        assert_eq!(air.ias_mps, Some(0.0));
    }

    #[test]
    fn an_invalid_or_unusable_pressure_gives_nothing() {
        let invalid = Pressure {
            valid: false,
            ..pressure(1013.25, 15.0)
        };
        assert_eq!(
            AirData::of(Some(&invalid), None, Some(1.0)),
            AirData::default()
        );
        let air = AirData::of(Some(&pressure(f32::NAN, 15.0)), None, Some(1.0));
        assert_eq!(
            (
                air.static_hpa,
                air.pressure_altitude_m,
                air.vertical_speed_mps
            ),
            (None, None, None)
        );
        assert!(air.ias_mps.is_some());
        let air = AirData::of(Some(&pressure(1013.25, f32::INFINITY)), None, None);
        assert_eq!((air.dynamic_pa, air.ias_mps), (None, None));
    }

    #[test]
    fn an_invalid_or_absurd_temperature_gives_no_true_airspeed() {
        let p = pressure(1013.25, 15.3125);
        for t in [
            Temp {
                valid: false,
                timestamp_ms: 0.0,
                celsius: 15.0,
            },
            Temp {
                valid: true,
                timestamp_ms: 0.0,
                celsius: -300.0,
            },
        ] {
            let air = AirData::of(Some(&p), Some(&t), None);
            assert_eq!((air.celsius, air.tas_mps), (None, None));
            assert!(air.ias_mps.is_some());
        }
    }

    #[test]
    fn temperature_stays_fresh_longer_than_pressure() {
        let t0 = Instant::now();
        let mut src = AirDataSource::default();
        src.take(
            &Message::Temp(Temp {
                valid: true,
                timestamp_ms: 0.0,
                celsius: 15.0,
            }),
            t0,
        );
        let at = t0 + Duration::from_millis(2400);
        src.take(&Message::Pressure(pressure(1013.25, 15.3125)), at);
        assert!(src.at(at).tas_mps.is_some());
        assert_eq!(src.at(t0 + Duration::from_millis(2600)).tas_mps, None);
        assert!(src.at(t0 + Duration::from_millis(2600)).ias_mps.is_some());
    }
}

/// The examples of this module's items, as tests (the items are crate-private, so rustdoc
/// does not run them).
#[cfg(test)]
#[allow(unused_imports, clippy::unnecessary_wraps)]
mod examples {
    use super::*;

    #[test]
    fn air_density_example() -> Result<(), Box<dyn std::error::Error>> {
        let rho = air_density(1013.25, 15.0);
        assert!((rho - 1.225).abs() < 0.001);
        Ok(())
    }

    #[test]
    fn isa_altitude_m_example() -> Result<(), Box<dyn std::error::Error>> {
        assert!(isa_altitude_m(1013.25).abs() < 0.01);
        assert!((isa_altitude_m(898.76) - 1000.0).abs() < 1.0);
        Ok(())
    }

    #[test]
    fn indicated_airspeed_mps_example() -> Result<(), Box<dyn std::error::Error>> {
        // 1531.25 Pa is 50 m/s at sea-level density.
        assert!((indicated_airspeed_mps(1531.25).unwrap() - 50.0).abs() < 1e-9);
        assert_eq!(indicated_airspeed_mps(-3.0), Some(0.0));
        Ok(())
    }

    #[test]
    fn true_airspeed_mps_example() -> Result<(), Box<dyn std::error::Error>> {
        assert!((true_airspeed_mps(1531.25, 1013.25, 15.0).unwrap() - 50.0).abs() < 0.01);
        // The same dynamic pressure in thinner air is a higher true airspeed.
        assert!(true_airspeed_mps(1531.25, 700.0, -10.0).unwrap() > 55.0);
        Ok(())
    }

    #[test]
    fn of_example() -> Result<(), Box<dyn std::error::Error>> {
        use aeolus_proto::message::{Pressure, Temp};
        let p = Pressure {
            valid: true,
            timestamp_ms: 0.0,
            static_mbar: 1013.25,
            pitot_mbar: 15.3125,
            airspeed_mps: 0.0,
        };
        let t = Temp {
            valid: true,
            timestamp_ms: 0.0,
            celsius: 15.0,
        };
        let air = AirData::of(Some(&p), Some(&t), None);
        assert!((air.ias_mps.unwrap() - 50.0).abs() < 1e-4);
        assert!((air.tas_mps.unwrap() - 50.0).abs() < 0.01);
        assert_eq!(AirData::of(Some(&p), None, None).tas_mps, None);
        Ok(())
    }

    #[test]
    fn airdatasource_example() -> Result<(), Box<dyn std::error::Error>> {
        use aeolus_proto::message::{Message, Pressure};
        use std::time::{Duration, Instant};
        let mut air = AirDataSource::default();
        let t0 = Instant::now();
        air.take(
            &Message::Pressure(Pressure {
                valid: true,
                timestamp_ms: 0.0,
                static_mbar: 1013.25,
                pitot_mbar: 15.3125,
                airspeed_mps: 0.0,
            }),
            t0,
        );
        assert!((air.at(t0).ias_mps.unwrap() - 50.0).abs() < 1e-4);
        // More than a second later the PRESSURE is stale: no airspeed at all.
        assert_eq!(air.at(t0 + Duration::from_millis(1001)).ias_mps, None);
        Ok(())
    }

    #[test]
    fn take_example() -> Result<(), Box<dyn std::error::Error>> {
        let mut v = VerticalSpeed::default();
        for ms in (0..=1000).step_by(100) {
            v.take(f64::from(ms), 1000.0 + 2.5 * f64::from(ms) / 1000.0);
        }
        assert!((v.mps().unwrap() - 2.5).abs() < 1e-9);
        Ok(())
    }
}
