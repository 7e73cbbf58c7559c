//! A climbing (or descending) turn: the altitude moves at the climb rate, the nose is up by the
//! flight path angle, and every sensor agrees with that attitude; at the edge of the
//! troposphere the flight levels off.

use flight_sim::{EarthField, Error, Flight, FlightParams, G, Quaternion, atmosphere};

fn climbing(climb_mps: f32) -> Flight {
    Flight::new(FlightParams {
        climb_mps,
        ..FlightParams::DEFAULT
    })
    .expect("valid parameters")
}

#[test]
fn the_altitude_moves_at_the_climb_rate_and_the_air_data_follow() {
    let f = climbing(2.5);
    let (s0, s1) = (f.state(0), f.state(60_000));
    assert_eq!(s0.gps_altitude_m, 1000.0);
    assert_eq!(s1.gps_altitude_m, 1150.0);
    let p1150 = atmosphere::pressure_pa(1150.0) / 100.0;
    assert!((s1.static_pressure_mbar - p1150).abs() < 1e-3);
    assert!((s1.oat_celsius - (atmosphere::temperature_k(1150.0) - 273.15)).abs() < 1e-4);
    let q = atmosphere::dynamic_pressure_pa(1150.0, 50.0) / 100.0;
    assert!((s1.pitot_pressure_mbar - q).abs() < 1e-4);
    // 2.5 m/s at 50 m/s: γ = asin(0.05) = 2.866°.
    let gamma = 0.05f32.asin();
    assert!((s1.euler.pitch - gamma).abs() < 1e-6, "{}", s1.euler.pitch);
    // A descent goes the other way.
    let d = climbing(-4.0).state(10_000);
    assert_eq!(d.gps_altitude_m, 960.0);
    assert!((d.euler.pitch + (4.0f32 / 50.0).asin()).abs() < 1e-6);
}

#[test]
fn the_climb_levels_off_at_the_edge_of_the_troposphere() {
    let f = climbing(25.0);
    // 10 000 m at 25 m/s: 400 s.
    let before = f.state(399_000);
    assert_eq!(before.gps_altitude_m, 10_975.0);
    assert!(before.euler.pitch > 0.5);
    let after = f.state(401_000);
    assert_eq!(after.gps_altitude_m, atmosphere::MAX_ALTITUDE_M);
    assert_eq!(after.euler.pitch, 0.0);
    let bank = FlightParams::DEFAULT.bank_deg.to_radians();
    assert!((after.accel_mps2[2] + G / bank.cos()).abs() < 1e-4);
    assert_eq!(after.accel_mps2[0], 0.0);
    let down = climbing(-25.0).state(u64::MAX / 2);
    assert_eq!(down.gps_altitude_m, atmosphere::MIN_ALTITUDE_M);
}

#[test]
fn the_quaternion_the_gyro_the_accelerometer_and_the_magnetometer_agree() {
    let field = EarthField::CENTRAL_EUROPE;
    for climb in [2.5f32, -7.0, 20.0] {
        let f = climbing(climb);
        for t in (0..120_000).step_by(3_333) {
            let s = f.state(t);
            // The quaternion is the Euler angles' rotation (pitch included).
            let q = s.euler.to_quaternion();
            let d = [
                q.x - s.quaternion.x,
                q.y - s.quaternion.y,
                q.z - s.quaternion.z,
                q.w - s.quaternion.w,
            ];
            assert!(
                d.iter().all(|d| d.abs() < 2e-6),
                "climb {climb}, t {t}: {q:?} vs {:?}",
                s.quaternion
            );
            // The magnetometer is the Earth field in body axes.
            let m =
                s.quaternion
                    .ned_to_body([field.north_gauss, field.east_gauss, field.down_gauss]);
            for (a, b) in m.iter().zip(s.mag_gauss) {
                assert!(
                    (a - b).abs() < 2e-6,
                    "climb {climb}, t {t}: {m:?} vs {:?}",
                    s.mag_gauss
                );
            }
            // The accelerometer is the centripetal acceleration (horizontal, ω times the
            // horizontal speed, to the right of the track through the air) minus gravity.
            let psi = s.euler.yaw;
            let vh = 50.0 * s.euler.pitch.cos();
            let a = s.turn_rate_rad_s * vh;
            let specific = [-a * psi.sin(), a * psi.cos(), -G];
            let body = s.quaternion.ned_to_body(specific);
            for (x, y) in body.iter().zip(s.accel_mps2) {
                assert!(
                    (x - y).abs() < 1e-4,
                    "climb {climb}, t {t}: {body:?} vs {:?}",
                    s.accel_mps2
                );
            }
            assert!(s.accel_mps2[1].abs() < 1e-6, "coordinated: no side force");
        }
        // The gyro integrates into the attitude: q(t + dt) = q(t) ⊗ exp(½·ω·dt).
        for t in [0u64, 5_000, 31_000] {
            let (s0, s1) = (f.state(t), f.state(t + 100));
            let [wx, wy, wz] = s0.gyro_rad_s;
            let rate = (wx * wx + wy * wy + wz * wz).sqrt();
            let half = 0.5 * rate * 0.1;
            let k = half.sin() / rate;
            let step = Quaternion {
                x: wx * k,
                y: wy * k,
                z: wz * k,
                w: half.cos(),
            };
            let predicted = (s0.quaternion * step).canonical();
            let got = s1.quaternion;
            let err = (predicted.x - got.x).abs()
                + (predicted.y - got.y).abs()
                + (predicted.z - got.z).abs()
                + (predicted.w - got.w).abs();
            assert!(err < 1e-5, "climb {climb}, t {t}: {predicted:?} vs {got:?}");
        }
    }
}

#[test]
fn the_horizontal_path_shrinks_by_the_cosine_of_the_path_angle() {
    let level = Flight::new(FlightParams::DEFAULT).expect("valid");
    let steep = climbing(20.0);
    let cos = (1.0f32 - 0.4 * 0.4).sqrt();
    assert!((steep.turn_radius_m() - level.turn_radius_m() * cos).abs() < 0.05);
    assert_eq!(steep.turn_rate_rad_s(), level.turn_rate_rad_s());
}

#[test]
fn a_climb_above_half_the_airspeed_is_refused() {
    for climb in [25.01f32, -25.01, f32::NAN] {
        let p = FlightParams {
            climb_mps: climb,
            ..FlightParams::DEFAULT
        };
        let want = if climb.is_nan() {
            Error::NotFinite
        } else {
            Error::Climb
        };
        assert_eq!(Flight::new(p), Err(want), "{climb}");
    }
    assert!(
        Flight::new(FlightParams {
            climb_mps: 25.0,
            ..FlightParams::DEFAULT
        })
        .is_ok()
    );
}
