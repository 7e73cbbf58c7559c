//! `protolink web`: a glass cockpit in the browser, fed live from an AEOLUS endpoint.
//!
//! | module | holds |
//! | --- | --- |
//! | [`state`] | the model ([`View`](crate::telemetry::View), as `watch` shows it, plus track and jitter) and the JSON [`state::State`] |
//! | [`hub`] | the one-slot hub: the decoder publishes the newest snapshot, each stream takes it when ready |
//! | [`server`] | the bounded read-only HTTP server: the page, `GET /api/state`, `GET /events` (server-sent events) |
//! | [`assets`] | the page, its script and style, built into the binary (no network needed) |
//!
//! [`run`] reads the endpoint on the calling thread, exactly as `watch` does, and publishes a
//! snapshot [`DISPLAY_RATE_HZ`] times a second; the server sends each client the newest one
//! when it is ready for it. So 1,000 messages a second cost the browser 20 updates.

pub(crate) mod assets;
pub(crate) mod hub;
pub(crate) mod server;
pub mod state;

use std::io::Write as _;
use std::net::{IpAddr, SocketAddr};
use std::time::{Duration, Instant};

use clap::Args;

use crate::endpoint::{Endpoint, Input};
use crate::error::Result;
use crate::render::{Out, text, to_json};
use crate::stop::{self, Deadline};
use server::Server;
use state::Cockpit;

/// How many snapshots a second the page gets.
pub(crate) const DISPLAY_RATE_HZ: u32 = 20;

/// The address `protolink web` listens on unless told otherwise.
pub(crate) const DEFAULT_LISTEN: &str = "127.0.0.1:8080";

/// Arguments of `protolink web`.
#[derive(Debug, Clone, Args)]
pub(crate) struct WebArgs {
    /// Where the AEOLUS telemetry comes from (tcp:HOST:PORT, udp:PORT, serial:PATH@BAUD, file:PATH, -).
    #[arg(long, value_name = "ENDPOINT")]
    pub(crate) from: Endpoint,
    /// The address the page is served on: IP:PORT (port 0 picks a free one). Anything but a
    /// loopback address shows the page to the network.
    #[arg(long, value_name = "IP:PORT", default_value = DEFAULT_LISTEN, value_parser = listen_addr)]
    pub(crate) listen: SocketAddr,
    /// Stop after this long: `10` (seconds), `500ms`, `2min` (default: on Ctrl-C).
    #[arg(long, value_name = "DURATION", value_parser = crate::args::run_time)]
    pub(crate) seconds: Option<Duration>,
    /// Display units: `si` (m/s, m, as the box sends them) or `aviation` (knots, feet, feet
    /// per minute).
    #[arg(long, value_enum, default_value_t = crate::units::Units::Si)]
    pub(crate) units: crate::units::Units,
}

/// Parses `--listen`: an IP address and a port, such as `127.0.0.1:8080` or `[::1]:8080`.
///
/// # Errors
/// A sentence naming the expected form.
pub(crate) fn listen_addr(text: &str) -> std::result::Result<SocketAddr, String> {
    text.trim().parse::<SocketAddr>().map_err(|_| {
        format!(
            "'{text}' is not an address to listen on: expected IP:PORT, such as 127.0.0.1:8080 \
             or [::1]:8080 (port 0 picks a free one)"
        )
    })
}

fn is_loopback(ip: IpAddr) -> bool {
    ip.is_loopback()
}

/// Runs `protolink web`.
///
/// # Errors
/// Opening or reading the endpoint, binding the address, or writing the output.
pub(crate) fn run(args: &WebArgs) -> Result<()> {
    let mut link = args.from.open()?;
    let server = Server::start(args.listen)?;
    stop::install_ctrl_c();
    let deadline = Deadline::after(args.seconds);
    let source = link.name().to_string();
    {
        let mut err = std::io::stderr().lock();
        let _ = writeln!(
            err,
            "web: http://{}/ shows {source} (Ctrl-C to stop)",
            server.addr()
        );
        if !is_loopback(server.addr().ip()) {
            let _ = writeln!(
                err,
                "web: {} is not a loopback address: the page is visible to the network (read-only)",
                server.addr().ip()
            );
        }
        let _ = err.flush();
    }
    let frame = Duration::from_secs(1) / DISPLAY_RATE_HZ;
    let started = Instant::now();
    let mut cockpit = Cockpit::new(&source, started).with_units(args.units);
    let mut buf = vec![0u8; 65_536];
    let mut next_frame = started;
    let mut ended = false;
    while !deadline.reached() {
        let wait = deadline.left(next_frame.saturating_duration_since(Instant::now()));
        if ended {
            std::thread::sleep(wait);
        } else {
            match link.read(&mut buf, wait)? {
                Input::Data(n) => {
                    cockpit.feed(&buf[..n], link.is_datagram(), Instant::now());
                }
                Input::Idle => {}
                Input::End => {
                    // The page keeps showing the last state until Ctrl-C or --seconds.
                    ended = true;
                    let _ = writeln!(std::io::stderr(), "web: end of {source}; still serving");
                }
            }
        }
        let now = Instant::now();
        if now >= next_frame {
            let state = cockpit.state(now, server.counters());
            let json = serde_json::to_string(&state).unwrap_or_else(|_| "{}".to_owned());
            server.hub().publish(json);
            next_frame += frame;
            if next_frame < now {
                next_frame = now + frame;
            }
        }
    }
    let now = Instant::now();
    let last = cockpit.state(now, server.counters());
    drop(server);
    let mut out = Out::new();
    let mut summary = to_json(&last.server);
    if let serde_json::Value::Object(map) = &mut summary {
        map.insert("bytes".into(), last.bytes.into());
        map.insert(
            "seconds".into(),
            serde_json::json!((cockpit.uptime(now).as_secs_f64() * 10.0).round() / 10.0),
        );
    }
    out.line(&format!("web: {}", text(&summary)))?;
    out.flush()
}

/// The examples of this module's items, as tests (the items are crate-private, so rustdoc
/// does not run them).
#[cfg(test)]
#[allow(unused_imports, clippy::unnecessary_wraps)]
mod examples {
    use super::*;

    #[test]
    fn listen_addr_example() -> Result<(), Box<dyn std::error::Error>> {
        assert_eq!(listen_addr("127.0.0.1:8080").unwrap().port(), 8080);
        assert!(
            listen_addr("localhost:8080")
                .unwrap_err()
                .contains("IP:PORT")
        );
        assert!(listen_addr("127.0.0.1").is_err());
        assert!(listen_addr("127.0.0.1:65536").is_err());
        Ok(())
    }
}
