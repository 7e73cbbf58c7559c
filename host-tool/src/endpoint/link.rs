//! The byte streams an [`Endpoint`] opens ([`Endpoint::open`]): a [`Link`] that reads with a
//! timeout (whole datagrams on UDP, stdin through a bounded queue) and writes.

use std::fmt;
use std::fs::File;
use std::io::{self, Read, Write};
use std::net::{SocketAddr, TcpStream, ToSocketAddrs, UdpSocket};
use std::sync::mpsc::{Receiver, RecvTimeoutError, sync_channel};
use std::time::Duration;

use super::Endpoint;
use crate::error::{Error, Result};

/// How many 64 KiB chunks of stdin may wait to be decoded: the reader thread blocks beyond
/// that, so a fast producer is slowed down instead of filling memory.
pub const STDIN_CHUNKS: usize = 4;
/// How long connecting to a TCP endpoint may take.
pub const CONNECT_TIMEOUT: Duration = Duration::from_secs(5);

/// What one [`Link::read`] got.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Input {
    /// This many bytes (for UDP: one whole datagram).
    Data(usize),
    /// Nothing arrived within the timeout.
    Idle,
    /// The stream ended (end of file, or the peer closed the connection).
    End,
}

enum Kind {
    #[cfg(feature = "serial")]
    Serial(Box<dyn serialport::SerialPort>),
    Tcp(TcpStream),
    Udp {
        socket: UdpSocket,
        peer: Option<SocketAddr>,
    },
    File(File),
    Stdio {
        chunks: Receiver<io::Result<Vec<u8>>>,
        pending: Vec<u8>,
        ended: bool,
    },
}

/// An open endpoint: a byte stream with timed reads.
pub struct Link {
    kind: Kind,
    name: String,
}

impl fmt::Debug for Link {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Link").field("name", &self.name).finish()
    }
}

fn timeout_or_tick(timeout: Duration) -> Duration {
    // A zero timeout means "block forever" to the socket APIs.
    timeout.max(Duration::from_millis(1))
}

fn is_timeout(e: &io::Error) -> bool {
    matches!(
        e.kind(),
        io::ErrorKind::WouldBlock | io::ErrorKind::TimedOut | io::ErrorKind::Interrupted
    )
}

impl Endpoint {
    /// Opens the endpoint.
    ///
    /// ```
    /// use protolink::endpoint::{Endpoint, Input};
    /// let dir = std::env::temp_dir().join(format!("protolink-doc-{}", std::process::id()));
    /// std::fs::write(&dir, b"abc")?;
    /// let mut link = Endpoint::File(dir.clone()).open()?;
    /// let mut buf = [0u8; 8];
    /// assert_eq!(link.read(&mut buf, std::time::Duration::from_millis(10))?, Input::Data(3));
    /// assert_eq!(link.read(&mut buf, std::time::Duration::from_millis(10))?, Input::End);
    /// std::fs::remove_file(dir)?;
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    ///
    /// # Errors
    /// [`Error::Open`] with the operating system's reason.
    pub fn open(&self) -> Result<Link> {
        let name = self.to_string();
        let open_err = |source: io::Error| Error::Open {
            endpoint: name.clone(),
            source,
        };
        let kind = match self {
            #[cfg(not(feature = "serial"))]
            Endpoint::Serial { .. } => {
                return Err(Error::Unsupported(format!(
                    "cannot open {name}: this protolink was built without serial ports (its `serial` feature)"
                )));
            }
            #[cfg(feature = "serial")]
            Endpoint::Serial { path, baud } => {
                let port = serialport::new(path, *baud)
                    .timeout(Duration::from_millis(10))
                    .open()
                    .map_err(|e| open_err(io::Error::other(e.description)))?;
                Kind::Serial(port)
            }
            Endpoint::Tcp(addr) => {
                let addrs: Vec<SocketAddr> = addr.to_socket_addrs().map_err(open_err)?.collect();
                let mut last = io::Error::new(io::ErrorKind::NotFound, "no address found");
                let mut stream = None;
                for a in addrs {
                    match TcpStream::connect_timeout(&a, CONNECT_TIMEOUT) {
                        Ok(s) => {
                            stream = Some(s);
                            break;
                        }
                        Err(e) => last = e,
                    }
                }
                let stream = stream.ok_or_else(|| open_err(last))?;
                // Small command frames should leave at once.
                stream.set_nodelay(true).map_err(open_err)?;
                Kind::Tcp(stream)
            }
            Endpoint::Udp(addr) => Kind::Udp {
                socket: UdpSocket::bind(addr).map_err(open_err)?,
                peer: None,
            },
            Endpoint::File(path) => Kind::File(File::open(path).map_err(open_err)?),
            Endpoint::Stdio => {
                let (tx, rx) = sync_channel(STDIN_CHUNKS);
                std::thread::spawn(move || {
                    let mut stdin = io::stdin().lock();
                    let mut buf = vec![0u8; 64 * 1024];
                    loop {
                        let r = stdin.read(&mut buf);
                        let done = !matches!(r, Ok(n) if n > 0);
                        if tx.send(r.map(|n| buf[..n].to_vec())).is_err() || done {
                            break;
                        }
                    }
                });
                Kind::Stdio {
                    chunks: rx,
                    pending: Vec::new(),
                    ended: false,
                }
            }
        };
        Ok(Link { kind, name })
    }
}

impl Link {
    /// The endpoint as written, for messages.
    pub(crate) fn name(&self) -> &str {
        &self.name
    }

    /// Whether each read returns one datagram (UDP), so a frame never spans two reads.
    pub fn is_datagram(&self) -> bool {
        matches!(self.kind, Kind::Udp { .. })
    }

