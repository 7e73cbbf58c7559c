//! The coordinated turn: parameters, the precomputed flight and its state.

use crate::attitude::{Euler, Quaternion};
use crate::turn::{self, Fixed3, mul};
use crate::{Error, G, STANDARD_RATE_RAD_S, atmosphere, geo};

const DEG: f32 = core::f32::consts::PI / 180.0;
const DEG_F64: f64 = core::f64::consts::PI / 180.0;
const TAU_F64: f64 = core::f64::consts::TAU;
/// 2^64 / 360: longitude units (2^-64 turn) per degree.
const LON_UNITS_PER_DEG: f64 = 18_446_744_073_709_551_616.0 / 360.0;

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
        let field = Fixed3::new([self.north_gauss, self.east_gauss, self.down_gauss]);
        turn::to_deg_signed(field_declination(field))
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
    /// Altitude above mean sea level at t = 0, m (ISA troposphere: -500..=11 000).
    pub altitude_m: f32,
    /// Vertical speed, m/s, positive up, at most half the airspeed. The aircraft climbs (or
    /// descends) at this rate until the edge of the ISA troposphere (11 000 m, -500 m), then
    /// flies level. 0 flies level throughout.
    pub climb_mps: f32,
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
        climb_mps: 0.0,
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
            self.climb_mps,
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
        if self.climb_mps.abs() > self.airspeed_mps / 2.0
            || (self.climb_mps != 0.0 && !cfg!(feature = "climb"))
        {
            return Err(Error::Climb);
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
/// [`Flight::state`] is cheap: no `libm` call and little floating point per state (the angles
/// and rotations in fixed point, README "Cost"), about 3 100 instructions on a Cortex-M3 without
/// an FPU.
///
/// Roll and pitch are constant in the turn, so everything that depends on them (the gyro,
/// the accelerometer, the half-bank quaternion factors) is computed here once; a state
/// rotates by the yaw alone. The heading advances by a fixed fraction of a turn per
/// millisecond ([`Flight::state`]).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Flight {
    params: FlightParams,
    bank_rad: f32,
    /// Turn rate, rad/s.
    omega: f32,
    static_mbar: f32,
    pitot_mbar: f32,
    oat_c: f32,
    wind_from_deg: f32,
    /// Body rates and specific force: constant in a coordinated turn.
    gyro: [f32; 3],
    accel: [f32; 3],
    /// Start heading, angle units (2^32 = one turn), and its sine and cosine, Q30.
    heading0: u32,
    heading0_sin_cos: (i32, i32),
    /// Heading change per millisecond, 2^-64 turn (two's complement: negative turns left).
    turn_per_ms: u64,
    /// Until this time (ms) the turn has not reached half a circle: the chord is computed
    /// from the time, which keeps its precision however slow the turn.
    first_half_turn_ms: u64,
    /// sin and cos of the bank angle φ and of φ/2, Q30.
    bank_sin_cos: (i32, i32),
    half_bank_sin_cos: (i32, i32),
    /// The Earth field, NED.
    field: Fixed3,
    /// Magnetic declination, angle units.
    declination: u32,
    /// Airspeed and the wind's north and east components, one fixed-point scale.
    speeds: Fixed3,
    /// Degrees of latitude and longitude units (below) per Q30 unit of `sin α · cos` / `sin`
    /// of the chord's direction, times the time in ms (before the first half turn) or times
    /// `α` in quarter turns (after it).
    chord_by_time: [f32; 2],
    chord_by_angle: [f32; 2],
    /// Degrees of latitude per ms of drift (the wind; and the airspeed when the wings are
    /// level).
    lat_drift_deg_per_ms: f64,
    /// The start longitude and the longitude's drift per ms in 2^-64 turn: the sum wraps
    /// into [-180°, 180°) by itself, in integers (two `f64` additions and a multiplication
    /// are about 400 Cortex-M3 instructions).
    lon0: i64,
    lon_drift_per_ms: i64,
    /// The climb or descent, if [`FlightParams::climb_mps`] is not 0.
    climb: Option<Climb>,
}

