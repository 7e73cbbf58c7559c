//! The one random AEOLUS message generator: the corruption figures, the resync tests and the
//! benchmarks' input streams all draw their messages here.
//!
//! The caller picks the type (its own mix) and the timestamp; [`Values`] says whether every
//! field is random or only those a box's telemetry varies (the benchmarks' streams, whose
//! bytes stay as they were measured).

use crate::rng::Rng;
use aeolus_proto::message::*;

/// The message types the generator builds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// GYRO.
    Gyro,
    /// ACCEL.
    Accel,
    /// MAGNET.
    Magnet,
    /// PRESSURE.
    Pressure,
    /// ATTITUDE.
    Attitude,
    /// COMPASS.
    Compass,
    /// GPS.
    Gps,
    /// TOAST (a random text of up to 39 bytes).
    Toast,
    /// WIND.
    Wind,
}

/// Which fields are random.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Values {
    /// Every field of the type.
    All,
    /// Those a box's telemetry varies: the vectors, pressures, attitude angles and heading;
    /// the slip ball at 0, COMPASS calibrated with its defaults, GPS a fix of 9 satellites
    /// with the position at its defaults.
    Telemetry,
}

/// A message of `kind` stamped `t`, its fields drawn from `rng` as `values` says.
pub fn message(rng: &mut Rng, kind: Kind, t: f64, values: Values) -> Message<'static> {
    let all = values == Values::All;
    match kind {
        Kind::Gyro => {
            let [x, y, z] = vector(rng);
            Message::Gyro(Gyro {
                valid: true,
                timestamp_ms: t,
                x,
                y,
                z,
            })
        }
        Kind::Accel => {
            let [x, y, z] = vector(rng);
            Message::Accel(Accel {
                valid: true,
                timestamp_ms: t,
                x,
                y,
                z,
            })
        }
        Kind::Magnet => {
            let [x, y, z] = vector(rng);
            Message::Magnet(Magnet {
                valid: true,
                timestamp_ms: t,
                x,
                y,
                z,
            })
        }
        Kind::Pressure => {
            let [static_mbar, pitot_mbar, airspeed_mps] = vector(rng);
            Message::Pressure(Pressure {
                valid: true,
                timestamp_ms: t,
                static_mbar,
                pitot_mbar,
                airspeed_mps,
            })
        }
        Kind::Attitude => Message::Attitude(attitude(rng, t, all)),
        Kind::Compass => Message::Compass(compass(rng, t, all)),
        Kind::Gps => Message::Gps(gps(rng, t, all)),
        Kind::Toast => {
            let n = rng.below(40) as usize;
            let text: Vec<u8> = (0..n).map(|_| 1 + rng.byte() % 255).collect();
            Message::Toast(Text::from_bytes(&text).unwrap_or_default())
        }
        Kind::Wind => {
            let [speed_mps, direction_deg] = [rng.f32(), rng.f32()];
            Message::Wind(Wind {
                valid: true,
                timestamp_ms: t,
                speed_mps,
                direction_deg,
            })
        }
    }
}

/// Three draws, in order.
fn vector(rng: &mut Rng) -> [f32; 3] {
    [rng.f32(), rng.f32(), rng.f32()]
}

fn attitude(rng: &mut Rng, t: f64, all: bool) -> Attitude {
    let [roll_rad, pitch_rad, yaw_rad] = vector(rng);
    let slip_ball = if all { rng.f32() } else { 0.0 };
    let turn_coordinator = rng.f32();
    let [qx, qy, qz] = vector(rng);
    Attitude {
        valid: true,
        timestamp_ms: t,
        roll_rad,
        pitch_rad,
        yaw_rad,
        slip_ball,
        turn_coordinator,
        qx,
        qy,
        qz,
        qw: rng.f32(),
    }
}

fn compass(rng: &mut Rng, t: f64, all: bool) -> Compass {
    let heading_deg = rng.f32();
    if !all {
        return Compass {
            valid: true,
            timestamp_ms: t,
            heading_deg,
            ..Compass::default()
        };
    }
    Compass {
        valid: true,
        calibration: CalibrationStatus::Ok,
        has_value: true,
        calibration_percent: 100,
        calibration_remaining: 0,
        timestamp_ms: t,
        heading_deg,
        soft_iron: vector(rng),
        hard_iron: [rng.f32(); 9],
    }
}

fn gps(rng: &mut Rng, t: f64, all: bool) -> Gps {
    if !all {
        return Gps {
            valid: true,
            has_fix: true,
            satellites: 9,
            timestamp_ms: t,
            ..Gps::default()
        };
    }
    Gps {
        valid: true,
        has_fix: true,
        satellites: rng.byte(),
        timestamp_ms: t,
        latitude_deg: rng.f32(),
        longitude_deg: rng.f32(),
        altitude_m: rng.f32(),
        ground_speed_mps: rng.f32(),
    }
}
