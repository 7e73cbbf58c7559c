//! The sensor box's integration tests: one test binary, one module per file of `tests/all/`,
//! named `FILE::test` (`cargo test -p sensor-box --test all noise::`). `common` is the test
//! support they share (the flash models, the genuine AOK commands).

mod aeolus_link;
mod aok_link;
mod aydp_link;
mod common;
mod flash_faults;
mod frame_entry_points;
mod log;
mod noise;
mod persist;
mod poll_pending;
mod power_cut;
mod schedule;
mod serial;
mod serial_slices;
mod slice_ports;
mod storage;
mod supervisor;
mod tx_queue;
