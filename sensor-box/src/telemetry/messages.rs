//! Building the messages: one AEOLUS [`Message`] of a [`Kind`] from the simulated flight.

use super::Kind;
use aeolus_proto::message::{
    Accel, AeolusInfo, Attitude, CalibrationStatus, Compass, Gps, Gyro, Magnet, Message, Pressure,
    Temp, Wind,
};
use flight_sim::State;

/// AEOLUSINFO model byte: 83 = `'S'`, AEOLUS-SENSE (DECISIONS.md A10).
pub const MODEL: u8 = b'S';

/// The firmware version sent in AEOLUSINFO: this crate's version, large/middle/small.
pub const FIRMWARE_VERSION: [u8; 3] = [
    parse_u8(env!("CARGO_PKG_VERSION_MAJOR")),
    parse_u8(env!("CARGO_PKG_VERSION_MINOR")),
    parse_u8(env!("CARGO_PKG_VERSION_PATCH")),
];

/// The MAC address sent in AEOLUSINFO: a fixed, locally administered unicast address (the
/// example has no WiFi adapter).
pub const MAC: [u8; 6] = [0x02, 0xAE, 0x01, 0x05, 0x00, 0x01];

/// GPS satellites reported in use.
pub const GPS_SATELLITES: u8 = 9;

/// A decimal `u8` at compile time (saturating; stops at the first non-digit).
const fn parse_u8(s: &str) -> u8 {
    let bytes = s.as_bytes();
    let mut value: u32 = 0;
    let mut i = 0;
    while i < bytes.len() {
        let d = bytes[i];
        if !d.is_ascii_digit() {
            break;
        }
        value = value * 10 + (d - b'0') as u32;
        if value > u8::MAX as u32 {
            return u8::MAX;
        }
        i += 1;
    }
    value as u8
}

/// The message of `kind` describing `state`, time-stamped `now_ms` (ms since boot).
///
/// The mapping, one sensor per message:
///
/// | message | from the state |
/// |---|---|
/// | GYRO, ACCEL, MAGNET | `gyro_rad_s`, `accel_mps2`, `mag_gauss` (body axes) |
/// | ATTITUDE | `euler` (rad), `slip_ball`, `turn_coordinator` (standard-rate units), `quaternion` |
/// | COMPASS | `magnetic_heading_deg`; calibration OK, 100 %; parameters of an ideal sensor |
/// | PRESSURE | `static_pressure_mbar`, `pitot_pressure_mbar` (dynamic pressure), `airspeed_mps` |
/// | GPS | fix with [`GPS_SATELLITES`], `latitude_deg`/`longitude_deg` (as f32), `gps_altitude_m`, `ground_speed_mps` |
/// | TEMP | `oat_celsius` |
/// | WIND | `wind_speed_mps`, `wind_from_deg` |
/// | AEOLUSINFO | [`MODEL`], [`FIRMWARE_VERSION`], [`MAC`] |
///
/// ```
/// use sensor_box::telemetry::{Kind, build};
/// use aeolus_proto::message::Message;
///
/// let state = flight_sim::Flight::default().state(2_000);
/// let Message::Pressure(p) = build(Kind::Pressure, &state, 2_000) else { unreachable!() };
/// assert_eq!(p.timestamp_ms, 2_000.0);
/// assert!((p.static_mbar - 898.75).abs() < 0.05); // ISA at 1000 m
/// ```
pub fn build(kind: Kind, state: &State, now_ms: u64) -> Message<'static> {
    build_at(kind, state, now_ms as f64)
}

/// [`build`] with the timestamp already converted (`now_ms as f64`): a caller that builds
/// several messages of one instant converts it once (on a core without an FPU the conversion
/// of a `u64` costs about 45 instructions).
///
/// ```
/// use sensor_box::telemetry::{Kind, build, build_at};
/// let state = flight_sim::Flight::default().state(2_000);
/// assert_eq!(build_at(Kind::Gyro, &state, 2_000.0), build(Kind::Gyro, &state, 2_000));
/// ```
pub fn build_at(kind: Kind, state: &State, timestamp_ms: f64) -> Message<'static> {
    let [gx, gy, gz] = state.gyro_rad_s;
    let [ax, ay, az] = state.accel_mps2;
    let [mx, my, mz] = state.mag_gauss;
    match kind {
        Kind::Gyro => Message::Gyro(Gyro {
            valid: true,
            timestamp_ms,
            x: gx,
            y: gy,
            z: gz,
        }),
        Kind::Accel => Message::Accel(Accel {
            valid: true,
            timestamp_ms,
            x: ax,
            y: ay,
            z: az,
        }),
        Kind::Magnet => Message::Magnet(Magnet {
            valid: true,
            timestamp_ms,
            x: mx,
            y: my,
            z: mz,
        }),
        Kind::Attitude => Message::Attitude(Attitude {
            valid: true,
            timestamp_ms,
            roll_rad: state.euler.roll,
            pitch_rad: state.euler.pitch,
            yaw_rad: state.euler.yaw,
            slip_ball: state.slip_ball,
            turn_coordinator: state.turn_coordinator,
            qx: state.quaternion.x,
            qy: state.quaternion.y,
            qz: state.quaternion.z,
            qw: state.quaternion.w,
        }),
        Kind::Compass => Message::Compass(Compass {
            valid: true,
            calibration: CalibrationStatus::Ok,
            has_value: true,
            calibration_percent: 100,
            calibration_remaining: 0,
            timestamp_ms,
            heading_deg: state.magnetic_heading_deg,
            // An ideal sensor: no offsets (the 3-value group), unit matrix (the 9-value group).
            soft_iron: [0.0; 3],
            hard_iron: [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0],
        }),
        Kind::Pressure => Message::Pressure(Pressure {
            valid: true,
            timestamp_ms,
            static_mbar: state.static_pressure_mbar,
            pitot_mbar: state.pitot_pressure_mbar,
            airspeed_mps: state.airspeed_mps,
        }),
        Kind::Gps => Message::Gps(Gps {
            valid: true,
            has_fix: true,
            satellites: GPS_SATELLITES,
            timestamp_ms,
            latitude_deg: state.latitude_deg as f32,
            longitude_deg: state.longitude_deg as f32,
            altitude_m: state.gps_altitude_m,
            ground_speed_mps: state.ground_speed_mps,
        }),
        Kind::Temp => Message::Temp(Temp {
            valid: true,
            timestamp_ms,
            celsius: state.oat_celsius,
        }),
        Kind::Wind => Message::Wind(Wind {
            valid: true,
            timestamp_ms,
            speed_mps: state.wind_speed_mps,
            direction_deg: state.wind_from_deg,
        }),
        Kind::AeolusInfo => Message::AeolusInfo(AeolusInfo {
            model: MODEL,
            firmware: FIRMWARE_VERSION,
            mac: MAC,
        }),
    }
}
