//! The boards' host-testable glue: one test binary, one module per file of `tests/all/`.

mod clock;
