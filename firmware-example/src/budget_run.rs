//! The `cpu-budget` build's run: warm up, account a window of the box's clock, report, exit.
//!
//! After [`WARMUP_MS`] the main loop calibrates and starts the account from zero;
//! [`WINDOW_MS`] later it logs the report (`firmware_example::budget_report`, the lines
//! `scripts/budget.py` reads, the same as the async firmware's) and exits through semihosting.

use crate::board;
use firmware_example::budget_report::{self, Counts, WARMUP_MS, WINDOW_MS};
use sensor_box::App;
use sensor_box::budget;

/// Where the run is.
pub struct Run {
    start_ms: u64,
    /// The counters when the window opened (`None`: not yet).
    before: Option<Counts>,
}

impl Run {
    /// The run of a box booted at `now_ms`.
    pub fn new(now_ms: u64) -> Self {
        Run {
            start_ms: now_ms.saturating_add(WARMUP_MS),
            before: None,
        }
    }

    /// When [`Run::poll`] next has something to do, ms: the window's start, then its end.
    pub fn next_ms(&self) -> u64 {
        if self.before.is_some() {
            self.start_ms.saturating_add(WINDOW_MS)
        } else {
            self.start_ms
        }
    }

    /// Called once per main-loop turn.
    pub fn poll(&mut self, now_ms: u64, app: &App, ports: [&board::Port; 3]) {
        match &self.before {
            None if now_ms >= self.start_ms => {
                budget_report::calibrate();
                self.start_ms = now_ms;
                self.before = Some(Counts::take(app, ports.map(|p| p.counters())));
                budget::start();
            }
            Some(before) if now_ms >= self.start_ms.saturating_add(WINDOW_MS) => {
                let after = Counts::take(app, ports.map(|p| p.counters()));
                budget_report::report(now_ms - self.start_ms, before, &after);
                semihosting::process::exit(0)
            }
            _ => {}
        }
    }
}
