//! What the page shows: [`Cockpit`] keeps the telemetry model ([`View`], as `watch` shows it) plus the two things a
//! picture needs and a table does not (the GPS ground track of the last minutes, and the
//! recent intervals of every message type for the jitter sparklines), and turns it into one
//! [`State`], serialised once per display frame for every client and for `GET /api/state`.

use std::collections::{BTreeMap, VecDeque};
use std::time::{Duration, Instant};

use aeolus_proto::Decoder;
use aeolus_proto::message::{
    AeolusInfo, Attitude, CalibrationStatus, Compass, Gps, Message, Pressure,
};
use serde::Serialize;

use crate::air_data::AirData;
use crate::decoders::AEOLUS_CAPACITY;
use crate::telemetry::{EVENTS, NO_DATA_AFTER, View};
use crate::units::{UnitScales, Units};

/// How many track points the page keeps: five minutes at [`TRACK_STEP_MS`].
pub(crate) const TRACK_POINTS: usize = 600;
/// The box time between two track points (GPS fixes closer together are skipped).
pub(crate) const TRACK_STEP_MS: f64 = 500.0;
/// How many recent intervals of each message type the jitter sparkline shows.
pub(crate) const JITTER_INTERVALS: usize = 48;

/// The live model behind the page: the telemetry model ([`View`]), the decoder that feeds it, the
/// ground track and the recent intervals. Every part is bounded.
pub struct Cockpit {
    view: View,
    decoder: Box<Decoder<AEOLUS_CAPACITY>>,
    source: String,
    started: Instant,
    track: VecDeque<[f64; 2]>,
    last_track_ms: Option<f64>,
    intervals: BTreeMap<u8, Intervals>,
}

/// The recent intervals of one message type, ms (box clock when the message has a
/// timestamp, host clock otherwise).
#[derive(Debug, Default)]
struct Intervals {
    last_box_ms: Option<f64>,
    last_host: Option<Instant>,
    recent: VecDeque<f32>,
}

impl Intervals {
    fn take(&mut self, box_ms: Option<f64>, now: Instant) {
        let step = match (box_ms, self.last_box_ms, self.last_host) {
            (Some(t), Some(prev), _) if t > prev => Some(t - prev),
            // A box clock that stepped back (a reboot) starts again.
            (Some(_), Some(_), _) => None,
            (None, _, Some(prev)) => Some(now.duration_since(prev).as_secs_f64() * 1000.0),
            _ => None,
        };
        if let Some(ms) = step {
            if self.recent.len() == JITTER_INTERVALS {
                self.recent.pop_front();
            }
            self.recent.push_back(ms as f32);
        }
        self.last_box_ms = box_ms;
        self.last_host = Some(now);
    }

    fn mean_ms(&self) -> Option<f64> {
        let n = self.recent.len();
        (n > 0).then(|| self.recent.iter().map(|&v| f64::from(v)).sum::<f64>() / n as f64)
    }
}

impl Cockpit {
    /// An empty cockpit for telemetry from `source` (the endpoint's name, shown on the page).
    pub fn new(source: &str, now: Instant) -> Self {
        Cockpit {
            view: View::default(),
            decoder: Box::new(Decoder::new()),
            source: source.to_owned(),
            started: now,
            track: VecDeque::with_capacity(TRACK_POINTS),
            last_track_ms: None,
            intervals: BTreeMap::new(),
        }
    }

    /// The same cockpit showing `units` on the page (SI unless told).
    pub(crate) fn with_units(mut self, units: Units) -> Self {
        self.view.units = units;
        self
    }

