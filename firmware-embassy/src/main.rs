//! `sensor-box-embassy`: the sensor box on `embassy-executor`, on one of two boards chosen by
//! feature. The application is the `sensor-box` crate; the async glue around it is written
//! once, board-independent, over `embedded-io-async` ports, the `embassy-time` clock and an
//! `embedded-storage(-async)` flash: [`links`] (the RX loops, the TX pumps, the 1 ms tick,
//! the store task, the supervisor) and [`aok`] (the AOK task). A board is its `main`: it
//! brings up the chip, builds the ports, the flash and the watchdog, and spawns the tasks.
//!
//! | feature | target | board | module |
//! |---|---|---|---|
//! | `board-stm32f411` (default) | `thumbv7em-none-eabihf` | STM32F411 with `embassy-stm32`: DMA rings, the IWDG, the flash | `stm32f411.rs` |
//! | `board-qemu` | `thumbv7m-none-eabi` | QEMU `lm3s6965evb`: interrupt-driven PL011 UARTs, SysTick as the time driver, the luminary watchdog, the settings in RAM | `qemu/` |
#![no_std]
#![no_main]

#[cfg(all(feature = "board-qemu", feature = "board-stm32f411"))]
compile_error!(
    "choose one board: `board-stm32f411` (the default) or `--no-default-features --features board-qemu`"
);
#[cfg(not(any(feature = "board-qemu", feature = "board-stm32f411")))]
compile_error!("the firmware needs a board: `board-stm32f411` or `board-qemu`");

mod aok;
mod links;

#[cfg(feature = "board-qemu")]
mod qemu;
#[cfg(feature = "board-stm32f411")]
mod stm32f411;

use embassy_executor::{SpawnError, SpawnToken, Spawner};

/// Starts a task; a task that is already running (none is spawned twice beyond its pool) is
/// logged, not a panic.
fn spawn<S>(spawner: &Spawner, token: Result<SpawnToken<S>, SpawnError>) {
    match token {
        Ok(token) => spawner.spawn(token),
        Err(_) => defmt::error!("task pool exhausted: a task did not start"),
    }
}