/// What a climb (or descent) changes: the altitude moves with time until the edge of the
/// troposphere, and while it moves the nose is up (down) by the flight path angle
/// γ = asin(climb / V) (zero angle of attack). The turn rate stays ω = g·tan φ / V, and the
/// horizontal speed is V·cos γ throughout (levelling off keeps the ground path: a
/// simplification of 0.13 % at 2.5 m/s and 50 m/s).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
struct Climb {
    /// Altitude change per ms, m.
    m_per_ms: f32,
    /// When the altitude reaches the edge of the troposphere, ms (then it stays there).
    until_ms: u64,
    /// The pitch angle γ while climbing, rad.
    pitch_rad: f32,
    /// sin and cos of γ, Q30.
    pitch_sin_cos: (i32, i32),
    /// qy(γ) ⊗ qx(φ), the attitude before the yaw, Q30 (x, y, z, w).
    pitch_bank_q: [i32; 4],
    /// Body rates and specific force while climbing: (-ω·sin γ, ω·cos γ·sin φ, ω·cos γ·cos φ)
    /// and (g·sin γ, 0, -g·cos γ / cos φ).
    gyro: [f32; 3],
    accel: [f32; 3],
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
        let airspeed = params.airspeed_mps;
        let bank = turn::from_deg(f64::from(params.bank_deg));
        let bank_sin_cos = turn::sin_cos(bank);
        // sin φ = x · S with x = φ in quarter turns, taken from the degrees rather than the
        // angle units (1.5e-9 rad would be a 1e-5 relative error of a bank of 0.01°).
        let one = f64::from(turn::ONE);
        let (s, c) = turn::poly(bank as i32);
        let sin_bank = f64::from(params.bank_deg) / 90.0 * f64::from(s) / one;
        let cos_bank = f64::from(c) / one;
        let omega = G * ((sin_bank / cos_bank) as f32) / airspeed;
        let (sin_bank, cos_bank) = (sin_bank as f32, cos_bank as f32);
        let half_bank_sin_cos = turn::sin_cos(((bank as i32) >> 1) as u32);
        let climb = Self::build_climb(&params, omega, bank_sin_cos, half_bank_sin_cos);
        // The horizontal speed, V·cos γ (V when level).
        let v = match climb {
            Some(c) => airspeed * q30(c.pitch_sin_cos.1),
            None => airspeed,
        };
        let turn_per_ms = turn::from_f64(f64::from(omega) / (TAU_F64 * 1000.0), 64) as u64;
        let turning = turn_per_ms != 0;
        // Half a turn is 2^63 units; capped so that the time converts as a positive i64.
        let first_half_turn_ms = (1u64 << 63)
            .checked_div((turn_per_ms as i64).unsigned_abs())
            .map_or(1 << 62, |t| t.min(1 << 62));

        let (sin_from, cos_from) = turn::sin_cos(turn::from_deg(f64::from(params.wind_from_deg)));
        let w = params.wind_speed_mps;
        let wind_ne = [-w * q30(cos_from), -w * q30(sin_from)];
        let heading0 = turn::from_deg(f64::from(params.start_heading_deg));

