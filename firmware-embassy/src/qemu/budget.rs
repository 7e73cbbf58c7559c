//! The CPU budget build of the QEMU board (feature `cpu-budget`): `sensor-box`'s account
//! (`sensor_box::budget`, SysTick counts per category) over a window of the box's clock, then
//! the report `scripts/budget.py` reads and a semihosting exit. The same account and report
//! lines as the blocking QEMU board's `cpu-budget` build, so the script runs either ELF
//! (`--elf`).
//!
//! What is charged where: the code `sensor-box` marks (telemetry, the flight simulation, the
//! links' writes into the TX queues, the AOK link) to its categories; the UART interrupts to
//! `rx-irq`, SysTick (the time driver) to `systick`; the time the executor waits for work
//! (from `embassy-executor`'s `executor_idle` trace hook to its next `poll_start`, its `wfi`
//! in between) to `idle`; everything else (the executor's polls, the async readers' decoding,
//! the pumps, the tick's glue) to `other`.

use core::cell::Cell;

use critical_section::Mutex;
use firmware_example::budget_report::{self, Counts, WARMUP_MS, WINDOW_MS};
use sensor_box::budget::{self, Category};

use crate::links::{Application, Shared, now_ms};

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

/// The report's counters now.
fn take(a: &Application) -> Counts {
    Counts::take(
        &a.app,
        [
            a.aeolus_tx.counters(),
            a.aydp_tx.counters(),
            a.aok_tx.counters(),
        ],
    )
}

/// The budget run: waits [`WARMUP_MS`], calibrates, opens the window, and at its end logs the
/// report (`firmware_example::budget_report`, the blocking board's lines), then exits.
#[embassy_executor::task]
pub async fn run(shared: &'static Shared) {
    embassy_time::Timer::after_millis(WARMUP_MS).await;
    budget_report::calibrate();
    let start = now_ms();
    let Some(before) = shared.with(|a| take(a)) else {
        return;
    };
    budget::start();
    embassy_time::Timer::after_millis(WINDOW_MS).await;
    let end = now_ms();
    let Some(after) = shared.with(|a| take(a)) else {
        return;
    };
    budget_report::report(end - start, &before, &after);
    semihosting::process::exit(0)
}
