//! Which AEOLUS messages are due when, built from the simulated flight.
//!
//! Two independent pieces, both pure (no I/O, no clock, no allocation), so the firmware and the
//! host tool (`protolink sim`, which sends the same messages over UDP) share them:
//!
//! * [`Telemetry`]: the schedule. [`Telemetry::due`] says which [`Kind`]s are due at `now_ms`
//!   for the [`Intervals`] in the settings (spec figure 1c by default).
//! * [`build`]: one AEOLUS [`Message`] of a [`Kind`] from a [`flight_sim::State`].
//!
//! ```
//! use sensor_box::state::Intervals;
//! use sensor_box::telemetry::{Kind, Telemetry, build};
//! use aeolus_proto::{CrcMode, message::Message};
//!
//! let flight = flight_sim::Flight::default();
//! let mut telemetry = Telemetry::new(0);
//! let mut wire = [0u8; 256];
//! let mut sent = 0;
//! for now_ms in 0..1_000u64 {
//!     let state = flight.state(now_ms);
//!     for kind in telemetry.due(now_ms, &Intervals::SPEC) {
//!         let msg = build(kind, &state, now_ms);
//!         let n = msg.encode(&mut wire, CrcMode::Compute).unwrap();
//!         // ... hand wire[..n] to the UART or the UDP socket
//!         # let _ = n;
//!         sent += 1;
//!     }
//! }
//! // One second: 143 of each 7 ms type, 200 PRESSURE, 11 GPS, 2 TEMP (0 and 829 ms),
//! // one WIND and one AEOLUSINFO.
//! assert_eq!(sent, 5 * 143 + 200 + 11 + 2 + 1 + 1);
//! ```
//!
//! # Schedule rules
//!
//! * **No drift.** Each kind has a next-due instant; when it is sent the next one is the
//!   previous due instant plus the interval, not `now_ms` plus the interval, so late polls do
//!   not stretch the period.
//! * **Bounded catch-up.** A kind is yielded at most once per [`Telemetry::due`] call (all the
//!   messages of one call carry the same timestamp, so sending more would only repeat data),
//!   and at most [`Telemetry::MAX_LATE`] due instants are kept: after a stall the older ones
//!   are dropped and counted ([`Telemetry::skipped`]) instead of going out as a burst. The
//!   phase is kept: due instants stay on the grid `start + k * interval`.
//! * **Interval 0 turns a kind off**; a shortened interval takes effect at once.
//! * Callers poll at least as often as the shortest interval (the firmware polls every
//!   millisecond); a slower caller gets lower rates, never bursts.

use super::state::Intervals;
use aeolus_proto::message::{
    Accel, AeolusInfo, Attitude, CalibrationStatus, Compass, Gps, Gyro, Magnet, Message, Pressure,
    Temp, Wind,
};
use flight_sim::State;

/// The periodic AEOLUS messages the box sends (the AEOLUS-SENSE set).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(all(feature = "defmt", target_os = "none"), derive(defmt::Format))]
pub enum Kind {
    /// GYRO (62).
    Gyro,
    /// ACCEL (63).
    Accel,
    /// MAGNET (64).
    Magnet,
    /// ATTITUDE (71).
    Attitude,
    /// COMPASS (72).
    Compass,
    /// PRESSURE (61).
    Pressure,
    /// GPS (66).
    Gps,
    /// TEMP (65).
    Temp,
    /// WIND (73).
    Wind,
    /// AEOLUSINFO (51).
    AeolusInfo,
}

impl Kind {
    /// Number of kinds.
    pub const COUNT: usize = 10;

    /// Every kind, in the order [`Telemetry::due`] yields them.
    pub const ALL: [Kind; Kind::COUNT] = [
        Kind::Gyro,
        Kind::Accel,
        Kind::Magnet,
        Kind::Attitude,
        Kind::Compass,
        Kind::Pressure,
        Kind::Gps,
        Kind::Temp,
        Kind::Wind,
        Kind::AeolusInfo,
    ];

