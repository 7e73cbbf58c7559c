//! `protolink gdl90`: the box's AEOLUS telemetry as GDL90 for EFB apps (ForeFlight, Garmin
//! Pilot, SkyDemon, Avare...), which listen on UDP port 4000.
//!
//! Once a second: heartbeat, ForeFlight ID, ownship report and ownship geometric altitude;
//! five times a second: ForeFlight AHRS and the Stratux AHRS report (`--ahrs` chooses). What
//! goes in ([`Picture`]):
//!
//! | GDL90 field | from |
//! | --- | --- |
//! | AHRS roll, pitch | ATTITUDE |
//! | AHRS heading (magnetic) | COMPASS (never the GPS track) |
//! | AHRS IAS | PRESSURE pitot (dynamic) pressure at sea-level density ([`crate::air_data`]) |
//! | AHRS TAS | PRESSURE pitot pressure at the air density from PRESSURE static pressure and TEMP ([`crate::air_data`]) |
//! | ownship position, geometric altitude, ground speed | GPS, only with a fix |
//! | ownship track, vertical rate | the last two GPS fixes (on the box's clock) |
//! | ownship pressure altitude | PRESSURE static pressure, standard atmosphere (29.92 inHg) |
//! | ownship address, address type, call sign | `--icao` (ICAO, type 0) or the box's MAC (self-assigned, type 1); `--callsign` or `AEOLUS` ([`ownship`]) |
//! | heartbeat GPS-valid bit | a fresh GPS fix |
//! | Stratux roll, pitch, heading, IAS | as the ForeFlight AHRS |
//! | Stratux slip/skid | ATTITUDE slip ball (the angle of its tangent) |
//! | Stratux yaw rate | ATTITUDE turn coordinator (1.0 = 3 °/s) |
//! | Stratux G | ACCEL: minus the body z specific force over g |
//! | Stratux pressure altitude, vertical speed | PRESSURE static pressure; its rate over the last second (box clock) |
//!
//! Anything older than [`FRESH`](crate::fresh::FRESH) or marked invalid by the box goes
//! out as GDL90's invalid marker, never as a stale value. Datagrams go to one address (`--to`, 127.0.0.1:4000 by
//! default); to a broadcast address only with `--broadcast`; with `--discover`, to the first
//! host whose ForeFlight announcement arrives on UDP 63093 (`--discover=follow`: the latest
//! one), from a socket bound to every interface so that the datagrams can reach it.

use std::io::Write as _;
use std::net::{IpAddr, SocketAddr, UdpSocket};
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use aeolus_proto::message::{Accel, Attitude, Compass, Gps, Message};
use clap::{Args, ValueEnum};
use gdl90_proto::message::{
    AddressType, Ahrs, AltitudeDatum, CallSign, ForeFlightId, GeoAltitude, Heading, Heartbeat,
    LatLon, Message as Gdl90Message, Name, Report, StratuxAhrs, Track,
};
use serde_json::json;

use crate::air_data::AirDataSource;
use crate::decoders::AEOLUS_CAPACITY;
use crate::endpoint::udp_out::{Sends, bind_for};
use crate::endpoint::{Endpoint, Input, parse_local_addr};
use crate::error::{Error, Result};
use crate::fresh::fresh;
use crate::render::{Out, text};
use crate::stop::{self, Deadline};
use crate::telemetry::decode_read;
use crate::units::{FT_PER_M as FEET_PER_M, KT_PER_MPS as KNOTS_PER_MPS};

pub(crate) mod ownship;

/// The AHRS period (5 Hz).
pub(crate) const AHRS_PERIOD: Duration = Duration::from_millis(200);
/// The heartbeat, ID, ownship and geometric altitude period (1 Hz).
pub(crate) const SECOND: Duration = Duration::from_secs(1);
/// The port ForeFlight announces itself on.
pub(crate) const DISCOVERY_PORT: u16 = 63093;

/// Standard gravity, m/s².
const G0: f64 = 9.806_65;

/// Whom `--discover` sends to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum Discover {
    /// The first host that announces itself; later announcements from other hosts are
    /// ignored (counted and named on stderr), so nobody else can take the stream over.
    First,
    /// Whichever host announced itself last.
    Follow,
}

