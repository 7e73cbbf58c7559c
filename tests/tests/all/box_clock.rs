//! The box's clock judged from outside: the release firmware in QEMU without `-icount` (so
//! QEMU's virtual clock follows the host's), and the GYRO timestamps it sends compared with
//! the host's clock over at least 10 s, on every board.
//!
//! Every other test judges intervals in the box's own clock, so a box whose millisecond is
//! short (a wrong core-clock figure behind the SysTick reload) passes them all. This one fails
//! when the box's clock runs faster than the host's by more than [`FAST_LIMIT`]. The bound is
//! one-sided: a loaded host makes QEMU late (the box's clock then runs slow), never early.
//!
//! The host time of a frame is when it was read, which is late by a varying delay (QEMU's
//! socket, this process being scheduled). The delay is never negative, so the least
//! `host - box` offset seen near the start and near the end of the window estimates the true
//! offset at both ends; their difference is the drift.

use crate::harness::*;
use std::time::{Duration, Instant};

/// The longest a box second may be short of a host second: 0.5 %.
const FAST_LIMIT: f64 = 0.005;
/// How long the host listens after the first GYRO: the two edges' least offsets are then at
/// least 10 s apart.
const WINDOW: Duration = Duration::from_secs(14);
/// The stretch at each end of the window whose least offset is taken.
const EDGE: Duration = Duration::from_secs(2);

/// This test's ports (UART0..UART2, the STM32's GDB stub at +3).
const PORTS: Ports = Ports::BOX_CLOCK;

on_every_board!(the_boxs_clock_keeps_the_hosts_time);

fn the_boxs_clock_keeps_the_hosts_time(board: Board) {
    let Some(mut q) = boot(board, PORTS.on(board)) else {
        return;
    };
    const GYRO: u8 = 62;
    q.uart0
        .read_until(Duration::from_secs(10), |f| f.id == GYRO);
    // A second to settle: what queued in the socket while the test started is not timed.
    q.uart0.read_for(Duration::from_secs(1));
    // (host seconds since the start, box seconds) for each GYRO, taken as it is read.
    let start = Instant::now();
    let mut samples: Vec<(f64, f64)> = Vec::new();
    let mut seen = q.uart0.frames.len();
    while start.elapsed() < WINDOW {
        q.uart0.read_for(Duration::from_millis(1));
        let host = start.elapsed().as_secs_f64();
        for f in &q.uart0.frames[seen..] {
            if f.id == GYRO
                && let Some(ms) = f.timestamp()
            {
                samples.push((host, ms / 1000.0));
            }
        }
        seen = q.uart0.frames.len();
    }
    let log = q.stop();
    assert!(
        samples.len() > 500,
        "only {} GYRO frames in {WINDOW:?}; log:\n{log}",
        samples.len()
    );
    let (first_host, last_host) = (samples[0].0, samples[samples.len() - 1].0);
    let least_offset = |from: f64, to: f64| {
        samples
            .iter()
            .filter(|(h, _)| (from..=to).contains(h))
            .map(|&(h, b)| (h - b, h, b))
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .expect("GYRO frames at each end of the window")
    };
    let edge = EDGE.as_secs_f64();
    let (_, h0, b0) = least_offset(first_host, first_host + edge);
    let (_, h1, b1) = least_offset(last_host - edge, last_host);
    let (host_s, box_s) = (h1 - h0, b1 - b0);
    assert!(
        host_s >= 10.0,
        "the estimate spans {host_s:.2} s of host time"
    );
    let ratio = box_s / host_s;
    println!(
        "{}: {} GYRO frames; box {box_s:.4} s against host {host_s:.4} s: ratio {ratio:.5} \
         ({:.1} GYRO frames per host second)",
        board.machine(),
        samples.len(),
        samples.len() as f64 / (last_host - first_host)
    );
    assert!(
        ratio <= 1.0 + FAST_LIMIT,
        "the box's clock runs {:.2} % fast: {box_s:.3} s of GYRO timestamps in {host_s:.3} s \
         of host time (allowed: {:.1} %)",
        (ratio - 1.0) * 100.0,
        FAST_LIMIT * 100.0
    );
}
