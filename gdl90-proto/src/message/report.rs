//! Ownship Report (ID 10) and Traffic Report (ID 20): one layout (ICD 3.4, 3.5).

use super::layout::report as f;
use super::scale::{div_round, round_f32, round_f64};
use super::{CallSign, check_len, emit_into};
use crate::{EncodeError, Error};

/// Degrees per latitude/longitude step: 180 / 2^23.
const DEG_PER_LSB: f64 = 180.0 / 8_388_608.0;
/// Degrees per track step: 360 / 256.
const TRACK_DEG_PER_LSB: f32 = 360.0 / 256.0;
/// Pressure altitude: raw 0 is -1000 ft, 25 ft per step, 0xFFF invalid.
const ALT_OFFSET_FT: i64 = 1000;
const ALT_STEP_FT: i64 = 25;
const ALT_INVALID: u64 = 0xFFF;
const SPEED_INVALID: u64 = 0xFFF;
const VRATE_INVALID: i64 = -0x800;
/// Vertical rate: 64 fpm per step, at most 510 steps (32640 fpm) either way; beyond is
/// reserved.
const VRATE_STEP_FPM: i64 = 64;
const VRATE_MAX_STEPS: i64 = 510;

/// A position in degrees (WGS-84).
///
/// ```
/// use gdl90_proto::message::{LatLon, Report};
/// let own = Report { position: Some(LatLon { lat_deg: 45.0, lon_deg: -90.0 }), nic: 8, ..Report::default() };
/// let mut data = [0u8; Report::LEN];
/// own.emit(&mut data).unwrap();
/// // 24-bit signed steps of 180/2^23 degrees: 0x200000 and -0x400000.
/// assert_eq!(&data[4..10], &[0x20, 0x00, 0x00, 0xC0, 0x00, 0x00]);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct LatLon {
    /// Latitude, degrees, north positive. Encoding clamps to ±90.
    pub lat_deg: f64,
    /// Longitude, degrees, east positive. Encoding brings any value into -180..180 (the
    /// same meridian).
    pub lon_deg: f64,
}

/// What the report's track byte holds (the `m` field's track type).
///
/// ```
/// use gdl90_proto::message::{Report, Track};
/// let own = Report { track: Some(Track::TrueTrack(90.0)), ..Report::default() };
/// let mut data = [0u8; Report::LEN];
/// own.emit(&mut data).unwrap();
/// assert_eq!((data[11] & 0x03, data[16]), (1, 64)); // track type 1, 64 x 360/256 degrees
/// assert_eq!(Report::parse(10, &data).unwrap().track, Some(Track::TrueTrack(90.0)));
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub enum Track {
    /// True track over the ground, degrees.
    TrueTrack(f32),
    /// Magnetic heading, degrees.
    MagneticHeading(f32),
    /// True heading, degrees.
    TrueHeading(f32),
}

impl Track {
    /// The angle in degrees, whatever its reference.
    ///
    /// ```
    /// use gdl90_proto::message::Track;
    /// assert_eq!(Track::MagneticHeading(271.5).degrees(), 271.5);
    /// ```
    pub const fn degrees(&self) -> f32 {
        match *self {
            Track::TrueTrack(d) | Track::MagneticHeading(d) | Track::TrueHeading(d) => d,
        }
    }
}

/// The `t` field: what kind of address the report carries.
///
/// ```
/// use gdl90_proto::message::{AddressType, Report};
/// let traffic = Report { address_type: AddressType::TisbIcao, ..Report::default() };
/// let mut data = [0u8; Report::LEN];
/// traffic.emit(&mut data).unwrap();
/// assert_eq!(data[0], 0x02); // the low nibble of byte 0
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub enum AddressType {
    /// 0: ADS-B with ICAO address.
    #[default]
    AdsbIcao,
    /// 1: ADS-B with self-assigned address.
    AdsbSelfAssigned,
    /// 2: TIS-B with ICAO address.
    TisbIcao,
    /// 3: TIS-B with track file ID.
    TisbTrackFile,
    /// 4: surface vehicle.
    SurfaceVehicle,
    /// 5: ground station beacon.
    GroundStationBeacon,
    /// 6..=15: reserved, kept as received.
    Reserved(u8),
}

