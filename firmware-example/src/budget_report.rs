//! The `cpu-budget` builds' report, the same lines from both QEMU boards (the blocking one,
//! `src/budget_run.rs`, and the async firmware's, `firmware-embassy/src/qemu/budget.rs`), which
//! `scripts/budget.py` reads: the calibration, then over the window the account per category,
//! the telemetry sent, the late-skipped slots and the UART counters. A board opens the window
//! [`WARMUP_MS`] after boot (boot, the boot TOAST and the first burst of every telemetry kind
//! are left out) and closes it [`WINDOW_MS`] later; how it waits and how it exits is its own.
//!
//! The calibration, made once before the window: SysTick counts for a known number of
//! instructions (`cortex_m::asm::delay`, two lengths, their difference) and for a known
//! number of switches of the account, so a reader can convert counts and correct for the
//! account's own cost.

use cortex_m::interrupt::free;
use cortex_m::peripheral::SYST;
use sensor_box::budget::{self, Category};
use sensor_box::serial::PortCounters;
use sensor_box::telemetry::Kind;
use sensor_box::{App, info};

/// Left out at the start, ms of the box's clock.
pub const WARMUP_MS: u64 = 1_000;

/// The calibration's delays are `delay(CAL)` and `delay(2 * CAL)`: their difference is
/// `2 * CAL` instructions (cortex-m 0.7's `delay(n)` runs `n + 1` iterations of `subs; bne`).
const CAL: u32 = 100_000;

/// Rounds of the account the calibration times, two switches each (`enter`, `leave`).
const SWITCHES: u32 = 1_000;

/// The window, ms of the box's clock (`BUDGET_SECONDS` at build time, default 10 s).
pub const WINDOW_MS: u64 = window_ms();

/// [`WINDOW_MS`] from `BUDGET_SECONDS` (whole seconds; 10 s when unset or 0).
const fn window_ms() -> u64 {
    let s = match option_env!("BUDGET_SECONDS") {
        Some(s) => s.as_bytes(),
        None => b"10",
    };
    let mut n: u64 = 0;
    let mut i = 0;
    while i < s.len() {
        let d = s[i];
        if d.is_ascii_digit() {
            n = n * 10 + (d - b'0') as u64;
        }
        i += 1;
    }
    if n == 0 { 10_000 } else { n * 1_000 }
}

/// Logs the two calibrations (interrupts off while they run). Leaves the account started.
pub fn calibrate() {
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

/// SysTick counts elapsed from `from` to `to` (counting down, at most one reload between).
fn counts(from: u32, to: u32, period: u32) -> u32 {
    if to <= from {
        from - to
    } else {
        from.wrapping_add(period).wrapping_sub(to)
    }
}

/// What the report counts over the window, at one instant: the telemetry sent, the
/// late-skipped slots, the three ports' counters.
#[derive(Clone, Copy)]
pub struct Counts {
    sent: [u32; Kind::COUNT],
    skipped: u32,
    ports: [PortCounters; 3],
}

impl Counts {
    /// The application's and the ports' counters now..
    pub fn take(app: &App, ports: [PortCounters; 3]) -> Self {
        Counts {
            sent: app.aeolus.counters().sent,
            skipped: app.aeolus.telemetry().skipped(),
            ports,
        }
    }
}

/// Logs the report of a window of `window_ms` from `before` to `after`, with the account as
/// it stands, and its last line, `budget: end`..
pub fn report(window_ms: u64, before: &Counts, after: &Counts) {
    let account = budget::snapshot();
    info!(
        "budget: window {=u64} ms, systick period {=u32} counts",
        window_ms,
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
    for k in Kind::ALL {
        let i = k.index();
        let n = after.sent.get(i).copied().unwrap_or(0);
        let b = before.sent.get(i).copied().unwrap_or(0);
        info!(
            "budget: telemetry {=str} {=u32}",
            k.name(),
            n.wrapping_sub(b)
        );
    }
    info!(
        "budget: telemetry late-skipped {=u32}",
        after.skipped.wrapping_sub(before.skipped)
    );
    for (i, (c, b)) in after.ports.iter().zip(before.ports).enumerate() {
        info!(
            "budget: UART{=usize} rx {=u32} dropped {=u32} errors {=u32} tx {=u32}",
            i,
            c.rx_bytes.wrapping_sub(b.rx_bytes),
            c.rx_dropped.wrapping_sub(b.rx_dropped),
            c.rx_errors.wrapping_sub(b.rx_errors),
            c.tx_bytes.wrapping_sub(b.tx_bytes)
        );
    }
    info!("budget: end");
}