        // Latitude and longitude per metre north and east (spherical Earth, the tangent
        // plane at the start point, as `geo::offset`).
        let deg_per_m = [
            1.0 / (geo::EARTH_RADIUS_M * DEG_F64),
            1.0 / (geo::EARTH_RADIUS_M * geo::lon_scale(params.start_lat_deg) * DEG_F64),
        ];
        // Per metre in the units the state sums: degrees of latitude, 2^-64 turn of longitude.
        let per_m = [deg_per_m[0], deg_per_m[1] * LON_UNITS_PER_DEG];
        let mut velocity_ne = [f64::from(wind_ne[0]), f64::from(wind_ne[1])];
        let (chord_by_time, chord_by_angle) = if turning {
            // Chord of the arc: 2·r·sin α along the mean heading, α = Δψ/2 = ω·t/2.
            // sin α = x · S (turn::poly) with x = α in quarter turns: before the first half
            // turn x = ω·t/π exactly, so 2·r·sin α = V·t·S / (π/2).
            let by_time = f64::from(v) / (1000.0 * core::f64::consts::FRAC_PI_2);
            let by_angle = 2.0 * f64::from(v) / f64::from(omega);
            (
                per_m.map(|k| (by_time * k) as f32),
                per_m.map(|k| (by_angle * k) as f32),
            )
        } else {
            // Wings level: a straight line at the airspeed, along the start heading.
            let (s, c) = turn::sin_cos(heading0);
            velocity_ne[0] += f64::from(v) * f64::from(q30(c));
            velocity_ne[1] += f64::from(v) * f64::from(q30(s));
            ([0.0; 2], [0.0; 2])
        };
        let field = params.earth_field;
        let field = Fixed3::new([field.north_gauss, field.east_gauss, field.down_gauss]);
        Flight {
            params,
            bank_rad: params.bank_deg * DEG,
            omega,
            static_mbar: atmosphere::pressure_pa(params.altitude_m) / 100.0,
            pitot_mbar: atmosphere::dynamic_pressure_pa(params.altitude_m, v) / 100.0,
            oat_c: atmosphere::temperature_k(params.altitude_m) - 273.15,
            wind_from_deg: turn::to_deg(turn::from_deg(f64::from(params.wind_from_deg))),
            // The turn rate about NED down, in body axes: (0, ω·sin φ, ω·cos φ).
            gyro: [0.0, omega * sin_bank, omega * cos_bank],
            // Centripetal V·ω = g·tan φ plus gravity, in body axes: (0, 0, -g / cos φ).
            accel: [0.0, 0.0, -G / cos_bank],
            heading0,
            heading0_sin_cos: turn::sin_cos(heading0),
            turn_per_ms,
            first_half_turn_ms,
            bank_sin_cos,
            half_bank_sin_cos,
            declination: field_declination(field),
            field,
            speeds: Fixed3::new([v, wind_ne[0], wind_ne[1]]),
            chord_by_time,
            chord_by_angle,
            lat_drift_deg_per_ms: velocity_ne[0] * per_m[0] / 1000.0,
            lon0: {
                let turns = params.start_lon_deg / 360.0; // [-0.5, 0.5]
                turn::from_f64(if turns >= 0.5 { turns - 1.0 } else { turns }, 64)
            },
            lon_drift_per_ms: turn::from_f64(velocity_ne[1] * per_m[1] / 1000.0, 0),
            climb,
        }
    }

    /// The constants of a climb (`None` when level), from the turn rate and the bank's (and
    /// half bank's) sine and cosine, Q30. In fixed point like the rest of the flight: the
    /// firmware links this code too.
    fn build_climb(
        params: &FlightParams,
        omega: f32,
        (sb, cb): (i32, i32),
        (sb2, cb2): (i32, i32),
    ) -> Option<Climb> {
        let rate = params.climb_mps;
        if rate == 0.0 || !cfg!(feature = "climb") {
            return None;
        }
        let v = params.airspeed_mps;
        // γ = atan2(climb, horizontal speed), in a scale where V is below 1.
        let along = libm::sqrtf(v * v - rate * rate);
        let speeds = Fixed3::new([rate, along, v]);
        let (gamma, _) = turn::atan2_hypot(speeds.q[0], speeds.q[1], speeds.frac_bits);
        let (sg, cg) = turn::sin_cos(gamma);
        let (sg2, cg2) = turn::sin_cos(((gamma as i32) >> 1) as u32);
        let edge = if rate > 0.0 {
            atmosphere::MAX_ALTITUDE_M
        } else {
            atmosphere::MIN_ALTITUDE_M
        };
        let until_s = (edge - params.altitude_m) / rate;
        let (fsg, fcg, fsb, fcb) = (q30(sg), q30(cg), q30(sb), q30(cb));
        Some(Climb {
            m_per_ms: rate / 1000.0,
            until_ms: (until_s * 1000.0) as u64,
            pitch_rad: turn::to_rad(gamma),
            pitch_sin_cos: (sg, cg),
            pitch_bank_q: [mul(cg2, sb2), mul(sg2, cb2), -mul(sg2, sb2), mul(cg2, cb2)],
            gyro: [-omega * fsg, omega * fcg * fsb, omega * fcg * fcb],
            accel: [G * fsg, 0.0, -G * fcg / fcb],
        })
    }

    /// The climb, if any: always `None` without the `climb` feature, so that none of its
    /// code is linked then.
    fn climb(&self) -> Option<Climb> {
        if cfg!(feature = "climb") {
            self.climb
        } else {
            None
        }
    }

    /// The altitude `t_ms` after the start, m: the start altitude plus the climb (feature
    /// `climb`), up to the edge of the troposphere.
    ///
    /// ```
    /// use flight_sim::{Flight, FlightParams};
    /// # if cfg!(feature = "climb") {
    /// let f = Flight::new(FlightParams { climb_mps: 2.5, ..FlightParams::DEFAULT })?;
    /// assert_eq!(f.altitude_m(10_000), 1025.0);
    /// assert_eq!(f.altitude_m(u64::MAX), 11_000.0); // the tropopause, then level
    /// # }
    /// # Ok::<(), flight_sim::Error>(())
    /// ```
    pub fn altitude_m(&self, t_ms: u64) -> f32 {
        match self.climb() {
            Some(c) if t_ms < c.until_ms => self.params.altitude_m + c.m_per_ms * t_ms as f32,
            Some(c) if c.m_per_ms > 0.0 => atmosphere::MAX_ALTITUDE_M,
            Some(_) => atmosphere::MIN_ALTITUDE_M,
            None => self.params.altitude_m,
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
            let v = match self.climb() {
                Some(c) => self.params.airspeed_mps * q30(c.pitch_sin_cos.1),
                None => self.params.airspeed_mps,
            };
            v / self.omega.abs()
        }
    }

    /// The state `t_ms` milliseconds after boot (t = 0 is the start point).
    ///
    /// The heading change since t = 0 is `t_ms` times a fixed fraction of a turn per
    /// millisecond, in integers that wrap at one turn: exact for any `t_ms`, no drift. The
    /// attitude, the magnetometer and the ground velocity are rotations by that heading in
    /// fixed point; the position is the chord of the arc plus the drift, in `f64` degrees.
    ///
    /// ```
    /// let f = flight_sim::Flight::new(Default::default())?;
    /// let s = f.state(1_000);
    /// assert_eq!(s.time_ms, 1_000.0);
    /// assert!((s.static_pressure_mbar - 898.75).abs() < 0.05);
    /// // One second of a 20° bank at 50 m/s: the heading has advanced by ω · 1 s.
    /// assert!((s.heading_deg - f.turn_rate_rad_s().to_degrees()).abs() < 1e-4);
    /// # Ok::<(), flight_sim::Error>(())
    /// ```
    pub fn state(&self, t_ms: u64) -> State {
        let p = &self.params;
        // Heading change Δψ since t = 0 in 2^-64 turn, in [-π, π).
        let turned = t_ms.wrapping_mul(self.turn_per_ms) as i64;
        let yaw = self.heading0.wrapping_add((turned >> 32) as u32);
        // The yaw's half angle (for the quaternion), and the yaw from it.
        let (sin_half_yaw, cos_half_yaw) = turn::sin_cos(yaw >> 1);
        let sin_yaw = 2 * mul(sin_half_yaw, cos_half_yaw);
        let cos_yaw = turn::dot(cos_half_yaw, cos_half_yaw, -sin_half_yaw, sin_half_yaw);

        // While climbing or descending, the nose is up (down) by γ.
        let climbing = self.climb().filter(|c| t_ms < c.until_ms);
        let [x, y, z, w] = self.attitude_q(climbing, sin_half_yaw, cos_half_yaw);

        let mag = self.field_in_body_axes(climbing, sin_yaw, cos_yaw);

        // The altitude and what the atmosphere makes of it.
        let altitude = self.altitude_m(t_ms);
        let (static_mbar, pitot_mbar, oat_c) = match self.climb() {
            None => (self.static_mbar, self.pitot_mbar, self.oat_c),
            Some(_) => (
                atmosphere::pressure_pa(altitude) / 100.0,
                atmosphere::dynamic_pressure_pa(altitude, p.airspeed_mps) / 100.0,
                atmosphere::temperature_k(altitude) - 273.15,
            ),
        };
        let (pitch, gyro, accel) = match climbing {
            None => (0.0, self.gyro, self.accel),
            Some(c) => (c.pitch_rad, c.gyro, c.accel),
        };

        let time_ms = t_ms as f64;
        let (lat, lon) = self.position(t_ms, turned);

        // Ground velocity = air velocity + wind.
        let [speed, wind_n, wind_e] = self.speeds.q;
        let (track, ground_speed) = turn::atan2_hypot(
            mul(speed, sin_yaw) + wind_e,
            mul(speed, cos_yaw) + wind_n,
            self.speeds.frac_bits,
        );

        State {
            time_ms,
            euler: Euler {
                roll: self.bank_rad,
                pitch,
                yaw: turn::to_rad(yaw),
            },
            quaternion: Quaternion { x, y, z, w },
            gyro_rad_s: gyro,
            accel_mps2: accel,
            mag_gauss: mag,
            static_pressure_mbar: static_mbar,
            pitot_pressure_mbar: pitot_mbar,
            airspeed_mps: p.airspeed_mps,
            oat_celsius: oat_c,
            latitude_deg: lat.clamp(-90.0, 90.0),
            // (lon >> 9) · 360 < 2^63: degrees · 2^55.
            longitude_deg: turn::to_f64((lon >> 9) * 360, 55),
            gps_altitude_m: altitude,
            ground_speed_mps: ground_speed,
            track_deg: turn::to_deg(track),
            heading_deg: turn::to_deg(yaw),
            magnetic_heading_deg: turn::to_deg(yaw.wrapping_sub(self.declination)),
            // -ay / az with ay = 0: the turn is exactly coordinated.
            slip_ball: 0.0,
            turn_rate_rad_s: self.omega,
            turn_coordinator: self.omega / STANDARD_RATE_RAD_S,
            wind_speed_mps: p.wind_speed_mps,
            wind_from_deg: self.wind_from_deg,
        }
    }

    /// The attitude quaternion at heading ψ (its half angle's sine and cosine): q = qz(ψ) ⊗
    /// qx(φ) in a level turn, qz(ψ) ⊗ (qy(γ) ⊗ qx(φ)) while climbing; w >= 0.
    #[inline(always)]
    fn attitude_q(
        &self,
        climbing: Option<Climb>,
        sin_half_yaw: i32,
        cos_half_yaw: i32,
    ) -> [f32; 4] {
        let sign = if cos_half_yaw < 0 { -1 } else { 1 };
        match climbing {
            // q = qz(ψ) ⊗ qx(φ) (pitch 0), w >= 0.
            None => {
                let (sr, cr) = self.half_bank_sin_cos;
                [
                    mul(sr, cos_half_yaw),
                    mul(sr, sin_half_yaw),
                    mul(cr, sin_half_yaw),
                    mul(cr, cos_half_yaw),
                ]
            }
            // q = qz(ψ) ⊗ (qy(γ) ⊗ qx(φ)).
            Some(c) => {
                let [px, py, pz, pw] = c.pitch_bank_q;
                [
                    turn::dot(cos_half_yaw, px, -sin_half_yaw, py),
                    turn::dot(cos_half_yaw, py, sin_half_yaw, px),
                    turn::dot(cos_half_yaw, pz, sin_half_yaw, pw),
                    turn::dot(cos_half_yaw, pw, -sin_half_yaw, pz),
                ]
            }
        }
        .map(|c| q30(sign * c))
    }

    /// The Earth field rotated into body axes at heading ψ: Rx(φ)ᵀ · Ry(γ)ᵀ · Rz(ψ)ᵀ · m.
    #[inline(always)]
    fn field_in_body_axes(&self, climbing: Option<Climb>, sin_yaw: i32, cos_yaw: i32) -> [f32; 3] {
        let [mn, me, md] = self.field.q;
        let (sb, cb) = self.bank_sin_cos;
        let heading_x = turn::dot(mn, cos_yaw, me, sin_yaw);
        let heading_y = turn::dot(me, cos_yaw, -mn, sin_yaw);
        let (pitched_x, pitched_z) = match climbing {
            None => (heading_x, md),
            Some(c) => {
                let (sg, cg) = c.pitch_sin_cos;
                (
                    turn::dot(cg, heading_x, -sg, md),
                    turn::dot(sg, heading_x, cg, md),
                )
            }
        };
        [
            pitched_x,
            turn::dot(cb, heading_y, sb, pitched_z),
            turn::dot(cb, pitched_z, -sb, heading_y),
        ]
        .map(|c| turn::to_f32(i64::from(c), self.field.frac_bits))
    }

    /// The position at `t_ms` (`turned`: the heading change since t = 0, 2^-64 turn): the chord
    /// of the arc, 2·r·sin α along the mean heading ψ0 + α, plus the drift. The latitude in
    /// degrees, the longitude in 2^-64 turn.
    #[inline(always)]
    fn position(&self, t_ms: u64, turned: i64) -> (f64, i64) {
        let p = &self.params;
        // α = Δψ/2 in quarter turns, Q30 (which is also angle units).
        let half = (turned >> 33) as i32;
        let (sinc, cos_half) = turn::poly(half);
        let sin_half = mul(half, sinc);
        let (sin_h0, cos_h0) = self.heading0_sin_cos;
        let sin_dir = turn::dot(sin_h0, cos_half, cos_h0, sin_half);
        let cos_dir = turn::dot(cos_h0, cos_half, -sin_h0, sin_half);
        let (along, k) = if t_ms < self.first_half_turn_ms {
            (turn::to_f32(t_ms as i64, 0), &self.chord_by_time)
        } else {
            (turn::to_f32(turned, 63), &self.chord_by_angle)
        };
        let north_deg = along * k[0] * q30(mul(sinc, cos_dir));
        let east = (along * k[1] * q30(mul(sinc, sin_dir))) as i64; // 2^-64 turn, saturating
        let lat = p.start_lat_deg + f64::from(north_deg) + t_ms as f64 * self.lat_drift_deg_per_ms;
        let lon = self
            .lon0
            .wrapping_add(t_ms.wrapping_mul(self.lon_drift_per_ms as u64) as i64)
            .wrapping_add(east);
        (lat, lon)
    }
}

/// A Q30 value as `f32`.
fn q30(v: i32) -> f32 {
    turn::to_f32(i64::from(v), 30)
}

/// The declination of a field (its horizontal direction east of north), angle units.
fn field_declination(field: Fixed3) -> u32 {
    turn::atan2_hypot(field.q[1], field.q[0], field.frac_bits).0
}
