//! `protolink bridge`: the AEOLUS box's WiFi side. AEOLUS frames from a UART go out as UDP
//! datagrams; datagrams arriving on the in-port go to the UART.
//!
//! Only frames the decoder accepts are forwarded (good CRC, or no CRC as the spec allows), each
//! re-escaped byte for byte as it arrived. The destination defaults to 127.0.0.1; a broadcast
//! address is used only when `--broadcast` names it (DECISIONS.md A9).

use std::io::{self, Write};
use std::net::{IpAddr, Ipv4Addr, SocketAddr, UdpSocket};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{SyncSender, sync_channel};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use aeolus_proto::{Decoder, ESCAPE, FLAG};
use clap::Args;
use serde_json::json;

use crate::decode::AEOLUS_CAPACITY;
use crate::endpoint::{Endpoint, Input, parse_local_addr};
use crate::error::{Error, Result};
use crate::render::{Out, text, to_json};
use crate::stop::{self, Deadline};

/// The largest datagram a pack may grow to: one Ethernet MTU less the IP and UDP headers, so
/// datagrams are never fragmented. A single larger frame still goes out, alone.
pub const MAX_DATAGRAM: usize = 1472;
/// How long a partly filled pack may wait for more frames.
pub const PACK_HOLD: Duration = Duration::from_millis(20);

/// The UDP side of a box, shared by `bridge` and `sim`: where datagrams go, where they arrive,
/// how many frames a datagram packs.
#[derive(Debug, Clone, Args)]
pub struct UdpArgs {
    /// Where datagrams go: PORT (on 127.0.0.1) or ADDR:PORT.
    #[arg(long, value_name = "[ADDR:]PORT", default_value = "127.0.0.1:5001", value_parser = parse_local_addr)]
    pub udp_out: SocketAddr,
    /// The port datagrams for the box arrive on: PORT (bound to 127.0.0.1) or ADDR:PORT
    /// (0.0.0.0:5002 listens on every interface).
    #[arg(long, value_name = "[ADDR:]PORT", default_value = "5002", value_parser = parse_local_addr)]
    pub udp_in: SocketAddr,
    /// Pack up to N frames into one datagram (1: one frame per datagram).
    #[arg(long, value_name = "N", default_value_t = 1, value_parser = clap::value_parser!(u16).range(1..))]
    pub pack: u16,
    /// Send to this broadcast address instead (on the --udp-out port). Never a default.
    #[arg(long, value_name = "ADDR")]
    pub broadcast: Option<IpAddr>,
}

impl UdpArgs {
    /// Where datagrams go: `--udp-out`, or the `--broadcast` address on its port.
    ///
    /// ```
    /// use clap::Parser;
    /// #[derive(Parser)]
    /// struct Cli {
    ///     #[command(flatten)]
    ///     udp: protolink::bridge::UdpArgs,
    /// }
    /// let cli = Cli::parse_from(["x", "--udp-out", "6001"]);
    /// assert_eq!(cli.udp.destination().to_string(), "127.0.0.1:6001");
    /// let cli = Cli::parse_from(["x", "--broadcast", "10.0.0.255"]);
    /// assert_eq!(cli.udp.destination().to_string(), "10.0.0.255:5001");
    /// ```
    pub fn destination(&self) -> SocketAddr {
        match self.broadcast {
            Some(addr) => SocketAddr::new(addr, self.udp_out.port()),
            None => self.udp_out,
        }
    }

    /// The [`Packer`] for the destination and the bound, non-blocking in-port.
    ///
    /// # Errors
    /// A socket cannot be bound.
    pub fn open(&self) -> Result<(Packer, UdpSocket)> {
        let packer = Packer::open(self.destination(), self.broadcast.is_some(), self.pack)?;
        Ok((packer, bind_in_port(self.udp_in)?))
    }
}

