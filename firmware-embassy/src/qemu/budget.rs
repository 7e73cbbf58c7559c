//! The CPU budget build of the QEMU board (feature `cpu-budget`): `sensor-box`'s account
//! (`sensor_box::budget`, SysTick counts per category) over a window of the box's clock, then
//! the report `scripts/budget.py` reads and a semihosting exit. The same account and report
//! lines as the blocking QEMU board's `cpu-budget` build, so the script runs either ELF
//! (`--elf`).
//!
//! What is charged where: the code `sensor-box` marks (telemetry, the flight simulation, the
//! links' writes into the TX queues, the AOK link) to its categories; the UART interrupts to
//! `rx-irq`, SysTick (the time driver) to `systick`; the time the executor waits for work
//! (from `embassy-executor`'s `executor_idle` trace hook to its next `poll_start`, its `wfe`
//! in between) to `idle`; everything else (the executor's polls, the async readers' decoding,
//! the pumps, the tick's glue) to `other`.

use core::cell::Cell;

use cortex_m::interrupt::free;
use cortex_m::peripheral::SYST;
use critical_section::Mutex;
use firmware_example::serial::PortCounters;
use sensor_box::budget::{self, Category};
use sensor_box::telemetry::Kind;

use crate::links::{Application, Shared, now_ms};

/// Time after boot before the window opens, ms.
const WARMUP_MS: u64 = 1_000;
/// The calibration's delays: `delay(CAL)` and `delay(2 * CAL)`, whose difference is `2 * CAL`
/// instructions (cortex-m 0.7's `delay(n)` runs `n + 1` iterations of `subs; bne`), as the
/// blocking board's budget build logs it.
const CAL: u32 = 100_000;
/// Rounds of the account the calibration times, two switches each (`enter`, `leave`).
const SWITCHES: u32 = 1_000;

/// The window, ms: `BUDGET_SECONDS` at build time (whole seconds), 10 s without it.
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

/// The category the executor left when it went idle (`None`: not idle).
static IDLE_FROM: Mutex<Cell<Option<Category>>> = Mutex::new(Cell::new(None));

#[unsafe(no_mangle)]
fn _embassy_trace_executor_idle(_executor_id: u32) {
    critical_section::with(|cs| {
        let slot = IDLE_FROM.borrow(cs);
        if slot.get().is_none() {
            slot.set(Some(budget::enter(Category::Idle)));
        }
    });
}

#[unsafe(no_mangle)]
fn _embassy_trace_poll_start(_executor_id: u32) {
    critical_section::with(|cs| {
        if let Some(previous) = IDLE_FROM.borrow(cs).take() {
            budget::leave(previous);
        }
    });
}

#[unsafe(no_mangle)]
fn _embassy_trace_task_new(_executor_id: u32, _task_id: u32) {}

#[unsafe(no_mangle)]
fn _embassy_trace_task_end(_executor_id: u32, _task_id: u32) {}

#[unsafe(no_mangle)]
fn _embassy_trace_task_exec_begin(_executor_id: u32, _task_id: u32) {}

#[unsafe(no_mangle)]
fn _embassy_trace_task_exec_end(_executor_id: u32, _task_id: u32) {}

#[unsafe(no_mangle)]
fn _embassy_trace_task_ready_begin(_executor_id: u32, _task_id: u32) {}

/// Counts between two SysTick readings (it counts down, reloading at `period`).
fn counts(from: u32, to: u32, period: u32) -> u32 {
    if to <= from {
        from - to
    } else {
        from.wrapping_add(period).wrapping_sub(to)
    }
}

/// The calibration line: SysTick counts of two delays (their difference is `2 * CAL`
/// instructions) and of [`SWITCHES`] rounds of the account (`2 * SWITCHES` switches).
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
    defmt::info!(
        "budget: calibration {=u32} instructions = {=u32} counts; {=u32} switches = {=u32} counts",
        2 * CAL,
        long.saturating_sub(short),
        2 * SWITCHES,
        switch
    );
}

/// The telemetry sent, the late-skipped count and the ports' counters, at one instant.
struct Counts {
    sent: [u32; Kind::COUNT],
    skipped: u32,
    ports: [PortCounters; 3],
}

fn take(a: &Application) -> Counts {
    Counts {
        sent: a.app.aeolus.counters().sent,
        skipped: a.app.aeolus.telemetry().skipped(),
        ports: [
            a.aeolus_tx.counters(),
            a.aydp_tx.counters(),
            a.aok_tx.counters(),
        ],
    }
}

/// The budget run: waits [`WARMUP_MS`], calibrates, opens the window, and at its end logs the
/// account, the telemetry sent and the ports' counters over the window, then exits.
#[embassy_executor::task]
pub async fn run(shared: &'static Shared) {
    embassy_time::Timer::after_millis(WARMUP_MS).await;
    calibrate();
    let start = now_ms();
    let Some(before) = shared.with(|a| take(a)) else {
        return;
    };
    budget::start();
    embassy_time::Timer::after_millis(window_ms()).await;
    let account = budget::snapshot();
    let end = now_ms();
    let Some(after) = shared.with(|a| take(a)) else {
        return;
    };
    defmt::info!(
        "budget: window {=u64} ms, systick period {=u32} counts",
        end - start,
        SYST::get_reload().wrapping_add(1)
    );
    for c in Category::ALL {
        let i = c as usize;
        defmt::info!(
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
        defmt::info!(
            "budget: telemetry {=str} {=u32}",
            k.name(),
            n.wrapping_sub(b)
        );
    }
    defmt::info!(
        "budget: telemetry late-skipped {=u32}",
        after.skipped.wrapping_sub(before.skipped)
    );
    for (i, (c, b)) in after.ports.iter().zip(before.ports).enumerate() {
        defmt::info!(
            "budget: UART{=usize} rx {=u32} dropped {=u32} errors {=u32} tx {=u32}",
            i,
            c.rx_bytes.wrapping_sub(b.rx_bytes),
            c.rx_dropped.wrapping_sub(b.rx_dropped),
            c.rx_errors.wrapping_sub(b.rx_errors),
            c.tx_bytes.wrapping_sub(b.tx_bytes)
        );
    }
    defmt::info!("budget: end");
    semihosting::process::exit(0)
}
