//! A hostile soak of the firmware in QEMU (lm3s6965evb): random bytes on all three UARTs at a
//! steady rate, interleaved with valid AEOLUS COMMANDs and SETTIMEs, AYDP requests and AOK
//! parameter reads, for `SOAK_SECONDS` (60 by default: CI's short form; `SOAK_SECONDS=600
//! cargo test --release -p protolink-tests --test all soak:: -- --nocapture` is the 10-minute one).
//!
//! Checked: every valid command answered, the telemetry intervals on the box's clock, no reset
//! (one boot TOAST, one boot line in the log) and no fault (neither the HardFault handler's
//! line nor the panic handler's in the log), the stack high-water below half the stack, the
//! UART counters of the firmware's last report (every byte the test sent counted as received,
//! none dropped, no error), the read-only system name unchanged, and no direct output obeyed
//! (direct control stays off).
//!
//! On both lm3s6965evb boards ([`on_every_board!`]`(lm3s6965evb: ..)`): the blocking firmware
//! and the async one (`firmware-embassy`'s QEMU board, the same report lines). Not tried on
//! the simulated STM32, which falls behind real time on this 2-core host even without a flood
//! (the harness runs it alone for that reason).

use crate::harness::*;
use aok_proto::Client;
use std::io::Write;
use std::net::TcpStream;
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

/// What the firmware logs when it faults: its HardFault handler's fixed line
/// (`firmware-example/src/board/mod.rs`), the QEMU board's panic handler (`panic at FILE:LINE`)
/// and panic-probe's on the STM32 (`panicked at`).
const FAULT_LINES: [&str; 3] = ["HardFault: resetting", "panic at", "panicked at"];

/// The stack may reach at most this share of its size: the margin left for a deeper path than
/// the soak found.
const STACK_SHARE_MAX: f64 = 0.5;

/// The firmware's report period (`REPORT_MS` in `firmware-example/src/main.rs`), and how long
/// the test waits after its last byte so that a report counts everything.
const REPORT_WAIT: Duration = Duration::from_millis(5_000 + 1_500);

/// The UART counters of the firmware's last report: `UART{n}: rx R dropped D errors E tx T`.
fn last_uart_counters(log: &str, uart: usize) -> Option<[u64; 4]> {
    let line = log
        .lines()
        .rev()
        .find(|l| l.contains(&format!("UART{uart}: rx ")))?;
    let rest = line.split(&format!("UART{uart}: ")).nth(1)?;
    let words: Vec<&str> = rest.split_whitespace().collect();
    let value = |name: &str| -> Option<u64> {
        let i = words.iter().position(|w| *w == name)?;
        words.get(i + 1)?.parse().ok()
    };
    Some([
        value("rx")?,
        value("dropped")?,
        value("errors")?,
        value("tx")?,
    ])
}

/// The last `stack high-water N of M bytes` of the firmware's log: (N, M).
fn last_stack_report(log: &str) -> Option<(usize, usize)> {
    let line = log
        .lines()
        .rev()
        .find(|l| l.contains(" of ") && l.contains("stack high-water"))?;
    let rest = line.split("stack high-water ").nth(1)?;
    let words: Vec<&str> = rest.split_whitespace().collect();
    Some((words.first()?.parse().ok()?, words.get(2)?.parse().ok()?))
}

/// UART2 for `aok_proto::Client`, counting every byte written.
struct CountingSerial(NbSerial, Arc<AtomicUsize>);

impl embedded_hal_nb::serial::ErrorType for CountingSerial {
    type Error = core::convert::Infallible;
}

impl embedded_hal_nb::serial::Read<u8> for CountingSerial {
    fn read(&mut self) -> nb::Result<u8, Self::Error> {
        self.0.read()
    }
}

impl embedded_hal_nb::serial::Write<u8> for CountingSerial {
    fn write(&mut self, word: u8) -> nb::Result<(), Self::Error> {
        self.0.write(word)?;
        self.1.fetch_add(1, Ordering::Relaxed);
        Ok(())
    }
    fn flush(&mut self) -> nb::Result<(), Self::Error> {
        self.0.flush()
    }
}