    /// The kind's position in [`Kind::ALL`] (for per-kind arrays).
    ///
    /// ```
    /// use sensor_box::telemetry::Kind;
    /// assert_eq!(Kind::ALL[Kind::Gps.index()], Kind::Gps);
    /// ```
    pub const fn index(self) -> usize {
        self as usize
    }

    /// The AEOLUS message ID.
    ///
    /// ```
    /// use sensor_box::telemetry::Kind;
    /// assert_eq!(Kind::Compass.id(), 72);
    /// ```
    pub const fn id(self) -> u8 {
        match self {
            Kind::Gyro => Gyro::ID,
            Kind::Accel => Accel::ID,
            Kind::Magnet => Magnet::ID,
            Kind::Attitude => Attitude::ID,
            Kind::Compass => Compass::ID,
            Kind::Pressure => Pressure::ID,
            Kind::Gps => Gps::ID,
            Kind::Temp => Temp::ID,
            Kind::Wind => Wind::ID,
            Kind::AeolusInfo => AeolusInfo::ID,
        }
    }

    /// The kind of a message ID, if it is one the box sends periodically.
    ///
    /// ```
    /// use sensor_box::telemetry::Kind;
    /// assert_eq!(Kind::from_id(61), Some(Kind::Pressure));
    /// assert_eq!(Kind::from_id(82), None); // TOAST is not periodic
    /// ```
    pub const fn from_id(id: u8) -> Option<Kind> {
        let mut i = 0;
        while i < Kind::COUNT {
            if Kind::ALL[i].id() == id {
                return Some(Kind::ALL[i]);
            }
            i += 1;
        }
        None
    }

    /// The spec's name of the message.
    ///
    /// ```
    /// use sensor_box::telemetry::Kind;
    /// assert_eq!(Kind::AeolusInfo.name(), "AEOLUSINFO");
    /// ```
    pub const fn name(self) -> &'static str {
        match self {
            Kind::Gyro => "GYRO",
            Kind::Accel => "ACCEL",
            Kind::Magnet => "MAGNET",
            Kind::Attitude => "ATTITUDE",
            Kind::Compass => "COMPASS",
            Kind::Pressure => "PRESSURE",
            Kind::Gps => "GPS",
            Kind::Temp => "TEMP",
            Kind::Wind => "WIND",
            Kind::AeolusInfo => "AEOLUSINFO",
        }
    }

    /// The data length of the message (the spec's table 6 size).
    ///
    /// ```
    /// use sensor_box::telemetry::Kind;
    /// assert_eq!(Kind::Attitude.data_len(), 52);
    /// ```
    pub const fn data_len(self) -> usize {
        match self {
            Kind::Gyro => Gyro::LEN,
            Kind::Accel => Accel::LEN,
            Kind::Magnet => Magnet::LEN,
            Kind::Attitude => Attitude::LEN,
            Kind::Compass => Compass::LEN,
            Kind::Pressure => Pressure::LEN,
            Kind::Gps => Gps::LEN,
            Kind::Temp => Temp::LEN,
            Kind::Wind => Wind::LEN,
            Kind::AeolusInfo => AeolusInfo::LEN,
        }
    }

    /// The kind's interval in `intervals`, ms (0 = off).
    ///
    /// ```
    /// use sensor_box::{state::Intervals, telemetry::Kind};
    /// assert_eq!(Kind::Temp.interval_ms(&Intervals::SPEC), 829);
    /// ```
    pub const fn interval_ms(self, intervals: &Intervals) -> u32 {
        match self {
            Kind::Gyro | Kind::Accel | Kind::Magnet | Kind::Attitude | Kind::Compass => {
                intervals.imu_ms
            }
            Kind::Pressure => intervals.pressure_ms,
            Kind::Gps => intervals.gps_ms,
            Kind::Temp => intervals.temp_ms,
            Kind::Wind => intervals.wind_ms,
            Kind::AeolusInfo => intervals.info_ms,
        }
    }
}

/// Unescaped bytes one frame of `data_len` data bytes takes on the wire: two flags, the ID
/// and the CRC around the data.
const fn frame_len(data_len: usize) -> u32 {
    (data_len + 5) as u32
}

