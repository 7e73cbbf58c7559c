//! The state the three links share, and the record kept in flash.

use crate::store_policy::{StorePolicy, Verdict};
use core::cell::Cell;
use flight_sim::{Flight, FlightParams};
use serde::{Deserialize, Serialize};

/// AEOLUS telemetry intervals in ms (spec figure 1c), settable over AYDP.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Intervals {
    /// GYRO, ACCEL, MAGNET, ATTITUDE and COMPASS.
    pub imu_ms: u32,
    /// PRESSURE.
    pub pressure_ms: u32,
    /// GPS.
    pub gps_ms: u32,
    /// TEMP.
    pub temp_ms: u32,
    /// WIND.
    pub wind_ms: u32,
    /// AEOLUSINFO.
    pub info_ms: u32,
}

impl Intervals {
    /// The AEOLUS-SENSE intervals of the spec's figure 1c.
    pub const SPEC: Intervals = Intervals {
        imu_ms: 7,
        pressure_ms: 5,
        gps_ms: 92,
        temp_ms: 829,
        wind_ms: 1000,
        info_ms: 1000,
    };

    /// The intervals from an array in the order of the fields (the order of AYDP 0x0100 and of
    /// the stored record).
    ///
    /// ```
    /// use sensor_box::state::Intervals;
    /// assert_eq!(Intervals::from_array([7, 5, 92, 829, 1000, 1000]), Intervals::SPEC);
    /// ```
    pub const fn from_array(a: [u32; 6]) -> Self {
        let [imu_ms, pressure_ms, gps_ms, temp_ms, wind_ms, info_ms] = a;
        Intervals {
            imu_ms,
            pressure_ms,
            gps_ms,
            temp_ms,
            wind_ms,
            info_ms,
        }
    }

    /// The intervals as an array in the order of the fields ([`Intervals::from_array`]'s
    /// inverse).
    ///
    /// ```
    /// use sensor_box::state::Intervals;
    /// assert_eq!(Intervals::SPEC.to_array(), [7, 5, 92, 829, 1000, 1000]);
    /// ```
    pub const fn to_array(self) -> [u32; 6] {
        [
            self.imu_ms,
            self.pressure_ms,
            self.gps_ms,
            self.temp_ms,
            self.wind_ms,
            self.info_ms,
        ]
    }
}

/// The box's own settings (AYDP addresses in the README), persisted by "store configuration".
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Settings {
    /// AEOLUS telemetry intervals.
    pub intervals: Intervals,
    /// Simulated true airspeed, m/s.
    pub airspeed_mps: f32,
    /// Simulated bank angle, degrees (positive: right turn).
    pub bank_deg: f32,
    /// Simulated altitude, m.
    pub altitude_m: f32,
    /// Period of the AOK debug value stream, ms (0 = as fast as the link allows).
    pub aok_debug_period_ms: u32,
}

impl Default for Settings {
    fn default() -> Self {
        let f = FlightParams::DEFAULT;
        Settings {
            intervals: Intervals::SPEC,
            airspeed_mps: f.airspeed_mps,
            bank_deg: f.bank_deg,
            altitude_m: f.altitude_m,
            aok_debug_period_ms: 20,
        }
    }
}

impl Settings {
    /// The flight parameters these settings ask for.
    pub fn flight_params(&self) -> FlightParams {
        FlightParams {
            airspeed_mps: self.airspeed_mps,
            bank_deg: self.bank_deg,
            altitude_m: self.altitude_m,
            ..FlightParams::DEFAULT
        }
    }
}

/// Number of AOK parameters the box holds.
pub const AOK_PARAMS: usize = 32;
/// Number of AOK parameter sets in flash.
pub const AOK_SETS: usize = 5;
/// AOK waypoint slots in flash: 0..=30 (waypoints 1..=31) and 31 (mission POI).
pub const AOK_FLASH_WAYPOINTS: usize = 32;

/// One AOK waypoint as stored: raw longitude, latitude and the two action words (K8).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct StoredWaypoint {
    /// Longitude, raw i32.
    pub lon: i32,
    /// Latitude, raw i32.
    pub lat: i32,
    /// Action word 1.
    pub action1: u32,
    /// Action word 2.
    pub action2: u32,
}

/// What the AOK side keeps in flash.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AokFlash {
    /// The parameter sets (`63 04 NUM` saves the RAM parameters into set NUM).
    pub sets: [[i32; AOK_PARAMS]; AOK_SETS],
    /// The set loaded at boot (`63 05 NUM`).
    pub start_set: u8,
    /// Waypoints 1..=31 and the mission POI (`63 08` saves RAM to flash).
    pub waypoints: [StoredWaypoint; AOK_FLASH_WAYPOINTS],
}

impl Default for AokFlash {
    fn default() -> Self {
        AokFlash {
            sets: [[0; AOK_PARAMS]; AOK_SETS],
            start_set: 0,
            waypoints: [StoredWaypoint::default(); AOK_FLASH_WAYPOINTS],
        }
    }
}

