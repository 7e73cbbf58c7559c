//! The coordinated turn: parameters, the precomputed flight and its state.

use crate::attitude::{Euler, Quaternion};
use crate::{Error, G, STANDARD_RATE_RAD_S, atmosphere, geo};
use core::f32::consts::PI;
use libm::{atan2f, cosf, sinf, sqrtf, tanf};

const DEG: f32 = PI / 180.0;

/// The Earth's magnetic field at the flight's location, NED components, Gauss.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct EarthField {
    /// North component, G.
    pub north_gauss: f32,
    /// East component, G.
    pub east_gauss: f32,
    /// Down component, G (positive in the northern hemisphere).
    pub down_gauss: f32,
}

impl EarthField {
    /// Roughly southern Germany: 0.21 G north, 0.01 G east (declination ≈ +2.7°),
    /// 0.43 G down (inclination ≈ 64°).
    pub const CENTRAL_EUROPE: EarthField = EarthField {
        north_gauss: 0.21,
        east_gauss: 0.01,
        down_gauss: 0.43,
    };

    /// Magnetic declination (east of true north positive), degrees.
    ///
    /// ```
    /// let d = flight_sim::EarthField::CENTRAL_EUROPE.declination_deg();
    /// assert!((d - 2.726).abs() < 0.01);
    /// ```
    pub fn declination_deg(&self) -> f32 {
        atan2f(self.east_gauss, self.north_gauss) / DEG
    }
}

/// What the simulated aircraft does. All angles in degrees.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct FlightParams {
    /// True airspeed, m/s, in `MIN_AIRSPEED_MPS..=MAX_AIRSPEED_MPS`.
    pub airspeed_mps: f32,
    /// Bank angle, degrees, positive = right wing down = right turn, within
    /// `±MAX_BANK_DEG`. 0 flies straight.
    pub bank_deg: f32,
    /// Altitude above mean sea level, m (ISA troposphere: -500..=11 000).
    pub altitude_m: f32,
    /// Latitude at t = 0, degrees north, within ±85°.
    pub start_lat_deg: f64,
    /// Longitude at t = 0, degrees east, within ±180°.
    pub start_lon_deg: f64,
    /// True heading at t = 0, degrees (0 = north, 90 = east).
    pub start_heading_deg: f32,
    /// Wind speed, m/s, below the airspeed.
    pub wind_speed_mps: f32,
    /// Direction the wind blows **from**, degrees true (meteorological).
    pub wind_from_deg: f32,
    /// The Earth's magnetic field in NED axes.
    pub earth_field: EarthField,
}

impl FlightParams {
    /// Lowest accepted airspeed, m/s.
    pub const MIN_AIRSPEED_MPS: f32 = 5.0;
    /// Highest accepted airspeed, m/s.
    pub const MAX_AIRSPEED_MPS: f32 = 150.0;
    /// Largest accepted bank angle, degrees.
    pub const MAX_BANK_DEG: f32 = 60.0;

    /// A light aircraft circling near Munich: 50 m/s, 20° right bank, 1000 m,
    /// 5 m/s wind from the west.
    pub const DEFAULT: FlightParams = FlightParams {
        airspeed_mps: 50.0,
        bank_deg: 20.0,
        altitude_m: 1000.0,
        start_lat_deg: 48.353_8,
        start_lon_deg: 11.786_1,
        start_heading_deg: 0.0,
        wind_speed_mps: 5.0,
        wind_from_deg: 270.0,
        earth_field: EarthField::CENTRAL_EUROPE,
    };