/// The average byte rate the schedule produces, bytes per second, before escaping (random
/// float bytes add about 0.8 % of `7D` escapes on top).
///
/// ```
/// use sensor_box::{state::Intervals, telemetry::nominal_byte_rate};
/// // GYRO 37 + ACCEL 45 + MAGNET 37 + ATTITUDE 57 + COMPASS 85 bytes every 7 ms, ...
/// assert_eq!(nominal_byte_rate(&Intervals::SPEC), 45_207);
/// ```
pub const fn nominal_byte_rate(intervals: &Intervals) -> u32 {
    // In bytes per 1000 s, so the sum stays an integer until the end.
    let mut milli: u64 = 0;
    let mut i = 0;
    while i < Kind::COUNT {
        let kind = Kind::ALL[i];
        let per_1000_s = frame_len(kind.data_len()) as u64 * 1_000_000;
        if let Some(n) = per_1000_s.checked_div(kind.interval_ms(intervals) as u64) {
            milli += n;
        }
        i += 1;
    }
    ((milli + 500) / 1000) as u32
}

/// The next-due instant of a kind whose interval is 0.
const OFF: u64 = u64::MAX;

/// The telemetry schedule: when each [`Kind`] is next due.
///
/// ```
/// use sensor_box::{state::Intervals, telemetry::{Kind, Telemetry}};
///
/// let mut t = Telemetry::new(1_000);
/// // At boot everything is due once.
/// assert_eq!(t.due(1_000, &Intervals::SPEC).count(), Kind::COUNT);
/// assert_eq!(t.due(1_001, &Intervals::SPEC).count(), 0);
/// // 5 ms later: PRESSURE; 7 ms later: the five IMU messages.
/// assert_eq!(t.due(1_005, &Intervals::SPEC).collect::<Vec<_>>(), [Kind::Pressure]);
/// assert_eq!(t.due(1_007, &Intervals::SPEC).count(), 5);
/// assert_eq!(t.next_due_ms(Kind::Gps), 1_092);
/// ```
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Telemetry {
    next_ms: [u64; Kind::COUNT],
    skipped: u32,
}

impl Telemetry {
    /// Due instants kept per kind after a stall; older ones are dropped.
    pub const MAX_LATE: u64 = 2;

    /// A schedule starting at `now_ms`: every kind is due at once.
    pub const fn new(now_ms: u64) -> Self {
        Telemetry {
            next_ms: [now_ms; Kind::COUNT],
            skipped: 0,
        }
    }

    /// Starts the schedule over at `now_ms` (after a pause): every kind is due at once and
    /// nothing missed meanwhile is sent or counted.
    ///
    /// ```
    /// use sensor_box::{state::Intervals, telemetry::Telemetry};
    /// let mut t = Telemetry::new(0);
    /// t.restart(60_000);
    /// assert_eq!(t.due(60_000, &Intervals::SPEC).count(), 10);
    /// assert_eq!(t.skipped(), 0);
    /// ```
    pub fn restart(&mut self, now_ms: u64) {
        self.next_ms = [now_ms; Kind::COUNT];
    }

    /// When `kind` is next due, ms (`u64::MAX` while its interval is 0).
    pub fn next_due_ms(&self, kind: Kind) -> u64 {
        self.next_ms.get(kind.index()).copied().unwrap_or(u64::MAX)
    }

    /// Due instants dropped after stalls (wrapping).
    ///
    /// ```
    /// use sensor_box::{state::Intervals, telemetry::{Kind, Telemetry}};
    /// let mut t = Telemetry::new(0);
    /// let _ = t.due(0, &Intervals::SPEC).count();
    /// // A 50 ms stall: PRESSURE had 10 due instants (5, 10, ..., 50), keeps 2 and sends one.
    /// let late: Vec<Kind> = t.due(50, &Intervals::SPEC).collect();
    /// assert!(late.contains(&Kind::Pressure));
    /// assert_eq!(t.next_due_ms(Kind::Pressure), 50); // the second kept instant, sent next poll
    /// assert_eq!(t.skipped(), 8 + 5 * 5); // PRESSURE 8 of 10, each 7 ms kind 5 of 7
    /// ```
    pub const fn skipped(&self) -> u32 {
        self.skipped
    }

