//! The host tool's integration tests: one test binary (linked once against the tool's
//! dependencies), one module per file of `tests/all/`, named `FILE::test`
//! (`cargo test -p protolink --test all gdl90::`). `common` is the helpers they share.

mod air_data;
mod aok;
mod aydp;
mod bridge;
mod capture;
mod cli;
mod columns;
mod common;
mod decode;
mod destinations;
mod export;
mod gdl90;
mod gpsd;
mod hostile;
mod nmea;
mod sim;
mod watch;
mod web;
mod wireshark;