impl AddressType {
    /// Decodes the nibble.
    ///
    /// ```
    /// use gdl90_proto::message::AddressType;
    /// assert_eq!(AddressType::from_nibble(2), AddressType::TisbIcao);
    /// assert_eq!(AddressType::from_nibble(9), AddressType::Reserved(9));
    /// ```
    pub const fn from_nibble(v: u8) -> Self {
        match v {
            0 => Self::AdsbIcao,
            1 => Self::AdsbSelfAssigned,
            2 => Self::TisbIcao,
            3 => Self::TisbTrackFile,
            4 => Self::SurfaceVehicle,
            5 => Self::GroundStationBeacon,
            other => Self::Reserved(other),
        }
    }

    /// The nibble (a reserved value above 15 is clamped to 15).
    ///
    /// ```
    /// use gdl90_proto::message::AddressType;
    /// assert_eq!(AddressType::TisbIcao.to_nibble(), 2);
    /// assert_eq!(AddressType::Reserved(20).to_nibble(), 15);
    /// ```
    pub const fn to_nibble(self) -> u8 {
        match self {
            Self::AdsbIcao => 0,
            Self::AdsbSelfAssigned => 1,
            Self::TisbIcao => 2,
            Self::TisbTrackFile => 3,
            Self::SurfaceVehicle => 4,
            Self::GroundStationBeacon => 5,
            Self::Reserved(v) => {
                if v > 15 {
                    15
                } else {
                    v
                }
            }
        }
    }
}

/// The `p` field: emergency / priority code.
///
/// ```
/// use gdl90_proto::message::{Emergency, Report};
/// let own = Report { emergency: Emergency::Medical, ..Report::default() };
/// let mut data = [0u8; Report::LEN];
/// own.emit(&mut data).unwrap();
/// assert_eq!(data[26], 0x20); // the high nibble of the last byte
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub enum Emergency {
    /// 0: no emergency.
    #[default]
    None,
    /// 1: general emergency.
    General,
    /// 2: medical emergency.
    Medical,
    /// 3: minimum fuel.
    MinimumFuel,
    /// 4: no communication.
    NoCommunication,
    /// 5: unlawful interference.
    UnlawfulInterference,
    /// 6: downed aircraft.
    Downed,
    /// 7..=15: reserved, kept as received.
    Reserved(u8),
}

impl Emergency {
    /// Decodes the nibble.
    ///
    /// ```
    /// use gdl90_proto::message::Emergency;
    /// assert_eq!(Emergency::from_nibble(2), Emergency::Medical);
    /// assert_eq!(Emergency::from_nibble(7), Emergency::Reserved(7));
    /// ```
    pub const fn from_nibble(v: u8) -> Self {
        match v {
            0 => Self::None,
            1 => Self::General,
            2 => Self::Medical,
            3 => Self::MinimumFuel,
            4 => Self::NoCommunication,
            5 => Self::UnlawfulInterference,
            6 => Self::Downed,
            other => Self::Reserved(other),
        }
    }

    /// The nibble (a reserved value above 15 is clamped to 15).
    ///
    /// ```
    /// use gdl90_proto::message::Emergency;
    /// assert_eq!(Emergency::Downed.to_nibble(), 6);
    /// assert_eq!(Emergency::Reserved(20).to_nibble(), 15);
    /// ```
    pub const fn to_nibble(self) -> u8 {
        match self {
            Self::None => 0,
            Self::General => 1,
            Self::Medical => 2,
            Self::MinimumFuel => 3,
            Self::NoCommunication => 4,
            Self::UnlawfulInterference => 5,
            Self::Downed => 6,
            Self::Reserved(v) => {
                if v > 15 {
                    15
                } else {
                    v
                }
            }
        }
    }
}