    /// The kinds due at `now_ms`, each at most once, in [`Kind::ALL`] order. Iterating
    /// consumes them (their next due instant moves on); kinds not reached because the iterator
    /// was dropped early stay due.
    pub fn due(&mut self, now_ms: u64, intervals: &Intervals) -> Due<'_> {
        Due {
            telemetry: self,
            now_ms,
            intervals: *intervals,
            index: 0,
        }
    }

    /// Whether `kind` is due at `now_ms`; if it is, moves its due instant on.
    fn take(&mut self, kind: Kind, now_ms: u64, interval_ms: u32) -> bool {
        let Some(next) = self.next_ms.get_mut(kind.index()) else {
            return false;
        };
        if interval_ms == 0 {
            *next = OFF;
            return false;
        }
        if *next == OFF {
            // Turned on again: due at once.
            *next = now_ms;
        }
        let interval = u64::from(interval_ms);
        let latest = now_ms.saturating_add(interval);
        if *next > latest {
            // The interval was shortened: do not wait out the old one.
            *next = latest;
        }
        if now_ms < *next {
            return false;
        }
        let due_instants = (now_ms - *next) / interval + 1;
        if due_instants > Self::MAX_LATE {
            let drop = due_instants - Self::MAX_LATE;
            *next = next.saturating_add(drop.saturating_mul(interval));
            self.skipped = self
                .skipped
                .wrapping_add(u32::try_from(drop).unwrap_or(u32::MAX));
        }
        *next = next.saturating_add(interval);
        true
    }
}

/// The iterator of [`Telemetry::due`].
pub struct Due<'a> {
    telemetry: &'a mut Telemetry,
    now_ms: u64,
    intervals: Intervals,
    index: usize,
}

impl Iterator for Due<'_> {
    type Item = Kind;

    fn next(&mut self) -> Option<Kind> {
        while let Some(&kind) = Kind::ALL.get(self.index) {
            self.index += 1;
            let interval = kind.interval_ms(&self.intervals);
            if self.telemetry.take(kind, self.now_ms, interval) {
                return Some(kind);
            }
        }
        None
    }
}

/// AEOLUSINFO model byte: 83 = `'S'`, AEOLUS-SENSE (DECISIONS.md A10).
pub const MODEL: u8 = b'S';

/// The firmware version sent in AEOLUSINFO: this crate's version, large/middle/small.
pub const FIRMWARE_VERSION: [u8; 3] = [
    parse_u8(env!("CARGO_PKG_VERSION_MAJOR")),
    parse_u8(env!("CARGO_PKG_VERSION_MINOR")),
    parse_u8(env!("CARGO_PKG_VERSION_PATCH")),
];

/// The MAC address sent in AEOLUSINFO: a fixed, locally administered unicast address (the
/// example has no WiFi adapter).
pub const MAC: [u8; 6] = [0x02, 0xAE, 0x01, 0x05, 0x00, 0x01];

/// GPS satellites reported in use.
pub const GPS_SATELLITES: u8 = 9;

/// A decimal `u8` at compile time (saturating; stops at the first non-digit).
const fn parse_u8(s: &str) -> u8 {
    let bytes = s.as_bytes();
    let mut value: u32 = 0;
    let mut i = 0;
    while i < bytes.len() {
        let d = bytes[i];
        if !d.is_ascii_digit() {
            break;
        }
        value = value * 10 + (d - b'0') as u32;
        if value > u8::MAX as u32 {
            return u8::MAX;
        }
        i += 1;
    }
    value as u8
}