/// Which AHRS messages `gdl90` sends.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum AhrsKind {
    /// ForeFlight's AHRS (0x65, sub-ID 1): ForeFlight, Garmin Pilot and most EFB apps.
    Foreflight,
    /// The Stratux AHRS report (0x4C): WingX, iFly, AvPlan and other apps that read Stratux.
    Stratux,
    /// Both, each five times a second.
    Both,
}

/// `--broadcast`: an IPv4 address. IPv6 has no broadcast; a datagram to several IPv6 hosts goes
/// to a multicast group, which `--to` takes.
fn parse_broadcast(text: &str) -> std::result::Result<IpAddr, String> {
    match text.parse::<IpAddr>() {
        Ok(ip @ IpAddr::V4(_)) => Ok(ip),
        Ok(IpAddr::V6(_)) => Err(format!(
            "'{text}' is an IPv6 address, and IPv6 has no broadcast: give a multicast group or a host with --to instead"
        )),
        Err(_) => Err(format!("'{text}' is not an IPv4 address")),
    }
}

/// Arguments of `protolink gdl90`.
#[derive(Debug, Clone, Args)]
pub(crate) struct Gdl90Args {
    /// Where the box's AEOLUS telemetry comes from (udp:5001, tcp:127.0.0.1:7000, ...).
    #[arg(long, value_name = "ENDPOINT")]
    pub(crate) from: Endpoint,
    /// Where the GDL90 datagrams go: PORT (on 127.0.0.1) or ADDR:PORT.
    #[arg(long, value_name = "[ADDR:]PORT", default_value = "127.0.0.1:4000", value_parser = parse_local_addr)]
    pub(crate) to: SocketAddr,
    /// Send to this broadcast address instead (on the --to port; IPv4: IPv6 has no broadcast).
    /// Never a default.
    #[arg(long, value_name = "ADDR", value_parser = parse_broadcast)]
    pub(crate) broadcast: Option<IpAddr>,
    /// Listen on UDP 63093 for ForeFlight's announcement and send to the host it came from,
    /// on the port it names: the first host to announce itself (`--discover`, the same as
    /// `--discover=first`), or whichever announced itself last (`--discover=follow`).
    #[arg(long, value_enum, value_name = "WHOM", num_args = 0..=1, require_equals = true,
          default_missing_value = "first")]
    pub(crate) discover: Option<Discover>,
    /// Which AHRS messages to send.
    #[arg(long, value_enum, default_value = "both")]
    pub(crate) ahrs: AhrsKind,
    /// The aircraft's 24-bit ICAO address (hex, such as A1B2C3): the ownship report then
    /// carries it as an ICAO address, so apps match it with the aircraft's own transponder
    /// in traffic. Kept for this --from box for later runs.
    #[arg(long, value_name = "HEX", value_parser = ownship::parse_icao)]
    pub(crate) icao: Option<u32>,
    /// The ownship call sign (1 to 8 of 0-9, A-Z), such as the registration without its
    /// dash. Kept for this --from box for later runs.
    #[arg(long, value_name = "CALLSIGN", value_parser = ownship::parse_callsign)]
    pub(crate) callsign: Option<String>,
    /// Stop after this long: `10` (seconds), `500ms`, `2min` (default: on Ctrl-C, or at the
    /// end of the input).
    #[arg(long, value_name = "DURATION", value_parser = crate::args::run_time)]
    pub(crate) seconds: Option<Duration>,
}

/// The latest of each telemetry message, with when it arrived, and the GPS fix before it.
#[derive(Debug, Default, Clone)]
pub struct Picture {
    attitude: Option<(Attitude, Instant)>,
    compass: Option<(Compass, Instant)>,
    accel: Option<(Accel, Instant)>,
    gps: Option<(Gps, Instant)>,
    previous_fix: Option<Gps>,
    /// The low 24 bits of the box's MAC, from AEOLUSINFO: the self-assigned address.
    address: Option<u32>,
    /// Airspeeds, pressure altitude and its rate.
    air: AirDataSource,
    /// `--icao` and `--callsign`, given or kept.
    pub(crate) identity: ownship::Identity,
}