/// An Ownship Report (ID 10) or a Traffic Report (ID 20): the same 27 data bytes. The
/// [`Message`](super::Message) variant says which, and so picks the ID
/// [`Message::encode`](super::Message::encode) frames it with.
///
/// Every field that has an "invalid" or "not available" code on the wire is an `Option`
/// here, so a value is never mistaken for a marker. Encoding clamps out-of-range values to
/// the largest valid code; it never wraps and never produces a marker from a value.
///
/// ```
/// use gdl90_proto::message::{CallSign, LatLon, Report, Track};
/// let own = Report {
///     address: 0xAB4549,
///     position: Some(LatLon { lat_deg: 44.90708, lon_deg: -122.99488 }),
///     pressure_altitude_ft: Some(5000),
///     airborne: true,
///     track: Some(Track::TrueTrack(45.0)),
///     nic: 10,
///     nacp: 9,
///     ground_speed_kt: Some(123),
///     vertical_rate_fpm: Some(64),
///     emitter: 1,
///     call_sign: CallSign::new("N825V").unwrap(),
///     ..Report::default()
/// };
/// let mut data = [0u8; Report::LEN];
/// own.emit(&mut data).unwrap();
/// let back = Report::parse(10, &data).unwrap();
/// assert_eq!(back.pressure_altitude_ft, Some(5000));
/// assert!((back.position.unwrap().lat_deg - 44.90708).abs() < 1e-4);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Report {
    /// `s`: a traffic alert is active (any non-zero status reads as an alert; written as 1).
    pub traffic_alert: bool,
    /// `t`: the kind of address.
    pub address_type: AddressType,
    /// `aa aa aa`: the 24-bit participant address. Encoding clamps to `0xFFFFFF`.
    pub address: u32,
    /// Latitude and longitude, 180/2^23-degree steps. `None` on the wire is latitude 0,
    /// longitude 0 and NIC 0 (ICD 3.4: "no valid position"); encoding `None`, or a
    /// non-finite coordinate, writes exactly that, NIC included.
    pub position: Option<LatLon>,
    /// Pressure altitude, feet, 25 ft steps from -1000 to 101 350; `None` is `0xFFF`.
    /// Encoding rounds to the nearest step and clamps.
    pub pressure_altitude_ft: Option<i32>,
    /// `m` bit 3: airborne (`false`: on the ground).
    pub airborne: bool,
    /// `m` bit 2: the report is extrapolated (`false`: updated).
    pub extrapolated: bool,
    /// Track or heading and its kind (`m` bits 1-0); `None` is track type 0, "not valid".
    /// Encoding brings the angle into 0..360 and rounds it to 360/256-degree steps.
    pub track: Option<Track>,
    /// `i`: navigation integrity category, 0..=15 (clamped).
    pub nic: u8,
    /// `a`: navigation accuracy category for position, 0..=15 (clamped).
    pub nacp: u8,
    /// Horizontal velocity, knots, 0..=4094; `None` is `0xFFF`. Encoding clamps.
    pub ground_speed_kt: Option<u16>,
    /// Vertical velocity, feet per minute, 64 fpm steps, ±32 640; `None` is `0x800`. The
    /// reserved codes beyond ±510 steps also read as `None`. Encoding rounds and clamps.
    pub vertical_rate_fpm: Option<i32>,
    /// `ee`: emitter category (0..=39 defined by the ICD; other values kept).
    pub emitter: u8,
    /// Call sign.
    pub call_sign: CallSign,
    /// `p`: emergency / priority code.
    pub emergency: Emergency,
}

impl Report {
    /// The Ownship Report ID.
    pub const OWNSHIP_ID: u8 = 10;
    /// The Traffic Report ID.
    pub const TRAFFIC_ID: u8 = 20;
    /// The data length in bytes (after the ID, before the CRC).
    pub const LEN: usize = f::LEN;

