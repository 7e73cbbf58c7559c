//! The units `watch` and `web` show (`--units si | aviation`): SI (m/s, m, mbar) as the box
//! sends them, or what a pilot reads (knots, feet, feet per minute, hPa and inHg). The box's
//! messages are always SI; only the display converts.

use serde::Serialize;

/// Metres per foot (international foot).
pub(crate) const M_PER_FT: f64 = 0.3048;
/// Metres per second per knot (1852 m per hour).
pub(crate) const MPS_PER_KT: f64 = 1852.0 / 3600.0;
/// Feet per metre.
pub(crate) const FT_PER_M: f64 = 1.0 / M_PER_FT;
/// Knots per metre per second.
pub(crate) const KT_PER_MPS: f64 = 1.0 / MPS_PER_KT;
/// Hectopascals (millibars) per inch of mercury (at 0 °C, standard gravity).
pub(crate) const HPA_PER_INHG: f64 = 33.863_886_666_7;

/// A system of display units.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
pub(crate) enum Units {
    /// m/s, m, m/s vertical, mbar: the units of the AEOLUS messages.
    #[default]
    Si,
    /// Knots, feet, feet per minute, hPa and inHg.
    Aviation,
}

/// How one quantity is shown: its unit's name and the factor from the SI value.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub(crate) struct Scale {
    /// The unit as printed: `kt`, `ft`, `ft/min`, `m/s`, `m`.
    pub(crate) unit: &'static str,
    /// Displayed value = SI value × `per_si`.
    pub(crate) per_si: f64,
}

impl Scale {
    /// The SI value in this unit.
    pub(crate) fn of(self, si: f64) -> f64 {
        si * self.per_si
    }
}

/// The scales of one [`Units`], as the page receives them (`units` in the JSON state).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub(crate) struct UnitScales {
    /// `si` or `aviation`.
    pub(crate) name: &'static str,
    /// Airspeed and ground speed (from m/s).
    pub(crate) speed: Scale,
    /// Altitude (from m).
    pub(crate) altitude: Scale,
    /// Vertical speed (from m/s).
    pub(crate) vertical_speed: Scale,
}

impl Units {
    /// Speeds: m/s or knots.
    pub(crate) fn speed(self) -> Scale {
        match self {
            Units::Si => Scale {
                unit: "m/s",
                per_si: 1.0,
            },
            Units::Aviation => Scale {
                unit: "kt",
                per_si: 1.0 / MPS_PER_KT,
            },
        }
    }

    /// Altitudes: m or ft.
    pub(crate) fn altitude(self) -> Scale {
        match self {
            Units::Si => Scale {
                unit: "m",
                per_si: 1.0,
            },
            Units::Aviation => Scale {
                unit: "ft",
                per_si: 1.0 / M_PER_FT,
            },
        }
    }

    /// Vertical speeds: m/s or ft/min.
    pub(crate) fn vertical_speed(self) -> Scale {
        match self {
            Units::Si => Scale {
                unit: "m/s",
                per_si: 1.0,
            },
            Units::Aviation => Scale {
                unit: "ft/min",
                per_si: 60.0 / M_PER_FT,
            },
        }
    }

    /// A pressure in mbar as these units print it: `898.75 mbar`, or `898.75 hPa (26.54 inHg)`.
    pub(crate) fn pressure(self, mbar: f32) -> String {
        let mbar = f64::from(mbar);
        match self {
            Units::Si => format!("{mbar:.2} mbar"),
            Units::Aviation => format!("{mbar:.2} hPa ({:.2} inHg)", mbar / HPA_PER_INHG),
        }
    }

    /// Every scale at once, for the page.
    pub(crate) fn scales(self) -> UnitScales {
        UnitScales {
            name: match self {
                Units::Si => "si",
                Units::Aviation => "aviation",
            },
            speed: self.speed(),
            altitude: self.altitude(),
            vertical_speed: self.vertical_speed(),
        }
    }
}

/// The examples of this module's items, as tests (the items are crate-private, so rustdoc
/// does not run them).
#[cfg(test)]
#[allow(unused_imports, clippy::unnecessary_wraps)]
mod examples {
    use super::*;

    #[test]
    fn of_example() -> Result<(), Box<dyn std::error::Error>> {
        assert!((Units::Aviation.vertical_speed().of(2.5) - 492.1).abs() < 0.1);
        Ok(())
    }

    #[test]
    fn speed_example() -> Result<(), Box<dyn std::error::Error>> {
        let kt = Units::Aviation.speed();
        assert_eq!(kt.unit, "kt");
        assert!((kt.of(50.0) - 97.19).abs() < 0.01);
        assert_eq!(Units::Si.speed().of(50.0), 50.0);
        Ok(())
    }

    #[test]
    fn altitude_example() -> Result<(), Box<dyn std::error::Error>> {
        assert!((Units::Aviation.altitude().of(1000.0) - 3280.84).abs() < 0.01);
        Ok(())
    }

    #[test]
    fn vertical_speed_example() -> Result<(), Box<dyn std::error::Error>> {
        assert_eq!(Units::Aviation.vertical_speed().unit, "ft/min");
        Ok(())
    }

    #[test]
    fn pressure_example() -> Result<(), Box<dyn std::error::Error>> {
        assert_eq!(Units::Si.pressure(1013.25), "1013.25 mbar");
        assert_eq!(
            Units::Aviation.pressure(1013.25),
            "1013.25 hPa (29.92 inHg)"
        );
        Ok(())
    }

    #[test]
    fn scales_example() -> Result<(), Box<dyn std::error::Error>> {
        assert_eq!(Units::Aviation.scales().altitude.unit, "ft");
        Ok(())
    }
}