    /// Checks every parameter's range.
    ///
    /// ```
    /// use flight_sim::{Error, FlightParams};
    /// let bad = FlightParams { bank_deg: 80.0, ..FlightParams::DEFAULT };
    /// assert_eq!(bad.validate(), Err(Error::Bank));
    /// assert_eq!(FlightParams::DEFAULT.validate(), Ok(()));
    /// ```
    pub fn validate(&self) -> Result<(), Error> {
        let f32s = [
            self.airspeed_mps,
            self.bank_deg,
            self.altitude_m,
            self.start_heading_deg,
            self.wind_speed_mps,
            self.wind_from_deg,
            self.earth_field.north_gauss,
            self.earth_field.east_gauss,
            self.earth_field.down_gauss,
        ];
        if f32s.iter().any(|v| !v.is_finite())
            || !self.start_lat_deg.is_finite()
            || !self.start_lon_deg.is_finite()
        {
            return Err(Error::NotFinite);
        }
        if !(Self::MIN_AIRSPEED_MPS..=Self::MAX_AIRSPEED_MPS).contains(&self.airspeed_mps) {
            return Err(Error::Airspeed);
        }
        if self.bank_deg.abs() > Self::MAX_BANK_DEG {
            return Err(Error::Bank);
        }
        if !(atmosphere::MIN_ALTITUDE_M..=atmosphere::MAX_ALTITUDE_M).contains(&self.altitude_m) {
            return Err(Error::Altitude);
        }
        if self.start_lat_deg.abs() > 85.0 || self.start_lon_deg.abs() > 180.0 {
            return Err(Error::Position);
        }
        if self.wind_speed_mps < 0.0 || self.wind_speed_mps >= self.airspeed_mps {
            return Err(Error::Wind);
        }
        Ok(())
    }
}

impl Default for FlightParams {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// Everything the sensor box measures at one instant. Axes are NED / body
/// (x forward, y right, z down); see [`crate::attitude`].
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct State {
    /// Milliseconds since boot (the AEOLUS timestamp).
    pub time_ms: f64,
    /// Euler angles, rad.
    pub euler: Euler,
    /// The same attitude as a quaternion (body → NED, `w >= 0`).
    pub quaternion: Quaternion,
    /// Body angular rates (gyro x, y, z), rad/s.
    pub gyro_rad_s: [f32; 3],
    /// Specific force in body axes (accelerometer x, y, z), m/s². Level flight
    /// reads `(0, 0, -g)`.
    pub accel_mps2: [f32; 3],
    /// Earth field in body axes (magnetometer x, y, z), Gauss.
    pub mag_gauss: [f32; 3],
    /// ISA static pressure at the altitude, mbar.
    pub static_pressure_mbar: f32,
    /// Pitot (differential) pressure: the dynamic pressure ½·ρ·V², mbar.
    pub pitot_pressure_mbar: f32,
    /// True airspeed, m/s.
    pub airspeed_mps: f32,
    /// Outside air temperature (ISA), °C.
    pub oat_celsius: f32,
    /// GPS latitude, degrees.
    pub latitude_deg: f64,
    /// GPS longitude, degrees.
    pub longitude_deg: f64,
    /// GPS altitude, m (the flight altitude).
    pub gps_altitude_m: f32,
    /// Speed over ground, m/s.
    pub ground_speed_mps: f32,
    /// Ground track, degrees true in `[0, 360)`.
    pub track_deg: f32,
    /// True heading of the nose, degrees in `[0, 360)` (the yaw angle).
    pub heading_deg: f32,
    /// Magnetic (compass) heading, degrees in `[0, 360)`: true heading minus
    /// the declination.
    pub magnetic_heading_deg: f32,
    /// Slip ball: lateral over normal specific force (`-ay / az`, the tangent of
    /// the ball's deflection), positive = ball right. 0 in a coordinated turn.
    pub slip_ball: f32,
    /// Turn rate (heading rate), rad/s, positive = right.
    pub turn_rate_rad_s: f32,
    /// Turn coordinator: the turn rate in standard-rate units (1.0 = 3 °/s
    /// right, -1.0 = 3 °/s left).
    pub turn_coordinator: f32,
    /// Wind speed, m/s.
    pub wind_speed_mps: f32,
    /// Direction the wind blows from, degrees true in `[0, 360)`.
    pub wind_from_deg: f32,
}

/// A validated flight with its constant quantities precomputed, so that
/// [`Flight::state`] is cheap (a few `sinf`/`cosf`, no `powf`).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Flight {
    params: FlightParams,
    bank_rad: f32,
    heading0_rad: f32,
    /// Turn rate, rad/s.
    omega: f32,
    /// Wind velocity (towards), north/east, m/s.
    wind_ne: [f32; 2],
    static_mbar: f32,
    pitot_mbar: f32,
    oat_c: f32,
}

