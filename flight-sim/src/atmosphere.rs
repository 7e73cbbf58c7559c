//! The International Standard Atmosphere, troposphere (0..=11 000 m).
//!
//! ```
//! let p = flight_sim::atmosphere::pressure_pa(0.0);
//! assert!((p - 101_325.0).abs() < 0.5);
//! ```

use libm::{expf, logf};

/// Sea-level standard pressure, Pa.
pub const P0_PA: f32 = 101_325.0;
/// Sea-level standard temperature, K.
pub const T0_K: f32 = 288.15;
/// Temperature lapse rate in the troposphere, K/m.
pub const LAPSE_K_PER_M: f32 = 0.006_5;
/// Specific gas constant of dry air, J/(kg·K).
pub const R_AIR: f32 = 287.052_87;
/// Lowest altitude the model accepts, m.
pub const MIN_ALTITUDE_M: f32 = -500.0;
/// Highest altitude the model accepts (the tropopause), m.
pub const MAX_ALTITUDE_M: f32 = 11_000.0;

/// ISA temperature at a geopotential altitude, K.
///
/// ```
/// assert!((flight_sim::atmosphere::temperature_k(1000.0) - 281.65).abs() < 1e-3);
/// ```
pub fn temperature_k(altitude_m: f32) -> f32 {
    T0_K - LAPSE_K_PER_M * altitude_m
}

/// ISA static pressure at a geopotential altitude, Pa:
/// `p = p0 · (T / T0)^(g / (L·R))`.
///
/// ```
/// let p = flight_sim::atmosphere::pressure_pa(1000.0);
/// assert!((p - 89_874.6).abs() < 2.0);
/// ```
pub fn pressure_pa(altitude_m: f32) -> f32 {
    let exponent = crate::G / (LAPSE_K_PER_M * R_AIR);
    // x^k as exp(k·ln x): on a Cortex-M this is ~1 KiB smaller than `powf`, same accuracy here.
    P0_PA * expf(exponent * logf(temperature_k(altitude_m) / T0_K))
}

/// ISA air density, kg/m³ (`ρ = p / (R·T)`).
///
/// ```
/// assert!((flight_sim::atmosphere::density_kg_m3(0.0) - 1.225).abs() < 1e-3);
/// ```
pub fn density_kg_m3(altitude_m: f32) -> f32 {
    pressure_pa(altitude_m) / (R_AIR * temperature_k(altitude_m))
}

/// Dynamic pressure `q = ½·ρ·V²` at an altitude and true airspeed, Pa.
///
/// ```
/// // 50 m/s at sea level: about 15.3 mbar.
/// let q = flight_sim::atmosphere::dynamic_pressure_pa(0.0, 50.0);
/// assert!((q - 1531.25).abs() < 1.0);
/// ```
pub fn dynamic_pressure_pa(altitude_m: f32, tas_mps: f32) -> f32 {
    0.5 * density_kg_m3(altitude_m) * tas_mps * tas_mps
}
