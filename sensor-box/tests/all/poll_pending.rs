//! `App::poll_pending`: a link runs only when its UART's flag is set or its own `has_work`
//! says so (a timer due, TX bytes waiting, bytes left by the RX budget). Bytes that arrive
//! without the flag wait in the port until the link runs for another reason.

use sensor_box::serial::{PortStats, QueuedSerial, Ring};
use sensor_box::storage::MemFlash;
use sensor_box::{App, aeolus_link, aok_link, aydp_link};

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
    // Its flag set, AOK runs at once and takes the read; AYDP still waits. The read is
    // obeyed when the silence after it is observed: AOK's own timer wakes it for that,
    // GAP_MS later, without a flag, and it answers.
    app.poll_pending(
        2,
        [false, false, true],
        &mut u0,
        &mut u1,
        &mut u2,
        &mut flash,
    );
    assert_eq!((u2.rx_pending(), i2.next_to_send()), (0, None));
    assert_eq!(app.aok.next_wake_ms(), 2 + aok_link::GAP_MS);
    assert!(!app.aok.has_work(2 + aok_link::GAP_MS - 1));
    app.poll_pending(
        2 + aok_link::GAP_MS,
        [false; 3],
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
    assert!(app.aeolus.has_work(0, &app.shared));
    app.poll_pending(0, [false; 3], &mut u0, &mut u1, &mut u2, &mut flash);
    assert_eq!(u0.rx_pending(), 0);
    assert!(!app.aeolus.has_work(0, &app.shared));
}

/// A main loop that sleeps until [`App::next_wake_ms`] (at the next millisecond at the
/// earliest) and wakes for received bytes, polling only the links with work, sends exactly what
/// a loop running every link every millisecond ([`App::poll`]) sends, byte for byte on all three UARTs, under a random script of commands that move the
/// links' timers: AEOLUS pause and resume, AYDP telemetry intervals (some turned off, some
/// shortened) and the AOK debug period, AOK debug on and off, and bursts of noise that leave
/// bytes behind the RX budget.
#[test]
fn sleeping_until_next_wake_sends_what_polling_every_millisecond_sends() {
    use aeolus_proto::CrcMode;
    use aeolus_proto::message::{Message, Text};
    use aydp_proto::{Encoder, Profile, SystemValueUpdate, UpdateMode};
    use proptest::prelude::*;
    use proptest::test_runner::{Config, TestRunner};

    /// One input: at `at` ms, these bytes arrive on UART `uart`.
    type Event = (u64, usize, Vec<u8>);

    fn aeolus(text: &str) -> Vec<u8> {
        let mut buf = [0u8; 64];
        let n = Message::Command(Text::new(text).unwrap())
            .encode(&mut buf, CrcMode::Compute)
            .unwrap();
        buf[..n].to_vec()
    }

    fn aydp(address: u16, mode: UpdateMode, data: &[u8]) -> Vec<u8> {
        let mut buf = [0u8; 256];
        let update = SystemValueUpdate {
            address,
            mode,
            data,
        };
        let n = Encoder::new(Profile::Spec)
            .encode(&update, None, &mut buf)
            .unwrap();
        buf[..n].to_vec()
    }

    fn event() -> impl Strategy<Value = Event> {
        let intervals = prop::collection::vec(prop_oneof![Just(0u32), 1u32..40, 40u32..1500], 6)
            .prop_map(|v| {
                let data: Vec<u8> = v.iter().flat_map(|x| x.to_le_bytes()).collect();
                (
                    1usize,
                    aydp(
                        aydp_link::addr::INTERVALS,
                        UpdateMode::Array { count: 6 },
                        &data,
                    ),
                )
            });
        let debug_period = (0u32..60).prop_map(|p| {
            (
                1usize,
                aydp(
                    aydp_link::addr::AOK_DEBUG_PERIOD,
                    UpdateMode::Single,
                    &p.to_le_bytes(),
                ),
            )
        });
        let input = prop_oneof![
            Just((0usize, aeolus("a pause"))),
            Just((0usize, aeolus("a resume"))),
            intervals,
            debug_period,
            Just((2usize, vec![0x63, 0x01])), // AOK debug off
            Just((2usize, vec![0x63, 0x02])), // AOK debug on
            prop::collection::vec(any::<u8>(), 200..400).prop_map(|noise| (0usize, noise)),
        ];
        (0u64..3_000, input).prop_map(|(at, (uart, bytes))| (at, uart, bytes))
    }

    /// Runs the box for 3.5 s of its clock with `events`; `sleeps`: only at the wake instants
    /// and for received bytes, else every link every millisecond. What each UART sent.
    fn run(events: &[Event], sleeps: bool) -> [Vec<u8>; 3] {
        let rig = Rig::new();
        let [(mut u0, mut i0), (mut u1, mut i1), (mut u2, mut i2)] = rig.ports();
        let mut mem = [0xFFu8; 4096];
        let mut flash = MemFlash::new(&mut mem);
        let mut app = App::new(&mut flash, 0);
        let mut sent: [Vec<u8>; 3] = Default::default();
        let mut wake = 0;
        for now in 0..3_500u64 {
            let mut received = [false; 3];
            for (_, uart, bytes) in events.iter().filter(|(at, ..)| *at == now) {
                let isr = match uart {
                    0 => &mut i0,
                    1 => &mut i1,
                    _ => &mut i2,
                };
                for &b in bytes {
                    isr.received(b);
                }
                received[*uart] = true;
            }
            if sleeps && now < wake && received == [false; 3] {
                continue;
            }
            if sleeps {
                app.poll_pending(now, received, &mut u0, &mut u1, &mut u2, &mut flash);
            } else {
                app.poll(now, &mut u0, &mut u1, &mut u2, &mut flash);
            }
            wake = app.next_wake_ms().max(now + 1);
            for (out, isr) in sent.iter_mut().zip([&mut i0, &mut i1, &mut i2]) {
                out.extend(core::iter::from_fn(|| isr.next_to_send()));
            }
        }
        sent
    }

    let mut runner = TestRunner::new(Config {
        cases: 24,
        ..Config::default()
    });
    runner
        .run(&prop::collection::vec(event(), 0..12), |events| {
            let every_ms = run(&events, false);
            let sleeping = run(&events, true);
            for (uart, (a, b)) in every_ms.iter().zip(&sleeping).enumerate() {
                prop_assert!(!a.is_empty(), "UART{} sent nothing", uart);
                prop_assert!(
                    a == b,
                    "UART{} differs: {} against {} bytes",
                    uart,
                    a.len(),
                    b.len()
                );
            }
            Ok(())
        })
        .unwrap();
}
