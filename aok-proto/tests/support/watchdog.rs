//! A deadline for a whole test binary: the client tests wait for replies in loops that only
//! end when the client makes progress, so a client that stops making it would hang the binary.
//! The first test to arm the watchdog starts a thread that ends the process with status 101
//! once the deadline has passed; the binary's tests take milliseconds.

use std::sync::Once;
use std::time::Duration;

/// Far above the milliseconds the tests of one binary take.
const DEADLINE: Duration = Duration::from_secs(10);

/// Starts the watchdog, once per binary.
pub fn arm() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        std::thread::spawn(|| {
            std::thread::sleep(DEADLINE);
            eprintln!("the tests of this binary did not end within {DEADLINE:?}: a wait spins");
            std::process::exit(101);
        });
    });
}