    /// Takes one read of the endpoint (a whole datagram when `datagram`).
    pub fn feed(&mut self, bytes: &[u8], datagram: bool, now: Instant) {
        let Cockpit {
            view,
            decoder,
            track,
            last_track_ms,
            intervals,
            ..
        } = self;
        view.feed(decoder, bytes, datagram, now, |m| {
            intervals
                .entry(m.id())
                .or_default()
                .take(m.timestamp_ms(), now);
            if let Message::Gps(g) = m
                && g.has_fix
                && g.latitude_deg.is_finite()
                && g.longitude_deg.is_finite()
            {
                let due = match *last_track_ms {
                    Some(prev) => !(g.timestamp_ms > prev && g.timestamp_ms < prev + TRACK_STEP_MS),
                    None => true,
                };
                if due {
                    if track.len() == TRACK_POINTS {
                        track.pop_front();
                    }
                    track.push_back([f64::from(g.latitude_deg), f64::from(g.longitude_deg)]);
                    *last_track_ms = Some(g.timestamp_ms);
                }
            }
        });
    }

    /// The state as the page and `/api/state` see it at `now`; `server` is the server's
    /// counters.
    pub fn state(&self, now: Instant, server: ServerState) -> State {
        let v = &self.view;
        let elapsed = now.saturating_duration_since(self.started);
        let no_data = (v.bytes == 0 && elapsed >= NO_DATA_AFTER).then(|| {
            format!(
                "nothing from {} for {:.1} s: is it the right port, is the box running, or does \
                 another client hold the QEMU socket (QEMU serves one client per UART)?",
                self.source,
                elapsed.as_secs_f64()
            )
        });
        State {
            source: self.source.clone(),
            uptime_s: elapsed.as_secs_f64(),
            bytes: v.bytes,
            no_data,
            attitude: v.attitude.map(attitude_state),
            air: v.pressure.map(|p| air_state(p, v.air.at(now))),
            heading: v.compass.map(heading_state),
            gps: v.gps.map(gps_state),
            wind: v.wind.map(|w| WindState {
                valid: w.valid,
                speed_mps: w.speed_mps,
                direction_deg: w.direction_deg,
            }),
            temp_c: v.temp.map(|t| t.celsius),
            info: v.info.map(info_state),
            toast: v.toast.clone(),
            types: self.types(now),
            errors: error_state(&self.decoder.stats(), v),
            track: self.track.iter().copied().collect(),
            server,
            units: v.units.scales(),
        }
    }

    /// Every message type seen, with its rate, intervals and state at `now`.
    fn types(&self, now: Instant) -> Vec<TypeState> {
        self.view
            .types
            .iter()
            .map(|(&id, (name, a))| {
                let recent = self.intervals.get(&id);
                let periodic = !EVENTS.contains(&id);
                let stale = a.stale(now).filter(|_| periodic);
                TypeState {
                    id,
                    name,
                    count: a.count,
                    rate_hz: recent
                        .and_then(Intervals::mean_ms)
                        .filter(|ms| *ms > 0.0)
                        .map(|ms| 1000.0 / ms),
                    interval_box_ms: a.box_interval_ms(),
                    interval_host_ms: a.host_interval_ms(),
                    intervals_ms: recent.map(|r| r.recent.iter().copied().collect()),
                    periodic,
                    stale: stale.is_some(),
                    age_s: now.saturating_duration_since(a.last_host).as_secs_f64(),
                }
            })
            .collect()
    }

    /// How long ago the cockpit started.
    pub(crate) fn uptime(&self, now: Instant) -> Duration {
        now.saturating_duration_since(self.started)
    }
}

fn attitude_state(a: Attitude) -> AttitudeState {
    AttitudeState {
        valid: a.valid,
        timestamp_ms: a.timestamp_ms,
        roll_deg: a.roll_rad.to_degrees(),
        pitch_deg: a.pitch_rad.to_degrees(),
        yaw_deg: a.yaw_rad.to_degrees(),
        slip_ball: a.slip_ball,
        turn_coordinator: a.turn_coordinator,
    }
}

fn air_state(p: Pressure, air: AirData) -> AirState {
    AirState {
        valid: p.valid,
        timestamp_ms: p.timestamp_ms,
        ias_mps: air.ias_mps,
        tas_mps: air.tas_mps,
        static_mbar: p.static_mbar,
        pitot_mbar: p.pitot_mbar,
        pressure_altitude_m: air.pressure_altitude_m,
        vertical_speed_mps: air.vertical_speed_mps,
    }
}

