//! `protolink bridge`: the AEOLUS box's WiFi side. AEOLUS frames from a UART go out as UDP
//! datagrams; datagrams arriving on the in-port go to the UART.
//!
//! Only frames the deframer accepts are forwarded (good CRC, or no CRC as the spec allows), each
//! re-escaped byte for byte as it arrived. The destination defaults to 127.0.0.1; a broadcast
//! address is used only when `--broadcast` names it (DECISIONS.md A9).

use std::io::{self, Write};
use std::net::{IpAddr, Ipv4Addr, SocketAddr, UdpSocket};
use std::time::{Duration, Instant};

use aeolus_proto::{Deframer, ESCAPE, FLAG};
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

/// Arguments of `protolink bridge`.
#[derive(Debug, Clone, Args)]
pub struct BridgeArgs {
    /// The box's UART (serial:PATH@BAUD, tcp:HOST:PORT, file:PATH, -).
    #[arg(long, value_name = "ENDPOINT")]
    pub uart: Endpoint,
    /// Where datagrams go: PORT (on 127.0.0.1) or ADDR:PORT.
    #[arg(long, value_name = "[ADDR:]PORT", default_value = "127.0.0.1:5001", value_parser = parse_local_addr)]
    pub udp_out: SocketAddr,
    /// The port datagrams for the UART arrive on: PORT (bound to 127.0.0.1) or ADDR:PORT
    /// (0.0.0.0:5002 listens on every interface).
    #[arg(long, value_name = "[ADDR:]PORT", default_value = "5002", value_parser = parse_local_addr)]
    pub udp_in: SocketAddr,
    /// Pack up to N frames into one datagram (1: one frame per datagram).
    #[arg(long, value_name = "N", default_value_t = 1, value_parser = clap::value_parser!(u16).range(1..))]
    pub pack: u16,
    /// Send to this broadcast address instead (on the --udp-out port). Never a default.
    #[arg(long, value_name = "ADDR")]
    pub broadcast: Option<IpAddr>,
    /// Stop after this many seconds (default: on Ctrl-C, or when the UART ends).
    #[arg(long, value_name = "N")]
    pub seconds: Option<f64>,
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

struct Sender {
    socket: UdpSocket,
    to: SocketAddr,
    pack: Vec<u8>,
    frames: usize,
    since: Option<Instant>,
}

impl Sender {
    fn send(&mut self, counters: &mut Counters) {
        if self.pack.is_empty() {
            return;
        }
        match self.socket.send_to(&self.pack, self.to) {
            Ok(_) => {
                counters.datagrams_sent += 1;
                counters.frames_forwarded += self.frames as u64;
            }
            Err(_) => counters.send_errors += 1,
        }
        self.pack.clear();
        self.frames = 0;
        self.since = None;
    }
}

/// Runs `protolink bridge`.
///
/// # Errors
/// Opening the UART or the sockets, reading the UART, or writing the output.
pub fn run(args: &BridgeArgs) -> Result<()> {
    let mut uart = args.uart.open()?;
    let to = match args.broadcast {
        Some(addr) => SocketAddr::new(addr, args.udp_out.port()),
        None => args.udp_out,
    };
    let bind = if to.ip().is_loopback() {
        SocketAddr::new(IpAddr::V4(Ipv4Addr::LOCALHOST), 0)
    } else {
        SocketAddr::new(IpAddr::V4(Ipv4Addr::UNSPECIFIED), 0)
    };
    let open_err = |what: String| {
        move |source: io::Error| Error::Open {
            endpoint: what,
            source,
        }
    };
    let out_socket = UdpSocket::bind(bind).map_err(open_err(format!("a UDP socket for {to}")))?;
    if args.broadcast.is_some() {
        out_socket
            .set_broadcast(true)
            .map_err(open_err(format!("a broadcast socket for {to}")))?;
    }
    let in_socket =
        UdpSocket::bind(args.udp_in).map_err(open_err(format!("udp:{}", args.udp_in)))?;
    in_socket
        .set_nonblocking(true)
        .map_err(open_err(format!("udp:{}", args.udp_in)))?;
    let mut sender = Sender {
        socket: out_socket,
        to,
        pack: Vec::with_capacity(MAX_DATAGRAM),
        frames: 0,
        since: None,
    };
    let _ = writeln!(
        io::stderr(),
        "bridging {} -> udp {to}, udp {} -> {} (Ctrl-C to stop)",
        uart.name(),
        args.udp_in,
        uart.name()
    );
    stop::install_ctrl_c();
    let deadline = Deadline::after_seconds(args.seconds);
    let mut counters = Counters::default();
    let mut deframer = Box::new(Deframer::<AEOLUS_CAPACITY>::new());
    let mut buf = vec![0u8; 65_536];
    let mut datagram = vec![0u8; 65_536];
    let mut warned = false;
    let pack = usize::from(args.pack);
    while !deadline.reached() {
        let input = uart.read(&mut buf, deadline.left(Duration::from_millis(5)))?;
        if let Input::Data(n) = input {
            counters.uart_bytes += n as u64;
            for &b in &buf[..n] {
                if let Some(Ok(frame)) = deframer.push(b) {
                    let raw = frame.raw();
                    let wire_len = 2 + raw.len() * 2;
                    if !sender.pack.is_empty() && sender.pack.len() + wire_len > MAX_DATAGRAM {
                        sender.send(&mut counters);
                    }
                    push_frame(raw, &mut sender.pack);
                    sender.frames += 1;
                    sender.since.get_or_insert_with(Instant::now);
                    if sender.frames >= pack {
                        sender.send(&mut counters);
                    }
                }
            }
        }
        let hold_over = sender.since.is_some_and(|t| t.elapsed() >= PACK_HOLD);
        if matches!(input, Input::Idle | Input::End) || hold_over {
            sender.send(&mut counters);
        }
        loop {
            match in_socket.recv_from(&mut datagram) {
                Ok((n, _from)) => {
                    counters.datagrams_received += 1;
                    match uart.write_all(&datagram[..n]) {
                        Ok(()) => counters.bytes_to_uart += n as u64,
                        Err(e) => {
                            counters.uart_write_errors += 1;
                            if !warned {
                                let _ = writeln!(io::stderr(), "warning: {e}");
                                warned = true;
                            }
                        }
                    }
                }
                Err(e) if e.kind() == io::ErrorKind::WouldBlock => break,
                Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
                Err(source) => {
                    return Err(Error::Io {
                        what: format!("receiving on udp:{}", args.udp_in),
                        source,
                    });
                }
            }
        }
        if input == Input::End {
            break;
        }
    }
    sender.send(&mut counters);
    let mut out = Out::new();
    out.line(&format!("bridge: {}", text(&to_json(&counters))))?;
    out.line(&format!(
        "uart deframer: {}",
        text(&json!(to_json(deframer.stats())))
    ))?;
    out.flush()
}
