//! One air-data truth: every face of `protolink` that shows or sends an airspeed gives the same
//! indicated and true airspeed for the same AEOLUS telemetry, at several airspeeds and
//! altitudes (PL39).
//!
//! The telemetry is what a box flying at a true airspeed `V` at an altitude `h` of the ISA
//! measures: static pressure `p(h)`, the pitot's dynamic pressure `½ ρ(h) V²`, the outside
//! temperature `T(h)`. PRESSURE's own airspeed field carries a value no face may use. The
//! expected values are computed here from the ICAO standard atmosphere, not by protolink's
//! code: the true airspeed is `V`, the indicated airspeed `V · sqrt(ρ(h) / 1.225)`.
//!
//! The faces, each read as its users read it, within its format's resolution: the ForeFlight
//! AHRS (IAS, TAS, whole knots) and the Stratux AHRS (IAS, whole knots) of `gdl90`; `nmea`'s
//! `$LXWP0` (TAS, 0.1 km/h) and the IAS XCSoar derives from `$POV`'s `Q` (0.01 Pa);
//! `watch`'s airspeed line (0.01 m/s); `web`'s state (`air.ias_mps`, `air.tas_mps`); and the
//! `AIR` object of `decode --udp-json`, the PlotJuggler output. The Python and C faces decode
//! the wire fields only and derive no airspeed.

use std::net::UdpSocket;
use std::time::{Duration, Instant};

use aeolus_proto::message::{Message, Pressure, Temp};
use aeolus_proto::{CrcMode, Stats};
use protolink::commands::decode::plot::PlotSender;
use protolink::commands::web::state::Cockpit;
use protolink::commands::{gdl90, nmea, watch};
use protolink::decoders::Decoder;
use protolink::proto::{Proto, Side};
use protolink::telemetry::View;
use serde_json::Value;

/// True airspeed (m/s) and altitude (m) of each case: slow and low to fast and high.
const CASES: [(f64, f64); 5] = [
    (15.0, -300.0),
    (50.0, 1000.0),
    (90.0, 3000.0),
    (120.0, 6000.0),
    (150.0, 10_000.0),
];

const KT_PER_MPS: f64 = 3600.0 / 1852.0;

/// The ICAO standard atmosphere's troposphere, written here: temperature (K), pressure (Pa)
/// and density (kg/m³) at `h` metres.
fn isa(h: f64) -> (f64, f64, f64) {
    let kelvin = 288.15 - 0.0065 * h;
    let pa = 101_325.0 * (kelvin / 288.15).powf(9.806_65 / (287.052_87 * 0.0065));
    (kelvin, pa, pa / (287.052_87 * kelvin))
}