fn heading_state(c: Compass) -> HeadingState {
    HeadingState {
        valid: c.valid && c.has_value,
        timestamp_ms: c.timestamp_ms,
        heading_deg: c.heading_deg,
        calibration: calibration(c.calibration),
    }
}

fn gps_state(g: Gps) -> GpsState {
    GpsState {
        valid: g.valid,
        fix: g.has_fix,
        satellites: g.satellites,
        timestamp_ms: g.timestamp_ms,
        latitude_deg: f64::from(g.latitude_deg),
        longitude_deg: f64::from(g.longitude_deg),
        altitude_m: g.altitude_m,
        ground_speed_mps: g.ground_speed_mps,
    }
}

fn info_state(i: AeolusInfo) -> InfoState {
    InfoState {
        model: match i.model {
            b'S' => "AEOLUS-SENSE".to_owned(),
            b'A' => "AEOLUS".to_owned(),
            m => format!("model {m}"),
        },
        firmware: format!("{}.{}.{}", i.firmware[0], i.firmware[1], i.firmware[2]),
        mac: i
            .mac
            .iter()
            .map(|b| format!("{b:02x}"))
            .collect::<Vec<_>>()
            .join(":"),
    }
}

fn error_state(stats: &aeolus_proto::Stats, v: &View) -> ErrorState {
    ErrorState {
        checksum_errors: stats.checksum_errors,
        frames_no_crc: stats.frames_no_crc,
        overflows: stats.overflows,
        too_short: stats.too_short,
        bad_escapes: stats.bad_escapes,
        bytes_discarded: stats.bytes_discarded,
        malformed: v.malformed,
        truncated: v.truncated,
    }
}

fn calibration(c: CalibrationStatus) -> String {
    format!("{c:?}")
}

/// Everything the page draws, as one JSON object (`GET /api/state`, and each server-sent
/// event). Numbers that are not finite (a hostile frame can carry NaN) become `null`.
#[derive(Debug, Clone, Serialize)]
pub struct State {
    /// The endpoint, as named on the command line.
    pub(crate) source: String,
    /// Seconds since `protolink web` started.
    pub(crate) uptime_s: f64,
    /// Bytes read from the endpoint.
    pub(crate) bytes: u64,
    /// Set when nothing at all has arrived for [`NO_DATA_AFTER`]: the sentence to show.
    pub(crate) no_data: Option<String>,
    /// The last ATTITUDE.
    pub(crate) attitude: Option<AttitudeState>,
    /// The last PRESSURE, with its ISA pressure altitude.
    pub(crate) air: Option<AirState>,
    /// The last COMPASS.
    pub(crate) heading: Option<HeadingState>,
    /// The last GPS.
    pub(crate) gps: Option<GpsState>,
    /// The last WIND.
    pub(crate) wind: Option<WindState>,
    /// The last TEMP, °C.
    pub(crate) temp_c: Option<f32>,
    /// The box's identity (AEOLUSINFO).
    pub(crate) info: Option<InfoState>,
    /// The last TOAST's text.
    pub(crate) toast: Option<String>,
    /// Every message type seen, by ID.
    pub(crate) types: Vec<TypeState>,
    /// The decoder's error counters.
    pub(crate) errors: ErrorState,
    /// The ground track, oldest first: `[latitude, longitude]` in degrees.
    pub(crate) track: Vec<[f64; 2]>,
    /// The web server's own counters.
    pub(crate) server: ServerState,
    /// The units the page shows, and the factors from the SI values above.
    pub(crate) units: UnitScales,
}

/// The last ATTITUDE, in degrees.
#[derive(Debug, Clone, Copy, Serialize)]
#[allow(missing_docs)]
pub(crate) struct AttitudeState {
    pub(crate) valid: bool,
    pub(crate) timestamp_ms: f64,
    pub(crate) roll_deg: f32,
    pub(crate) pitch_deg: f32,
    pub(crate) yaw_deg: f32,
    pub(crate) slip_ball: f32,
    pub(crate) turn_coordinator: f32,
}

