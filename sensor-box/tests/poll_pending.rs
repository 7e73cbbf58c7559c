//! `App::poll_pending`: a link runs only when its UART's flag is set or its own `has_work`
//! says so (a timer due, TX bytes waiting, bytes left by the RX budget). Bytes that arrive
//! without the flag wait in the port until the link runs for another reason.

use sensor_box::serial::{PortStats, QueuedSerial, Ring};
use sensor_box::storage::MemFlash;
use sensor_box::{App, aeolus_link, aydp_link};

type Port<'a> = QueuedSerial<'a, 512, 1024>;

struct Rig {
    rx: [Ring<512>; 3],
    tx: [Ring<1024>; 3],
    stats: [PortStats; 3],
}

impl Rig {
    fn new() -> Self {
        Rig {
            rx: [const { Ring::new() }; 3],
            tx: [const { Ring::new() }; 3],
            stats: [const { PortStats::new() }; 3],
        }
    }

    fn ports(&self) -> [(Port<'_>, sensor_box::serial::SerialIsr<'_, 512, 1024>); 3] {
        [0, 1, 2].map(|i| QueuedSerial::split(&self.rx[i], &self.tx[i], &self.stats[i], || {}))
    }
}

#[test]
fn only_the_flagged_link_or_a_due_timer_runs() {
    let rig = Rig::new();
    let [(mut u0, mut i0), (mut u1, mut i1), (mut u2, mut i2)] = rig.ports();
    let mut mem = [0xFFu8; 4096];
    let mut flash = MemFlash::new(&mut mem);
    let mut app = App::new(&mut flash, 0);
    // Boot: every link has its first messages due.
    app.poll_pending(0, [false; 3], &mut u0, &mut u1, &mut u2, &mut flash);
    for isr in [&mut i0, &mut i1, &mut i2] {
        while isr.next_to_send().is_some() {}
    }
    // AOK read parameter 3 arrives on UART2, AYDP garbage on UART1, but only UART0 is
    // flagged: neither AOK nor AYDP runs, their bytes stay in their ports.
    for b in [0x67, 0x03] {
        i2.received(b);
    }
    for b in [0x01, 0x02, 0x03] {
        i1.received(b);
    }
    assert!(!app.aok.has_work(1) && !app.aydp.has_work(1));
    app.poll_pending(
        1,
        [true, false, false],
        &mut u0,
        &mut u1,
        &mut u2,
        &mut flash,
    );
    assert_eq!((u1.rx_pending(), u2.rx_pending()), (3, 2));
    assert_eq!(i2.next_to_send(), None);
    assert_eq!(app.aok.decoder_stats().frames_ok, 0);
    // Its flag set, AOK runs at once and answers; AYDP still waits.
    app.poll_pending(
        2,
        [false, false, true],
        &mut u0,
        &mut u1,
        &mut u2,
        &mut flash,
    );
    let reply: Vec<u8> = core::iter::from_fn(|| i2.next_to_send()).collect();
    assert_eq!(reply, [0xFF, 0x03, 0, 0, 0, 0, 0]);
    assert_eq!(u1.rx_pending(), 3);
    // AYDP's own timer (the next heartbeat at 1 s) runs it without a flag: it takes its bytes.
    assert!(!app.aydp.has_work(999));
    assert!(app.aydp.has_work(aydp_link::HEARTBEAT_PERIOD_MS));
    app.poll_pending(1000, [false; 3], &mut u0, &mut u1, &mut u2, &mut flash);
    assert_eq!(u1.rx_pending(), 0);
    assert_eq!(app.aydp.decoder_stats().bytes_discarded, 3);
}

#[test]
fn a_link_that_hit_its_rx_budget_runs_again_without_a_flag() {
    let rig = Rig::new();
    let [(mut u0, mut i0), (mut u1, _i1), (mut u2, _i2)] = rig.ports();
    let mut mem = [0xFFu8; 4096];
    let mut flash = MemFlash::new(&mut mem);
    let mut app = App::new(&mut flash, 0);
    app.poll_pending(0, [true; 3], &mut u0, &mut u1, &mut u2, &mut flash);
    while i0.next_to_send().is_some() {}
    // 300 bytes of noise on UART0: one poll takes RX_BUDGET (256), the rest waits, and the
    // link says it has work within the same millisecond.
    for _ in 0..300 {
        i0.received(0x55);
    }
    app.poll_pending(
        0,
        [true, false, false],
        &mut u0,
        &mut u1,
        &mut u2,
        &mut flash,
    );
    assert_eq!(u0.rx_pending(), 300 - aeolus_link::RX_BUDGET);
    assert!(app.aeolus.has_work(0));
    app.poll_pending(0, [false; 3], &mut u0, &mut u1, &mut u2, &mut flash);
    assert_eq!(u0.rx_pending(), 0);
    assert!(!app.aeolus.has_work(0));
}