/// The message of `kind` describing `state`, time-stamped `now_ms` (ms since boot).
///
/// The mapping, one sensor per message:
///
/// | message | from the state |
/// |---|---|
/// | GYRO, ACCEL, MAGNET | `gyro_rad_s`, `accel_mps2`, `mag_gauss` (body axes) |
/// | ATTITUDE | `euler` (rad), `slip_ball`, `turn_coordinator` (standard-rate units), `quaternion` |
/// | COMPASS | `magnetic_heading_deg`; calibration OK, 100 %; parameters of an ideal sensor |
/// | PRESSURE | `static_pressure_mbar`, `pitot_pressure_mbar` (dynamic pressure), `airspeed_mps` |
/// | GPS | fix with [`GPS_SATELLITES`], `latitude_deg`/`longitude_deg` (as f32), `gps_altitude_m`, `ground_speed_mps` |
/// | TEMP | `oat_celsius` |
/// | WIND | `wind_speed_mps`, `wind_from_deg` |
/// | AEOLUSINFO | [`MODEL`], [`FIRMWARE_VERSION`], [`MAC`] |
///
/// ```
/// use sensor_box::telemetry::{Kind, build};
/// use aeolus_proto::message::Message;
///
/// let state = flight_sim::Flight::default().state(2_000);
/// let Message::Pressure(p) = build(Kind::Pressure, &state, 2_000) else { unreachable!() };
/// assert_eq!(p.timestamp_ms, 2_000.0);
/// assert!((p.static_mbar - 898.75).abs() < 0.05); // ISA at 1000 m
/// ```
pub fn build(kind: Kind, state: &State, now_ms: u64) -> Message<'static> {
    let timestamp_ms = now_ms as f64;
    let [gx, gy, gz] = state.gyro_rad_s;
    let [ax, ay, az] = state.accel_mps2;
    let [mx, my, mz] = state.mag_gauss;
    match kind {
        Kind::Gyro => Message::Gyro(Gyro {
            valid: true,
            timestamp_ms,
            x: gx,
            y: gy,
            z: gz,
        }),
        Kind::Accel => Message::Accel(Accel {
            valid: true,
            timestamp_ms,
            x: ax,
            y: ay,
            z: az,
        }),
        Kind::Magnet => Message::Magnet(Magnet {
            valid: true,
            timestamp_ms,
            x: mx,
            y: my,
            z: mz,
        }),
        Kind::Attitude => Message::Attitude(Attitude {
            valid: true,
            timestamp_ms,
            roll_rad: state.euler.roll,
            pitch_rad: state.euler.pitch,
            yaw_rad: state.euler.yaw,
            slip_ball: state.slip_ball,
            turn_coordinator: state.turn_coordinator,
            qx: state.quaternion.x,
            qy: state.quaternion.y,
            qz: state.quaternion.z,
            qw: state.quaternion.w,
        }),
        Kind::Compass => Message::Compass(Compass {
            valid: true,
            calibration: CalibrationStatus::Ok,
            has_value: true,
            calibration_percent: 100,
            calibration_remaining: 0,
            timestamp_ms,
            heading_deg: state.magnetic_heading_deg,
            // An ideal sensor: no offsets (the 3-value group), unit matrix (the 9-value group).
            soft_iron: [0.0; 3],
            hard_iron: [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0],
        }),
        Kind::Pressure => Message::Pressure(Pressure {
            valid: true,
            timestamp_ms,
            static_mbar: state.static_pressure_mbar,
            pitot_mbar: state.pitot_pressure_mbar,
            airspeed_mps: state.airspeed_mps,
        }),
        Kind::Gps => Message::Gps(Gps {
            valid: true,
            has_fix: true,
            satellites: GPS_SATELLITES,
            timestamp_ms,
            latitude_deg: state.latitude_deg as f32,
            longitude_deg: state.longitude_deg as f32,
            altitude_m: state.gps_altitude_m,
            ground_speed_mps: state.ground_speed_mps,
        }),
        Kind::Temp => Message::Temp(Temp {
            valid: true,
            timestamp_ms,
            celsius: state.oat_celsius,
        }),
        Kind::Wind => Message::Wind(Wind {
            valid: true,
            timestamp_ms,
            speed_mps: state.wind_speed_mps,
            direction_deg: state.wind_from_deg,
        }),
        Kind::AeolusInfo => Message::AeolusInfo(AeolusInfo {
            model: MODEL,
            firmware: FIRMWARE_VERSION,
            mac: MAC,
        }),
    }
}
