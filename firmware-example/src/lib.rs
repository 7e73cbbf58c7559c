//! The sensor-box firmware example: the boards' board-independent glue.
//!
//! The application (the box's behaviour: telemetry, the three links, the
//! flash record) is the `sensor-box` crate ([`sensor_box`]). This library
//! holds what the boards put around it and what can be tested on the host,
//! with no `unsafe` and no board crate:
//!
//! * [`clock`]: the [`Clock`] trait (a monotonic millisecond clock) and a
//!   [`ManualClock`] for host tests and simulations;
//! * [`serial`]: [`QueuedSerial`], the serial port type the application sees on
//!   every board. It implements `embedded_io`'s `Read`, `ReadReady`, `Write`
//!   and `WriteReady` (slices: what the links use) and
//!   `embedded_hal_nb::serial::{Read, Write}` (bytes) over two `bbqueue` rings ([`serial::Ring`]); the other ends ([`SerialIsr`]) belong to the
//!   board's UART interrupt handler;
//! * [`storage`]: `embedded-storage` NOR flash over a byte slice ([`MemFlash`],
//!   the QEMU board's flash store and the host tests' store) and a
//!   [`FlashWindow`] that gives a sub-range of a bigger flash.
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

pub mod clock;
mod error;
pub mod serial;
pub mod storage;

pub use clock::{Clock, ManualClock};
pub use error::Error;
pub use serial::{PortStats, QueuedSerial, SerialIsr};
pub use storage::{FlashWindow, MemFlash};
