//! The physical consistency of the simulated coordinated turn.

use flight_sim::{
    EarthField, Error, Flight, FlightParams, G, Quaternion, STANDARD_RATE_RAD_S, State, atmosphere,
    geo,
};

const D: f32 = core::f32::consts::PI / 180.0;

fn calm(bank_deg: f32) -> FlightParams {
    FlightParams {
        bank_deg,
        wind_speed_mps: 0.0,
        ..FlightParams::DEFAULT
    }
}

fn flight(p: FlightParams) -> Flight {
    Flight::new(p).expect("valid parameters")
}

fn close3(a: [f32; 3], b: [f32; 3], tol: f32) -> bool {
    a.iter().zip(b.iter()).all(|(x, y)| (x - y).abs() <= tol)
}

const TIMES: [u64; 7] = [0, 7, 1_000, 12_345, 60_000, 3_600_000, 86_400_000];

#[test]
fn isa_pressure_temperature_density() {
    assert!((atmosphere::pressure_pa(0.0) / 100.0 - 1013.25).abs() < 0.005);
    assert!((atmosphere::pressure_pa(1000.0) / 100.0 - 898.75).abs() < 0.02);
    assert!((atmosphere::pressure_pa(5000.0) / 100.0 - 540.20).abs() < 0.02);
    assert!((atmosphere::density_kg_m3(0.0) - 1.225).abs() < 0.0005);
    assert!((atmosphere::temperature_k(0.0) - 288.15).abs() < 1e-4);

    let s = flight(FlightParams::DEFAULT).state(5_000);
    assert!((s.static_pressure_mbar - 898.75).abs() < 0.02);
    assert!((s.oat_celsius - 8.5).abs() < 1e-3);
    // Pitot pressure is the dynamic pressure: ½·1.1117 kg/m³·(50 m/s)² = 13.896 mbar.
    assert!(
        (s.pitot_pressure_mbar - 13.896).abs() < 0.005,
        "{}",
        s.pitot_pressure_mbar
    );
    assert_eq!(s.airspeed_mps, 50.0);

    let sea = flight(FlightParams {
        altitude_m: 0.0,
        ..FlightParams::DEFAULT
    })
    .state(0);
    assert!((sea.static_pressure_mbar - 1013.25).abs() < 0.005);
    assert!((sea.oat_celsius - 15.0).abs() < 1e-3);
    assert!((sea.pitot_pressure_mbar - 15.3125).abs() < 0.005);
}

#[test]
fn level_flight_reads_minus_g() {
    let f = flight(calm(0.0));
    for t in TIMES {
        let s = f.state(t);
        assert!(
            close3(s.accel_mps2, [0.0, 0.0, -G], 1e-5),
            "{:?}",
            s.accel_mps2
        );
        assert!(close3(s.gyro_rad_s, [0.0; 3], 1e-9));
        assert_eq!(s.turn_coordinator, 0.0);
        assert_eq!(s.heading_deg, 0.0);
    }
}

#[test]
fn coordinated_turn_accel_gyro_ball_and_turn_coordinator() {
    for bank in [-60.0f32, -30.0, -5.0, 10.0, 20.0, 45.0, 60.0] {
        for v in [20.0f32, 50.0, 120.0] {
            let p = FlightParams {
                airspeed_mps: v,
                ..calm(bank)
            };
            let f = flight(p);
            let phi = bank * D;
            let omega = G * phi.tan() / v;
            assert!((f.turn_rate_rad_s() - omega).abs() < 1e-6);
            for t in TIMES {
                let s = f.state(t);
                let want = [0.0, 0.0, -G / phi.cos()];
                assert!(
                    close3(s.accel_mps2, want, 2e-4),
                    "{bank} {v} {t}: {:?}",
                    s.accel_mps2
                );
                let want = [0.0, omega * phi.sin(), omega * phi.cos()];
                assert!(
                    close3(s.gyro_rad_s, want, 1e-6),
                    "{bank} {v} {t}: {:?}",
                    s.gyro_rad_s
                );
                assert!(s.slip_ball.abs() < 1e-5, "{}", s.slip_ball);
                assert!((s.turn_coordinator * STANDARD_RATE_RAD_S - omega).abs() < 1e-6);
                assert!((s.turn_rate_rad_s - omega).abs() < 1e-6);
                assert_eq!(s.euler.roll, phi);
                assert_eq!(s.euler.pitch, 0.0);
            }
        }
    }
    // A standard-rate turn at 50 m/s needs about 15° of bank.
    let bank = (STANDARD_RATE_RAD_S * 50.0 / G).atan() / D;
    let s = flight(calm(bank)).state(1_000);
    assert!((s.turn_coordinator - 1.0).abs() < 1e-4);
}