    /// Reads what is available, waiting at most `timeout`. For UDP, `buf` should hold 65 535
    /// bytes; a longer datagram is cut.
    ///
    /// # Errors
    /// [`Error::Io`] when the operating system reports a read error.
    pub fn read(&mut self, buf: &mut [u8], timeout: Duration) -> Result<Input> {
        let what = || format!("reading from {}", self.name);
        let result = match &mut self.kind {
            #[cfg(feature = "serial")]
            Kind::Serial(port) => {
                if port.timeout() != timeout {
                    port.set_timeout(timeout)
                        .map_err(|e| io::Error::other(e.description))
                        .map_err(|source| Error::Io {
                            what: what(),
                            source,
                        })?;
                }
                match port.read(buf) {
                    Ok(0) => Ok(Input::Idle),
                    Ok(n) => Ok(Input::Data(n)),
                    Err(e) => Err(e),
                }
            }
            Kind::Tcp(stream) => {
                stream
                    .set_read_timeout(Some(timeout_or_tick(timeout)))
                    .map_err(|source| Error::Io {
                        what: what(),
                        source,
                    })?;
                match stream.read(buf) {
                    Ok(0) => Ok(Input::End),
                    Ok(n) => Ok(Input::Data(n)),
                    Err(e) if e.kind() == io::ErrorKind::ConnectionReset => Ok(Input::End),
                    Err(e) => Err(e),
                }
            }
            Kind::Udp { socket, peer } => {
                socket
                    .set_read_timeout(Some(timeout_or_tick(timeout)))
                    .map_err(|source| Error::Io {
                        what: what(),
                        source,
                    })?;
                match socket.recv_from(buf) {
                    Ok((n, from)) => {
                        *peer = Some(from);
                        Ok(Input::Data(n))
                    }
                    Err(e) => Err(e),
                }
            }
            Kind::File(file) => match file.read(buf) {
                Ok(0) => Ok(Input::End),
                Ok(n) => Ok(Input::Data(n)),
                Err(e) => Err(e),
            },
            Kind::Stdio {
                chunks,
                pending,
                ended,
            } => {
                if pending.is_empty() && !*ended {
                    match chunks.recv_timeout(timeout) {
                        Ok(Ok(chunk)) if chunk.is_empty() => *ended = true,
                        Ok(Ok(chunk)) => *pending = chunk,
                        Ok(Err(e)) => {
                            *ended = true;
                            return Err(Error::Io {
                                what: what(),
                                source: e,
                            });
                        }
                        Err(RecvTimeoutError::Timeout) => return Ok(Input::Idle),
                        Err(RecvTimeoutError::Disconnected) => *ended = true,
                    }
                }
                if pending.is_empty() {
                    return Ok(Input::End);
                }
                let n = pending.len().min(buf.len());
                buf[..n].copy_from_slice(&pending[..n]);
                pending.drain(..n);
                return Ok(Input::Data(n));
            }
        };
        match result {
            Ok(input) => Ok(input),
            Err(e) if is_timeout(&e) => Ok(Input::Idle),
            Err(source) => Err(Error::Io {
                what: what(),
                source,
            }),
        }
    }

    /// A second handle that writes to the same endpoint, for a writer thread, so that slow
    /// writes never hold up reads.
    ///
    /// # Errors
    /// [`Error::Unsupported`] for `file:` and `udp:` endpoints; [`Error::Io`] when the
    /// operating system cannot duplicate the handle.
    pub(crate) fn writer(&self) -> Result<Box<dyn Write + Send>> {
        let io_err = |source| Error::Io {
            what: format!("duplicating {}", self.name),
            source,
        };
        match &self.kind {
            #[cfg(feature = "serial")]
            Kind::Serial(port) => Ok(Box::new(
                port.try_clone()
                    .map_err(|e| io_err(io::Error::other(e.description)))?,
            )),
            Kind::Tcp(stream) => Ok(Box::new(stream.try_clone().map_err(io_err)?)),
            Kind::Stdio { .. } => Ok(Box::new(io::stdout())),
            Kind::Udp { .. } | Kind::File(_) => Err(Error::Unsupported(format!(
                "{} cannot take bytes from a second writer",
                self.name
            ))),
        }
    }

    /// Writes all of `bytes` (for UDP: one datagram to the last sender).
    ///
    /// # Errors
    /// [`Error::Unsupported`] for a file endpoint, or a UDP endpoint that has not heard from
    /// anyone yet; [`Error::Io`] when the operating system reports a write error.
    pub fn write_all(&mut self, bytes: &[u8]) -> Result<()> {
        let io_err = |source| Error::Io {
            what: format!("writing to {}", self.name),
            source,
        };
        match &mut self.kind {
            #[cfg(feature = "serial")]
            Kind::Serial(port) => {
                port.write_all(bytes).map_err(io_err)?;
                port.flush().map_err(io_err)
            }
            Kind::Tcp(stream) => stream.write_all(bytes).map_err(io_err),
            Kind::Udp { socket, peer } => match peer {
                Some(to) => socket.send_to(bytes, *to).map(|_| ()).map_err(io_err),
                None => Err(Error::Unsupported(format!(
                    "cannot send on {}: it answers the last sender, and no datagram has arrived yet",
                    self.name
                ))),
            },
            Kind::File(_) => Err(Error::Unsupported(format!(
                "{} is read-only: a file endpoint cannot receive bytes",
                self.name
            ))),
            Kind::Stdio { .. } => {
                let mut out = io::stdout().lock();
                out.write_all(bytes).map_err(io_err)?;
                out.flush().map_err(io_err)
            }
        }
    }
}