/// An AYDP request on UART1, counting its bytes into `sent`.
fn counted_request(port: &mut TcpStream, address: u16, sent: &mut usize) -> Option<Vec<u8>> {
    let req =
        aydp_proto::Message::SystemControl(aydp_proto::SystemControl::RequestData { address });
    let mut buf = [0u8; 128];
    *sent += aydp_proto::Encoder::new(aydp_proto::Profile::Spec)
        .encode(&req, None, &mut buf)
        .expect("encode");
    request(port, address)
}

/// Garbage per UART per second, bytes.
const GARBAGE_RATE: usize = 2_000;

/// A small deterministic generator (xorshift64*).
struct Rng(u64);

impl Rng {
    fn byte(&mut self) -> u8 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 56) as u8
    }

    fn bytes(&mut self, n: usize) -> Vec<u8> {
        (0..n).map(|_| self.byte()).collect()
    }
}

on_every_board!(lm3s6965evb: hostile_soak);

fn hostile_soak(board: Board) {
    let seconds: u64 = std::env::var("SOAK_SECONDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(60);
    let Some(mut q) = boot(board, Ports::SOAK.on(board)) else {
        return;
    };
    let first = q.uart0.read_until(Duration::from_secs(10), |_| true);
    assert_eq!(q.uart0.frames[first].toast().as_deref(), Some("AEOLUS on"));
    let mut uart1_sent = 0usize;
    let name_before = counted_request(&mut q.uart1, 0x0001, &mut uart1_sent).expect("system name");
    let aok_port = q.uart2.try_clone().expect("clone UART2");
    aok_port.set_nonblocking(true).expect("nonblocking");
    let uart2_sent = Arc::new(AtomicUsize::new(0));
    let mut aok = Client::new(
        CountingSerial(NbSerial::new(aok_port), uart2_sent.clone()),
        emulated_aok_config(),
    );
    let t0 = Instant::now();
    let mut rng = Rng(0x50A4_0000_0000_0001);
    let mut per_uart = 0usize;
    let (mut aeolus_sent, mut aydp_sent, mut aydp_answered) = (0u32, 0u32, 0u32);
    let (mut aok_sent, mut aok_answered, mut garbage) = (0u32, 0u32, 0usize);
    let mut next_commands = t0 + Duration::from_secs(1);
    while t0.elapsed() < Duration::from_secs(seconds) {
        // The garbage due by now on each UART, at GARBAGE_RATE: every byte value, AOK's
        // unchecked `63` control commands (reset among them) included, which the box obeys only
        // in a burst framed by silence (docs/protocol-notes.md, PL38).
        let due = (GARBAGE_RATE as u128 * t0.elapsed().as_millis() / 1000) as usize;
        let chunk = due.saturating_sub(per_uart).min(GARBAGE_RATE);
        per_uart += chunk;
        q.uart0.queue_raw(&rng.bytes(chunk));
        q.uart0.flush_commands();
        q.uart1.write_all(&rng.bytes(chunk)).expect("UART1");
        q.uart2.write_all(&rng.bytes(chunk)).expect("UART2");
        uart1_sent += chunk;
        uart2_sent.fetch_add(chunk, Ordering::Relaxed);
        garbage += 3 * chunk;
        q.uart0.read_for(Duration::from_millis(10));
        if Instant::now() < next_commands {
            continue;
        }
        next_commands += Duration::from_secs(1);
        // Once a second, after 100 ms of quiet on UART1 and UART2 (an AOK frame has no start
        // byte: a quiet line is how the device drops a false partial frame), one valid
        // command per link.
        q.uart0.read_for(Duration::from_millis(100));
        q.uart0.command(&format!("a soak {aeolus_sent}"));
        aeolus_sent += 1;
        if counted_request(&mut q.uart1, 0x0001, &mut uart1_sent).is_some() {
            aydp_answered += 1;
        }
        aydp_sent += 1;
        let now = || t0.elapsed().as_millis() as u32;
        if aok.read_parameter(12, now).is_ok() {
            aok_answered += 1;
        }
        aok_sent += 1;
    }
    q.uart0.read_for(Duration::from_millis(500));
    let name_after =
        counted_request(&mut q.uart1, 0x0001, &mut uart1_sent).expect("system name after the soak");
    let direct = counted_request(&mut q.uart1, 0x0000, &mut uart1_sent)
        .expect("direct control after the soak");
    let outputs =
        counted_request(&mut q.uart1, 0x0200, &mut uart1_sent).expect("outputs after the soak");
    // Nothing more is sent: the firmware's next report counts every byte.
    q.uart0.read_for(REPORT_WAIT);
    let frames = std::mem::take(&mut q.uart0.frames);
    let toasts: Vec<String> = frames.iter().filter_map(Frame::toast).collect();
    let answered = toasts
        .iter()
        .filter(|t| t.starts_with("unknown command: a soak"))
        .count();
    let boots = toasts.iter().filter(|t| *t == "AEOLUS on").count();
    println!(
        "soak {seconds} s: {garbage} garbage bytes; AEOLUS {answered}/{aeolus_sent} commands \
         answered, AYDP {aydp_answered}/{aydp_sent}, AOK {aok_answered}/{aok_sent}; \
         {} frames, {boots} boot TOAST(s)",
        frames.len()
    );
    let uart0_sent = q.uart0.sent;
    let log = q.stop();
    for fault in FAULT_LINES {
        assert!(
            !log.contains(fault),
            "the firmware logged {fault:?}:\n{log}"
        );
    }
    // The log is decoded (defmt-print) and the box booted once in it.
    assert_eq!(
        log.matches("booted: App").count(),
        1,
        "one boot line expected in the firmware's log (is defmt-print installed?):\n{log}"
    );
    assert_eq!(boots, 1, "the box reset during the soak");
    for p in TELEMETRY.iter().filter(|p| p.id != 51) {
        let ts: Vec<f64> = frames
            .iter()
            .filter(|f| f.id == p.id)
            .filter_map(Frame::timestamp)
            .collect();
        let mean = (ts[ts.len() - 1] - ts[0]) / (ts.len() - 1) as f64;
        println!(
            "{:>10}: {:6} frames, mean interval {mean:8.3} ms",
            p.name,
            ts.len()
        );
        assert!(
            (mean - p.interval_ms).abs() <= 0.02 * p.interval_ms,
            "{}: mean interval {mean} ms under the soak, spec {} ms",
            p.name,
            p.interval_ms
        );
    }
    let (high_water, stack) = last_stack_report(&log).expect("a stack report in the log");
    println!("stack high-water {high_water} of {stack} bytes");
    assert!(
        (high_water as f64) < STACK_SHARE_MAX * stack as f64,
        "the stack reached {high_water} of {stack} bytes, more than {STACK_SHARE_MAX} of it"
    );
    let sent = [uart0_sent, uart1_sent, uart2_sent.load(Ordering::Relaxed)];
    for (uart, sent) in sent.into_iter().enumerate() {
        let [rx, dropped, errors, tx] =
            last_uart_counters(&log, uart).expect("a UART report in the log");
        println!("UART{uart}: sent {sent}, rx {rx} dropped {dropped} errors {errors} tx {tx}");
        assert_eq!(
            rx, sent as u64,
            "UART{uart}: bytes received against bytes sent"
        );
        assert_eq!((dropped, errors), (0, 0), "UART{uart}: dropped, errors");
        assert!(tx > 0, "UART{uart} sent nothing");
    }
    assert_eq!(answered as u32, aeolus_sent, "AEOLUS commands answered");
    assert_eq!(aydp_answered, aydp_sent, "AYDP requests answered");
    assert_eq!(aok_answered, aok_sent, "AOK reads answered");
    assert_eq!(name_after, name_before, "a read-only value changed");
    assert_eq!(direct, [0], "direct control was switched on by garbage");
    assert!(
        outputs.iter().all(|&b| b == 0),
        "an output was set: {outputs:?}"
    );
}