#[test]
fn state_quaternion_matches_euler() {
    let f = flight(FlightParams::DEFAULT);
    for t in (0..200_000).step_by(777) {
        let s = f.state(t);
        // The same rotation as the Euler angles: the state's quaternion is computed from the
        // half-angle sine and cosine of the yaw in fixed point, `to_quaternion` with libm, so
        // they agree to a few f32 ulps (5e-7 covers the yaw's own rounding to f32 radians).
        let q = s.euler.to_quaternion();
        let d = [
            q.x - s.quaternion.x,
            q.y - s.quaternion.y,
            q.z - s.quaternion.z,
            q.w - s.quaternion.w,
        ];
        assert!(
            d.iter().all(|d| d.abs() < 5e-7),
            "{q:?} vs {:?}",
            s.quaternion
        );
        assert!((s.quaternion.norm() - 1.0).abs() < 3e-7);
        assert!(s.quaternion.w >= 0.0);
        let back = s.quaternion.to_euler();
        assert!((back.roll - s.euler.roll).abs() < 1e-4);
        assert!(back.pitch.abs() < 1e-4);
        let dy = (back.yaw - s.euler.yaw).abs();
        assert!(dy < 1e-4 || (dy - 2.0 * core::f32::consts::PI).abs() < 1e-4);
        let hd = s.heading_deg - s.euler.yaw / D;
        assert!(
            hd.abs() < 1e-3 || (hd - 360.0).abs() < 1e-3,
            "{} {}",
            s.heading_deg,
            s.euler.yaw
        );
    }
}

/// The gyro integrates into the attitude: q(t + dt) = q(t) ⊗ exp(½·ω_body·dt).
#[test]
fn gyro_integrates_to_the_attitude() {
    let f = flight(FlightParams::DEFAULT);
    for t in [0u64, 5_000, 31_000, 77_777] {
        let s0 = f.state(t);
        let s1 = f.state(t + 100);
        let dt = 0.1f32;
        let [wx, wy, wz] = s0.gyro_rad_s;
        let rate = (wx * wx + wy * wy + wz * wz).sqrt();
        let half = 0.5 * rate * dt;
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
        assert!(err < 1e-5, "t={t}: {predicted:?} vs {got:?}");
    }
}

#[test]
fn heading_advances_at_the_turn_rate() {
    let f = flight(calm(20.0));
    let omega_deg = f.turn_rate_rad_s() / D;
    let h0 = f.state(0).heading_deg;
    let h10 = f.state(10_000).heading_deg;
    assert!((h10 - h0 - 10.0 * omega_deg).abs() < 1e-3, "{h0} {h10}");
    // One full circle later the heading is back.
    let period_ms = (2.0 * core::f64::consts::PI / f64::from(f.turn_rate_rad_s()) * 1000.0) as u64;
    let back = f.state(period_ms).heading_deg;
    assert!(back.min(360.0 - back) < 0.01, "{back}");
    // Left turn: the heading decreases.
    let l = flight(calm(-20.0));
    assert!((l.state(1_000).heading_deg - (360.0 - omega_deg)).abs() < 1e-3);
}

fn path_length_m(f: &Flight, from_ms: u64, to_ms: u64, step_ms: u64) -> f64 {
    let mut prev = f.state(from_ms);
    let mut sum = 0.0;
    let mut t = from_ms;
    while t < to_ms {
        t += step_ms;
        let s = f.state(t);
        sum += geo::distance_m(
            prev.latitude_deg,
            prev.longitude_deg,
            s.latitude_deg,
            s.longitude_deg,
        );
        prev = s;
    }
    sum
}