/// The last PRESSURE as the box sent it, and the air data ([`crate::air_data`]) at the
/// moment of the state: `null` where stale or invalid.
#[derive(Debug, Clone, Copy, Serialize)]
#[allow(missing_docs)]
pub(crate) struct AirState {
    pub(crate) valid: bool,
    pub(crate) timestamp_ms: f64,
    /// Indicated airspeed from the pitot's dynamic pressure, m/s.
    pub(crate) ias_mps: Option<f64>,
    /// True airspeed from the dynamic pressure and the air density (static pressure, TEMP),
    /// m/s.
    pub(crate) tas_mps: Option<f64>,
    pub(crate) static_mbar: f32,
    pub(crate) pitot_mbar: f32,
    /// The ISA altitude of the static pressure, m.
    pub(crate) pressure_altitude_m: Option<f64>,
    /// The vertical speed: the pressure altitude's change over the last second of the box's
    /// clock, m/s, positive up (`null` until half a second of PRESSURE has arrived).
    pub(crate) vertical_speed_mps: Option<f64>,
}

/// The last COMPASS.
#[derive(Debug, Clone, Serialize)]
#[allow(missing_docs)]
pub(crate) struct HeadingState {
    /// Valid and carrying a value.
    pub(crate) valid: bool,
    pub(crate) timestamp_ms: f64,
    pub(crate) heading_deg: f32,
    pub(crate) calibration: String,
}

/// The last GPS.
#[derive(Debug, Clone, Copy, Serialize)]
#[allow(missing_docs)]
pub(crate) struct GpsState {
    pub(crate) valid: bool,
    pub(crate) fix: bool,
    pub(crate) satellites: u8,
    pub(crate) timestamp_ms: f64,
    pub(crate) latitude_deg: f64,
    pub(crate) longitude_deg: f64,
    pub(crate) altitude_m: f32,
    pub(crate) ground_speed_mps: f32,
}

/// The last WIND: where it blows from, and how fast.
#[derive(Debug, Clone, Copy, Serialize)]
#[allow(missing_docs)]
pub(crate) struct WindState {
    pub(crate) valid: bool,
    pub(crate) speed_mps: f32,
    pub(crate) direction_deg: f32,
}

/// The box's identity.
#[derive(Debug, Clone, Serialize)]
#[allow(missing_docs)]
pub(crate) struct InfoState {
    pub(crate) model: String,
    pub(crate) firmware: String,
    pub(crate) mac: String,
}

/// One message type's arrivals.
#[derive(Debug, Clone, Serialize)]
pub(crate) struct TypeState {
    /// The message ID.
    pub(crate) id: u8,
    /// The message name.
    pub(crate) name: &'static str,
    /// Messages received.
    pub(crate) count: u64,
    /// The rate over the recent intervals, Hz.
    pub(crate) rate_hz: Option<f64>,
    /// Mean interval on the box's clock since the start, ms.
    pub(crate) interval_box_ms: Option<f64>,
    /// Mean interval of arrival on the host since the start, ms.
    pub(crate) interval_host_ms: Option<f64>,
    /// The last [`JITTER_INTERVALS`] intervals, oldest first, ms.
    pub(crate) intervals_ms: Option<Vec<f32>>,
    /// Whether the box sends it on a schedule (telemetry), not as an event (TOAST, LOG,
    /// COMMAND, SETTIME): only a scheduled type can be stale.
    pub(crate) periodic: bool,
    /// A scheduled type that missed three intervals (`watch`'s rule).
    pub(crate) stale: bool,
    /// Seconds since the last one arrived.
    pub(crate) age_s: f64,
}

