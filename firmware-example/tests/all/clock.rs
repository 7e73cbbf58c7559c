//! The clock trait and the manual clock used by host tests.

use firmware_example::{Clock, ManualClock};

fn elapsed<C: Clock>(clock: &C, since: u64) -> u64 {
    clock.now_ms() - since
}

#[test]
fn manual_clock_moves_only_forward() {
    let c = ManualClock::new(1_000);
    assert_eq!(c.now_ms(), 1_000);
    c.advance(7);
    assert_eq!(elapsed(&c, 1_000), 7);
    c.set(500);
    assert_eq!(c.now_ms(), 1_007);
    c.set(2_000);
    assert_eq!(elapsed(&&c, 0), 2_000); // through the `&C` impl
    c.advance(u64::MAX);
    assert_eq!(c.now_ms(), u64::MAX);
}
