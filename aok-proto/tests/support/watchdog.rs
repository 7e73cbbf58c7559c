//! A deadline for each client test: the client tests wait for replies in loops that only end
//! when the client makes progress, so a client that stops making it would hang the test binary.
//! A test arms the watchdog for as long as it runs (`let _watchdog = watchdog::arm();`, the
//! guard dropped when the test returns or panics); the first test to arm it starts a thread
//! that ends the process with status 101 once an armed test has run past the deadline. A
//! client test takes milliseconds; the deadline is each test's own, not the binary's, as the
//! binary also holds the crate's other tests (property tests that run for seconds).

use std::io::Write;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Mutex, MutexGuard, Once};
use std::time::{Duration, Instant};

/// Far above the milliseconds a client test takes.
const DEADLINE: Duration = Duration::from_secs(10);

/// How often the watchdog looks at the armed tests.
const TICK: Duration = Duration::from_millis(100);

/// Each armed test still running: its guard's number and when it armed.
static ARMED: Mutex<Vec<(u64, Instant)>> = Mutex::new(Vec::new());

fn armed() -> MutexGuard<'static, Vec<(u64, Instant)>> {
    // A test that panics never does so holding the lock; a poisoned list is still right.
    ARMED.lock().unwrap_or_else(|e| e.into_inner())
}

/// Keeps its test under the watchdog until it is dropped.
#[must_use = "the watchdog watches a test only while its guard lives"]
pub struct Armed(u64);

impl Drop for Armed {
    fn drop(&mut self) {
        armed().retain(|&(id, _)| id != self.0);
    }
}

/// Puts the calling test under the watchdog until the returned guard is dropped; starts the
/// watchdog's thread, once per binary.
pub fn arm() -> Armed {
    static ONCE: Once = Once::new();
    static NEXT: AtomicU64 = AtomicU64::new(0);
    ONCE.call_once(|| {
        std::thread::spawn(|| {
            loop {
                std::thread::sleep(TICK);
                let oldest = armed().iter().map(|&(_, since)| since).min();
                if oldest.is_some_and(|since| since.elapsed() >= DEADLINE) {
                    // To stderr itself: `eprintln!` in a thread a test started is captured
                    // with that test's output, which the exit throws away.
                    let _ = writeln!(
                        std::io::stderr(),
                        "a client test did not end within {DEADLINE:?}: a wait spins"
                    );
                    std::process::exit(101);
                }
            }
        });
    });
    let id = NEXT.fetch_add(1, Ordering::Relaxed);
    armed().push((id, Instant::now()));
    Armed(id)
}