/// The decoder's error counters (`watch` shows the same).
#[derive(Debug, Clone, Copy, Serialize)]
#[allow(missing_docs)]
pub(crate) struct ErrorState {
    pub(crate) checksum_errors: u32,
    pub(crate) frames_no_crc: u32,
    pub(crate) overflows: u32,
    pub(crate) too_short: u32,
    pub(crate) bad_escapes: u32,
    pub(crate) bytes_discarded: u32,
    /// Frames with a good check whose content did not parse.
    pub(crate) malformed: u32,
    /// Datagrams that ended inside a frame.
    pub(crate) truncated: u32,
}

/// The web server's counters.
#[derive(Debug, Clone, Copy, Default, Serialize)]
pub struct ServerState {
    /// Live-update streams open now.
    pub(crate) clients: u64,
    /// Live-update streams closed to give their place to a newer one (of the same address, or
    /// of an address holding fewer).
    pub(crate) replaced: u64,
    /// Connections refused with 503 (too many clients, connections, or from one address).
    pub(crate) refused: u64,
    /// Requests answered with an error status (bad request, too large, unknown path, not GET).
    pub(crate) bad_requests: u64,
    /// Requests refused with 403 as made by another site's page.
    pub(crate) cross_site: u64,
    /// Connections closed while still sending their request head, to let a newer one in.
    pub(crate) evicted: u64,
    /// Snapshots sent on live-update streams.
    pub(crate) frames_sent: u64,
    /// Snapshots a slow client never got (it got a newer one instead).
    pub(crate) frames_dropped: u64,
}

#[cfg(test)]
mod tests {
    use super::*;
    use aeolus_proto::CrcMode;
    use aeolus_proto::message::Gps;

    fn gps(ms: f64, lat: f32) -> Vec<u8> {
        let mut buf = vec![0u8; 128];
        let n = Message::Gps(Gps {
            valid: true,
            has_fix: true,
            satellites: 9,
            timestamp_ms: ms,
            latitude_deg: lat,
            longitude_deg: 11.0,
            altitude_m: 1000.0,
            ground_speed_mps: 50.0,
        })
        .encode(&mut buf, CrcMode::Compute)
        .unwrap();
        buf.truncate(n);
        buf
    }

    #[test]
    fn the_track_is_thinned_and_bounded() {
        let t0 = Instant::now();
        let mut c = Cockpit::new("test", t0);
        // Ten fixes a second for twenty minutes: a point every 500 ms, the last 600 kept.
        for i in 0..12_000u32 {
            let ms = f64::from(i) * 100.0;
            c.feed(&gps(ms, 48.0 + i as f32 * 1e-5), false, t0);
        }
        let s = c.state(t0, ServerState::default());
        assert_eq!(s.track.len(), TRACK_POINTS);
        let types = &s.types[0];
        assert_eq!(types.name, "GPS");
        assert_eq!(types.intervals_ms.as_ref().unwrap().len(), JITTER_INTERVALS);
        assert!((types.rate_hz.unwrap() - 10.0).abs() < 1e-6);
    }

    #[test]
    fn garbage_and_nan_never_break_the_json() {
        let t0 = Instant::now();
        let mut c = Cockpit::new("test", t0);
        c.feed(&gps(0.0, f32::NAN), false, t0);
        c.feed(&[0x7E, 0x41, 0x00, 0x7E, 0x7D, 0x7D, 0x7E], true, t0);
        let json = serde_json::to_string(&c.state(t0, ServerState::default())).unwrap();
        let v: serde_json::Value = serde_json::from_str(&json).unwrap();
        assert!(v["gps"]["latitude_deg"].is_null(), "{v}");
        assert!(v["track"].as_array().unwrap().is_empty());
    }
}

/// The examples of this module's items, as tests (the items are crate-private, so rustdoc
/// does not run them).
#[cfg(test)]
#[allow(unused_imports, clippy::unnecessary_wraps)]
mod examples {
    use super::*;

    #[test]
    fn with_units_example() -> Result<(), Box<dyn std::error::Error>> {
        use crate::units::Units;
        let now = std::time::Instant::now();
        let c = Cockpit::new("udp:5001", now).with_units(Units::Aviation);
        assert_eq!(c.state(now, Default::default()).units.altitude.unit, "ft");
        Ok(())
    }
}