fn knots(mps: f64) -> Option<u16> {
    let kt = (mps * KNOTS_PER_MPS).round();
    (kt.is_finite() && kt >= 0.0).then(|| kt.min(f64::from(u16::MAX - 1)) as u16)
}

impl Picture {
    /// Takes one telemetry message that arrived at `now`.
    pub fn take(&mut self, m: &Message<'_>, now: Instant) {
        match m {
            Message::Attitude(v) => self.attitude = Some((*v, now)),
            Message::Pressure(_) | Message::Temp(_) => self.air.take(m, now),
            Message::Accel(v) => self.accel = Some((*v, now)),
            Message::Compass(v) => self.compass = Some((*v, now)),
            Message::Gps(v) => {
                if let Some((old, _)) = self.gps
                    && old.valid
                    && old.has_fix
                {
                    self.previous_fix = Some(old);
                }
                self.gps = Some((*v, now));
            }
            Message::AeolusInfo(i) => {
                self.address = Some(
                    u32::from(i.mac[3]) << 16 | u32::from(i.mac[4]) << 8 | u32::from(i.mac[5]),
                );
            }
            _ => {}
        }
    }

    /// A fresh, valid GPS fix.
    fn fix(&self, now: Instant) -> Option<Gps> {
        fresh(&self.gps, now).filter(|g| g.valid && g.has_fix)
    }

    /// The ForeFlight AHRS message for `now`.
    pub fn ahrs(&self, now: Instant) -> Ahrs {
        let attitude = fresh(&self.attitude, now).filter(|a| a.valid);
        let air = self.air.at(now);
        let heading = fresh(&self.compass, now)
            .filter(|c| c.valid && c.has_value && c.heading_deg.is_finite())
            .map(|c| Heading::Magnetic(c.heading_deg.rem_euclid(360.0)));
        Ahrs {
            roll_deg: attitude.map(|a| a.roll_rad.to_degrees()),
            pitch_deg: attitude.map(|a| a.pitch_rad.to_degrees()),
            heading,
            indicated_airspeed_kt: air.ias_mps.and_then(knots),
            true_airspeed_kt: air.tas_mps.and_then(knots),
        }
    }

    /// The Stratux AHRS report for `now` (its layout in [`StratuxAhrs`]).
    pub fn stratux_ahrs(&self, now: Instant) -> StratuxAhrs {
        let ff = self.ahrs(now);
        let attitude = fresh(&self.attitude, now).filter(|a| a.valid);
        let air = self.air.at(now);
        let finite = |v: f64| v.is_finite().then_some(v as f32);
        let whole =
            |v: f64| (v.is_finite() && v.abs() < f64::from(i16::MAX)).then(|| v.round() as i16);
        StratuxAhrs {
            roll_deg: ff.roll_deg,
            pitch_deg: ff.pitch_deg,
            heading_deg: ff.heading.map(|h| h.degrees()),
            slip_skid_deg: attitude
                .and_then(|a| finite(f64::from(a.slip_ball).atan().to_degrees())),
            yaw_rate_dps: attitude.and_then(|a| finite(f64::from(a.turn_coordinator) * 3.0)),
            g_load: fresh(&self.accel, now)
                .filter(|a| a.valid)
                .and_then(|a| finite(-f64::from(a.z) / G0)),
            indicated_airspeed_kt: ff
                .indicated_airspeed_kt
                .and_then(|kt| i16::try_from(kt).ok()),
            pressure_altitude_ft: air
                .pressure_altitude_m
                .map(|m| (m * FEET_PER_M).round() as i32),
            vertical_speed_fpm: air
                .vertical_speed_mps
                .and_then(|mps| whole(mps * FEET_PER_M * 60.0)),
        }
    }

