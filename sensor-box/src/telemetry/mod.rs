//! Which AEOLUS messages are due when, built from the simulated flight.
//!
//! Two independent pieces, both pure (no I/O, no clock, no allocation), so the firmware and the
//! host tool (`protolink sim`, which sends the same messages over UDP) share them:
//!
//! * [`Telemetry`]: the schedule. [`Telemetry::due`] says which [`Kind`]s are due at `now_ms`
//!   for the [`Intervals`] in the settings (spec figure 1c by default).
//! * [`build`]: one AEOLUS [`Message`](aeolus_proto::message::Message) of a [`Kind`] from a
//!   [`flight_sim::State`].
//!
//! This file holds the [`Kind`]s (ids, names, lengths, intervals) and the byte rate they add
//! up to; `schedule.rs` is the schedule and `messages.rs` the message building.
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

mod messages;
mod schedule;

pub use messages::{FIRMWARE_VERSION, GPS_SATELLITES, MAC, MODEL, build, build_at};
pub use schedule::{Due, Telemetry};

use crate::state::Intervals;
use aeolus_proto::message::{
    Accel, AeolusInfo, Attitude, Compass, Gps, Gyro, Magnet, Pressure, Temp, Wind,
};

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

    /// Whether the message carries values that change with the flight's time (attitude,
    /// motion, heading, position). PRESSURE, TEMP, WIND and AEOLUSINFO carry only values
    /// that are constant over one simulated flight (a coordinated turn at constant altitude
    /// and airspeed in a steady wind), so they need no new flight state.
    ///
    /// ```
    /// use sensor_box::telemetry::Kind;
    /// assert!(Kind::Gyro.moves_with_time());
    /// assert!(!Kind::Pressure.moves_with_time());
    /// ```
    pub const fn moves_with_time(self) -> bool {
        matches!(
            self,
            Kind::Gyro | Kind::Accel | Kind::Magnet | Kind::Attitude | Kind::Compass | Kind::Gps
        )
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
