//! The UDP side of an AEOLUS box, shared by `bridge` and `sim`: escaped frames packed into
//! datagrams ([`Packer`]), the in-port datagrams arrive on, and the `--udp-out`, `--udp-in`,
//! `--pack` and `--broadcast` arguments ([`UdpArgs`]).

use std::io;
use std::net::{IpAddr, SocketAddr, UdpSocket};
use std::time::{Duration, Instant};

use clap::Args;

use crate::endpoint::parse_local_addr;
use crate::endpoint::udp_out::{Sends, bind_for};
use crate::error::{Error, Result};

/// The largest datagram a pack may grow to: one Ethernet MTU less the IP and UDP headers, so
/// datagrams are never fragmented. A single larger frame still goes out, alone.
pub(crate) const MAX_DATAGRAM: usize = 1472;
/// How long a partly filled pack may wait for more frames.
pub(crate) const PACK_HOLD: Duration = Duration::from_millis(20);

/// The UDP side of a box, shared by `bridge` and `sim`: where datagrams go, where they arrive,
/// how many frames a datagram packs.
#[derive(Debug, Clone, Args)]
pub(crate) struct UdpArgs {
    /// Where datagrams go: PORT (on 127.0.0.1) or ADDR:PORT.
    #[arg(long, value_name = "[ADDR:]PORT", default_value = "127.0.0.1:5001", value_parser = parse_local_addr)]
    pub(crate) udp_out: SocketAddr,
    /// The port datagrams for the box arrive on: PORT (bound to 127.0.0.1) or ADDR:PORT
    /// (0.0.0.0:5002 listens on every interface).
    #[arg(long, value_name = "[ADDR:]PORT", default_value = "5002", value_parser = parse_local_addr)]
    pub(crate) udp_in: SocketAddr,
    /// Pack up to N frames into one datagram (1: one frame per datagram).
    #[arg(long, value_name = "N", default_value_t = 1, value_parser = clap::value_parser!(u16).range(1..))]
    pub(crate) pack: u16,
    /// Send to this broadcast address instead (on the --udp-out port). Never a default.
    #[arg(long, value_name = "ADDR")]
    pub(crate) broadcast: Option<IpAddr>,
}

impl UdpArgs {
    /// Where datagrams go: `--udp-out`, or the `--broadcast` address on its port.
    pub(crate) fn destination(&self) -> SocketAddr {
        match self.broadcast {
            Some(addr) => SocketAddr::new(addr, self.udp_out.port()),
            None => self.udp_out,
        }
    }

    /// The [`Packer`] for the destination and the bound, non-blocking in-port.
    ///
    /// # Errors
    /// A socket cannot be bound.
    pub(crate) fn open(&self) -> Result<(Packer, UdpSocket)> {
        let packer = Packer::open(self.destination(), self.broadcast.is_some(), self.pack)?;
        Ok((packer, bind_in_port(self.udp_in)?))
    }
}

/// What a [`Packer`] has sent.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub(crate) struct SendCounters {
    /// Frames that went out inside a datagram.
    pub(crate) frames: u64,
    /// Datagrams sent.
    pub(crate) datagrams: u64,
    /// Datagrams whose send failed.
    pub(crate) errors: u64,
}

/// Most datagrams taken from the in-port per turn of a loop, so a flood cannot keep the loop
/// from its other work.
pub(crate) const DATAGRAMS_PER_TURN: usize = 64;
/// Packs escaped AEOLUS frames into UDP datagrams and sends them: up to `pack` frames per
/// datagram, never more than [`MAX_DATAGRAM`] bytes (a single longer frame goes out alone),
/// and a partly filled pack waits at most [`PACK_HOLD`]. Used by `bridge` and `sim`.
#[derive(Debug)]
pub(crate) struct Packer {
    socket: UdpSocket,
    to: SocketAddr,
    limit: usize,
    pack: Vec<u8>,
    frames: usize,
    since: Option<Instant>,
    /// Frames that went out inside a datagram.
    frames_sent: u64,
    sends: Sends,
}

impl Packer {
    /// A packer sending to `to` (from an ephemeral port of `to`'s family, on the loopback
    /// address when `to` is one, on every interface otherwise: [`bind_for`]), `pack` frames
    /// per datagram at most (0 is taken as 1). `broadcast` allows a broadcast destination.
    ///
    /// # Errors
    /// Binding the socket or allowing broadcast fails.
    pub(crate) fn open(to: SocketAddr, broadcast: bool, pack: u16) -> Result<Self> {
        let socket = bind_for(to, false)?;
        if broadcast {
            socket.set_broadcast(true).map_err(|source| Error::Open {
                endpoint: format!("a UDP socket for {to}"),
                source,
            })?;
        }
        Ok(Packer {
            socket,
            to,
            limit: usize::from(pack.max(1)),
            pack: Vec::with_capacity(MAX_DATAGRAM),
            frames: 0,
            since: None,
            frames_sent: 0,
            sends: Sends::default(),
        })
    }