/// Arguments of `protolink bridge`.
#[derive(Debug, Clone, Args)]
pub struct BridgeArgs {
    /// The box's UART (serial:PATH@BAUD, tcp:HOST:PORT, file:PATH, -).
    #[arg(long, value_name = "ENDPOINT")]
    pub uart: Endpoint,
    /// The UDP side.
    #[command(flatten)]
    pub udp: UdpArgs,
    /// Stop after this long: `10` (seconds), `500ms`, `2min` (default: on Ctrl-C, or when the UART ends).
    #[arg(long, value_name = "DURATION", value_parser = crate::args::run_time)]
    pub seconds: Option<std::time::Duration>,
}

/// What the bridge did, printed on exit.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub struct Counters {
    /// Bytes read from the UART.
    pub uart_bytes: u64,
    /// Frames forwarded to UDP.
    pub frames_forwarded: u64,
    /// Datagrams sent.
    pub datagrams_sent: u64,
    /// Datagrams whose send failed.
    pub send_errors: u64,
    /// Datagrams received on the in-port.
    pub datagrams_received: u64,
    /// Bytes written to the UART.
    pub bytes_to_uart: u64,
    /// Datagrams that could not be written to the UART.
    pub uart_write_errors: u64,
    /// Datagrams dropped because the UART writer's queue was full (the UART is slower than
    /// the datagrams arriving).
    pub uart_queue_dropped: u64,
}

/// Appends `raw` (ID, data and CRC, unescaped) as one escaped frame with its two flags.
///
/// ```
/// let mut wire = Vec::new();
/// protolink::bridge::push_frame(&[0x52, 0x7e, 0x00, 0x7d], &mut wire);
/// assert_eq!(wire, [0x7e, 0x52, 0x7d, 0x5e, 0x00, 0x7d, 0x5d, 0x7e]);
/// ```
pub fn push_frame(raw: &[u8], wire: &mut Vec<u8>) {
    wire.push(FLAG);
    for &b in raw {
        if b == FLAG || b == ESCAPE {
            wire.extend([ESCAPE, b ^ 0x20]);
        } else {
            wire.push(b);
        }
    }
    wire.push(FLAG);
}

/// What a [`Packer`] has sent.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub struct SendCounters {
    /// Frames that went out inside a datagram.
    pub frames: u64,
    /// Datagrams sent.
    pub datagrams: u64,
    /// Datagrams whose send failed.
    pub errors: u64,
}

/// Most datagrams taken from the in-port per turn of a loop, so a flood cannot keep the loop
/// from its other work.
pub const DATAGRAMS_PER_TURN: usize = 64;
/// Datagrams that may wait for the UART writer; more are dropped and counted.
pub const UART_QUEUE: usize = 256;
/// How long the bridge waits at exit for datagrams still queued for the UART.
pub const UART_DRAIN: Duration = Duration::from_secs(1);

/// Packs escaped AEOLUS frames into UDP datagrams and sends them: up to `pack` frames per
/// datagram, never more than [`MAX_DATAGRAM`] bytes (a single longer frame goes out alone),
/// and a partly filled pack waits at most [`PACK_HOLD`]. Used by `bridge` and `sim`.
///
/// ```
/// use std::net::UdpSocket;
/// use protolink::bridge::Packer;
/// let rx = UdpSocket::bind("127.0.0.1:0")?;
/// let mut packer = Packer::open(rx.local_addr()?, false, 2)?;
/// let toast = [0x7E, 0x52, b'h', b'i', 0, 0x73, 0xEC, 0x7E];
/// packer.push(&toast); // held: the pack takes two frames
/// packer.push(&toast); // full: sent
/// let mut buf = [0u8; 64];
/// assert_eq!(rx.recv(&mut buf)?, 16);
/// assert_eq!(packer.counters().frames, 2);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug)]
pub struct Packer {
    socket: UdpSocket,
    to: SocketAddr,
    limit: usize,
    pack: Vec<u8>,
    frames: usize,
    since: Option<Instant>,
    counters: SendCounters,
    last_error: Option<io::Error>,
}