/// The record kept in flash: a RAM mirror of what the flash holds after the last load or store.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Persisted {
    /// The box's settings.
    pub settings: Settings,
    /// The AOK parameter sets and waypoints.
    pub aok: AokFlash,
}

/// Requests the links make of the main loop.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Requests {
    /// Write [`Shared::persisted`] to flash.
    pub store: bool,
    /// Warm reset.
    pub reboot: bool,
}

/// Application-level counters (the protocol decoders keep their own). The store counters are
/// AYDP register 0x0310, in this order; `corrupt_items` is 0x0311.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Counters {
    /// Stores that wrote an image.
    pub stores_written: u32,
    /// Stores skipped: the record was unchanged since the newest image.
    pub stores_unchanged: u32,
    /// Flash writes that failed.
    pub store_failures: u32,
    /// Store requests refused because the box is flying (any link).
    pub stores_refused_in_flight: u32,
    /// Store requests refused by the rate limit (any link).
    pub stores_rate_limited: u32,
    /// Setting groups whose newest copy in flash did not verify at boot, loaded from an
    /// older copy instead ([`persist::Boot::corrupt_items`](crate::persist::Boot)).
    pub corrupt_items: u32,
}

impl Counters {
    /// Counts a store's outcome: written, unchanged or failed (every board's store counts it
    /// here, blocking or awaited).
    ///
    /// ```
    /// use sensor_box::persist::{StoreError, Stored};
    /// let mut c = sensor_box::state::Counters::default();
    /// c.count_store(&Ok(Stored::Unchanged));
    /// c.count_store(&Ok(Stored::Written(2)));
    /// c.count_store(&Err(StoreError::Verify));
    /// assert_eq!((c.stores_unchanged, c.stores_written, c.store_failures), (1, 1, 1));
    /// ```
    pub fn count_store(
        &mut self,
        outcome: &Result<crate::persist::Stored, crate::persist::StoreError>,
    ) {
        let counter = match outcome {
            Ok(crate::persist::Stored::Unchanged) => &mut self.stores_unchanged,
            Ok(_) => &mut self.stores_written,
            Err(_) => &mut self.store_failures,
        };
        *counter = counter.wrapping_add(1);
    }
}

/// Number of direct-output channels the box exposes (AYDP direct output control).
pub const OUTPUTS: usize = 8;

/// One direct output: the (device, channel) it answers to and its current value.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Output {
    /// AYDP output device.
    pub device: u8,
    /// AYDP output channel.
    pub channel: u8,
    /// Calibrated output value last set.
    pub value: f32,
}

/// The state the links share.
pub struct Shared {
    /// The flash record as last loaded or stored; the settings in it are live.
    pub persisted: Persisted,
    /// The simulated flight built from the settings. Replace it through
    /// [`Shared::settings_changed`] (or call it after writing this and `flight_epoch_ms`):
    /// [`Shared::flight_state`] keeps its last state until then.
    pub flight: Flight,
    /// When the flight started (ms since boot).
    pub flight_epoch_ms: u64,
    /// Telemetry paused by the AEOLUS command "a pause".
    pub paused: bool,
    /// Wall-clock time from the last SETTIME, and when it arrived (ms since boot).
    pub wall_clock: Option<(aeolus_proto::message::SetTime, u64)>,
    /// AYDP address 0x0000: direct output control enabled.
    pub direct_control: bool,
    /// The direct outputs (device 1, channels 0..OUTPUTS).
    pub outputs: [Output; OUTPUTS],
    /// Requests to the main loop.
    pub requests: Requests,
    /// Counters.
    pub counters: Counters,
    /// When a store may be asked for ([`Shared::request_store`]).
    pub store_policy: StorePolicy,
    /// The last state [`Shared::flight_state`] computed and the time it is for (the flight's
    /// epoch and the time since it): the links ask for the same millisecond (AEOLUS telemetry
    /// and AOK debug frames fall on the same millisecond on their grids), and one state costs
    /// about 3 100 instructions on a Cortex-M3 without an FPU. Cleared when the flight
    /// changes. The key apart from the state, so that a look at it does not copy the state
    /// (about 130 instructions on a Cortex-M3).
    flight_at: Cell<Option<(u64, u64)>>,
    /// The state [`Shared::flight_at`] is for (the boot flight's first state before that).
    flight_last: Cell<flight_sim::State>,
}

impl Shared {
    /// The shared state after boot.
    pub fn new(persisted: Persisted, now_ms: u64) -> Self {
        let flight = build_flight(&persisted.settings);
        let first = flight.state(0);
        let mut outputs = [Output::default(); OUTPUTS];
        for (i, o) in outputs.iter_mut().enumerate() {
            o.device = 1;
            o.channel = i as u8;
        }
        Shared {
            persisted,
            flight,
            flight_epoch_ms: now_ms,
            paused: false,
            wall_clock: None,
            direct_control: false,
            outputs,
            requests: Requests::default(),
            flight_at: Cell::new(None),
            flight_last: Cell::new(first),
            counters: Counters::default(),
            store_policy: StorePolicy::new(),
        }
    }

