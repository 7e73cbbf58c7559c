//! `protolink replay`: a capture's payloads sent to an endpoint with their original timing,
//! or faster, once or in a loop.
//!
//! Every UDP payload, TCP payload and stream chunk is sent in capture order; other packets are
//! skipped. To a `udp:ADDR:PORT` endpoint each one is one datagram sent to that address (from
//! an ephemeral local port); to `tcp:`, `serial:` and `-` the bytes are written to the stream;
//! to `file:` they are written to a new file.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::net::{SocketAddr, UdpSocket};
use std::path::PathBuf;
use std::time::{Duration, Instant};

use clap::Args;

use crate::capture::{CaptureReader, Payload};
use crate::endpoint::udp_out::bind_for;
use crate::endpoint::{Endpoint, Link};
use crate::error::{Error, Result};
use crate::stop::{self, Deadline};

/// Arguments of `protolink replay`.
#[derive(Debug, Clone, Args)]
pub(crate) struct ReplayArgs {
    /// The capture (pcapng or pcap).
    #[arg(value_name = "FILE")]
    pub(crate) file: PathBuf,
    /// Where to send it: udp:ADDR:PORT (a datagram each), tcp:HOST:PORT, serial:PATH@BAUD, file:PATH, -.
    #[arg(long, value_name = "ENDPOINT")]
    pub(crate) to: Endpoint,
    /// How much faster than recorded: 2 is twice as fast, 0.5 half (0.01 to 1000).
    #[arg(long, value_name = "X", default_value = "1", value_parser = speed)]
    pub(crate) speed: f64,
    /// Start again at the end, until --seconds or Ctrl-C.
    #[arg(long = "loop")]
    pub(crate) repeat: bool,
    /// Stop after this long: `10` (seconds), `500ms`, `2min` (default: at the end of the capture, or on Ctrl-C).
    #[arg(long, value_name = "DURATION", value_parser = crate::args::run_time)]
    pub(crate) seconds: Option<Duration>,
}

/// Parses `--speed`: a finite number from 0.01 to 1000.
///
/// # Errors
/// One sentence naming the range.
pub(crate) fn speed(text: &str) -> std::result::Result<f64, String> {
    crate::args::number_in(text, 0.01, 1000.0, "times the recorded speed").map(f64::from)
}

enum Sink {
    Udp { socket: UdpSocket, to: SocketAddr },
    Link(Link),
    File(BufWriter<File>, String),
}

impl Sink {
    fn open(to: &Endpoint) -> Result<Self> {
        match to {
            Endpoint::Udp(addr) => Ok(Sink::Udp {
                socket: bind_for(*addr, false)?,
                to: *addr,
            }),
            Endpoint::File(path) => {
                let f = File::create(path).map_err(|source| Error::Open {
                    endpoint: to.to_string(),
                    source,
                })?;
                Ok(Sink::File(BufWriter::new(f), to.to_string()))
            }
            other => Ok(Sink::Link(other.open()?)),
        }
    }

    fn send(&mut self, bytes: &[u8]) -> Result<()> {
        match self {
            Sink::Udp { socket, to } => {
                socket
                    .send_to(bytes, *to)
                    .map(|_| ())
                    .map_err(|source| Error::Io {
                        what: format!("sending to udp:{to}"),
                        source,
                    })
            }
            Sink::Link(link) => link.write_all(bytes),
            Sink::File(f, name) => f.write_all(bytes).map_err(|source| Error::Io {
                what: format!("writing {name}"),
                source,
            }),
        }
    }

    fn flush(&mut self) -> Result<()> {
        match self {
            Sink::File(f, name) => f.flush().map_err(|source| Error::Io {
                what: format!("writing {name}"),
                source,
            }),
            _ => Ok(()),
        }
    }
}

/// What `replay` sent.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) struct Replayed {
    /// Payloads sent.
    pub(crate) sent: u64,
    /// Payload bytes sent.
    pub(crate) bytes: u64,
    /// Records skipped (not UDP, TCP or one of our stream link types, or empty).
    pub(crate) skipped: u64,
    /// Passes through the capture begun.
    pub(crate) passes: u64,
}

/// Runs `protolink replay`.
///
/// # Errors
/// Opening or reading the capture, or sending.
pub(crate) fn run(args: &ReplayArgs) -> Result<()> {
    stop::install_ctrl_c();
    let r = replay(args, Deadline::after(args.seconds))?;
    eprintln!(
        "replayed {} payloads, {} bytes in {} pass(es); {} records skipped",
        r.sent, r.bytes, r.passes, r.skipped
    );
    Ok(())
}

/// Sleeps until `at`, waking for the deadline; false when the deadline came first.
fn wait_until(at: Instant, deadline: Deadline) -> bool {
    loop {
        if deadline.reached() {
            return false;
        }
        let now = Instant::now();
        if now >= at {
            return true;
        }
        std::thread::sleep(deadline.left((at - now).min(Duration::from_millis(50))));
    }
}

/// Replays until the capture ends (or, with `--loop`, until `deadline`).
///
/// # Errors
/// Opening or reading the capture, or sending.
pub(crate) fn replay(args: &ReplayArgs, deadline: Deadline) -> Result<Replayed> {
    // Checked before anything is sent, so a wrong file is reported at once.
    CaptureReader::open(&args.file)?;
    let mut sink = Sink::open(&args.to)?;
    let mut r = Replayed::default();
    'passes: while !deadline.reached() {
        let mut reader = CaptureReader::open(&args.file)?;
        r.passes += 1;
        let start = Instant::now();
        let mut first: Option<Duration> = None;
        let mut sent_this_pass = 0u64;
        while let Some(rec) = reader.next_record()? {
            let bytes = match rec.payload {
                Payload::Ip { bytes, .. } | Payload::Stream { bytes, .. } if !bytes.is_empty() => {
                    bytes
                }
                _ => {
                    r.skipped += 1;
                    continue;
                }
            };
            let t0 = *first.get_or_insert(rec.time);
            let offset = rec.time.saturating_sub(t0).as_secs_f64() / args.speed;
            let at = start
                .checked_add(Duration::try_from_secs_f64(offset).unwrap_or(Duration::ZERO))
                .unwrap_or(start);
            if !wait_until(at, deadline) {
                break 'passes;
            }
            sink.send(&bytes)?;
            r.sent += 1;
            r.bytes += bytes.len() as u64;
            sent_this_pass += 1;
        }
        // A capture with nothing to send would loop without pause.
        if !args.repeat || sent_this_pass == 0 {
            break;
        }
    }
    sink.flush()?;
    Ok(r)
}

/// The examples of this module's items, as tests (the items are crate-private, so rustdoc
/// does not run them).
#[cfg(test)]
#[allow(unused_imports, clippy::unnecessary_wraps)]
mod examples {
    use super::*;

    #[test]
    fn speed_example() -> Result<(), Box<dyn std::error::Error>> {
        assert_eq!(speed("4"), Ok(4.0));
        assert!(speed("0").is_err());
        assert!(speed("NaN").is_err());
        Ok(())
    }
}