impl Packer {
    /// A packer sending to `to` (from an ephemeral port on 127.0.0.1 when `to` is a loopback
    /// address, on every interface otherwise), `pack` frames per datagram at most (0 is
    /// taken as 1). `broadcast` allows a broadcast destination.
    ///
    /// # Errors
    /// Binding the socket or allowing broadcast fails.
    pub fn open(to: SocketAddr, broadcast: bool, pack: u16) -> Result<Self> {
        let bind = if to.ip().is_loopback() {
            SocketAddr::new(IpAddr::V4(Ipv4Addr::LOCALHOST), 0)
        } else {
            SocketAddr::new(IpAddr::V4(Ipv4Addr::UNSPECIFIED), 0)
        };
        let open_err = |source| Error::Open {
            endpoint: format!("a UDP socket for {to}"),
            source,
        };
        let socket = UdpSocket::bind(bind).map_err(open_err)?;
        if broadcast {
            socket.set_broadcast(true).map_err(open_err)?;
        }
        Ok(Packer {
            socket,
            to,
            limit: usize::from(pack.max(1)),
            pack: Vec::with_capacity(MAX_DATAGRAM),
            frames: 0,
            since: None,
            counters: SendCounters::default(),
            last_error: None,
        })
    }

    /// Where the datagrams go.
    pub fn destination(&self) -> SocketAddr {
        self.to
    }

    /// What has been sent so far.
    pub fn counters(&self) -> SendCounters {
        self.counters
    }

    /// Fails when datagrams were to be sent and not one of them went out, naming the last
    /// reason: a box whose every send fails must not look like one that worked.
    ///
    /// # Errors
    /// [`Error::Io`] with the last send error.
    pub fn check(&mut self) -> Result<()> {
        match self.last_error.take() {
            Some(source) if self.counters.datagrams == 0 => Err(Error::Io {
                what: format!(
                    "sending every one of {} datagrams to {}",
                    self.counters.errors, self.to
                ),
                source,
            }),
            _ => Ok(()),
        }
    }