/// The telemetry of a box at `tas` m/s and `h` m (TEMP, then PRESSURE), and the expected
/// (IAS, TAS) in m/s.
fn case(tas: f64, h: f64) -> ([Message<'static>; 2], (f64, f64)) {
    let (kelvin, pa, rho) = isa(h);
    let pressure = Pressure {
        valid: true,
        timestamp_ms: 1000.0,
        static_mbar: (pa / 100.0) as f32,
        pitot_mbar: (0.5 * rho * tas * tas / 100.0) as f32,
        // Neither IAS nor TAS: a face that shows this field fails.
        airspeed_mps: 3.0,
    };
    let temp = Temp {
        valid: true,
        timestamp_ms: 1000.0,
        celsius: (kelvin - 273.15) as f32,
    };
    (
        [Message::Temp(temp), Message::Pressure(pressure)],
        (tas * (rho / 1.225).sqrt(), tas),
    )
}

fn frames(messages: &[Message<'_>]) -> Vec<u8> {
    let mut out = Vec::new();
    for m in messages {
        let mut buf = [0u8; 128];
        let n = m.encode(&mut buf, CrcMode::Compute).unwrap();
        out.extend_from_slice(&buf[..n]);
    }
    out
}

/// `got` within `resolution / 2` (the format's rounding) of `want`, with a margin for the
/// f32 fields of the telemetry.
fn within(face: &str, what: &str, got: f64, want: f64, resolution: f64, at: (f64, f64)) {
    let margin = resolution / 2.0 + want.abs() * 1e-5;
    assert!(
        (got - want).abs() <= margin,
        "{face}: {what} {got} where {want:.4} is right (±{margin:.4}) at {} m/s TAS, {} m",
        at.0,
        at.1
    );
}

#[test]
fn every_face_gives_the_same_ias_and_tas() {
    for (tas, h) in CASES {
        let (messages, (want_ias, want_tas)) = case(tas, h);
        let at = (tas, h);
        let now = Instant::now();

        // gdl90: the ForeFlight AHRS and the Stratux AHRS, in whole knots.
        let mut efb = gdl90::Picture::default();
        for m in &messages {
            efb.take(m, now);
        }
        let ahrs = efb.ahrs(now);
        let kt = |v: Option<u16>| f64::from(v.expect("an airspeed"));
        within(
            "ForeFlight AHRS",
            "IAS kt",
            kt(ahrs.indicated_airspeed_kt),
            want_ias * KT_PER_MPS,
            1.0,
            at,
        );
        within(
            "ForeFlight AHRS",
            "TAS kt",
            kt(ahrs.true_airspeed_kt),
            want_tas * KT_PER_MPS,
            1.0,
            at,
        );
        let stratux = efb.stratux_ahrs(now);
        let ias = f64::from(stratux.indicated_airspeed_kt.expect("an airspeed"));
        within(
            "Stratux AHRS",
            "IAS kt",
            ias,
            want_ias * KT_PER_MPS,
            1.0,
            at,
        );

        // nmea: $LXWP0's TAS in km/h; $POV's Q, from which XCSoar takes IAS = sqrt(2 Q / 1.225).
        let mut app = nmea::Picture::default();
        for m in &messages {
            app.take(m, now);
        }
        let lxwp0 = protolink::nmea::sentence::lxwp0(&app.lxwp0(now));
        let field: f64 = lxwp0.split(',').nth(2).unwrap().parse().unwrap();
        within("nmea $LXWP0", "TAS km/h", field, want_tas * 3.6, 0.1, at);
        let pov = protolink::nmea::sentence::pov(&app.pov(now)).expect("a $POV");
        let q: f64 = pov
            .split(',')
            .skip_while(|f| *f != "Q")
            .nth(1)
            .expect("a Q pair")
            .parse()
            .unwrap();
        let pov_ias = (2.0 * q / 1.225).sqrt();
        // 0.005 Pa of rounding in Q is at most 0.005 / (1.225 IAS) m/s.
        within(
            "nmea $POV Q",
            "IAS m/s",
            pov_ias,
            want_ias,
            0.01 / (1.225 * want_ias),
            at,
        );

        // watch: "ias X m/s  tas Y m/s".
        let mut view = View::default();
        for m in &messages {
            view.take(m, now);
        }
        let lines = watch::lines(&view, "test", Duration::ZERO, now, &Stats::default());
        let line = lines.iter().find(|l| l.starts_with("airspeed")).unwrap();
        let number_after = |key: &str| -> f64 {
            let rest = line
                .split(key)
                .nth(1)
                .unwrap_or_else(|| panic!("no {key} in {line}"));
            rest.split_whitespace()
                .next()
                .unwrap()
                .parse()
                .unwrap_or_else(|_| panic!("{line}"))
        };
        within("watch", "IAS m/s", number_after("ias "), want_ias, 0.01, at);
        within("watch", "TAS m/s", number_after("tas "), want_tas, 0.01, at);

        // web: the state the page draws (the tape is the IAS, the readout under it the TAS).
        let mut cockpit = Cockpit::new("test", now);
        cockpit.feed(&frames(&messages), false, now);
        let state = serde_json::to_value(cockpit.state(now, Default::default())).unwrap();
        let number = |key: &str| {
            state["air"][key]
                .as_f64()
                .unwrap_or_else(|| panic!("{state}"))
        };
        within("web", "IAS m/s", number("ias_mps"), want_ias, 0.0, at);
        within("web", "TAS m/s", number("tas_mps"), want_tas, 0.0, at);

        // decode --udp-json: the AIR object after the PRESSURE.
        let plotjuggler = UdpSocket::bind("127.0.0.1:0").unwrap();
        plotjuggler
            .set_read_timeout(Some(Duration::from_secs(5)))
            .unwrap();
        let mut sender = PlotSender::new(plotjuggler.local_addr().unwrap()).unwrap();
        let mut decoder = Decoder::new(Proto::Aeolus, Default::default(), Side::default());
        let events = decoder.events(&frames(&messages), 0, false);
        sender.send(Proto::Aeolus, &events, 1.7e9);
        let mut air = None;
        let mut buf = [0u8; 2048];
        for _ in 0..events.len() + 1 {
            let n = plotjuggler.recv(&mut buf).expect("a datagram");
            let v: Value = serde_json::from_slice(&buf[..n]).unwrap();
            if v.get("AIR/ias_mps").is_some() {
                air = Some(v);
            }
        }
        let air = air.expect("an AIR object");
        let number = |key: &str| air[key].as_f64().unwrap_or_else(|| panic!("{air}"));
        within(
            "decode --udp-json",
            "AIR/ias_mps",
            number("AIR/ias_mps"),
            want_ias,
            0.0,
            at,
        );
        within(
            "decode --udp-json",
            "AIR/tas_mps",
            number("AIR/tas_mps"),
            want_tas,
            0.0,
            at,
        );
    }
}
