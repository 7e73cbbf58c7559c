//! `Flight::state` (fixed-point angles, constants precomputed per flight) against the formula
//! it replaced (libm `sinf`/`cosf`/`atan2f`/`sqrtf`, the quaternion built from the Euler angles
//! and rotations of every vector, f64 turn reduction), kept here verbatim as the reference.
//!
//! The two compute the same flight: the differences below are the rounding of the old `f32`
//! formula (its yaw went through `f32` radians, about 2.4e-7 rad of rounding at ±π; its chord
//! and its direction were `f32`) and of the new fixed point (angles to 1.5e-9 rad, sines to
//! 4e-9). Checked every 0.997 s over six hours of each flight, and at days and weeks, so a
//! drift of the heading (the new one advances by a fixed fraction of a turn per millisecond)
//! would show.

use flight_sim::{Euler, Flight, FlightParams, G, STANDARD_RATE_RAD_S, State, geo};
use libm::{atan2f, cosf, sinf, sqrtf, tanf};

const DEG: f32 = core::f32::consts::PI / 180.0;

/// The old turn rate, `G * tanf(bank) / V`.
fn old_omega(p: &FlightParams) -> f32 {
    G * tanf(p.bank_deg * DEG) / p.airspeed_mps
}

/// The old `Flight::state` (before the fixed-point rewrite), on the old precomputed values,
/// except the turn rate `omega`: the new one may differ from [`old_omega`] by an ulp (tan φ
/// from a fixed-point sine and cosine instead of `tanf`), and a 1e-7 relative difference of
/// the turn rate is 0.02 rad of heading after 30 days. Both headings advance at exactly the
/// turn rate their state reports; the comparison gives both the same one.
fn reference(p: &FlightParams, omega: f32, t_ms: u64) -> State {
    let bank_rad = p.bank_deg * DEG;
    let heading0_rad = p.start_heading_deg * DEG;
    let v = p.airspeed_mps;
    let from = p.wind_from_deg * DEG;
    let w = p.wind_speed_mps;
    let wind_ne = [-w * cosf(from), -w * sinf(from)];

    let t_s = t_ms as f64 / 1000.0;
    let turned = remainder(f64::from(omega) * t_s, core::f64::consts::TAU) as f32;
    let yaw = wrap_pi(heading0_rad + turned);
    let (sin_yaw, cos_yaw) = (sinf(yaw), cosf(yaw));
    let euler = Euler {
        roll: bank_rad,
        pitch: 0.0,
        yaw,
    };
    let q = euler.to_quaternion();
    let gyro = q.ned_to_body([0.0, 0.0, omega]);
    let a_lat = v * omega;
    let accel = q.ned_to_body([-a_lat * sin_yaw, a_lat * cos_yaw, -G]);
    let field = p.earth_field;
    let mag = q.ned_to_body([field.north_gauss, field.east_gauss, field.down_gauss]);
    let (air_n, air_e) = if omega == 0.0 {
        let d = f64::from(v) * t_s;
        (
            d * f64::from(cosf(heading0_rad)),
            d * f64::from(sinf(heading0_rad)),
        )
    } else {
        let chord = 2.0 * (v / omega) * sinf(turned * 0.5);
        let dir = heading0_rad + turned * 0.5;
        (f64::from(chord * cosf(dir)), f64::from(chord * sinf(dir)))
    };
    let north = air_n + f64::from(wind_ne[0]) * t_s;
    let east = air_e + f64::from(wind_ne[1]) * t_s;
    let (lat, lon) = geo::offset(p.start_lat_deg, p.start_lon_deg, north, east);
    let ground_n = v * cos_yaw + wind_ne[0];
    let ground_e = v * sin_yaw + wind_ne[1];
    let heading_deg = wrap_360(yaw / DEG);
    let slip_ball = if accel[2] == 0.0 {
        0.0
    } else {
        -accel[1] / accel[2]
    };
    let declination = atan2f(field.east_gauss, field.north_gauss) / DEG;
    State {
        time_ms: t_ms as f64,
        euler,
        quaternion: q,
        gyro_rad_s: gyro,
        accel_mps2: accel,
        mag_gauss: mag,
        // Constant over a flight, not part of the rewrite: taken from the new state.
        static_pressure_mbar: 0.0,
        pitot_pressure_mbar: 0.0,
        airspeed_mps: v,
        oat_celsius: 0.0,
        latitude_deg: lat,
        longitude_deg: lon,
        gps_altitude_m: p.altitude_m,
        ground_speed_mps: sqrtf(ground_n * ground_n + ground_e * ground_e),
        track_deg: wrap_360(atan2f(ground_e, ground_n) / DEG),
        heading_deg,
        magnetic_heading_deg: wrap_360(heading_deg - declination),
        slip_ball,
        turn_rate_rad_s: omega,
        turn_coordinator: omega / STANDARD_RATE_RAD_S,
        wind_speed_mps: w,
        wind_from_deg: wrap_360(p.wind_from_deg),
    }
}