    /// Adds one escaped frame (flags included); sends the pack when it is full.
    pub fn push(&mut self, wire: &[u8]) {
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
    pub fn poll(&mut self) {
        if self.since.is_some_and(|t| t.elapsed() >= PACK_HOLD) {
            self.flush();
        }
    }

    /// Sends what is packed now.
    pub fn flush(&mut self) {
        if self.pack.is_empty() {
            return;
        }
        match self.socket.send_to(&self.pack, self.to) {
            Ok(_) => {
                self.counters.datagrams += 1;
                self.counters.frames += self.frames as u64;
            }
            Err(e) => {
                self.counters.errors += 1;
                self.last_error = Some(e);
            }
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
pub fn bind_in_port(udp_in: SocketAddr) -> Result<UdpSocket> {
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
pub fn receive_some(socket: &UdpSocket, buf: &mut [u8], mut f: impl FnMut(&[u8])) -> Result<usize> {
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

/// Writes datagrams to the UART from a thread of its own through a bounded queue, so a slow
/// UART never holds up reading it, and a flood is dropped (and counted) instead of queued.
struct UartWriter {
    queue: Option<SyncSender<Vec<u8>>>,
    thread: Option<std::thread::JoinHandle<()>>,
    written: Arc<AtomicU64>,
    errors: Arc<AtomicU64>,
    first_error: Arc<Mutex<Option<String>>>,
    dropped: u64,
}

impl UartWriter {
    /// A writer for `to`, or, when the UART takes no bytes (`file:`), one that counts every
    /// datagram as a write error with that reason.
    fn start(to: Result<Box<dyn Write + Send>>) -> Self {
        let mut to = match to {
            Ok(to) => to,
            Err(e) => {
                return UartWriter {
                    queue: None,
                    thread: None,
                    written: Arc::default(),
                    errors: Arc::default(),
                    first_error: Arc::new(Mutex::new(Some(e.to_string()))),
                    dropped: 0,
                };
            }
        };
        let (tx, rx) = sync_channel::<Vec<u8>>(UART_QUEUE);
        let written = Arc::new(AtomicU64::new(0));
        let errors = Arc::new(AtomicU64::new(0));
        let first_error = Arc::new(Mutex::new(None));
        let (w, e, f) = (written.clone(), errors.clone(), first_error.clone());
        let thread = std::thread::spawn(move || {
            for datagram in rx {
                match to.write_all(&datagram).and_then(|()| to.flush()) {
                    Ok(()) => {
                        w.fetch_add(datagram.len() as u64, Ordering::Relaxed);
                    }
                    Err(err) => {
                        e.fetch_add(1, Ordering::Relaxed);
                        if let Ok(mut slot) = f.lock() {
                            slot.get_or_insert_with(|| err.to_string());
                        }
                    }
                }
            }
        });
        UartWriter {
            queue: Some(tx),
            thread: Some(thread),
            written,
            errors,
            first_error,
            dropped: 0,
        }
    }

    fn send(&mut self, datagram: &[u8]) {
        match &self.queue {
            Some(q) => {
                if q.try_send(datagram.to_vec()).is_err() {
                    self.dropped += 1;
                }
            }
            None => {
                self.errors.fetch_add(1, Ordering::Relaxed);
            }
        }
    }

    /// Lets the queue drain for at most [`UART_DRAIN`] (a UART that takes nothing must not
    /// hold the exit), then fills in the counters.
    fn finish(mut self, counters: &mut Counters) -> Option<String> {
        drop(self.queue.take());
        if let Some(t) = self.thread.take() {
            let started = Instant::now();
            while !t.is_finished() && started.elapsed() < UART_DRAIN {
                std::thread::sleep(Duration::from_millis(5));
            }
            if t.is_finished() {
                let _ = t.join();
            }
        }
        counters.bytes_to_uart = self.written.load(Ordering::Relaxed);
        counters.uart_write_errors = self.errors.load(Ordering::Relaxed);
        counters.uart_queue_dropped = self.dropped;
        self.first_error.lock().ok().and_then(|mut e| e.take())
    }
}

/// Runs `protolink bridge`.
///
/// # Errors
/// Opening the UART or the sockets, reading the UART, or writing the output.
pub fn run(args: &BridgeArgs) -> Result<()> {
    let mut uart = args.uart.open()?;
    let (mut packer, in_socket) = args.udp.open()?;
    let to = packer.destination();
    let _ = writeln!(
        io::stderr(),
        "bridging {} -> udp {to}, udp {} -> {} (Ctrl-C to stop)",
        uart.name(),
        args.udp.udp_in,
        uart.name()
    );
    stop::install_ctrl_c();
    let deadline = Deadline::after(args.seconds);
    let mut counters = Counters::default();
    let mut decoder = Box::new(Decoder::<AEOLUS_CAPACITY>::new());
    let mut buf = vec![0u8; 65_536];
    let mut datagram = vec![0u8; 65_536];
    let mut wire = Vec::with_capacity(2 * AEOLUS_CAPACITY + 2);
    let mut writer = UartWriter::start(uart.writer());
    while !deadline.reached() {
        let input = uart.read(&mut buf, deadline.left(Duration::from_millis(5)))?;
        if let Input::Data(n) = input {
            counters.uart_bytes += n as u64;
            decoder.feed(&buf[..n], |event| {
                if let Ok(frame) = event {
                    wire.clear();
                    push_frame(frame.raw(), &mut wire);
                    packer.push(&wire);
                }
            });
        }
        if matches!(input, Input::Idle | Input::End) {
            packer.flush();
        } else {
            packer.poll();
        }
        receive_some(&in_socket, &mut datagram, |d| {
            counters.datagrams_received += 1;
            writer.send(d);
        })?;
        if input == Input::End {
            break;
        }
    }
    packer.flush();
    let write_error = writer.finish(&mut counters);
    let sent = packer.counters();
    counters.frames_forwarded = sent.frames;
    counters.datagrams_sent = sent.datagrams;
    counters.send_errors = sent.errors;
    let mut out = Out::new();
    out.line(&format!("bridge: {}", text(&to_json(&counters))))?;
    out.line(&format!(
        "uart decoder: {}",
        text(&json!(to_json(&decoder.stats())))
    ))?;
    out.flush()?;
    if let Some(e) = write_error {
        let _ = writeln!(
            io::stderr(),
            "warning: {} of {} datagrams could not be written to {}: {e}",
            counters.uart_write_errors,
            counters.datagrams_received,
            uart.name()
        );
    }
    packer.check()
}
