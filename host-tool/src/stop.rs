//! Stopping long-running commands (`decode`, `bridge`, `watch`): Ctrl-C (SIGINT) and
//! `--seconds N`. The short request/reply commands keep the default Ctrl-C, which ends them at once.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

static STOP: AtomicBool = AtomicBool::new(false);

/// Installs the Ctrl-C handler: it only sets a flag, so every loop finishes its current step and
/// prints its counters. Calling it twice is harmless.
pub(crate) fn install_ctrl_c() {
    // An error means a handler is already installed, which is what we want anyway.
    let _ = ctrlc::set_handler(|| STOP.store(true, Ordering::SeqCst));
}

/// Whether Ctrl-C was pressed.
pub(crate) fn requested() -> bool {
    STOP.load(Ordering::SeqCst)
}

/// When a command should end by itself: `--seconds N`, or never.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Deadline(Option<Instant>);

impl Deadline {
    /// A deadline `run_time` from now (`None`: never). A time too far ahead to represent is
    /// taken as never.
    pub(crate) fn after(run_time: Option<Duration>) -> Self {
        Deadline(run_time.and_then(|d| Instant::now().checked_add(d)))
    }

    /// Whether the deadline has passed or Ctrl-C was pressed.
    pub(crate) fn reached(&self) -> bool {
        requested() || self.0.is_some_and(|t| Instant::now() >= t)
    }

    /// How long is left, capped at `cap` (`cap` when there is no deadline).
    pub(crate) fn left(&self, cap: Duration) -> Duration {
        match self.0 {
            Some(t) => t.saturating_duration_since(Instant::now()).min(cap),
            None => cap,
        }
    }
}

/// The examples of this module's items, as tests (the items are crate-private, so rustdoc
/// does not run them).
#[cfg(test)]
#[allow(unused_imports, clippy::unnecessary_wraps)]
mod examples {
    use super::*;

    #[test]
    fn deadline_example() -> Result<(), Box<dyn std::error::Error>> {
        use std::time::Duration;
        assert!(!Deadline::after(None).reached());
        assert!(Deadline::after(Some(Duration::ZERO)).reached());
        Ok(())
    }
}