    /// Where the datagrams go.
    pub(crate) fn destination(&self) -> SocketAddr {
        self.to
    }

    /// What has been sent so far.
    pub(crate) fn counters(&self) -> SendCounters {
        SendCounters {
            frames: self.frames_sent,
            datagrams: self.sends.sent,
            errors: self.sends.failed,
        }
    }

    /// Fails when datagrams were to be sent and not one of them went out, naming the last
    /// reason ([`Sends::check`], the rule of every command that sends).
    ///
    /// # Errors
    /// [`Error::Io`] with the last send error.
    pub(crate) fn check(&mut self) -> Result<()> {
        self.sends.check(self.to)
    }

    /// Adds one escaped frame (flags included); sends the pack when it is full.
    pub(crate) fn push(&mut self, wire: &[u8]) {
        if !self.pack.is_empty() && self.pack.len() + wire.len() > MAX_DATAGRAM {
            self.flush();
        }
        self.pack.extend_from_slice(wire);
        self.frames += 1;
        self.since.get_or_insert_with(Instant::now);
        if self.frames >= self.limit {
            self.flush();
        }
    }

    /// Sends a partly filled pack that has waited [`PACK_HOLD`].
    pub(crate) fn poll(&mut self) {
        if self.since.is_some_and(|t| t.elapsed() >= PACK_HOLD) {
            self.flush();
        }
    }

    /// Sends what is packed now.
    pub(crate) fn flush(&mut self) {
        if self.pack.is_empty() {
            return;
        }
        if self.sends.count(self.socket.send_to(&self.pack, self.to)) {
            self.frames_sent += self.frames as u64;
        }
        self.pack.clear();
        self.frames = 0;
        self.since = None;
    }
}

/// Binds the in-port (`udp_in`), non-blocking.
///
/// # Errors
/// The address is taken or cannot be bound.
pub(crate) fn bind_in_port(udp_in: SocketAddr) -> Result<UdpSocket> {
    let open_err = |source| Error::Open {
        endpoint: format!("udp:{udp_in}"),
        source,
    };
    let socket = UdpSocket::bind(udp_in).map_err(open_err)?;
    socket.set_nonblocking(true).map_err(open_err)?;
    Ok(socket)
}

/// Takes the datagrams waiting on the non-blocking `socket`, at most [`DATAGRAMS_PER_TURN`],
/// handing each to `f`. Returns how many it took.
///
/// # Errors
/// Receiving fails for another reason than "nothing waiting".
pub(crate) fn receive_some(
    socket: &UdpSocket,
    buf: &mut [u8],
    mut f: impl FnMut(&[u8]),
) -> Result<usize> {
    let mut taken = 0;
    while taken < DATAGRAMS_PER_TURN {
        match socket.recv_from(buf) {
            Ok((n, _from)) => {
                taken += 1;
                f(buf.get(..n).unwrap_or(&[]));
            }
            Err(e) if e.kind() == io::ErrorKind::WouldBlock => break,
            Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
            Err(source) => {
                return Err(Error::Io {
                    what: format!(
                        "receiving on udp:{}",
                        socket
                            .local_addr()
                            .map_or_else(|_| "?".to_owned(), |a| a.to_string())
                    ),
                    source,
                });
            }
        }
    }
    Ok(taken)
}

/// The examples of this module's items, as tests (the items are crate-private, so rustdoc
/// does not run them).
#[cfg(test)]
#[allow(unused_imports, clippy::unnecessary_wraps)]
mod examples {
    use super::*;

    #[test]
    fn destination_example() -> Result<(), Box<dyn std::error::Error>> {
        use clap::Parser;
        #[derive(Parser)]
        struct Cli {
            #[command(flatten)]
            udp: UdpArgs,
        }
        let cli = Cli::parse_from(["x", "--udp-out", "6001"]);
        assert_eq!(cli.udp.destination().to_string(), "127.0.0.1:6001");
        let cli = Cli::parse_from(["x", "--broadcast", "10.0.0.255"]);
        assert_eq!(cli.udp.destination().to_string(), "10.0.0.255:5001");
        Ok(())
    }

    #[test]
    fn packer_example() -> Result<(), Box<dyn std::error::Error>> {
        use std::net::UdpSocket;
        let rx = UdpSocket::bind("127.0.0.1:0")?;
        let mut packer = Packer::open(rx.local_addr()?, false, 2)?;
        let toast = [0x7E, 0x52, b'h', b'i', 0, 0x73, 0xEC, 0x7E];
        packer.push(&toast); // held: the pack takes two frames
        packer.push(&toast); // full: sent
        let mut buf = [0u8; 64];
        assert_eq!(rx.recv(&mut buf)?, 16);
        assert_eq!(packer.counters().frames, 2);
        Ok(())
    }
}
