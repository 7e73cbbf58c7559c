//! `sensor-box`: the firmware binary, one for both boards.
//!
//! The board is chosen by feature (`board-qemu` or `board-stm32f411`); the
//! `.cargo/config.toml` aliases `cargo qemu` and `cargo stm32` pick the
//! target and feature. For now `main` is the boot smoke test of the board
//! layer:
//!
//! * logs the boot with `defmt`;
//! * counts boots in the flash store (shows that the store survives a warm
//!   reset) and writes a greeting line on each UART;
//! * echoes every byte received on each UART back out of the same UART;
//! * a `0x12` byte (Ctrl-R) on UART0 warm-resets the box (smoke test only;
//!   the application will use AEOLUS "a reboot");
//! * every 5 s logs the uptime, the stack high-water mark and the port
//!   counters.
//!
//! On the host this file builds a stub `main` that says how to run it.
#![cfg_attr(target_os = "none", no_std)]
#![cfg_attr(target_os = "none", no_main)]

#[cfg(target_os = "none")]
mod board;

#[cfg(target_os = "none")]
mod app {
    use crate::board;
    use core::fmt::Write as _;
    use cortex_m as _;
    use embedded_hal_nb::serial::{Read, Write};
    use embedded_storage::nor_flash::{NorFlash, ReadNorFlash};
    use firmware_example::{Clock, QueuedSerial, info, warn};

    /// "BOOT" little-endian: marks a valid boot counter in the store.
    const BOOT_MAGIC: u32 = 0x544F_4F42;

    /// Reads, increments and stores the boot counter; 1 on an empty store.
    fn count_boot<S: NorFlash>(store: &mut S) -> u32 {
        let mut word = [0u8; 8];
        let stored = match store.read(0, &mut word) {
            Ok(()) => {
                let (magic, count) = word.split_at(4);
                let magic = u32::from_le_bytes(magic.try_into().unwrap_or([0; 4]));
                let count = u32::from_le_bytes(count.try_into().unwrap_or([0; 4]));
                (magic == BOOT_MAGIC).then_some(count)
            }
            Err(_) => None,
        };
        if stored.is_none() {
            warn!("flash store: no boot counter, starting at 1");
        }
        let boots = stored.unwrap_or(0).wrapping_add(1);
        let mut new = [0u8; 8];
        new[..4].copy_from_slice(&BOOT_MAGIC.to_le_bytes());
        new[4..].copy_from_slice(&boots.to_le_bytes());
        let erase_to = u32::try_from(S::ERASE_SIZE).unwrap_or(u32::MAX);
        if store
            .erase(0, erase_to)
            .and_then(|()| store.write(0, &new))
            .is_err()
        {
            warn!("flash store: could not write the boot counter");
        }
        boots
    }

    /// Writes all of `bytes`, waiting while the TX queue is full.
    fn send(port: &mut QueuedSerial<'static>, bytes: &[u8]) {
        for &b in bytes {
            let _ = nb::block!(port.write(b));
        }
    }

    #[cortex_m_rt::entry]
    fn main() -> ! {
        let mut b = board::init();
        info!(
            "sensor-box {=str} on {=str}: booting",
            env!("CARGO_PKG_VERSION"),
            board::NAME
        );
        let boots = count_boot(&mut b.store);
        info!(
            "boot #{=u32}; flash store {=usize} bytes",
            boots,
            b.store.capacity()
        );

        let mut ports = [b.uart0, b.uart1, b.uart2];
        for (i, port) in ports.iter_mut().enumerate() {
            let mut line: heapless::String<64> = heapless::String::new();
            let _ = write!(line, "sensor-box boot #{boots} UART{i} echo ready\r\n");
            send(port, line.as_bytes());
        }

        let flight = flight_sim::Flight::new(flight_sim::FlightParams::DEFAULT).ok();
        let mut next_report = 5_000u64;
        loop {
            for (i, port) in ports.iter_mut().enumerate() {
                while let Ok(byte) = port.read() {
                    if i == 0 && byte == 0x12 {
                        info!("Ctrl-R on UART0: warm reset");
                        board::reset();
                    }
                    let _ = nb::block!(port.write(byte));
                }
            }
            let now = b.clock.now_ms();
            if now >= next_report {
                next_report = now.saturating_add(5_000);
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
                if let Some(f) = &flight {
                    let s = f.state(now);
                    info!(
                        "sim: heading {=f32} deg, lat {=f64} lon {=f64}",
                        s.heading_deg, s.latitude_deg, s.longitude_deg
                    );
                }
            }
            cortex_m::asm::wfi();
        }
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
