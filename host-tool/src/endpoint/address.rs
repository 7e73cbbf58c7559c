//! The endpoint syntax: [`Endpoint`] parsed from and shown as `serial:PATH@BAUD`,
//! `tcp:HOST:PORT`, `udp:[ADDR:]PORT`, `file:PATH`, a bare path or `-`; and
//! [`parse_local_addr`] for `PORT` or `ADDR:PORT` arguments.

use std::fmt;
use std::net::{IpAddr, Ipv4Addr, SocketAddr};
use std::path::PathBuf;
use std::str::FromStr;

use crate::error::{Error, Result};

/// The baud rate used when a serial endpoint gives none.
pub const DEFAULT_BAUD: u32 = 115_200;

/// Where bytes come from or go to, parsed from the command line.
///
/// ```
/// use protolink::endpoint::Endpoint;
/// let e: Endpoint = "serial:/dev/ttyUSB0@921600".parse()?;
/// assert_eq!(e, Endpoint::Serial { path: "/dev/ttyUSB0".into(), baud: 921_600 });
/// assert_eq!("udp:5001".parse::<Endpoint>()?.to_string(), "udp:127.0.0.1:5001");
/// assert!("http://example".parse::<Endpoint>().is_err());
/// assert_eq!("capture.bin".parse::<Endpoint>()?, Endpoint::File("capture.bin".into()));
/// # Ok::<(), protolink::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Endpoint {
    /// A serial port and its baud rate.
    Serial {
        /// The device path, e.g. `/dev/ttyUSB0`.
        path: String,
        /// The baud rate.
        baud: u32,
    },
    /// A TCP server to connect to, as `HOST:PORT`.
    Tcp(String),
    /// A local UDP address to bind.
    Udp(SocketAddr),
    /// A file to read.
    File(PathBuf),
    /// Standard input (and standard output for writes).
    Stdio,
}

fn bad(text: &str, reason: impl Into<String>) -> Error {
    Error::Endpoint {
        text: text.to_owned(),
        reason: reason.into(),
    }
}

/// Parses `PORT` (bound to 127.0.0.1) or `ADDR:PORT`.
///
/// ```
/// use protolink::endpoint::parse_local_addr;
/// assert_eq!(parse_local_addr("5002").unwrap().to_string(), "127.0.0.1:5002");
/// assert_eq!(parse_local_addr("0.0.0.0:5002").unwrap().to_string(), "0.0.0.0:5002");
/// assert!(parse_local_addr("99999").is_err());
/// ```
pub fn parse_local_addr(text: &str) -> std::result::Result<SocketAddr, String> {
    if let Ok(port) = text.parse::<u16>() {
        return Ok(SocketAddr::new(IpAddr::V4(Ipv4Addr::LOCALHOST), port));
    }
    text.parse::<SocketAddr>().map_err(|_| {
        format!("'{text}' is neither a port (0..=65535) nor an IP address with a port (ADDR:PORT)")
    })
}

impl FromStr for Endpoint {
    type Err = Error;

    fn from_str(text: &str) -> Result<Self> {
        if text == "-" {
            return Ok(Endpoint::Stdio);
        }
        let known = ["serial", "tcp", "udp", "file"];
        let Some((scheme, rest)) = text
            .split_once(':')
            .filter(|(scheme, _)| known.contains(scheme))
        else {
            // A bare path is a file to read (`protolink decode --from capture.bin`).
            if !text.is_empty() && (!text.contains(':') || std::path::Path::new(text).exists()) {
                return Ok(Endpoint::File(PathBuf::from(text)));
            }
            let kind = text.split_once(':').map_or(text, |(k, _)| k);
            return Err(bad(
                text,
                format!(
                    "unknown kind '{kind}': expected serial:PATH@BAUD, tcp:HOST:PORT, udp:PORT, \
                     file:PATH, a file's path, or - for stdin"
                ),
            ));
        };
        match scheme {
            "serial" => {
                let (path, baud) = match rest.rsplit_once('@') {
                    Some((path, baud)) => {
                        let baud = baud
                            .parse::<u32>()
                            .ok()
                            .filter(|&b| b > 0)
                            .ok_or_else(|| bad(text, format!("'{baud}' is not a baud rate")))?;
                        (path, baud)
                    }
                    None => (rest, DEFAULT_BAUD),
                };
                if path.is_empty() {
                    return Err(bad(text, "the serial port path is empty"));
                }
                Ok(Endpoint::Serial {
                    path: path.to_owned(),
                    baud,
                })
            }
            "tcp" => {
                let Some((host, port)) = rest.rsplit_once(':') else {
                    return Err(bad(text, "expected tcp:HOST:PORT"));
                };
                if host.is_empty() {
                    return Err(bad(text, "the host is empty"));
                }
                if port.parse::<u16>().is_err() {
                    return Err(bad(text, format!("'{port}' is not a port (0..=65535)")));
                }
                Ok(Endpoint::Tcp(rest.to_owned()))
            }
            "udp" => parse_local_addr(rest)
                .map(Endpoint::Udp)
                .map_err(|reason| bad(text, reason)),
            // "file", the only kind left after the filter above.
            _ => {
                if rest.is_empty() {
                    return Err(bad(text, "the file path is empty"));
                }
                Ok(Endpoint::File(PathBuf::from(rest)))
            }
        }
    }
}

impl fmt::Display for Endpoint {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Endpoint::Serial { path, baud } => write!(f, "serial:{path}@{baud}"),
            Endpoint::Tcp(addr) => write!(f, "tcp:{addr}"),
            Endpoint::Udp(addr) => write!(f, "udp:{addr}"),
            Endpoint::File(path) => write!(f, "file:{}", path.display()),
            Endpoint::Stdio => f.write_str("-"),
        }
    }
}