/// The flight of [`FlightParams::DEFAULT`] (valid by construction; pinned by a test).
impl Default for Flight {
    fn default() -> Self {
        Self::build(FlightParams::DEFAULT)
    }
}

impl Flight {
    /// Validates the parameters and precomputes the turn.
    ///
    /// ```
    /// let f = flight_sim::Flight::new(flight_sim::FlightParams::DEFAULT)?;
    /// assert!(f.turn_radius_m() > 600.0);
    /// # Ok::<(), flight_sim::Error>(())
    /// ```
    pub fn new(params: FlightParams) -> Result<Flight, Error> {
        params.validate()?;
        Ok(Self::build(params))
    }

    /// Precomputes the turn for parameters already validated.
    fn build(params: FlightParams) -> Flight {
        let bank_rad = params.bank_deg * DEG;
        let omega = G * tanf(bank_rad) / params.airspeed_mps;
        let from = params.wind_from_deg * DEG;
        let w = params.wind_speed_mps;
        Flight {
            params,
            bank_rad,
            heading0_rad: params.start_heading_deg * DEG,
            omega,
            wind_ne: [-w * cosf(from), -w * sinf(from)],
            static_mbar: atmosphere::pressure_pa(params.altitude_m) / 100.0,
            pitot_mbar: atmosphere::dynamic_pressure_pa(params.altitude_m, params.airspeed_mps)
                / 100.0,
            oat_c: atmosphere::temperature_k(params.altitude_m) - 273.15,
        }
    }

    /// The parameters this flight was built from.
    ///
    /// ```
    /// let f = flight_sim::Flight::new(Default::default())?;
    /// assert_eq!(f.params().airspeed_mps, 50.0);
    /// # Ok::<(), flight_sim::Error>(())
    /// ```
    pub const fn params(&self) -> &FlightParams {
        &self.params
    }

    /// Turn rate ω = g·tan φ / V, rad/s (positive = right).
    ///
    /// ```
    /// let f = flight_sim::Flight::new(Default::default())?;
    /// assert!((f.turn_rate_rad_s() - 0.07139).abs() < 1e-4);
    /// # Ok::<(), flight_sim::Error>(())
    /// ```
    pub const fn turn_rate_rad_s(&self) -> f32 {
        self.omega
    }

    /// Turn radius through the air V² / (g·tan |φ|), m; infinite when the
    /// wings are level.
    ///
    /// ```
    /// let f = flight_sim::Flight::new(Default::default())?;
    /// assert!((f.turn_radius_m() - 700.4).abs() < 0.5);
    /// # Ok::<(), flight_sim::Error>(())
    /// ```
    pub fn turn_radius_m(&self) -> f32 {
        if self.omega == 0.0 {
            f32::INFINITY
        } else {
            self.params.airspeed_mps / self.omega.abs()
        }
    }

