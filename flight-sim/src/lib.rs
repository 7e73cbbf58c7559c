//! A physically consistent simulated flight for the sensor-box example.
//!
//! The aircraft flies a **steady coordinated turn**: constant bank angle φ,
//! constant true airspeed V, constant altitude, optionally in a steady wind.
//! Everything an AEOLUS sensor box reports is derived from that one motion, so
//! the values agree with each other the way real sensors would:
//!
//! * turn rate ω = g·tan φ / V, turn radius r = V² / (g·tan φ);
//! * Euler angles and quaternion describe the same attitude ([`attitude`]);
//! * gyro = the turn rate seen in body axes, `(0, ω·sin φ, ω·cos φ)`;
//! * accelerometer = specific force in body axes, `(0, 0, -g / cos φ)`;
//! * magnetometer = the Earth field rotated into body axes;
//! * static pressure, air density and temperature from the ISA ([`atmosphere`]);
//! * pitot pressure = dynamic pressure ½·ρ·V²;
//! * GPS positions move along the circle (plus the wind drift) at the ground
//!   speed ([`geo`]).
//!
//! The crate is a plain `no_std` library without protocol types: the firmware
//! and the host tool (`protolink sim`) both map a [`State`] to AEOLUS messages.
//!
//! ```
//! use flight_sim::{Flight, FlightParams};
//!
//! let flight = Flight::new(FlightParams::DEFAULT)?;
//! let s = flight.state(10_000); // 10 s after boot
//! // A coordinated turn: the accelerometer reads (0, 0, -g / cos φ).
//! let bank = FlightParams::DEFAULT.bank_deg.to_radians();
//! assert!((s.accel_mps2[2] + flight_sim::G / libm::cosf(bank)).abs() < 1e-3);
//! assert!(s.slip_ball.abs() < 1e-6);
//! # Ok::<(), flight_sim::Error>(())
//! ```
#![no_std]
#![forbid(unsafe_code)]
#![deny(missing_docs)]

pub mod atmosphere;
pub mod attitude;
mod error;
mod flight;
pub mod geo;
mod turn;

pub use attitude::{Euler, Quaternion};
pub use error::Error;
pub use flight::{EarthField, Flight, FlightParams, State};

/// Standard gravity, m/s².
pub const G: f32 = 9.806_65;

/// One standard-rate turn (3 °/s, a full circle in two minutes), in rad/s.
/// [`State::turn_coordinator`] is the turn rate in these units.
pub const STANDARD_RATE_RAD_S: f32 = 3.0 * core::f32::consts::PI / 180.0;