#[test]
fn gps_moves_along_the_circle_at_ground_speed() {
    for bank in [20.0f32, -35.0] {
        let f = flight(calm(bank));
        let v = f64::from(FlightParams::DEFAULT.airspeed_mps);
        let r = f64::from(f.turn_radius_m());
        let phi = f64::from(bank * D);
        assert!((r - v * v / (9.806_65 * phi.tan().abs())).abs() < 0.01);
        // Distance travelled over 10 s: ground speed × 10 s (no wind: V).
        let s0 = f.state(0);
        assert!((f64::from(s0.ground_speed_mps) - v).abs() < 1e-4);
        let travelled = path_length_m(&f, 0, 10_000, 10);
        assert!((travelled - v * 10.0).abs() < 0.05, "{travelled}");
        // Every fix lies on the circle of radius r around the centre, which is
        // r to the right (bank > 0) or left of the start heading (north).
        let side = if bank > 0.0 { 1.0 } else { -1.0 };
        let (clat, clon) = geo::offset(s0.latitude_deg, s0.longitude_deg, 0.0, side * r);
        for t in (0..120_000).step_by(250) {
            let s = f.state(t);
            let d = geo::distance_m(clat, clon, s.latitude_deg, s.longitude_deg);
            assert!((d - r).abs() < 0.05, "bank {bank} t {t}: {d} vs {r}");
        }
        // The chord after 10 s is 2·r·sin(ω·10 s / 2).
        let s10 = f.state(10_000);
        let chord = geo::distance_m(
            s0.latitude_deg,
            s0.longitude_deg,
            s10.latitude_deg,
            s10.longitude_deg,
        );
        let want = 2.0 * r * (f64::from(f.turn_rate_rad_s()).abs() * 10.0 / 2.0).sin();
        assert!((chord - want).abs() < 0.05, "{chord} vs {want}");
    }
}

#[test]
fn wind_drifts_the_circle_and_sets_ground_speed_and_track() {
    let f = flight(FlightParams::DEFAULT); // 5 m/s from the west
    let s0 = f.state(0);
    // Heading north with a westerly wind: ground speed √(50² + 5²), track east of north.
    assert!((s0.ground_speed_mps - (2525.0f32).sqrt()).abs() < 1e-3);
    assert!((s0.track_deg - (5.0f32 / 50.0).atan() / D).abs() < 1e-3);
    assert_eq!((s0.wind_speed_mps, s0.wind_from_deg), (5.0, 270.0));
    // Velocity from the fixes matches the reported ground speed and track.
    for t in [1_000u64, 20_000, 44_000, 70_000] {
        let a = f.state(t - 50);
        let b = f.state(t + 50);
        let s = f.state(t);
        let d = geo::distance_m(
            a.latitude_deg,
            a.longitude_deg,
            b.latitude_deg,
            b.longitude_deg,
        );
        assert!(
            (d / 0.1 - f64::from(s.ground_speed_mps)).abs() < 0.01,
            "t {t}: {}",
            d / 0.1
        );
    }
    // Over a whole circle the aircraft drifts downwind by wind × period.
    let period_s = 2.0 * core::f64::consts::PI / f64::from(f.turn_rate_rad_s());
    let end = f.state((period_s * 1000.0).round() as u64);
    let drift = geo::distance_m(
        s0.latitude_deg,
        s0.longitude_deg,
        end.latitude_deg,
        end.longitude_deg,
    );
    assert!((drift - 5.0 * period_s).abs() < 0.1, "{drift}");
    assert!(end.longitude_deg > s0.longitude_deg);
    // Distance over 10 s is the integral of the ground speed.
    let mut integral = 0.0;
    for t in (0..10_000).step_by(10) {
        let (a, b) = (f.state(t), f.state(t + 10));
        integral += 0.005 * f64::from(a.ground_speed_mps + b.ground_speed_mps);
    }
    let travelled = path_length_m(&f, 0, 10_000, 10);
    assert!(
        (travelled - integral).abs() < 0.05,
        "{travelled} vs {integral}"
    );
}

#[test]
fn straight_flight_goes_along_the_heading() {
    let f = flight(FlightParams {
        start_heading_deg: 90.0,
        ..calm(0.0)
    });
    let (s0, s) = (f.state(0), f.state(60_000));
    let d = geo::distance_m(
        s0.latitude_deg,
        s0.longitude_deg,
        s.latitude_deg,
        s.longitude_deg,
    );
    assert!((d - 3000.0).abs() < 0.05, "{d}");
    assert!((s.latitude_deg - s0.latitude_deg).abs() < 1e-6);
    assert_eq!(f.turn_radius_m(), f32::INFINITY);
}