    /// The ownship report for `now`.
    pub(crate) fn ownship(&self, now: Instant) -> Report {
        let fix = self.fix(now);
        let (track, vertical_rate_fpm) = match (fix, self.previous_fix) {
            (Some(g), Some(p)) if g.timestamp_ms > p.timestamp_ms => {
                let dt_min = (g.timestamp_ms - p.timestamp_ms) / 60_000.0;
                let climb = f64::from(g.altitude_m - p.altitude_m) * FEET_PER_M / dt_min;
                (
                    bearing_deg(&p, &g).map(Track::TrueTrack),
                    climb.is_finite().then(|| climb.round() as i32),
                )
            }
            _ => (None, None),
        };
        let (address_type, address) = match self.identity.icao {
            Some(icao) => (AddressType::AdsbIcao, icao),
            None => (AddressType::AdsbSelfAssigned, self.address.unwrap_or(0)),
        };
        let call_sign = self
            .identity
            .callsign
            .as_deref()
            .and_then(CallSign::new)
            .or_else(|| CallSign::new("AEOLUS"))
            .unwrap_or_default();
        Report {
            address_type,
            address,
            position: fix.map(|g| LatLon {
                lat_deg: f64::from(g.latitude_deg),
                lon_deg: f64::from(g.longitude_deg),
            }),
            pressure_altitude_ft: self
                .air
                .at(now)
                .pressure_altitude_m
                .map(|m| (m * FEET_PER_M).round() as i32),
            airborne: fix.is_some_and(|g| g.ground_speed_mps > 15.0),
            track,
            // AEOLUS reports no accuracy: a GPS fix is given typical values.
            nic: if fix.is_some() { 8 } else { 0 },
            nacp: if fix.is_some() { 9 } else { 0 },
            ground_speed_kt: fix.and_then(|g| knots(f64::from(g.ground_speed_mps))),
            vertical_rate_fpm,
            emitter: 1,
            call_sign,
            ..Report::default()
        }
    }

    /// The ownship geometric altitude, only with a fresh fix (the message has no invalid
    /// marker for the altitude).
    pub(crate) fn geo_altitude(&self, now: Instant) -> Option<GeoAltitude> {
        self.fix(now).map(|g| GeoAltitude {
            altitude_ft: (f64::from(g.altitude_m) * FEET_PER_M).round() as i32,
            vertical_warning: false,
            vfom_m: None,
        })
    }

    /// The heartbeat, with the host's UTC time of day.
    pub(crate) fn heartbeat(&self, now: Instant, seconds_since_midnight: u32) -> Heartbeat {
        Heartbeat {
            gps_position_valid: self.fix(now).is_some(),
            uat_initialized: true,
            utc_ok: true,
            seconds_since_midnight,
            ..Heartbeat::default()
        }
    }

    /// The ForeFlight ID of this bridge.
    pub(crate) fn foreflight_id(&self) -> ForeFlightId {
        ForeFlightId {
            version: 1,
            serial: self.address.map(u64::from),
            name: Name::new("AEOLUS").unwrap_or_default(),
            long_name: Name::new("AEOLUS protolink").unwrap_or_default(),
            altitude_datum: AltitudeDatum::Msl,
            other_capabilities: 0,
        }
    }
}

/// The true course from fix `a` to fix `b`, when they are at least a metre apart.
fn bearing_deg(a: &Gps, b: &Gps) -> Option<f32> {
    let (la1, la2) = (
        f64::from(a.latitude_deg).to_radians(),
        f64::from(b.latitude_deg).to_radians(),
    );
    let dlon = f64::from(b.longitude_deg - a.longitude_deg).to_radians();
    let y = dlon.sin() * la2.cos();
    let x = la1.cos() * la2.sin() - la1.sin() * la2.cos() * dlon.cos();
    let metres = (y.hypot(x)) * 6_371_000.0;
    (metres >= 1.0).then(|| y.atan2(x).to_degrees().rem_euclid(360.0) as f32)
}

/// What `gdl90` sent, printed on exit.
#[derive(Debug, Default, Clone, Copy, serde::Serialize)]
pub(crate) struct Counters {
    /// AEOLUS messages taken in.
    pub(crate) telemetry_in: u64,
    /// Heartbeats sent.
    pub(crate) heartbeats: u64,
    /// ForeFlight AHRS messages sent.
    pub(crate) ahrs: u64,
    /// Stratux AHRS reports sent.
    pub(crate) stratux_ahrs: u64,
    /// Ownship reports sent.
    pub(crate) ownship: u64,
    /// Geometric altitudes sent.
    pub(crate) geo_altitude: u64,
    /// ForeFlight IDs sent.
    pub(crate) foreflight_id: u64,
    /// Datagrams whose send failed.
    pub(crate) send_errors: u64,
    /// ForeFlight announcements ignored: from another host than the one followed
    /// (`--discover`), or not an announcement.
    pub(crate) announcements_ignored: u64,
}

