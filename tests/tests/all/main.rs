//! The cross-crate and end-to-end tests: one test binary, one module per file of `tests/all/`,
//! named `FILE::test` (`cargo test -p protolink-tests --test all soak::`). `harness` boots the
//! firmware in QEMU for the `*_qemu`, `qemu_firmware`, `protolink_*`, `soak`, `box_clock`,
//! `readme_examples` and `realtime_flood` tests, at most `QEMU_JOBS` emulators at once (see
//! its docs); `test_layout` checks that every crate keeps this one-binary layout.

mod box_clock;
mod capture_qemu;
mod corruption;
mod gdl90_qemu;
mod harness;
mod module_layers;
mod nmea_qemu;
mod noise_qemu;
mod protolink_e2e;
mod protolink_help;
mod qemu_firmware;
mod readme_examples;
mod realtime_flood;
mod resync;
mod soak;
mod test_layout;
mod watchdog_qemu;
#[cfg(feature = "browser")]
mod web_qemu;