    /// A link asks for the record to be stored at `now_ms`: the [store
    /// policy](crate::store_policy) decides, and an accepted request is set for the main loop
    /// ([`Requests::store`]); a refusal is counted and logged, and the link answers it. Change
    /// the record only when this says [`Verdict::Accepted`].
    ///
    /// ```
    /// use sensor_box::store_policy::Verdict;
    /// use sensor_box::{Persisted, Shared};
    /// let mut shared = Shared::new(Persisted::default(), 0);
    /// assert_eq!(shared.request_store(0, true), Verdict::InFlight);
    /// assert_eq!(shared.counters.stores_refused_in_flight, 1);
    /// assert!(!shared.requests.store);
    /// assert_eq!(shared.request_store(0, false), Verdict::Accepted);
    /// assert!(shared.requests.store);
    /// ```
    pub fn request_store(&mut self, now_ms: u64, flying: bool) -> Verdict {
        let verdict = self.store_policy.check(now_ms, flying);
        let c = &mut self.counters;
        match verdict {
            Verdict::Accepted => self.requests.store = true,
            Verdict::InFlight => {
                crate::warn!("flash store refused: flying");
                c.stores_refused_in_flight = c.stores_refused_in_flight.wrapping_add(1);
            }
            Verdict::TooSoon => {
                crate::warn!("flash store refused: rate limit");
                c.stores_rate_limited = c.stores_rate_limited.wrapping_add(1);
            }
        }
        verdict
    }

    /// The live settings.
    pub fn settings(&self) -> &Settings {
        &self.persisted.settings
    }

    /// Rebuilds the simulated flight after the settings changed (invalid parameters keep the
    /// previous flight).
    pub fn settings_changed(&mut self, now_ms: u64) {
        if let Ok(f) = Flight::new(self.persisted.settings.flight_params()) {
            self.flight = f;
            self.flight_epoch_ms = now_ms;
            self.flight_at.set(None);
        } else {
            crate::warn!("settings: flight parameters out of range, flight unchanged");
        }
    }

    /// The simulated state at `now_ms`.
    ///
    /// The last state is kept: asking again for the same time of the same flight returns it
    /// without recomputing (the same value: the simulation is a pure function of both). A
    /// new flight (through [`Shared::settings_changed`]) or epoch is computed again.
    ///
    /// ```
    /// use sensor_box::{Persisted, Shared};
    /// let mut shared = Shared::new(Persisted::default(), 0);
    /// let a = shared.flight_state(1_000);
    /// assert_eq!(shared.flight_state(1_000), a);
    /// assert_eq!(a, shared.flight.state(1_000));
    /// shared.flight_epoch_ms = 500; // a new flight time: computed again
    /// assert_eq!(shared.flight_state(1_000), shared.flight.state(500));
    /// ```
    pub fn flight_state(&self, now_ms: u64) -> flight_sim::State {
        let epoch = self.flight_epoch_ms;
        let t = now_ms.saturating_sub(epoch);
        if self.flight_at.get() == Some((epoch, t)) {
            return self.flight_last.get();
        }
        let state =
            crate::budget::span(crate::budget::Category::FlightSim, || self.flight.state(t));
        self.flight_last.set(state);
        self.flight_at.set(Some((epoch, t)));
        state
    }
    /// A state of the current flight for the values that do not change with its time
    /// (pressures, airspeed, temperature, wind: see
    /// [`Kind::moves_with_time`](crate::telemetry::Kind::moves_with_time)): the last state
    /// computed for this flight, whatever its time, or the state at `now_ms` if there is none.
    /// PRESSURE alone is due 200 times a second, and a state costs about 3 100 instructions
    /// on a Cortex-M3 without an FPU.
    ///
    /// ```
    /// use sensor_box::{Persisted, Shared};
    /// let shared = Shared::new(Persisted::default(), 0);
    /// let moving = shared.flight_state(1_000);
    /// let steady = shared.steady_state(1_005); // the state of 1 000 ms, not recomputed
    /// assert_eq!(steady, moving);
    /// assert_eq!(steady.static_pressure_mbar, shared.flight.state(1_005).static_pressure_mbar);
    /// ```
    pub fn steady_state(&self, now_ms: u64) -> flight_sim::State {
        match self.flight_at.get() {
            Some((at_epoch, _)) if at_epoch == self.flight_epoch_ms => self.flight_last.get(),
            _ => self.flight_state(now_ms),
        }
    }
}

fn build_flight(settings: &Settings) -> Flight {
    Flight::new(settings.flight_params()).unwrap_or_default()
}
