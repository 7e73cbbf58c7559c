//! `decode --udp-json ADDR`: one flat JSON object per decoded message, sent as one UDP datagram,
//! the form PlotJuggler's "UDP Server" (JSON message protocol) plots.
//!
//! The object holds `timestamp` (seconds since the Unix epoch: the capture's time for a
//! capture, the host's clock otherwise) and every numeric field as `NAME/field` (booleans as 0
//! or 1, arrays as `NAME/field/i`), e.g.
//! `{"timestamp":1700000000.25,"GYRO/valid":1,"GYRO/timestamp_ms":7.0,"GYRO/x":0.0,...}`.
//! Texts and raw bytes are left out. Sends never block: a datagram the socket cannot take at
//! once is dropped and counted.
//!
//! For AEOLUS, each PRESSURE is followed by an `AIR` object with the air data every other
//! face shows ([`crate::air_data`]): `AIR/ias_mps`, `AIR/tas_mps` (once a TEMP came within
//! 2.5 s of the plot's clock), `AIR/pressure_altitude_m`, `AIR/vertical_speed_mps`, each only
//! when known. PRESSURE's own `airspeed_mps` is the wire field, sent as it came.

use std::net::{Ipv4Addr, Ipv6Addr, SocketAddr, UdpSocket};
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use aeolus_proto::message::{Pressure, Temp};
use serde_json::{Map, Value, json};

use crate::air_data::{AirData, AirDataSource};
use crate::decoders::{Body, Event};
use crate::error::{Error, Result};
use crate::proto::Proto;

/// The flat object for one event, or `None` for an error event or a message without numbers.
pub(crate) fn flat(event: &Event, timestamp: f64) -> Option<Value> {
    let Body::Message { name, fields, .. } = &event.body else {
        return None;
    };
    let mut m = Map::new();
    m.insert("timestamp".into(), json!(timestamp));
    add(&mut m, name, fields);
    (m.len() > 1).then_some(Value::Object(m))
}

fn add(m: &mut Map<String, Value>, key: &str, v: &Value) {
    match v {
        Value::Number(_) => {
            m.insert(key.to_owned(), v.clone());
        }
        Value::Bool(b) => {
            m.insert(key.to_owned(), json!(u8::from(*b)));
        }
        Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                add(m, &format!("{key}/{i}"), x);
            }
        }
        Value::Object(o) => {
            for (k, x) in o {
                add(m, &format!("{key}/{k}"), x);
            }
        }
        _ => {}
    }
}

/// The `AIR` object of `air` stamped `timestamp`: each known value as `AIR/name`, or `None`
/// when nothing is known.
pub(crate) fn air_flat(air: &AirData, timestamp: f64) -> Option<Value> {
    let mut m = Map::new();
    m.insert("timestamp".into(), json!(timestamp));
    for (name, v) in [
        ("ias_mps", air.ias_mps),
        ("tas_mps", air.tas_mps),
        ("pressure_altitude_m", air.pressure_altitude_m),
        ("vertical_speed_mps", air.vertical_speed_mps),
    ] {
        if let Some(v) = v {
            m.insert(format!("AIR/{name}"), json!(v));
        }
    }
    (m.len() > 1).then_some(Value::Object(m))
}

/// An AEOLUS PRESSURE or TEMP event as the message it was decoded from.
enum AirMessage {
    Pressure(Pressure),
    Temp(Temp),
}

fn air_message(event: &Event) -> Option<AirMessage> {
    let Body::Message { name, fields, .. } = &event.body else {
        return None;
    };
    // Most messages are neither: told apart by name before any field is looked up.
    if name != "PRESSURE" && name != "TEMP" {
        return None;
    }
    let valid = fields.get("valid")?.as_bool()?;
    let timestamp_ms = fields.get("timestamp_ms")?.as_f64()?;
    let f32_of = |key: &str| fields.get(key).and_then(Value::as_f64).map(|v| v as f32);
    match name.as_str() {
        "PRESSURE" => Some(AirMessage::Pressure(Pressure {
            valid,
            timestamp_ms,
            static_mbar: f32_of("static_mbar")?,
            pitot_mbar: f32_of("pitot_mbar")?,
            airspeed_mps: f32_of("airspeed_mps")?,
        })),
        "TEMP" => Some(AirMessage::Temp(Temp {
            valid,
            timestamp_ms,
            celsius: f32_of("celsius")?,
        })),
        _ => None,
    }
}

/// The host's clock as seconds since the Unix epoch.
pub(crate) fn now() -> f64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .unwrap_or(Duration::ZERO)
        .as_secs_f64()
}