    /// Parses the data bytes of a report with ID `id` (10 or 20; the ID only goes into
    /// errors).
    ///
    /// ```
    /// use gdl90_proto::{Error, message::Report};
    /// let mut data = [0u8; Report::LEN];
    /// data[1..4].copy_from_slice(&[0xAB, 0x45, 0x49]); // the address
    /// data[10] = 0x0F; // pressure altitude 0x0F0: 240 x 25 ft - 1000 ft
    /// let r = Report::parse(20, &data).unwrap();
    /// assert_eq!((r.address, r.pressure_altitude_ft, r.position), (0xAB4549, Some(5000), None));
    /// data[4..7].copy_from_slice(&[0x7F, 0xFF, 0xFF]); // a latitude beyond 90 degrees
    /// assert_eq!(Report::parse(20, &data), Err(Error::OutOfRange { id: 20, field: "latitude" }));
    /// ```
    ///
    /// # Errors
    /// [`Error::WrongLength`] unless `data` is exactly [`Self::LEN`] bytes;
    /// [`Error::OutOfRange`] for a latitude beyond ±90 degrees (a corrupt report: nothing in
    /// it can be trusted).
    pub fn parse(id: u8, data: &[u8]) -> Result<Self, Error> {
        check_len(id, Self::LEN, data)?;
        let lat = f::LATITUDE.get_signed(data);
        if lat.abs() > 1 << 22 {
            return Err(Error::OutOfRange {
                id,
                field: "latitude",
            });
        }
        let lon = f::LONGITUDE.get_signed(data);
        let nic = f::NIC.get(data) as u8;
        let position = (lat != 0 || lon != 0 || nic != 0).then_some(LatLon {
            lat_deg: lat as f64 * DEG_PER_LSB,
            lon_deg: lon as f64 * DEG_PER_LSB,
        });
        let alt = f::ALTITUDE.get(data);
        let pressure_altitude_ft =
            (alt != ALT_INVALID).then_some((alt as i64 * ALT_STEP_FT - ALT_OFFSET_FT) as i32);
        let speed = f::GROUND_SPEED.get(data);
        let vrate = f::VERTICAL_RATE.get_signed(data);
        let track_deg = f::TRACK.get(data) as f32 * TRACK_DEG_PER_LSB;
        let track = match f::TRACK_TYPE.get(data) {
            1 => Some(Track::TrueTrack(track_deg)),
            2 => Some(Track::MagneticHeading(track_deg)),
            3 => Some(Track::TrueHeading(track_deg)),
            _ => None,
        };
        let mut call_sign = [b' '; 8];
        if let Some(src) = data.get(f::CALL_SIGN) {
            // Zipped copies: no length check left to a panic when the copy is not inlined.
            call_sign.iter_mut().zip(src).for_each(|(d, s)| *d = *s);
        }
        Ok(Report {
            traffic_alert: f::ALERT_STATUS.get(data) != 0,
            address_type: AddressType::from_nibble(f::ADDRESS_TYPE.get(data) as u8),
            address: f::ADDRESS.get(data) as u32,
            position,
            pressure_altitude_ft,
            airborne: f::AIRBORNE.get_flag(data),
            extrapolated: f::EXTRAPOLATED.get_flag(data),
            track,
            nic,
            nacp: f::NACP.get(data) as u8,
            ground_speed_kt: (speed != SPEED_INVALID).then_some(speed as u16),
            vertical_rate_fpm: (vrate != VRATE_INVALID && vrate.abs() <= VRATE_MAX_STEPS)
                .then_some((vrate * VRATE_STEP_FPM) as i32),
            emitter: f::EMITTER.get(data) as u8,
            call_sign: CallSign::from_bytes(call_sign),
            emergency: Emergency::from_nibble(f::EMERGENCY.get(data) as u8),
        })
    }