#[test]
fn magnetometer_is_the_earth_field_in_body_axes() {
    let field = EarthField::CENTRAL_EUROPE;
    let f = flight(FlightParams::DEFAULT);
    let strength =
        (field.north_gauss.powi(2) + field.east_gauss.powi(2) + field.down_gauss.powi(2)).sqrt();
    for t in (0..90_000).step_by(1_234) {
        let s: State = f.state(t);
        let [mx, my, mz] = s.mag_gauss;
        assert!(((mx * mx + my * my + mz * mz).sqrt() - strength).abs() < 1e-5);
        // Tilt-compensated compass: undo roll and pitch, then atan2.
        let (r, p) = (s.euler.roll, s.euler.pitch);
        let hx = mx * p.cos() + (my * r.sin() + mz * r.cos()) * p.sin();
        let hy = my * r.cos() - mz * r.sin();
        let mut heading = (-hy).atan2(hx) / D;
        if heading < 0.0 {
            heading += 360.0;
        }
        let diff = (heading - s.magnetic_heading_deg).abs();
        assert!(
            diff < 1e-2 || (diff - 360.0).abs() < 1e-2,
            "{heading} vs {}",
            s.magnetic_heading_deg
        );
        let decl = s.heading_deg - s.magnetic_heading_deg;
        assert!(
            (decl - field.declination_deg()).abs() < 1e-3
                || (decl + 360.0 - field.declination_deg()).abs() < 1e-3
        );
    }
}

#[test]
fn invalid_parameters_are_refused() {
    let d = FlightParams::DEFAULT;
    let cases = [
        (
            FlightParams {
                airspeed_mps: f32::NAN,
                ..d
            },
            Error::NotFinite,
        ),
        (
            FlightParams {
                start_lat_deg: f64::INFINITY,
                ..d
            },
            Error::NotFinite,
        ),
        (
            FlightParams {
                airspeed_mps: 4.9,
                ..d
            },
            Error::Airspeed,
        ),
        (
            FlightParams {
                airspeed_mps: 151.0,
                ..d
            },
            Error::Airspeed,
        ),
        (
            FlightParams {
                bank_deg: -60.1,
                ..d
            },
            Error::Bank,
        ),
        (
            FlightParams {
                altitude_m: 11_001.0,
                ..d
            },
            Error::Altitude,
        ),
        (
            FlightParams {
                start_lat_deg: 85.5,
                ..d
            },
            Error::Position,
        ),
        (
            FlightParams {
                start_lon_deg: -181.0,
                ..d
            },
            Error::Position,
        ),
        (
            FlightParams {
                wind_speed_mps: 50.0,
                ..d
            },
            Error::Wind,
        ),
        (
            FlightParams {
                wind_speed_mps: -1.0,
                ..d
            },
            Error::Wind,
        ),
    ];
    for (p, e) in cases {
        assert_eq!(Flight::new(p).err(), Some(e), "{p:?}");
        assert!(!e.to_string().is_empty());
    }
}

#[test]
fn any_time_gives_finite_values() {
    let f = flight(FlightParams {
        bank_deg: -60.0,
        airspeed_mps: 5.0,
        wind_speed_mps: 4.9,
        ..FlightParams::DEFAULT
    });
    for t in [0, 1, u64::from(u32::MAX), u64::MAX / 2, u64::MAX] {
        let s = f.state(t);
        let vals = [
            s.euler.yaw,
            s.quaternion.w,
            s.accel_mps2[2],
            s.gyro_rad_s[1],
            s.mag_gauss[0],
            s.ground_speed_mps,
            s.track_deg,
            s.heading_deg,
            s.magnetic_heading_deg,
            s.slip_ball,
        ];
        assert!(vals.iter().all(|v| v.is_finite()), "{t}: {s:?}");
        assert!(s.latitude_deg.is_finite() && (-90.0..=90.0).contains(&s.latitude_deg));
        assert!(
            (-180.0..180.0).contains(&s.longitude_deg),
            "{}",
            s.longitude_deg
        );
        assert!((0.0..360.0).contains(&s.heading_deg));
    }
}

/// The values the box sends without a new state (`sensor_box`'s steady kinds: PRESSURE, TEMP,
/// WIND) are the same at every time of one flight, exactly, bit for bit.
#[test]
fn air_data_and_wind_are_constant_over_a_flight() {
    for p in [
        FlightParams::DEFAULT,
        calm(0.0),
        calm(-45.0),
        FlightParams {
            altitude_m: 3_000.0,
            airspeed_mps: 80.0,
            wind_speed_mps: 20.0,
            wind_from_deg: 270.0,
            ..FlightParams::DEFAULT
        },
    ] {
        let f = flight(p);
        let at0 = f.state(0);
        for t in TIMES {
            let s = f.state(t);
            let steady = |s: &State| {
                [
                    s.static_pressure_mbar,
                    s.pitot_pressure_mbar,
                    s.airspeed_mps,
                    s.oat_celsius,
                    s.wind_speed_mps,
                    s.wind_from_deg,
                ]
                .map(f32::to_bits)
            };
            assert_eq!(steady(&s), steady(&at0), "at {t} ms, {p:?}");
        }
    }
}
