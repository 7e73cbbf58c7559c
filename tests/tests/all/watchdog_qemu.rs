//! The watchdog resets a hung box, and the box keeps its settings (issue 42).
//!
//! The firmware is built with the test-only feature `fault-hang` of `firmware-example` (never
//! in a firmware shipped to a user): its first unknown AEOLUS command hangs the main loop, with
//! the interrupts still running (SysTick ticks, the UARTs send the command's answer). Only the
//! main loop feeds the watchdog, so the box must reset about 4 s later (QEMU board: 2 s load,
//! the first time-out raises the interrupt, the second resets; `firmware-example/src/board/
//! qemu.rs`), boot again and come back with what it had stored.
//!
//! The async firmware (`firmware-embassy`'s QEMU board, [`Board::Embassy`]) is built with its
//! own `fault-hang`: the command stops its 1 ms tick, the task that schedules telemetry, while
//! the other tasks (the TX pumps, the RX tasks, the supervisor) run on. Its supervisor feeds
//! the same watchdog only while every task it watches shows progress, so it starves the
//! watchdog within a second and the box resets about 4 s after the last feed too.
//!
//! The lm3s6965evb boards only. QEMU 7.2's `netduinoplus2` (the STM32F411 board's simulation)
//! has no IWDG model: the address is an unimplemented-device stub that ignores writes (`info
//! mtree` lists `IWDG` at 0x4000_3000 with priority -1000), so a hang there is never reset in
//! QEMU; the real F411's IWDG is not tested here.

use crate::harness::*;
use std::time::{Duration, Instant};

#[test]
fn a_hung_loop_is_reset_and_keeps_its_settings() {
    a_hung_box_is_reset_and_keeps_its_settings(Board::Lm3s6965evb);
}

#[test]
fn a_hung_task_of_the_async_firmware_is_reset_and_keeps_its_settings() {
    a_hung_box_is_reset_and_keeps_its_settings(Board::Embassy);
}

fn a_hung_box_is_reset_and_keeps_its_settings(board: Board) {
    if !qemu_installed() {
        boot(board, Ports::WATCHDOG.on(board));
        return;
    }
    let elf = firmware_elf_with(board, &["fault-hang"]);
    let Some(mut q) = boot_elf(board, Ports::WATCHDOG.on(board), &elf) else {
        return;
    };
    let log = q.log().display().to_string();
    let first = q.uart0.read_until(Duration::from_secs(10), |_| true);
    assert_eq!(
        q.uart0.frames[first].toast().as_deref(),
        Some("AEOLUS on"),
        "log: {log}"
    );

    // A stored setting: airspeed to 72 m/s, read back, then, landed, "store configuration".
    store_airspeed(&mut q, 72.0, &log);
    let value = 72.0f32.to_le_bytes();

    // The hang: the answer still leaves (interrupts run), then telemetry stops (the main loop
    // schedules it), then the box boots again.
    q.uart0.command("a hang");
    let answer = q
        .uart0
        .read_until(Duration::from_secs(2), |f| f.toast().is_some());
    let hung = Instant::now();
    assert_eq!(
        q.uart0.frames[answer].toast().as_deref(),
        Some("unknown command: a hang"),
        "log: {log}"
    );
    let again = q.uart0.read_until(Duration::from_secs(15), |f| {
        f.toast().as_deref() == Some("AEOLUS on")
    });
    let after = hung.elapsed();
    println!("second boot {after:?} after the hang's answer");
    // Between the answer and the second boot only what the 512-byte TX ring held (a few dozen
    // frames); a loop that ran on would have sent about 700 frames a second.
    let between = &q.uart0.frames[answer + 1..again];
    println!(
        "{} frames between the answer and the second boot",
        between.len()
    );
    assert!(
        between.len() < 200,
        "{} frames while hung: the loop ran on; log: {log}",
        between.len()
    );
    // 4 s after the last feed (the pass that took the command fed it just before); allow the
    // host's scheduling on either side.
    assert!(
        (Duration::from_millis(3_000)..Duration::from_secs(8)).contains(&after),
        "reset {after:?} after the hang, the watchdog's 4 s expected; log: {log}"
    );

    // The stored airspeed is back after the watchdog's reset.
    assert_eq!(
        request(&mut q.uart1, AIRSPEED).as_deref(),
        Some(&value[..]),
        "log: {log}"
    );
    let fw_log = q.stop();
    println!("firmware log:\n{fw_log}");
    let boots = fw_log.matches(board.log_name()).count();
    assert_eq!(boots, 2, "one boot, then one after the watchdog's reset");
    assert!(fw_log.contains("fault-hang: the main loop hangs"));
    // The reset cause: QEMU's RESC never says watchdog (its model sets no bits), so the
    // firmware's own record of a reset it did not ask for tells it.
    assert!(
        fw_log.contains("not asked for false (0 since power-on)"),
        "the first boot after power-on"
    );
    assert!(
        fw_log.contains("not asked for true (1 since power-on)"),
        "the second boot counts the watchdog's reset"
    );
    assert!(!fw_log.contains("HardFault"));
}
