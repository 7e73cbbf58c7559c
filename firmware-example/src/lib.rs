//! The sensor-box firmware example: the boards' board-independent glue.
//!
//! The application (the box's behaviour: telemetry, the three links, the
//! flash record) is the `sensor-box` crate ([`sensor_box`]). This library
//! holds what the boards put around it and what can be tested on the host,
//! with no `unsafe` and no board crate:
//!
//! * [`clock`]: the [`Clock`] trait (a monotonic millisecond clock) and a
//!   [`ManualClock`] for host tests and simulations;
//! * [`serial`] and [`storage`], re-exported from `sensor-box` (where they live, so that
//!   the box's own tests use them without depending on this crate): [`QueuedSerial`],
//!   the serial port type the application sees on every board (two `bbqueue` rings; the
//!   other ends, [`SerialIsr`], belong to the board's UART interrupt handler), and
//!   [`MemFlash`] / [`FlashWindow`], NOR flash over a byte slice and a sub-range of a
//!   bigger flash;
//! * [`lm3s6965`]: the register map of the chip QEMU's `lm3s6965evb` models, and its
//!   interrupt table, shared by the blocking QEMU board and the async firmware's;
//! * `budget_report` (on the target only): the `cpu-budget` builds' calibration and report
//!   lines, the same from both QEMU boards.
//!
//! The boards themselves (`src/board/qemu.rs`, `src/board/stm32f411.rs`) and
//! the `sensor-box` binary live in the binary target: all `unsafe` of the
//! example is there.
//!
//! ```
//! use embedded_hal_nb::serial::{Read, Write};
//! use firmware_example::serial::{PortStats, QueuedSerial};
//! use firmware_example::serial::Ring;
//!
//! let (rxq, txq) = (Ring::<8>::new(), Ring::<8>::new());
//! let stats = PortStats::new();
//! let (mut port, mut isr) = QueuedSerial::split(&rxq, &txq, &stats, || {});
//! isr.received(0x7E); // what the UART interrupt does for each byte
//! assert_eq!(port.read(), Ok(0x7E));
//! port.write(0x55).unwrap();
//! assert_eq!(isr.next_to_send(), Some(0x55)); // the interrupt sends it
//! ```
#![no_std]
#![forbid(unsafe_code)]
#![deny(missing_docs)]

#[cfg(target_os = "none")]
pub mod budget_report;
pub mod clock;
pub mod lm3s6965;
pub use sensor_box::{serial, storage};

pub use clock::{Clock, ManualClock};
pub use serial::{PortStats, QueuedSerial, SerialIsr};
pub use storage::{Error, FlashWindow, MemFlash};
