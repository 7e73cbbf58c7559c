//! Sending datagrams to a destination, the same way in every command that sends (`sim`,
//! `bridge`, `gdl90`, `nmea --to`, `replay`, `aeolus`): from a socket of the destination's
//! family ([`bind_for`]), and with one rule for the run's outcome ([`Sends::check`]).

use std::fmt;
use std::io;
use std::net::{IpAddr, Ipv4Addr, Ipv6Addr, SocketAddr, UdpSocket};

use crate::error::{Error, Result};

/// A UDP socket to send to `to` from: bound to an ephemeral port of `to`'s family (IPv4 or
/// IPv6), on the loopback address when `to` is a loopback address and `every_interface` is
/// false, on every interface otherwise.
///
/// # Errors
/// [`Error::Open`] when the system cannot bind it (no IPv6 on this machine, say).
pub(crate) fn bind_for(to: SocketAddr, every_interface: bool) -> Result<UdpSocket> {
    let local = to.ip().is_loopback() && !every_interface;
    let ip: IpAddr = match (to, local) {
        (SocketAddr::V4(_), true) => Ipv4Addr::LOCALHOST.into(),
        (SocketAddr::V4(_), false) => Ipv4Addr::UNSPECIFIED.into(),
        (SocketAddr::V6(_), true) => Ipv6Addr::LOCALHOST.into(),
        (SocketAddr::V6(_), false) => Ipv6Addr::UNSPECIFIED.into(),
    };
    UdpSocket::bind((ip, 0)).map_err(|source| Error::Open {
        endpoint: format!("a UDP socket for {to}"),
        source,
    })
}

/// What a run sent to its destination: datagrams that went out, sends that failed, and the
/// last failure's reason.
#[derive(Debug, Default)]
pub(crate) struct Sends {
    /// Datagrams sent.
    pub(crate) sent: u64,
    /// Datagrams whose send failed.
    pub(crate) failed: u64,
    last_error: Option<io::Error>,
}

impl Sends {
    /// Counts one send's result; whether the datagram went out.
    pub(crate) fn count<T>(&mut self, result: io::Result<T>) -> bool {
        match result {
            Ok(_) => {
                self.sent += 1;
                true
            }
            Err(e) => {
                self.failed += 1;
                self.last_error = Some(e);
                false
            }
        }
    }

    /// The outcome of a run that sends: it fails when datagrams were to go out to `to` and
    /// not one did, naming how many and the last reason, so that a run whose every send
    /// failed never looks like one that worked. A run that got at least one datagram out, or
    /// had none to send, succeeds (its counters tell the rest).
    ///
    /// # Errors
    /// [`Error::Io`] with the last send error.
    pub(crate) fn check(&mut self, to: impl fmt::Display) -> Result<()> {
        match self.last_error.take() {
            Some(source) if self.sent == 0 => Err(Error::Io {
                what: format!("sending every one of {} datagrams to {to}", self.failed),
                source,
            }),
            _ => Ok(()),
        }
    }
}

/// The examples of this module's items, as tests (the items are crate-private, so rustdoc
/// does not run them).
#[cfg(test)]
#[allow(unused_imports, clippy::unnecessary_wraps)]
mod examples {
    use super::*;

    #[test]
    fn bind_for_example() -> Result<(), Box<dyn std::error::Error>> {
        let to: SocketAddr = "127.0.0.1:4000".parse()?;
        assert!(bind_for(to, false)?.local_addr()?.ip().is_loopback());
        assert!(bind_for(to, true)?.local_addr()?.ip().is_unspecified());
        // An IPv6 destination gets an IPv6 socket (where the system has IPv6).
        if UdpSocket::bind("[::1]:0").is_ok() {
            assert!(
                bind_for("[::1]:4000".parse()?, false)?
                    .local_addr()?
                    .is_ipv6()
            );
        }
        Ok(())
    }

    #[test]
    fn sends_example() -> Result<(), Box<dyn std::error::Error>> {
        let mut sends = Sends::default();
        assert!(sends.check("127.0.0.1:0").is_ok(), "nothing to send");
        assert!(!sends.count(Err::<usize, _>(io::Error::other("refused"))));
        let err = sends.check("127.0.0.1:0").unwrap_err().to_string();
        assert_eq!(
            err,
            "sending every one of 1 datagrams to 127.0.0.1:0 failed: refused"
        );
        let mut sends = Sends::default();
        sends.count(Ok(8));
        sends.count(Err::<usize, _>(io::Error::other("refused")));
        assert!(sends.check("127.0.0.1:0").is_ok(), "one went out");
        Ok(())
    }
}