    /// Writes the data bytes into `out` (spare bits zero, values clamped as each field
    /// says); returns [`Self::LEN`].
    ///
    /// ```
    /// use gdl90_proto::message::Report;
    /// let mut data = [0u8; Report::LEN];
    /// assert_eq!(Report::default().emit(&mut data), Ok(27));
    /// // Altitude 0xFFF, ground speed 0xFFF, vertical rate 0x800: all "not available".
    /// assert_eq!(&data[10..16], &[0xFF, 0xF0, 0x00, 0xFF, 0xF8, 0x00]);
    /// assert_eq!(&data[18..26], b"        "); // no call sign
    /// ```
    ///
    /// # Errors
    /// [`EncodeError::BufferTooSmall`] if `out` is shorter than [`Self::LEN`].
    pub fn emit(&self, out: &mut [u8]) -> Result<usize, EncodeError> {
        emit_into(out, Self::LEN, |d| {
            f::ALERT_STATUS.put(d, self.traffic_alert as u64);
            f::ADDRESS_TYPE.put(d, self.address_type.to_nibble() as u64);
            f::ADDRESS.put(d, (self.address as u64).min(f::ADDRESS.max()));
            let nic = (self.nic as u64).min(f::NIC.max());
            match self
                .position
                .and_then(|p| Some((lat_raw(p.lat_deg)?, lon_raw(p.lon_deg)?)))
            {
                Some((lat, lon)) => {
                    f::LATITUDE.put(d, lat as u64);
                    f::LONGITUDE.put(d, lon as u64);
                    f::NIC.put(d, nic);
                }
                None => {
                    f::LATITUDE.put(d, 0);
                    f::LONGITUDE.put(d, 0);
                    f::NIC.put(d, 0);
                }
            }
            let alt = match self.pressure_altitude_ft {
                Some(ft) => div_round(ft as i64 + ALT_OFFSET_FT, ALT_STEP_FT)
                    .clamp(0, ALT_INVALID as i64 - 1) as u64,
                None => ALT_INVALID,
            };
            f::ALTITUDE.put(d, alt);
            f::AIRBORNE.put_flag(d, self.airborne);
            f::EXTRAPOLATED.put_flag(d, self.extrapolated);
            let (kind, byte) = match self.track {
                None => (0, 0),
                Some(t) => {
                    let kind = match t {
                        Track::TrueTrack(_) => 1,
                        Track::MagneticHeading(_) => 2,
                        Track::TrueHeading(_) => 3,
                    };
                    // An angle: 360 degrees is 0, so reducing modulo 256 steps is exact.
                    let steps = round_f32(t.degrees() / TRACK_DEG_PER_LSB).unwrap_or(0);
                    (kind, steps.rem_euclid(256) as u64)
                }
            };
            f::TRACK_TYPE.put(d, kind);
            f::TRACK.put(d, byte);
            f::NACP.put(d, (self.nacp as u64).min(f::NACP.max()));
            let speed = match self.ground_speed_kt {
                Some(kt) => (kt as u64).min(SPEED_INVALID - 1),
                None => SPEED_INVALID,
            };
            f::GROUND_SPEED.put(d, speed);
            let vrate = match self.vertical_rate_fpm {
                Some(fpm) => {
                    div_round(fpm as i64, VRATE_STEP_FPM).clamp(-VRATE_MAX_STEPS, VRATE_MAX_STEPS)
                }
                None => VRATE_INVALID,
            };
            f::VERTICAL_RATE.put(d, vrate as u64);
            f::EMITTER.put(d, self.emitter as u64);
            if let Some(dst) = d.get_mut(f::CALL_SIGN) {
                dst.iter_mut()
                    .zip(self.call_sign.as_bytes())
                    .for_each(|(d, s)| *d = *s);
            }
            f::EMERGENCY.put(d, self.emergency.to_nibble() as u64);
        })
    }

    /// The data length [`Self::emit`] writes.
    ///
    /// ```
    /// use gdl90_proto::message::Report;
    /// assert_eq!(Report::default().buffer_len(), 27);
    /// ```
    pub const fn buffer_len(&self) -> usize {
        Self::LEN
    }
}

/// Latitude in steps, clamped to ±90 degrees; `None` if not finite.
fn lat_raw(deg: f64) -> Option<i64> {
    if !deg.is_finite() {
        return None;
    }
    let quarter = 1i64 << 22; // 90 degrees
    Some(round_f64(deg / DEG_PER_LSB)?.clamp(-quarter, quarter))
}

/// Longitude in steps, brought into -180..180 degrees; `None` if not finite.
fn lon_raw(deg: f64) -> Option<i64> {
    if !deg.is_finite() {
        return None;
    }
    let half = 1i64 << 23; // 180 degrees
    let steps = round_f64(deg / DEG_PER_LSB)?;
    // A meridian, not an overflow: +180 and -180 are the same line.
    Some((steps.saturating_add(half)).rem_euclid(2 * half) - half)
}
