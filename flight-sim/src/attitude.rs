//! Attitude: Euler angles, quaternions and rotations between body and NED axes.
//!
//! # Convention (pinned by the tests in `tests/all/attitude.rs`)
//!
//! * Axes: NED (x north, y east, z down) for the Earth frame, and x forward,
//!   y right wing, z down for the body frame. Right-handed; positive angles turn
//!   clockwise when looking along the axis.
//! * Euler angles are the aerospace Tait–Bryan set: starting from NED, **yaw ψ**
//!   about z, then **pitch θ** about the new y′, then **roll φ** about the new
//!   x″. The body→NED matrix is `C = Rz(ψ)·Ry(θ)·Rx(φ)`. Read as rotations of a
//!   vector about the *fixed* axes, this is "roll, then pitch, then yaw", which
//!   is how we read the AEOLUS spec's "r-p′-y″" (section 7.8). The literal
//!   intrinsic x-y′-z″ reading would show a non-zero pitch in a level banked
//!   turn, which no attitude indicator does.
//! * The quaternion is the Hamilton quaternion of the same rotation,
//!   `q = qz(ψ) ⊗ qy(θ) ⊗ qx(φ)`: `q ⊗ v ⊗ q*` takes a body vector to NED. Its
//!   scalar part `w` is kept `>= 0`. On the AEOLUS wire it goes out as
//!   `qx, qy, qz, qw`.
//! * Ranges: roll and yaw in `(-π, π]`, pitch in `[-π/2, π/2]`.
//!
//! ```
//! use flight_sim::{Euler, Quaternion};
//!
//! let e = Euler { roll: 0.5, pitch: -0.2, yaw: 2.0 };
//! let q = e.to_quaternion();
//! let back = q.to_euler();
//! assert!((back.roll - 0.5).abs() < 1e-5 && (back.yaw - 2.0).abs() < 1e-5);
//! // The nose (body x) points along the heading.
//! let nose = q.body_to_ned([1.0, 0.0, 0.0]);
//! assert!((nose[0] - libm::cosf(2.0) * libm::cosf(0.2)).abs() < 1e-5);
//! ```

use libm::{asinf, atan2f, cosf, sinf, sqrtf};

/// Euler angles in radians (see the [module docs](self) for the convention).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Euler {
    /// Roll φ about the body x axis, rad, positive right wing down.
    pub roll: f32,
    /// Pitch θ about the body y axis, rad, positive nose up.
    pub pitch: f32,
    /// Yaw ψ about the NED z axis, rad, positive clockwise seen from above
    /// (0 = north, π/2 = east).
    pub yaw: f32,
}

/// A Hamilton unit quaternion taking body vectors to NED.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Quaternion {
    /// Vector part, x.
    pub x: f32,
    /// Vector part, y.
    pub y: f32,
    /// Vector part, z.
    pub z: f32,
    /// Scalar part.
    pub w: f32,
}

impl Default for Quaternion {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl Euler {
    /// The quaternion of the same attitude, `qz(ψ) ⊗ qy(θ) ⊗ qx(φ)`, with `w >= 0`.
    ///
    /// ```
    /// let q = flight_sim::Euler { roll: 0.0, pitch: 0.0, yaw: core::f32::consts::PI / 2.0 }
    ///     .to_quaternion();
    /// assert!((q.z - core::f32::consts::FRAC_1_SQRT_2).abs() < 1e-6);
    /// ```
    pub fn to_quaternion(self) -> Quaternion {
        let (sr, cr) = (sinf(self.roll * 0.5), cosf(self.roll * 0.5));
        let (sp, cp) = (sinf(self.pitch * 0.5), cosf(self.pitch * 0.5));
        let (sy, cy) = (sinf(self.yaw * 0.5), cosf(self.yaw * 0.5));
        Quaternion {
            w: cr * cp * cy + sr * sp * sy,
            x: sr * cp * cy - cr * sp * sy,
            y: cr * sp * cy + sr * cp * sy,
            z: cr * cp * sy - sr * sp * cy,
        }
        .canonical()
    }

    /// The body→NED direction cosine matrix `Rz(ψ)·Ry(θ)·Rx(φ)`, row-major.
    ///
    /// ```
    /// let m = flight_sim::Euler::default().to_matrix();
    /// assert_eq!(m, [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);
    /// ```
    pub fn to_matrix(self) -> [[f32; 3]; 3] {
        let (sr, cr) = (sinf(self.roll), cosf(self.roll));
        let (sp, cp) = (sinf(self.pitch), cosf(self.pitch));
        let (sy, cy) = (sinf(self.yaw), cosf(self.yaw));
        [
            [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
            [-sp, cp * sr, cp * cr],
        ]
    }
}

impl Quaternion {
    /// No rotation.
    pub const IDENTITY: Quaternion = Quaternion {
        x: 0.0,
        y: 0.0,
        z: 0.0,
        w: 1.0,
    };

