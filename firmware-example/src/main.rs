//! `sensor-box`: the firmware binary, one for both boards.
//!
//! The board is chosen by feature (`board-qemu` or `board-stm32f411`); the
//! `.cargo/config.toml` aliases `cargo qemu` and `cargo stm32` pick the
//! target and feature. The binary is only the glue between the board and the
//! application (the `sensor-box` crate):
//!
//! 1. `board::init()`: clocks, SysTick, three interrupt-driven UARTs, the
//!    flash store;
//! 2. `App::with_layout(&mut store, board::store_layout(), now)`: loads the stored settings (defaults and a
//!    warning if the store is missing or corrupt) and queues the boot TOAST;
//! 3. the main loop: `App::poll_pending` with the three ports after every
//!    wake (the CPU sleeps in `wfi` until SysTick reaches the loop's deadline,
//!    the earliest instant a link's timer, the telemetry schedule or the report
//!    is due (`App::next_wake_ms`, `board::wake_at`), or a UART that
//!    wakes its link; other interrupts end the `wfi` and it sleeps again); only
//!    the links whose UART received, or whose own timer is due, run; then a `flush` of each port (on the QEMU board
//!    that starts one TX interrupt per burst instead of one per byte), a warm
//!    reset when a link asks for one, and every 5 s (`REPORT_MS`) log lines with the uptime, the stack high-water mark
//!    (cortex-m-rt paints the stack before `main`) and the UART counters. Each pass feeds the
//!    board's watchdog first, and no sleep lasts longer than `board::FEED_MS` (1 s), so only
//!    a loop that stops is reset (the time-outs: `board/mod.rs`, "The watchdog").
//!
//! At boot the log has the reset cause: the board's reset-status register (its watchdog bit),
//! and whether this reset was one the firmware did not ask for, with their count since
//! power-on (`board::unrequested_resets`: QEMU sets no reset-status bits, so there only the
//! count tells a watchdog reset).
//!
//! On the host this file builds a stub `main` that says how to run it.
#![cfg_attr(target_os = "none", no_std)]
#![cfg_attr(target_os = "none", no_main)]

#[cfg(target_os = "none")]
mod board;

/// Period of the status log line, ms.
#[cfg(target_os = "none")]
const REPORT_MS: u64 = 5_000;

/// How long a reboot waits for UART0 to send its last bytes (the answer
/// TOAST), ms.
#[cfg(target_os = "none")]
const REBOOT_FLUSH_MS: u64 = 20;

#[cfg(all(target_os = "none", feature = "cpu-budget"))]
mod budget_run;

#[cfg(target_os = "none")]
mod run {
    use super::{REBOOT_FLUSH_MS, REPORT_MS};
    use crate::board;
    use cortex_m as _;
    use embedded_hal_nb::serial::Write;
    use embedded_storage::nor_flash::ReadNorFlash;
    use firmware_example::Clock;
    use sensor_box::{App, Control, info};