fn remainder(x: f64, period: f64) -> f64 {
    let whole = (x / period) as i64;
    x - whole as f64 * period
}

fn wrap_pi(a: f32) -> f32 {
    let pi = core::f32::consts::PI;
    let w = remainder(f64::from(a + pi), core::f64::consts::TAU) as f32;
    let w = if w <= 0.0 { w + 2.0 * pi } else { w };
    w - pi
}

fn wrap_360(d: f32) -> f32 {
    let w = remainder(f64::from(d), 360.0) as f32;
    let w = if w < 0.0 { w + 360.0 } else { w };
    if w >= 360.0 { 0.0 } else { w }
}

/// The difference of two angles in the same unit, on the circle of `turn` units.
fn angle_diff(a: f32, b: f32, turn: f32) -> f32 {
    let d = (a - b).rem_euclid(turn);
    d.min(turn - d)
}

/// The largest differences seen, per quantity.
#[derive(Debug, Default)]
struct Worst {
    yaw_rad: f32,
    quaternion: f32,
    gyro: f32,
    accel: f32,
    mag_gauss: f32,
    heading_deg: f32,
    magnetic_deg: f32,
    /// The track's difference beyond 1e-4° (the degrees' f32 rounding, as for the heading)
    /// times the ground speed, a sideways velocity, m/s: the track is ill-conditioned when
    /// the wind nearly cancels the airspeed.
    track_mps: f32,
    /// Relative to airspeed + wind speed.
    ground_speed: f32,
    /// Position difference, and the same less 2e-8 of the distance flown through the air and
    /// drifted with the wind and 4e-7 of the chord (both computed the chord in f32: its ulp
    /// and the direction's, 2.4e-7 rad).
    position_m: f64,
    position_excess_m: f64,
    rates: f32,
}

fn compare(f: &Flight, t: u64, worst: &mut Worst) {
    let p = f.params();
    let (new, old) = (f.state(t), reference(p, f.turn_rate_rad_s(), t));
    let max3 = |a: [f32; 3], b: [f32; 3]| (0..3).map(|i| (a[i] - b[i]).abs()).fold(0.0, f32::max);
    let (q, r) = (new.quaternion, old.quaternion);
    // q and -q are the same attitude: both are kept with w >= 0, but at w = 0 either may
    // show.
    let dq = |sign: f32| {
        [
            q.x - sign * r.x,
            q.y - sign * r.y,
            q.z - sign * r.z,
            q.w - sign * r.w,
        ]
        .iter()
        .fold(0.0f32, |m, d| m.max(d.abs()))
    };
    let dq = dq(1.0).min(dq(-1.0));
    let tau = core::f32::consts::TAU;
    let w = worst;
    w.yaw_rad = w.yaw_rad.max(angle_diff(new.euler.yaw, old.euler.yaw, tau));
    w.quaternion = w.quaternion.max(dq);
    w.gyro = w.gyro.max(max3(new.gyro_rad_s, old.gyro_rad_s));
    w.accel = w.accel.max(max3(new.accel_mps2, old.accel_mps2));
    w.mag_gauss = w.mag_gauss.max(max3(new.mag_gauss, old.mag_gauss));
    w.heading_deg = w
        .heading_deg
        .max(angle_diff(new.heading_deg, old.heading_deg, 360.0));
    w.magnetic_deg = w.magnetic_deg.max(angle_diff(
        new.magnetic_heading_deg,
        old.magnetic_heading_deg,
        360.0,
    ));
    w.track_mps = w.track_mps.max(
        (angle_diff(new.track_deg, old.track_deg, 360.0) - 1e-4).max(0.0)
            * DEG
            * new.ground_speed_mps,
    );
    let fastest = p.airspeed_mps + p.wind_speed_mps;
    w.ground_speed = w
        .ground_speed
        .max((new.ground_speed_mps - old.ground_speed_mps).abs() / fastest);
    let d = geo::distance_m(
        new.latitude_deg,
        new.longitude_deg,
        old.latitude_deg,
        old.longitude_deg,
    );
    w.position_m = w.position_m.max(d);
    let flown = f64::from(p.airspeed_mps + p.wind_speed_mps) * t as f64 / 1000.0;
    let air = f64::from(p.airspeed_mps) * t as f64 / 1000.0;
    let chord = air.min(2.0 * f64::from(f.turn_radius_m()));
    w.position_excess_m = w.position_excess_m.max(d - 2e-8 * flown - 4e-7 * chord);
    w.rates = w
        .rates
        .max((new.turn_rate_rad_s - old.turn_rate_rad_s).abs())
        .max((new.turn_coordinator - old.turn_coordinator).abs())
        .max((new.slip_ball - old.slip_ball).abs());
    assert_eq!(
        (
            new.euler.roll,
            new.euler.pitch,
            new.time_ms,
            new.gps_altitude_m,
            new.wind_speed_mps
        ),
        (
            old.euler.roll,
            old.euler.pitch,
            old.time_ms,
            old.gps_altitude_m,
            old.wind_speed_mps
        )
    );
    assert_eq!(new.wind_from_deg, old.wind_from_deg);
}