    /// The Euler angles of this attitude (roll, yaw in `(-π, π]`, pitch in
    /// `[-π/2, π/2]`).
    ///
    /// ```
    /// let e = flight_sim::Quaternion::IDENTITY.to_euler();
    /// assert_eq!(e, flight_sim::Euler::default());
    /// ```
    pub fn to_euler(self) -> Euler {
        let Quaternion { x, y, z, w } = self;
        let sin_pitch = (2.0 * (w * y - z * x)).clamp(-1.0, 1.0);
        Euler {
            roll: atan2f(2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y)),
            pitch: asinf(sin_pitch),
            yaw: atan2f(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z)),
        }
    }

    /// The inverse rotation of a unit quaternion.
    ///
    /// ```
    /// let q = flight_sim::Quaternion { x: 0.0, y: 0.0, z: 1.0, w: 0.0 }.conjugate();
    /// assert_eq!(q.z, -1.0);
    /// ```
    pub const fn conjugate(self) -> Quaternion {
        Quaternion {
            x: -self.x,
            y: -self.y,
            z: -self.z,
            w: self.w,
        }
    }

    /// The Euclidean norm (1 for a rotation).
    ///
    /// ```
    /// assert_eq!(flight_sim::Quaternion::IDENTITY.norm(), 1.0);
    /// ```
    pub fn norm(self) -> f32 {
        sqrtf(self.x * self.x + self.y * self.y + self.z * self.z + self.w * self.w)
    }

    /// The same rotation with `w >= 0` (`q` and `-q` are the same attitude).
    ///
    /// ```
    /// let q = flight_sim::Quaternion { x: 0.0, y: 0.0, z: 0.0, w: -1.0 }.canonical();
    /// assert_eq!(q.w, 1.0);
    /// ```
    pub fn canonical(self) -> Quaternion {
        if self.w < 0.0 {
            Quaternion {
                x: -self.x,
                y: -self.y,
                z: -self.z,
                w: -self.w,
            }
        } else {
            self
        }
    }

    /// Rotates a body-axes vector into NED axes: `q ⊗ v ⊗ q*`.
    ///
    /// ```
    /// let q = flight_sim::Euler { roll: 0.0, pitch: 0.0, yaw: core::f32::consts::FRAC_PI_2 }
    ///     .to_quaternion();
    /// let v = q.body_to_ned([1.0, 0.0, 0.0]); // nose points east
    /// assert!(v[0].abs() < 1e-6 && (v[1] - 1.0).abs() < 1e-6);
    /// ```
    pub fn body_to_ned(self, v: [f32; 3]) -> [f32; 3] {
        rotate(self.x, self.y, self.z, self.w, v)
    }

    /// Rotates a NED vector into body axes: `q* ⊗ v ⊗ q`.
    ///
    /// ```
    /// let q = flight_sim::Euler { roll: core::f32::consts::FRAC_PI_2, pitch: 0.0, yaw: 0.0 }
    ///     .to_quaternion();
    /// let g = q.ned_to_body([0.0, 0.0, 1.0]); // 90° right bank: "down" is the right wing
    /// assert!((g[1] - 1.0).abs() < 1e-6);
    /// ```
    pub fn ned_to_body(self, v: [f32; 3]) -> [f32; 3] {
        rotate(-self.x, -self.y, -self.z, self.w, v)
    }
}

impl core::ops::Mul for Quaternion {
    type Output = Quaternion;

    /// The Hamilton product `self ⊗ rhs` (apply `rhs` first, then `self`).
    ///
    /// ```
    /// let q = flight_sim::Euler { roll: 0.3, pitch: 0.1, yaw: -1.0 }.to_quaternion();
    /// let p = q * q.conjugate();
    /// assert!((p.w - 1.0).abs() < 1e-6);
    /// ```
    fn mul(self, rhs: Quaternion) -> Quaternion {
        let (a, b) = (self, rhs);
        Quaternion {
            w: a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z,
            x: a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
            y: a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
            z: a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w,
        }
    }
}

/// `v' = v + 2w(u×v) + 2u×(u×v)` for the unit quaternion (u, w).
fn rotate(x: f32, y: f32, z: f32, w: f32, v: [f32; 3]) -> [f32; 3] {
    let [vx, vy, vz] = v;
    // t = 2 (u × v)
    let tx = 2.0 * (y * vz - z * vy);
    let ty = 2.0 * (z * vx - x * vz);
    let tz = 2.0 * (x * vy - y * vx);
    [
        vx + w * tx + (y * tz - z * ty),
        vy + w * ty + (z * tx - x * tz),
        vz + w * tz + (x * ty - y * tx),
    ]
}