fn seconds_since_midnight() -> u32 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| (d.as_secs() % 86_400) as u32)
}

/// Runs `protolink gdl90`.
///
/// # Errors
/// Opening the endpoints, reading the input, or every send failing.
pub(crate) fn run(args: &Gdl90Args) -> Result<()> {
    let mut link = args.from.open()?;
    let (mut to, mut sender) = Sender::open(args)?;
    let mut discovery = args.discover.map(Discovery::open).transpose()?;
    let _ = writeln!(
        std::io::stderr(),
        "gdl90: {} -> GDL90 on udp {to}{} (Ctrl-C to stop)",
        link.name(),
        match args.discover {
            Some(Discover::First) => ", or the first ForeFlight that announces itself",
            Some(Discover::Follow) => ", or the ForeFlight that announced itself last",
            None => "",
        }
    );
    stop::install_ctrl_c();
    let deadline = Deadline::after(args.seconds);
    let identity = ownship::Identity {
        icao: args.icao,
        callsign: args.callsign.clone(),
    };
    let mut picture = Picture {
        identity: ownship::resolve(
            &args.from.to_string(),
            identity,
            ownship::state_file().as_deref(),
        )?,
        ..Picture::default()
    };
    let mut counters = Counters::default();
    let mut decoder = Box::new(aeolus_proto::Decoder::<AEOLUS_CAPACITY>::new());
    let mut buf = vec![0u8; 65_536];
    let start = Instant::now();
    let (mut next_ahrs, mut next_second) = (start, start);
    while !deadline.reached() {
        let wait = next_ahrs
            .min(next_second)
            .saturating_duration_since(Instant::now());
        match link.read(&mut buf, deadline.left(wait.max(Duration::from_millis(1))))? {
            Input::Data(n) => {
                let now = Instant::now();
                let bytes = buf.get(..n).unwrap_or(&[]);
                decode_read(&mut decoder, bytes, link.is_datagram(), |m| {
                    counters.telemetry_in += 1;
                    picture.take(m, now);
                });
            }
            Input::Idle => {}
            Input::End => break,
        }
        if let Some(d) = discovery.as_mut()
            && let Some(addr) = d.poll(&mut counters, |note| {
                let _ = writeln!(std::io::stderr(), "gdl90: {note}");
            })
        {
            sender.follow(addr)?;
            to = addr;
        }
        let now = Instant::now();
        if now >= next_ahrs {
            sender.send_ahrs(to, &picture, now, args.ahrs, &mut counters);
            next_ahrs += AHRS_PERIOD;
        }
        if now >= next_second {
            sender.send_each_second(to, &picture, now, &mut counters);
            next_second += SECOND;
        }
    }
    sender.finish(to, counters)
}

/// ForeFlight's announcements (UDP 63093, every interface) and the host they lead to.
struct Discovery {
    socket: UdpSocket,
    whom: Discover,
    /// The host followed and the port it named.
    following: Option<SocketAddr>,
    /// Hosts whose announcements were ignored and named on stderr (at most
    /// [`Discovery::NAMED`], so a flood of spoofed sources cannot grow it).
    named: Vec<IpAddr>,
}

impl Discovery {
    /// At most this many ignored hosts are named on stderr (each once).
    const NAMED: usize = 16;

    /// Binds UDP 63093 on every interface, non-blocking.
    fn open(whom: Discover) -> Result<Self> {
        let open_err = |source| Error::Open {
            endpoint: format!("udp:0.0.0.0:{DISCOVERY_PORT} (ForeFlight discovery)"),
            source,
        };
        let socket = UdpSocket::bind(("0.0.0.0", DISCOVERY_PORT)).map_err(open_err)?;
        socket.set_nonblocking(true).map_err(open_err)?;
        Ok(Discovery {
            socket,
            whom,
            following: None,
            named: Vec::new(),
        })
    }