/// A non-blocking sender of flat objects to one address.
#[derive(Debug)]
pub struct PlotSender {
    socket: UdpSocket,
    to: SocketAddr,
    /// Datagrams sent.
    pub(crate) sent: u64,
    /// Datagrams the socket could not take at once (dropped).
    pub(crate) dropped: u64,
    /// The AEOLUS air data, on the plot's clock.
    air: AirDataSource,
    /// The first timestamp and when it was seen: the plot's clock as an [`Instant`].
    clock: Option<(f64, Instant)>,
}

impl PlotSender {
    /// Opens an ephemeral local socket for sending to `to`.
    ///
    /// # Errors
    /// Binding or configuring the socket.
    pub fn new(to: SocketAddr) -> Result<Self> {
        let local: SocketAddr = match to {
            SocketAddr::V4(a) if a.ip().is_loopback() => (Ipv4Addr::LOCALHOST, 0).into(),
            SocketAddr::V4(_) => (Ipv4Addr::UNSPECIFIED, 0).into(),
            SocketAddr::V6(_) => (Ipv6Addr::UNSPECIFIED, 0).into(),
        };
        let open = |source| Error::Open {
            endpoint: format!("udp-json {to}"),
            source,
        };
        let socket = UdpSocket::bind(local).map_err(open)?;
        socket.set_nonblocking(true).map_err(open)?;
        Ok(PlotSender {
            socket,
            to,
            sent: 0,
            dropped: 0,
            air: AirDataSource::default(),
            clock: None,
        })
    }

    /// Sends the flat objects of `events` of `proto` stamped `timestamp` (for AEOLUS, an
    /// `AIR` object after each PRESSURE).
    pub fn send(&mut self, proto: Proto, events: &[Event], timestamp: f64) {
        for e in events {
            if let Some(v) = flat(e, timestamp) {
                self.datagram(&v);
            }
            if proto != Proto::Aeolus {
                continue;
            }
            match air_message(e) {
                Some(AirMessage::Pressure(p)) => {
                    let at = self.instant(timestamp);
                    self.air.take_pressure(&p, at);
                    if let Some(v) = air_flat(&self.air.at(at), timestamp) {
                        self.datagram(&v);
                    }
                }
                Some(AirMessage::Temp(t)) => {
                    let at = self.instant(timestamp);
                    self.air.take(&aeolus_proto::message::Message::Temp(t), at);
                }
                None => {}
            }
        }
    }

    /// `timestamp` on the plot's clock as an [`Instant`] (a step back, or a time beyond what
    /// an `Instant` holds, reads as the first).
    fn instant(&mut self, timestamp: f64) -> Instant {
        let (first, origin) = *self.clock.get_or_insert((timestamp, Instant::now()));
        Duration::try_from_secs_f64(timestamp - first)
            .ok()
            .and_then(|since| origin.checked_add(since))
            .unwrap_or(origin)
    }

    fn datagram(&mut self, v: &Value) {
        match self.socket.send_to(v.to_string().as_bytes(), self.to) {
            Ok(_) => self.sent += 1,
            // Nobody listening (ICMP refused), a full buffer: dropped, counted.
            Err(_) => self.dropped += 1,
        }
    }

    /// The line printed on stderr at the end.
    pub(crate) fn report(&self) -> String {
        format!(
            "udp-json to {}: {} datagrams sent, {} dropped",
            self.to, self.sent, self.dropped
        )
    }
}

/// The examples of this module's items, as tests (the items are crate-private, so rustdoc
/// does not run them).
#[cfg(test)]
#[allow(unused_imports, clippy::unnecessary_wraps)]
mod examples {
    use super::*;

    #[test]
    fn flat_example() -> Result<(), Box<dyn std::error::Error>> {
        use crate::decoders::{Body, Event};
        let e = Event {
            offset: 0,
            body: Body::Message {
                name: "GYRO".into(),
                meta: Default::default(),
                fields: serde_json::json!({"valid": true, "x": 0.5, "m": [1, 2], "t": "x"}),
            },
        };
        assert_eq!(
            flat(&e, 2.5).unwrap().to_string(),
            r#"{"timestamp":2.5,"GYRO/valid":1,"GYRO/x":0.5,"GYRO/m/0":1,"GYRO/m/1":2}"#
        );
        Ok(())
    }

    #[test]
    fn air_flat_example() -> Result<(), Box<dyn std::error::Error>> {
        use crate::air_data::AirData;
        let air = AirData {
            ias_mps: Some(48.5),
            tas_mps: Some(50.0),
            ..AirData::default()
        };
        assert_eq!(
            air_flat(&air, 2.5).unwrap().to_string(),
            r#"{"timestamp":2.5,"AIR/ias_mps":48.5,"AIR/tas_mps":50.0}"#
        );
        assert_eq!(air_flat(&AirData::default(), 2.5), None);
        Ok(())
    }
}
