//! `decode --udp-json ADDR`: one flat JSON object per decoded message, sent as one UDP datagram,
//! the form PlotJuggler's "UDP Server" (JSON message protocol) plots.
//!
//! The object holds `timestamp` (seconds since the Unix epoch: the capture's time for a
//! capture, the host's clock otherwise) and every numeric field as `NAME/field` (booleans as 0
//! or 1, arrays as `NAME/field/i`), e.g.
//! `{"timestamp":1700000000.25,"GYRO/valid":1,"GYRO/timestamp_ms":7.0,"GYRO/x":0.0,...}`.
//! Texts and raw bytes are left out. Sends never block: a datagram the socket cannot take at
//! once is dropped and counted.

use std::net::{Ipv4Addr, Ipv6Addr, SocketAddr, UdpSocket};
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use serde_json::{Map, Value, json};

use crate::decoders::{Body, Event};
use crate::error::{Error, Result};

/// The flat object for one event, or `None` for an error event or a message without numbers.
///
/// ```
/// use protolink::decoders::{Body, Event};
/// use protolink::commands::decode::plot::flat;
/// let e = Event { offset: 0, body: Body::Message {
///     name: "GYRO".into(), meta: Default::default(),
///     fields: serde_json::json!({"valid": true, "x": 0.5, "m": [1, 2], "t": "x"}) } };
/// assert_eq!(flat(&e, 2.5).unwrap().to_string(),
///     r#"{"timestamp":2.5,"GYRO/valid":1,"GYRO/x":0.5,"GYRO/m/0":1,"GYRO/m/1":2}"#);
/// ```
pub fn flat(event: &Event, timestamp: f64) -> Option<Value> {
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

/// The host's clock as seconds since the Unix epoch.
pub fn now() -> f64 {
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
    pub sent: u64,
    /// Datagrams the socket could not take at once (dropped).
    pub dropped: u64,
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
        })
    }

    /// Sends the flat objects of `events` stamped `timestamp`.
    pub fn send(&mut self, events: &[Event], timestamp: f64) {
        for e in events {
            if let Some(v) = flat(e, timestamp) {
                match self.socket.send_to(v.to_string().as_bytes(), self.to) {
                    Ok(_) => self.sent += 1,
                    // Nobody listening (ICMP refused), a full buffer: dropped, counted.
                    Err(_) => self.dropped += 1,
                }
            }
        }
    }

    /// The line printed on stderr at the end.
    pub fn report(&self) -> String {
        format!(
            "udp-json to {}: {} datagrams sent, {} dropped",
            self.to, self.sent, self.dropped
        )
    }
}
