//! A hostile soak of the firmware in QEMU (lm3s6965evb): random bytes on all three UARTs at a
//! steady rate, interleaved with valid AEOLUS COMMANDs and SETTIMEs, AYDP requests and AOK
//! parameter reads, for `SOAK_SECONDS` (60 by default: CI's short form; `SOAK_SECONDS=600
//! cargo test --release -p protolink-tests --test soak -- --nocapture` is the 10-minute one).
//!
//! Checked and printed: every valid command answered, the telemetry intervals on the box's
//! clock, no reset (one boot TOAST) and no fault, the stack high-water and the UART counters
//! from the firmware's log, the read-only system name unchanged, and no direct output obeyed
//! (direct control stays off).

mod harness;

use aok_proto::{Client, Config, FirmwareVersion};
use harness::*;
use std::io::Write;
use std::time::{Duration, Instant};

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

    fn bytes(&mut self, n: usize, avoid: &[u8]) -> Vec<u8> {
        (0..n)
            .map(|_| {
                loop {
                    let b = self.byte();
                    if !avoid.contains(&b) {
                        break b;
                    }
                }
            })
            .collect()
    }
}

#[test]
fn hostile_soak() {
    let seconds: u64 = std::env::var("SOAK_SECONDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(60);
    let board = Board::Lm3s6965evb;
    let Some(mut q) = boot(board, Ports::SOAK.on(board)) else {
        return;
    };
    let first = q.uart0.read_until(Duration::from_secs(10), |_| true);
    assert_eq!(q.uart0.frames[first].toast().as_deref(), Some("AEOLUS on"));
    let name_before = request(&mut q.uart1, 0x0001).expect("system name");
    let aok_port = q.uart2.try_clone().expect("clone UART2");
    aok_port.set_nonblocking(true).expect("nonblocking");
    let mut aok = Client::new(NbSerial(aok_port), Config::new(FirmwareVersion::new(0, 35)));
    let t0 = Instant::now();
    let mut rng = Rng(0x50A4_0000_0000_0001);
    let mut per_uart = 0usize;
    let (mut aeolus_sent, mut aydp_sent, mut aydp_answered) = (0u32, 0u32, 0u32);
    let (mut aok_sent, mut aok_answered, mut garbage) = (0u32, 0u32, 0usize);
    let mut next_commands = t0 + Duration::from_secs(1);
    while t0.elapsed() < Duration::from_secs(seconds) {
        // The garbage due by now on each UART, at GARBAGE_RATE. AOK's 0x63 is a set of
        // unchecked control commands (reset among them): it is left out, so that what the
        // soak sees is the box's own behaviour.
        let due = (GARBAGE_RATE as u128 * t0.elapsed().as_millis() / 1000) as usize;
        let chunk = due.saturating_sub(per_uart).min(GARBAGE_RATE);
        per_uart += chunk;
        q.uart0.queue_raw(&rng.bytes(chunk, &[]));
        q.uart0.flush_commands();
        q.uart1.write_all(&rng.bytes(chunk, &[])).expect("UART1");
        q.uart2
            .write_all(&rng.bytes(chunk, &[0x63]))
            .expect("UART2");
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
        if request(&mut q.uart1, 0x0001).is_some() {
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
    let name_after = request(&mut q.uart1, 0x0001).expect("system name after the soak");
    let direct = request(&mut q.uart1, 0x0000).expect("direct control after the soak");
    let outputs = request(&mut q.uart1, 0x0200).expect("outputs after the soak");
    let frames = &q.uart0.frames;
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
    let log = q.stop();
    for line in log
        .lines()
        .filter(|l| l.contains("stack high-water") || l.contains("UART"))
    {
        println!("log: {line}");
    }
    assert_eq!(boots, 1, "the box reset during the soak");
    assert!(
        !log.contains("HardFault") && !log.contains("panicked"),
        "{log}"
    );
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