    /// The state `t_ms` milliseconds after boot (t = 0 is the start point).
    ///
    /// ```
    /// let f = flight_sim::Flight::new(Default::default())?;
    /// let s = f.state(1_000);
    /// assert_eq!(s.time_ms, 1_000.0);
    /// assert!((s.static_pressure_mbar - 898.75).abs() < 0.05);
    /// # Ok::<(), flight_sim::Error>(())
    /// ```
    pub fn state(&self, t_ms: u64) -> State {
        let p = &self.params;
        let v = p.airspeed_mps;
        let t_s = t_ms as f64 / 1000.0;
        // Heading change since t = 0, reduced to one turn in f64 so that f32
        // keeps its precision however long the box has been running.
        let turned =
            crate::geo::remainder(f64::from(self.omega) * t_s, core::f64::consts::TAU) as f32;
        let yaw = wrap_pi(self.heading0_rad + turned);
        let (sin_yaw, cos_yaw) = (sinf(yaw), cosf(yaw));

        let euler = Euler {
            roll: self.bank_rad,
            pitch: 0.0,
            yaw,
        };
        let q = euler.to_quaternion();
        let gyro = q.ned_to_body([0.0, 0.0, self.omega]);
        // Acceleration of the aircraft: centripetal, V·ω to the right of the
        // air-relative velocity (a steady wind adds none).
        let a_lat = v * self.omega;
        let specific_force_ned = [-a_lat * sin_yaw, a_lat * cos_yaw, -G];
        let accel = q.ned_to_body(specific_force_ned);
        let field = p.earth_field;
        let mag = q.ned_to_body([field.north_gauss, field.east_gauss, field.down_gauss]);

        // Position: the air-relative circle plus the wind drift.
        let (air_n, air_e) = if self.omega == 0.0 {
            let d = f64::from(v) * t_s;
            (
                d * f64::from(cosf(self.heading0_rad)),
                d * f64::from(sinf(self.heading0_rad)),
            )
        } else {
            // Chord of the arc: 2·r·sin(Δψ/2) along the mean heading.
            let chord = 2.0 * (v / self.omega) * sinf(turned * 0.5);
            let dir = self.heading0_rad + turned * 0.5;
            (f64::from(chord * cosf(dir)), f64::from(chord * sinf(dir)))
        };
        let north = air_n + f64::from(self.wind_ne[0]) * t_s;
        let east = air_e + f64::from(self.wind_ne[1]) * t_s;
        let (lat, lon) = geo::offset(p.start_lat_deg, p.start_lon_deg, north, east);

        let ground_n = v * cos_yaw + self.wind_ne[0];
        let ground_e = v * sin_yaw + self.wind_ne[1];
        let heading_deg = wrap_360(yaw / DEG);
        let slip_ball = if accel[2] == 0.0 {
            0.0
        } else {
            -accel[1] / accel[2]
        };

        State {
            time_ms: t_ms as f64,
            euler,
            quaternion: q,
            gyro_rad_s: gyro,
            accel_mps2: accel,
            mag_gauss: mag,
            static_pressure_mbar: self.static_mbar,
            pitot_pressure_mbar: self.pitot_mbar,
            airspeed_mps: v,
            oat_celsius: self.oat_c,
            latitude_deg: lat,
            longitude_deg: lon,
            gps_altitude_m: p.altitude_m,
            ground_speed_mps: sqrtf(ground_n * ground_n + ground_e * ground_e),
            track_deg: wrap_360(atan2f(ground_e, ground_n) / DEG),
            heading_deg,
            magnetic_heading_deg: wrap_360(heading_deg - field.declination_deg()),
            slip_ball,
            turn_rate_rad_s: self.omega,
            turn_coordinator: self.omega / STANDARD_RATE_RAD_S,
            wind_speed_mps: p.wind_speed_mps,
            wind_from_deg: wrap_360(p.wind_from_deg),
        }
    }
}

/// Wraps an angle into `(-π, π]`.
fn wrap_pi(a: f32) -> f32 {
    let w = crate::geo::remainder(f64::from(a + PI), core::f64::consts::TAU) as f32;
    let w = if w <= 0.0 { w + 2.0 * PI } else { w };
    w - PI
}

/// Wraps degrees into `[0, 360)`.
fn wrap_360(d: f32) -> f32 {
    let w = crate::geo::remainder(f64::from(d), 360.0) as f32;
    let w = if w < 0.0 { w + 360.0 } else { w };
    if w >= 360.0 { 0.0 } else { w }
}
