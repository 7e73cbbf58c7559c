//! The crate's error type.

use core::fmt;

/// Why a set of [`FlightParams`](crate::FlightParams) was refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Error {
    /// A parameter is NaN or infinite.
    NotFinite,
    /// Airspeed outside `MIN_AIRSPEED_MPS..=MAX_AIRSPEED_MPS`.
    Airspeed,
    /// Bank angle outside `-MAX_BANK_DEG..=MAX_BANK_DEG`.
    Bank,
    /// Altitude outside the ISA troposphere model's range.
    Altitude,
    /// Start latitude beyond ±85° or longitude beyond ±180°.
    Position,
    /// Wind speed negative or not below the airspeed.
    Wind,
    /// Climb (or descent) rate above half the airspeed (a flight path steeper than 30°), or
    /// any climb when the crate is built without its `climb` feature.
    Climb,
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Error::NotFinite => "a flight parameter is not a finite number",
            Error::Airspeed => "airspeed out of range",
            Error::Bank => "bank angle out of range",
            Error::Altitude => "altitude out of the ISA troposphere range",
            Error::Position => "start position out of range",
            Error::Wind => "wind speed negative or not below the airspeed",
            Error::Climb if cfg!(feature = "climb") => "climb rate above half the airspeed",
            Error::Climb => "climbs need flight-sim's `climb` feature",
        })
    }
}

impl core::error::Error for Error {}
