//! The deadline of the protocol crates' liveness unit tests (`aeolus-proto/src/liveness.rs`,
//! `aydp-proto/src/decoder/liveness.rs`, `aok-proto/src/decoder/liveness.rs` include this
//! file with `#[path]`): a loop that stops making progress ends the test binary at once
//! instead of hanging it.

extern crate std;

use std::sync::mpsc::{self, RecvTimeoutError};
use std::time::Duration;

/// Far above the work (microseconds): only a loop that never ends reaches it.
pub(crate) const DEADLINE: Duration = Duration::from_secs(10);

/// Runs `work` on its own thread and returns its result, or fails the test if it has not
/// returned by the deadline: then the test binary exits with status 101 at once.
pub(crate) fn returns<T: Send + 'static>(what: &'static str, work: fn() -> T) -> T {
    let (tx, rx) = mpsc::sync_channel(1);
    std::thread::spawn(move || tx.send(work()));
    match rx.recv_timeout(DEADLINE) {
        Ok(v) => v,
        Err(RecvTimeoutError::Timeout) => {
            // Ends the whole test binary, not only this test: another test of the same
            // binary spinning in the same loop would otherwise hold it open until an outer
            // timeout, and a mutation run would count a hang instead of a failure.
            std::eprintln!("{what} did not return within {DEADLINE:?}: a loop makes no progress");
            std::process::exit(101)
        }
        Err(RecvTimeoutError::Disconnected) => panic!("{what} panicked"),
    }
}
