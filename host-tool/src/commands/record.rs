//! `protolink record`: an endpoint's traffic into a pcapng file, written as it arrives.
//!
//! UDP endpoints are recorded as Ethernet/IPv4/UDP packets with the real addresses, ports and
//! arrival times; byte streams as timestamped chunks on a link type naming the protocol
//! (see [`crate::capture`] for the mapping). Nothing is held beyond one read buffer.

use std::net::{SocketAddr, SocketAddrV4, UdpSocket};
use std::path::PathBuf;
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use clap::Args;

use crate::capture::{CaptureWriter, StreamKind};
use crate::endpoint::{Endpoint, Input};
use crate::error::{Error, Result};
use crate::proto::{ProfileArg, Proto, Side};
use crate::stop::{self, Deadline};

/// Arguments of `protolink record`.
#[derive(Debug, Clone, Args)]
pub(crate) struct RecordArgs {
    /// What to record (udp:PORT, serial:PATH@BAUD, tcp:HOST:PORT, file:PATH, -).
    #[arg(long, value_name = "ENDPOINT")]
    pub(crate) from: Endpoint,
    /// The pcapng file to write (replaced if it exists).
    #[arg(long, value_name = "FILE")]
    pub(crate) out: PathBuf,
    /// Byte streams: the protocol they carry, which picks the link type (UDP ignores it).
    #[arg(long, value_enum, default_value_t = Proto::Aeolus)]
    pub(crate) proto: Proto,
    /// Byte streams of AYDP: the profile (link type USER1 spec, USER2 reference).
    #[arg(long, value_enum, default_value_t = ProfileArg::Spec)]
    pub(crate) profile: ProfileArg,
    /// Byte streams of AOK: who sent the bytes (link type USER3 pc, USER4 device).
    #[arg(long, value_enum, default_value_t = Side::Device)]
    pub(crate) side: Side,
    /// Stop after this long: `10` (seconds), `500ms`, `2min` (default: at the end of the input, or on Ctrl-C).
    #[arg(long, value_name = "DURATION", value_parser = crate::args::run_time)]
    pub(crate) seconds: Option<Duration>,
}

/// What `record` wrote, for its last line and for tests.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) struct Recorded {
    /// Records written.
    pub(crate) packets: u64,
    /// Payload bytes written.
    pub(crate) bytes: u64,
    /// UDP datagrams from an IPv6 sender, which an IPv4 record cannot hold: dropped, counted.
    pub(crate) dropped_ipv6: u64,
}

fn now() -> Duration {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .unwrap_or(Duration::ZERO)
}

/// Runs `protolink record`.
///
/// # Errors
/// Opening the endpoint or the file, reading, or writing.
pub(crate) fn run(args: &RecordArgs) -> Result<()> {
    stop::install_ctrl_c();
    let deadline = Deadline::after(args.seconds);
    let r = record(args, deadline)?;
    eprintln!(
        "recorded {} packets, {} bytes to {}{}",
        r.packets,
        r.bytes,
        args.out.display(),
        if r.dropped_ipv6 > 0 {
            format!(" ({} IPv6 datagrams dropped)", r.dropped_ipv6)
        } else {
            String::new()
        }
    );
    Ok(())
}

/// Records until the input ends or `deadline` passes.
///
/// # Errors
/// Opening the endpoint or the file, reading, or writing.
pub(crate) fn record(args: &RecordArgs, deadline: Deadline) -> Result<Recorded> {
    match &args.from {
        Endpoint::Udp(addr) => record_udp(*addr, args, deadline),
        other => record_stream(other, args, deadline),
    }
}

fn record_udp(addr: SocketAddr, args: &RecordArgs, deadline: Deadline) -> Result<Recorded> {
    let name = format!("udp:{addr}");
    let SocketAddr::V4(local) = addr else {
        return Err(Error::Unsupported(format!(
            "cannot record {name}: only IPv4 UDP endpoints can be recorded"
        )));
    };
    let socket = UdpSocket::bind(addr).map_err(|source| Error::Open {
        endpoint: name.clone(),
        source,
    })?;
    let mut out = CaptureWriter::create(&args.out, 1, &name)?;
    let mut buf = vec![0u8; 65_536];
    let mut r = Recorded::default();
    let io = |source| Error::Io {
        what: format!("reading from {name}"),
        source,
    };
    while !deadline.reached() {
        socket
            .set_read_timeout(Some(
                deadline
                    .left(Duration::from_millis(100))
                    .max(Duration::from_millis(1)),
            ))
            .map_err(io)?;
        match socket.recv_from(&mut buf) {
            Ok((n, SocketAddr::V4(from))) => {
                // A socket bound to 0.0.0.0 records the loopback address as its own.
                let dst = if local.ip().is_unspecified() {
                    SocketAddrV4::new(std::net::Ipv4Addr::LOCALHOST, local.port())
                } else {
                    local
                };
                out.udp(now(), from, dst, &buf[..n])?;
                r.packets += 1;
                r.bytes += n as u64;
            }
            Ok((_, SocketAddr::V6(_))) => r.dropped_ipv6 += 1,
            Err(e)
                if matches!(
                    e.kind(),
                    std::io::ErrorKind::WouldBlock
                        | std::io::ErrorKind::TimedOut
                        | std::io::ErrorKind::Interrupted
                ) =>
            {
                out.flush()?;
            }
            Err(e) => return Err(io(e)),
        }
    }
    out.flush()?;
    Ok(r)
}

fn record_stream(from: &Endpoint, args: &RecordArgs, deadline: Deadline) -> Result<Recorded> {
    let kind = StreamKind {
        proto: args.proto,
        profile: args.profile,
        side: args.side,
    };
    let mut link = from.open()?;
    let mut out = CaptureWriter::create(&args.out, kind.link_type(), link.name())?;
    let mut buf = vec![0u8; 65_536];
    let mut r = Recorded::default();
    while !deadline.reached() {
        match link.read(&mut buf, deadline.left(Duration::from_millis(100)))? {
            Input::Data(n) => {
                out.chunk(now(), &buf[..n])?;
                r.packets += 1;
                r.bytes += n as u64;
            }
            Input::Idle => out.flush()?,
            Input::End => break,
        }
    }
    out.flush()?;
    Ok(r)
}
