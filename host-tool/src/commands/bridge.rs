//! `protolink bridge`: the AEOLUS box's WiFi side. AEOLUS frames from a UART go out as UDP
//! datagrams; datagrams arriving on the in-port go to the UART.
//!
//! Only frames the decoder accepts are forwarded (good CRC, or no CRC as the spec allows), each
//! re-escaped byte for byte as it arrived. The destination defaults to 127.0.0.1; a broadcast
//! address is used only when `--broadcast` names it (DECISIONS.md A9).

use std::io::{self, Write};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{SyncSender, sync_channel};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use aeolus_proto::{Decode, Decoder, ESCAPE, FLAG};
use clap::Args;
use serde_json::json;

use crate::datagrams::{UdpArgs, receive_some};
use crate::decoders::AEOLUS_CAPACITY;
use crate::endpoint::{Endpoint, Input};
use crate::error::Result;
use crate::render::{Out, text, to_json};
use crate::stop::{self, Deadline};

/// Arguments of `protolink bridge`.
#[derive(Debug, Clone, Args)]
pub(crate) struct BridgeArgs {
    /// The box's UART (serial:PATH@BAUD, tcp:HOST:PORT, file:PATH, -).
    #[arg(long, value_name = "ENDPOINT")]
    pub(crate) uart: Endpoint,
    /// The UDP side.
    #[command(flatten)]
    pub(crate) udp: UdpArgs,
    /// Stop after this long: `10` (seconds), `500ms`, `2min` (default: on Ctrl-C, or when the UART ends).
    #[arg(long, value_name = "DURATION", value_parser = crate::args::run_time)]
    pub(crate) seconds: Option<std::time::Duration>,
}

/// What the bridge did, printed on exit.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub(crate) struct Counters {
    /// Bytes read from the UART.
    pub(crate) uart_bytes: u64,
    /// Frames forwarded to UDP.
    pub(crate) frames_forwarded: u64,
    /// Datagrams sent.
    pub(crate) datagrams_sent: u64,
    /// Datagrams whose send failed.
    pub(crate) send_errors: u64,
    /// Datagrams received on the in-port.
    pub(crate) datagrams_received: u64,
    /// Bytes written to the UART.
    pub(crate) bytes_to_uart: u64,
    /// Datagrams that could not be written to the UART.
    pub(crate) uart_write_errors: u64,
    /// Datagrams dropped because the UART writer's queue was full (the UART is slower than
    /// the datagrams arriving).
    pub(crate) uart_queue_dropped: u64,
}

/// Appends `raw` (ID, data and CRC, unescaped) as one escaped frame with its two flags.
pub(crate) fn push_frame(raw: &[u8], wire: &mut Vec<u8>) {
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

/// Datagrams that may wait for the UART writer; more are dropped and counted.
pub(crate) const UART_QUEUE: usize = 256;
/// How long the bridge waits at exit for datagrams still queued for the UART.
pub(crate) const UART_DRAIN: Duration = Duration::from_secs(1);

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
pub(crate) fn run(args: &BridgeArgs) -> Result<()> {
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

/// The examples of this module's items, as tests (the items are crate-private, so rustdoc
/// does not run them).
#[cfg(test)]
#[allow(unused_imports, clippy::unnecessary_wraps)]
mod examples {
    use super::*;

    #[test]
    fn push_frame_example() -> Result<(), Box<dyn std::error::Error>> {
        let mut wire = Vec::new();
        push_frame(&[0x52, 0x7e, 0x00, 0x7d], &mut wire);
        assert_eq!(wire, [0x7e, 0x52, 0x7d, 0x5e, 0x00, 0x7d, 0x5d, 0x7e]);
        Ok(())
    }
}