    /// Takes the announcements waiting; the new destination when it changes. `note` gets a
    /// sentence for a new destination and for each host ignored (the first time).
    fn poll(&mut self, counters: &mut Counters, mut note: impl FnMut(&str)) -> Option<SocketAddr> {
        let mut buf = [0u8; 1024];
        let before = self.following;
        while let Ok((n, from)) = self.socket.recv_from(&mut buf) {
            let Some(port) = buf.get(..n).and_then(announced_port) else {
                counters.announcements_ignored += 1;
                continue;
            };
            let at = SocketAddr::new(from.ip(), port);
            match self.following {
                Some(f) if self.whom == Discover::First && f.ip() != at.ip() => {
                    counters.announcements_ignored += 1;
                    if self.named.len() < Self::NAMED && !self.named.contains(&at.ip()) {
                        self.named.push(at.ip());
                        note(&format!(
                            "ignored the ForeFlight at {at}: sending to the first, {f} \
                             (--discover=follow follows the latest)"
                        ));
                    }
                }
                _ => self.following = Some(at),
            }
        }
        let now = self.following.filter(|f| Some(*f) != before)?;
        note(&format!("sending to the ForeFlight at {now}"));
        Some(now)
    }
}

/// Encodes into one buffer and sends it, counting what went out and what failed.
struct Sender {
    socket: UdpSocket,
    /// Whether the socket is bound to every interface (`--discover`).
    every_interface: bool,
    broadcast: bool,
    wire: [u8; gdl90_proto::MAX_ENCODED_LEN],
    sends: Sends,
}

impl Sender {
    /// The destination (`--to`, or the `--broadcast` address on its port) and a sender bound
    /// to an ephemeral port of the destination's family ([`bind_for`]): on every interface
    /// with `--discover` (the announcer may be on any network) or for a destination off this
    /// machine, else on the loopback address.
    fn open(args: &Gdl90Args) -> Result<(SocketAddr, Self)> {
        let to = match args.broadcast {
            Some(b) => SocketAddr::new(b, args.to.port()),
            None => args.to,
        };
        let every_interface = args.discover.is_some();
        let sender = Sender {
            socket: Self::bind(to, every_interface, args.broadcast.is_some())?,
            every_interface,
            broadcast: args.broadcast.is_some(),
            wire: [0; gdl90_proto::MAX_ENCODED_LEN],
            sends: Sends::default(),
        };
        Ok((to, sender))
    }

    fn bind(to: SocketAddr, every_interface: bool, broadcast: bool) -> Result<UdpSocket> {
        let socket = bind_for(to, every_interface)?;
        if broadcast {
            socket.set_broadcast(true).map_err(|source| Error::Open {
                endpoint: format!("a UDP socket for {to}"),
                source,
            })?;
        }
        Ok(socket)
    }

    /// Sends to `to` from now on: a destination of the other family (an IPv4 announcer
    /// after an IPv6 `--to`) gets a socket of its own family.
    fn follow(&mut self, to: SocketAddr) -> Result<()> {
        let family = |a: SocketAddr| a.is_ipv4();
        if self
            .socket
            .local_addr()
            .is_ok_and(|l| family(l) != family(to))
        {
            self.socket = Self::bind(to, self.every_interface, self.broadcast)?;
        }
        Ok(())
    }

    /// The AHRS messages `kind` asks for.
    fn send_ahrs(
        &mut self,
        to: SocketAddr,
        picture: &Picture,
        now: Instant,
        kind: AhrsKind,
        counters: &mut Counters,
    ) {
        if kind != AhrsKind::Stratux {
            let ahrs = picture.ahrs(now);
            counters.ahrs += self.send(to, |w| Gdl90Message::Ahrs(ahrs).encode(w));
        }
        if kind != AhrsKind::Foreflight {
            let report = picture.stratux_ahrs(now);
            counters.stratux_ahrs += self.send(to, |w| Gdl90Message::StratuxAhrs(report).encode(w));
        }
    }

