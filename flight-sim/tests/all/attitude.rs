//! Euler angles, quaternion and rotation matrix describe the same attitude.

use flight_sim::{Euler, Quaternion};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};

const TOL: f32 = 2e-5;

fn close3(a: [f32; 3], b: [f32; 3], tol: f32) -> bool {
    a.iter().zip(b.iter()).all(|(x, y)| (x - y).abs() <= tol)
}

fn mat_vec(m: [[f32; 3]; 3], v: [f32; 3]) -> [f32; 3] {
    [
        m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2],
        m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
        m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2],
    ]
}

fn assert_same_attitude(e: Euler) {
    let q = e.to_quaternion();
    let m = e.to_matrix();
    assert!((q.norm() - 1.0).abs() < 1e-6, "{q:?} not unit");
    assert!(q.w >= 0.0);
    for v in [
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.3, -0.7, 0.2],
    ] {
        let by_q = q.body_to_ned(v);
        let by_m = mat_vec(m, v);
        assert!(close3(by_q, by_m, TOL), "{e:?}: {by_q:?} vs {by_m:?}");
        let back = q.ned_to_body(by_q);
        assert!(close3(back, v, TOL), "{e:?}: round trip {back:?}");
    }
}

#[test]
fn convention_pins() {
    let d = core::f32::consts::PI / 180.0;
    // Yaw 90°: the nose points east.
    let q = Euler {
        roll: 0.0,
        pitch: 0.0,
        yaw: 90.0 * d,
    }
    .to_quaternion();
    assert!(close3(q.body_to_ned([1.0, 0.0, 0.0]), [0.0, 1.0, 0.0], TOL));
    // Positive roll: right wing (body y) goes down (NED z > 0).
    let q = Euler {
        roll: 30.0 * d,
        pitch: 0.0,
        yaw: 0.0,
    }
    .to_quaternion();
    let wing = q.body_to_ned([0.0, 1.0, 0.0]);
    assert!((wing[2] - 0.5).abs() < TOL, "{wing:?}");
    // ... and the quaternion is (sin 15°, 0, 0, cos 15°).
    assert!((q.x - 0.258_819).abs() < 1e-6 && (q.w - 0.965_926).abs() < 1e-6);
    assert!(q.y.abs() < 1e-7 && q.z.abs() < 1e-7);
    // Positive pitch: the nose goes up (NED z < 0).
    let q = Euler {
        roll: 0.0,
        pitch: 10.0 * d,
        yaw: 0.0,
    }
    .to_quaternion();
    let nose = q.body_to_ned([1.0, 0.0, 0.0]);
    assert!((nose[2] + (10.0 * d).sin()).abs() < TOL, "{nose:?}");
    // Order: yaw first about NED z, roll last about the body x axis. With yaw
    // 90° and roll 30°, the right wing points south and down.
    let q = Euler {
        roll: 30.0 * d,
        pitch: 0.0,
        yaw: 90.0 * d,
    }
    .to_quaternion();
    let wing = q.body_to_ned([0.0, 1.0, 0.0]);
    assert!(close3(wing, [-(30.0 * d).cos(), 0.0, 0.5], TOL), "{wing:?}");
}

#[test]
fn grid_quaternion_matrix_and_euler_agree() {
    let d = core::f32::consts::PI / 180.0;
    for roll in (-180..=180).step_by(15) {
        for pitch in (-85..=85).step_by(17) {
            for yaw in (-180..180).step_by(20) {
                let e = Euler {
                    roll: roll as f32 * d,
                    pitch: pitch as f32 * d,
                    yaw: yaw as f32 * d,
                };
                assert_same_attitude(e);
                let back = e.to_quaternion().to_euler();
                // Compare through the attitude (±180° roll is one attitude).
                let (a, b) = (e.to_matrix(), back.to_matrix());
                for (ra, rb) in a.iter().zip(b.iter()) {
                    assert!(close3(*ra, *rb, 1e-4), "{e:?} -> {back:?}");
                }
                assert!((back.pitch - e.pitch).abs() < 1e-4, "{e:?} -> {back:?}");
            }
        }
    }
}

#[test]
fn hamilton_product_composes_rotations() {
    let a = Euler {
        roll: 0.4,
        pitch: -0.3,
        yaw: 1.2,
    }
    .to_quaternion();
    let b = Euler {
        roll: -1.0,
        pitch: 0.2,
        yaw: -2.5,
    }
    .to_quaternion();
    let v = [0.2, 0.9, -0.4];
    let composed = (a * b).body_to_ned(v);
    let stepwise = a.body_to_ned(b.body_to_ned(v));
    assert!(close3(composed, stepwise, TOL));
    let id = a * a.conjugate();
    assert!(close3([id.x, id.y, id.z], [0.0; 3], 1e-6) && (id.w - 1.0).abs() < 1e-6);
    assert_eq!(Quaternion::default(), Quaternion::IDENTITY);
}

proptest! {
    #![proptest_config(Config { cases: 2000, rng_seed: RngSeed::Fixed(0x5EED_0A71), ..Config::default() })]

    #[test]
    fn random_attitudes_agree(
        roll in -3.1f32..3.1,
        pitch in -1.55f32..1.55,
        yaw in -3.1f32..3.1,
    ) {
        let e = Euler { roll, pitch, yaw };
        assert_same_attitude(e);
        let back = e.to_quaternion().to_euler();
        prop_assert!((back.roll - roll).abs() < 1e-3, "{:?} -> {:?}", e, back);
        prop_assert!((back.pitch - pitch).abs() < 1e-3, "{:?} -> {:?}", e, back);
        prop_assert!((back.yaw - yaw).abs() < 1e-3, "{:?} -> {:?}", e, back);
    }
}

#[test]
fn default_flight_is_the_validated_default() {
    assert_eq!(
        flight_sim::Flight::default(),
        flight_sim::Flight::new(flight_sim::FlightParams::DEFAULT).unwrap()
    );
}