    #[cortex_m_rt::entry]
    fn main() -> ! {
        let b = board::init();
        let (mut uart0, mut uart1, mut uart2) = (b.uart0, b.uart1, b.uart2);
        let (clock, mut store, mut watchdog) = (b.clock, b.store, b.watchdog);
        info!(
            "sensor-box {=str} on {=str}: booting; flash store {=usize} bytes",
            env!("CARGO_PKG_VERSION"),
            board::NAME,
            store.capacity()
        );
        let cause = board::reset_cause();
        let (unrequested, count) = board::unrequested_resets();
        info!(
            "reset cause: register {=u32:#x}, watchdog {=bool}; not asked for {=bool} ({=u32} since power-on)",
            cause,
            cause & board::WATCHDOG_CAUSE != 0,
            unrequested,
            count
        );

        let mut app = App::with_layout(&mut store, board::store_layout(), clock.now_ms());
        info!(
            "booted: App {=usize} bytes, stack high-water {=usize} bytes",
            core::mem::size_of::<App>(),
            board::stack_high_water()
        );
        let mut next_report = clock.now_ms().saturating_add(REPORT_MS);
        #[cfg(feature = "cpu-budget")]
        let mut budget = crate::budget_run::Run::new(clock.now_ms());
        loop {
            // The one place that feeds the watchdog: once per pass.
            watchdog.feed();
            let now = clock.now_ms();
            // Only the links with work run: the UARTs that received, and the timers due.
            let received = board::take_received();
            let control = app.poll_pending(
                now, received, &mut uart0, &mut uart1, &mut uart2, &mut store,
            );
            // The burst of this poll goes to the UARTs in one interrupt each (the ports are
            // `batched` on the QEMU board; elsewhere the kick is redundant).
            for port in [&mut uart0, &mut uart1, &mut uart2] {
                let _ = port.flush();
            }
            if control == Control::Reboot {
                info!("reboot requested: warm reset");
                flush(&mut uart0, &clock, now.saturating_add(REBOOT_FLUSH_MS));
                board::reset();
            }
            // Test only (feature `fault-hang`): an unknown AEOLUS command hangs the loop; its
            // answer still leaves (the UART interrupts run), the watchdog must reset the box.
            #[cfg(feature = "fault-hang")]
            if app.aeolus.counters().unknown_commands != 0 {
                info!("fault-hang: the main loop hangs");
                #[allow(clippy::empty_loop)]
                loop {}
            }
            if now >= next_report {
                next_report = now.saturating_add(REPORT_MS);
                report(now, &app, [&uart0, &uart1, &uart2]);
            }
            #[cfg(feature = "cpu-budget")]
            budget.poll(now, &app, [&uart0, &uart1, &uart2]);
            // SysTick wakes the loop when a link's timer, the schedule or the report is due,
            // and at the next millisecond at the earliest (a link with work left, such as TX
            // bytes waiting for room, runs once a millisecond, as a received byte's link does
            // below the wake threshold).
            let deadline = app
                .next_wake_ms()
                .min(next_report)
                .min(now.saturating_add(board::FEED_MS))
                .max(now.saturating_add(1));
            #[cfg(feature = "cpu-budget")]
            let deadline = deadline.min(budget.next_ms());
            board::wake_at(deadline);
            // Sleep until there is work: the next millisecond, or a UART that wakes its link
            // (interrupts off for the check: one that arrives after it still ends the `wfi`,
            // and runs when they are back on). A wake that leaves no work (received bytes
            // below the wake threshold, a TX FIFO refilled) costs the check and sleeps again.
            loop {
                cortex_m::interrupt::free(|_| {
                    if !board::has_work() {
                        sensor_box::budget::span(
                            sensor_box::budget::Category::Idle,
                            cortex_m::asm::wfi,
                        );
                    }
                });
                // The interrupt that ended the `wfi` has run: a plain load says whether it
                // left work.
                if board::has_work() {
                    break;
                }
            }
        }
    }

    /// Waits until `port` has handed its queued bytes to the UART, or until
    /// `deadline` (ms since boot).
    fn flush(port: &mut board::Port, clock: &impl Clock, deadline: u64) {
        while port.flush().is_err() && clock.now_ms() < deadline {}
    }

    /// The periodic status lines.
    fn report(now: u64, app: &App, ports: [&board::Port; 3]) {
        info!(
            "uptime {=u64} ms, stack high-water {=usize} of {=usize} bytes",
            now,
            board::stack_high_water(),
            board::stack_size()
        );
        for (i, port) in ports.iter().enumerate() {
            let c = port.counters();
            info!(
                "UART{=usize}: rx {=u32} dropped {=u32} errors {=u32} tx {=u32}",
                i, c.rx_bytes, c.rx_dropped, c.rx_errors, c.tx_bytes
            );
        }
        let a = app.aeolus.counters();
        let rx = app.aeolus.rx_stats();
        info!(
            "AEOLUS: telemetry {=u32} frames, toasts {=u32}, tx dropped {=u32}, late skipped {=u32}; rx ok {=u32} crc errors {=u32} commands {=u32} unknown {=u32} settime {=u32}; paused {=bool}",
            a.telemetry_total(),
            a.toasts,
            a.tx_dropped,
            app.aeolus.telemetry().skipped(),
            rx.frames_delivered(),
            rx.checksum_errors,
            a.commands,
            a.unknown_commands,
            a.settime,
            app.shared.paused
        );
        let k = app.aok.counters();
        let d = app.aok.decoder_stats();
        info!(
            "AOK: commands {=u32}, rx errors {=u32}, cut by a quiet line {=u32}, bursts discarded {=u32}, replies dropped {=u32}",
            d.frames_ok, k.rx_errors, d.abandoned, k.bursts_discarded, k.replies_dropped
        );
    }
}

#[cfg(not(target_os = "none"))]
fn main() {
    eprintln!(
        "sensor-box is firmware: run it with `cargo qemu` (QEMU lm3s6965evb) or \
         `cargo stm32` (STM32F411 via probe-rs)."
    );
    std::process::exit(2);
}