    /// The messages sent once a second: heartbeat, ForeFlight ID, ownship report and, with
    /// a GPS fix, geometric altitude.
    fn send_each_second(
        &mut self,
        to: SocketAddr,
        picture: &Picture,
        now: Instant,
        counters: &mut Counters,
    ) {
        let hb = picture.heartbeat(now, seconds_since_midnight());
        counters.heartbeats += self.send(to, |w| Gdl90Message::Heartbeat(hb).encode(w));
        let id = picture.foreflight_id();
        counters.foreflight_id += self.send(to, |w| Gdl90Message::ForeFlightId(id).encode(w));
        let own = picture.ownship(now);
        counters.ownship += self.send(to, |w| Gdl90Message::Ownship(own).encode(w));
        if let Some(geo) = picture.geo_altitude(now) {
            counters.geo_altitude += self.send(to, |w| Gdl90Message::GeoAltitude(geo).encode(w));
        }
    }

    /// Prints the counters; fails when datagrams were to go out and not one did
    /// ([`Sends::check`], the rule of every command that sends).
    fn finish(mut self, to: SocketAddr, mut counters: Counters) -> Result<()> {
        counters.send_errors = self.sends.failed;
        let mut out = Out::new();
        out.line(&format!("gdl90: {}", text(&json!(counters))))?;
        out.flush()?;
        self.sends.check(to)
    }

    /// Encodes with `encode` and sends to `to`; 1 when it went out, else 0.
    fn send(
        &mut self,
        to: SocketAddr,
        encode: impl FnOnce(&mut [u8]) -> std::result::Result<usize, gdl90_proto::EncodeError>,
    ) -> u64 {
        let Ok(n) = encode(&mut self.wire) else {
            return 0;
        };
        let sent = self.socket.send_to(self.wire.get(..n).unwrap_or(&[]), to);
        u64::from(self.sends.count(sent))
    }
}

/// The port a ForeFlight announcement names (`{"App":"ForeFlight","GDL90":{"port":4000}}`),
/// or `None` for anything else.
pub(crate) fn announced_port(datagram: &[u8]) -> Option<u16> {
    let v: serde_json::Value = serde_json::from_slice(datagram).ok()?;
    let port = v["GDL90"]["port"]
        .as_u64()
        .and_then(|p| u16::try_from(p).ok())?;
    (v["App"] == "ForeFlight" && port != 0).then_some(port)
}

#[cfg(test)]
mod tests {
    use std::net::IpAddr;

    use clap::Parser;

    use crate::commands::gdl90::{Gdl90Args, Sender};

    #[derive(Parser)]
    struct Cli {
        #[command(flatten)]
        args: Gdl90Args,
    }

    fn bound(argv: &[&str]) -> IpAddr {
        let cli = Cli::try_parse_from(argv).unwrap();
        let (_, sender) = Sender::open(&cli.args).unwrap();
        sender.socket.local_addr().unwrap().ip()
    }

    /// With `--discover` the announcer may be on any network, so the sender is bound to every
    /// interface: a socket on 127.0.0.1 could never reach a tablet on the LAN.
    #[test]
    fn discover_sends_from_every_interface() {
        assert!(bound(&["t", "--from", "udp:0"]).is_loopback());
        assert!(bound(&["t", "--from", "udp:0", "--discover"]).is_unspecified());
        assert!(bound(&["t", "--from", "udp:0", "--discover=follow"]).is_unspecified());
    }
}

/// The examples of this module's items, as tests (the items are crate-private, so rustdoc
/// does not run them).
#[cfg(test)]
#[allow(unused_imports, clippy::unnecessary_wraps)]
mod examples {
    use super::*;

    #[test]
    fn announced_port_example() -> Result<(), Box<dyn std::error::Error>> {
        assert_eq!(
            announced_port(br#"{"App":"ForeFlight","GDL90":{"port":4000}}"#),
            Some(4000)
        );
        assert_eq!(
            announced_port(br#"{"App":"Other","GDL90":{"port":4000}}"#),
            None
        );
        assert_eq!(announced_port(b"not json"), None);
        Ok(())
    }
}
