//! The `cpu-budget` build's run: warm up, account a window of the box's clock, report, exit.
//!
//! After [`WARMUP_MS`] (boot, the boot TOAST and the first burst of every telemetry kind are
//! left out) the account starts from zero; [`window_ms`] later the main loop logs the
//! account, the telemetry sent and the UART counters over the window, and exits through
//! semihosting. `scripts/budget.py` reads these `budget:` lines.
//!
//! The log also carries two calibrations, made once before the window: SysTick counts for a
//! known number of instructions (`cortex_m::asm::delay`, two lengths, their difference), and
//! the cost of one switch of the account, so a reader can convert and correct.

use crate::board;
use cortex_m::interrupt::free;
use cortex_m::peripheral::SYST;
use firmware_example::serial::PortCounters;
use sensor_box::budget::{self, Category};
use sensor_box::telemetry::Kind;
use sensor_box::{App, info};

/// Left out at the start, ms of the box's clock.
pub const WARMUP_MS: u64 = 1_000;

/// The window, ms of the box's clock (`BUDGET_SECONDS` at build time, default 10 s).
pub const fn window_ms() -> u64 {
    let s = match option_env!("BUDGET_SECONDS") {
        Some(s) => s.as_bytes(),
        None => b"10",
    };
    let mut n: u64 = 0;
    let mut i = 0;
    while i < s.len() {
        let d = s[i];
        if d >= b'0' && d <= b'9' {
            n = n * 10 + (d - b'0') as u64;
        }
        i += 1;
    }
    if n == 0 { 10_000 } else { n * 1_000 }
}

/// The calibration's difference `delay(2 * CAL)` minus `delay(CAL)` is `2 * CAL`
/// instructions (cortex-m 0.7's `delay(n)` runs `n + 1` iterations of `subs; bne`).
const CAL: u32 = 100_000;

/// Account switches timed for the switch-cost calibration.
const SWITCHES: u32 = 1_000;

/// Where the run is.
pub struct Run {
    start_ms: u64,
    started: bool,
    sent: [u32; Kind::COUNT],
    skipped: u32,
    ports: [PortCounters; 3],
}

impl Run {
    /// The run of a box booted at `now_ms`.
    pub fn new(now_ms: u64) -> Self {
        Run {
            start_ms: now_ms.saturating_add(WARMUP_MS),
            started: false,
            sent: [0; Kind::COUNT],
            skipped: 0,
            ports: [PortCounters::default(); 3],
        }
    }

    /// When [`Run::poll`] next has something to do, ms: the window's start, then its end.
    pub fn next_ms(&self) -> u64 {
        if self.started {
            self.start_ms.saturating_add(window_ms())
        } else {
            self.start_ms
        }
    }

    /// Called once per main-loop turn.
    pub fn poll(&mut self, now_ms: u64, app: &App, ports: [&board::Port; 3]) {
        if !self.started {
            if now_ms >= self.start_ms {
                calibrate();
                self.started = true;
                self.start_ms = now_ms;
                self.sent = app.aeolus.counters().sent;
                self.skipped = app.aeolus.telemetry().skipped();
                self.ports = ports.map(|p| p.counters());
                budget::start();
            }
            return;
        }
        if now_ms < self.start_ms.saturating_add(window_ms()) {
            return;
        }
        let account = budget::snapshot();
        info!(
            "budget: window {=u64} ms, systick period {=u32} counts",
            now_ms - self.start_ms,
            SYST::get_reload().wrapping_add(1)
        );
        for c in Category::ALL {
            let i = c as usize;
            info!(
                "budget: category {=str} counts {=u64} entries {=u32} nested {=u32}",
                c.name(),
                account.ticks.get(i).copied().unwrap_or(0),
                account.entries.get(i).copied().unwrap_or(0),
                account.nested.get(i).copied().unwrap_or(0)
            );
        }
        let sent = app.aeolus.counters().sent;
        for k in Kind::ALL {
            let i = k.index();
            let now = sent.get(i).copied().unwrap_or(0);
            let before = self.sent.get(i).copied().unwrap_or(0);
            info!(
                "budget: telemetry {=str} {=u32}",
                k.name(),
                now.wrapping_sub(before)
            );
        }
        info!(
            "budget: telemetry late-skipped {=u32}",
            app.aeolus.telemetry().skipped().wrapping_sub(self.skipped)
        );
        for (i, (p, before)) in ports.iter().zip(self.ports).enumerate() {
            let c = p.counters();
            info!(
                "budget: UART{=usize} rx {=u32} dropped {=u32} errors {=u32} tx {=u32}",
                i,
                c.rx_bytes.wrapping_sub(before.rx_bytes),
                c.rx_dropped.wrapping_sub(before.rx_dropped),
                c.rx_errors.wrapping_sub(before.rx_errors),
                c.tx_bytes.wrapping_sub(before.tx_bytes)
            );
        }
        info!("budget: end");
        semihosting::process::exit(0)
    }
}

/// SysTick counts elapsed from `from` to `to` (counting down, at most one reload between).
fn counts(from: u32, to: u32, period: u32) -> u32 {
    if to <= from {
        from - to
    } else {
        from.wrapping_add(period).wrapping_sub(to)
    }
}

/// Logs the two calibrations (interrupts off while they run).
fn calibrate() {
    let period = SYST::get_reload().wrapping_add(1);
    let (short, long, switch) = free(|_| {
        let t0 = SYST::get_current();
        cortex_m::asm::delay(CAL);
        let t1 = SYST::get_current();
        cortex_m::asm::delay(2 * CAL);
        let t2 = SYST::get_current();
        budget::start();
        for _ in 0..SWITCHES {
            let previous = budget::enter(Category::Other);
            budget::leave(previous);
        }
        let t3 = SYST::get_current();
        (
            counts(t0, t1, period),
            counts(t1, t2, period),
            counts(t2, t3, period),
        )
    });
    info!(
        "budget: calibration {=u32} instructions = {=u32} counts; {=u32} switches = {=u32} counts",
        2 * CAL,
        long.saturating_sub(short),
        2 * SWITCHES,
        switch
    );
}