fn flights() -> [FlightParams; 6] {
    let d = FlightParams::DEFAULT;
    [
        d,
        FlightParams {
            bank_deg: -60.0,
            airspeed_mps: 5.0,
            wind_speed_mps: 4.9,
            wind_from_deg: 33.0,
            ..d
        },
        FlightParams {
            bank_deg: 3.0,
            airspeed_mps: 150.0,
            wind_speed_mps: 40.0,
            start_heading_deg: 200.0,
            ..d
        },
        FlightParams {
            bank_deg: 0.0,
            start_heading_deg: 90.0,
            ..d
        },
        FlightParams {
            bank_deg: -25.0,
            start_heading_deg: -137.5,
            start_lat_deg: -33.9,
            start_lon_deg: 179.99,
            ..d
        },
        FlightParams {
            bank_deg: 0.01,
            airspeed_mps: 120.0,
            wind_speed_mps: 0.0,
            ..d
        },
    ]
}

#[test]
fn the_state_is_the_old_formula_within_its_rounding_over_hours_and_weeks() {
    for p in flights() {
        let f = Flight::new(p).expect("valid parameters");
        let (new, old) = (f.turn_rate_rad_s(), old_omega(&p));
        assert!(
            (new - old).abs() <= old.abs() * f32::EPSILON,
            "{new} vs {old}"
        );
        let mut hours = Worst::default();
        for t in (0..6 * 3_600_000).step_by(997) {
            compare(&f, t, &mut hours);
        }
        let mut weeks = Worst::default();
        for day in [1u64, 7, 30] {
            for t in (0..20_000).step_by(1_003) {
                compare(&f, day * 86_400_000 + t, &mut weeks);
            }
        }
        eprintln!("{p:?}\n  6 h: {hours:?}\n  days: {weeks:?}");
        for w in [&hours, &weeks] {
            // The old yaw was rounded in f32 radians (ulp 2.4e-7 at ±π) and then in degrees
            // (ulp 3.1e-5 above 256°): its rounding, not a difference of the flight.
            assert!(w.yaw_rad < 1e-6, "{w:?}");
            assert!(w.heading_deg < 1e-4 && w.magnetic_deg < 1e-4, "{w:?}");
            assert!(w.track_mps < 2e-5 && w.ground_speed < 4e-7, "{w:?}");
            assert!(w.quaternion < 5e-7 && w.mag_gauss < 5e-7, "{w:?}");
            // The old gyro and accelerometer were rotations of NED vectors (rounding at the
            // 1e-6 level); the new ones are the closed forms.
            assert!(w.gyro < 1e-6 && w.accel < 1e-5, "{w:?}");
            assert!(w.rates < 1e-6, "{w:?}");
        }
        // Positions: the old f32 chord and direction (0.1 mm on a 700 m circle), and a drift
        // that grows with time: the old wind direction in f32 radians (cos 270° = -1.2e-8
        // instead of 0) blew 6e-8 m/s sideways (1.3 mm in 6 h, 0.15 m in 30 days), the new
        // one is exact.
        for w in [&hours, &weeks] {
            assert!(w.position_excess_m < 1e-3, "{w:?}");
        }
    }
}
