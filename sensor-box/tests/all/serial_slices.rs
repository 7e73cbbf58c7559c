//! QueuedSerial through `embedded_io`: slices in and out of the queues, and when the
//! interrupt is kicked. Each test counts its kicks in its own static (tests run in parallel).

use core::sync::atomic::{AtomicU32, Ordering};
use embedded_io::{Read, ReadReady, Write, WriteReady};
use sensor_box::serial::{PortStats, QueuedSerial, Ring};

#[test]
fn a_read_drains_what_is_queued_in_order_and_a_full_queue_kicks_once() {
    static KICKS: AtomicU32 = AtomicU32::new(0);
    let (rxq, txq) = (Ring::<7>::new(), Ring::<4>::new());
    let stats = PortStats::new();
    let (mut port, mut isr) = QueuedSerial::split(&rxq, &txq, &stats, || {
        KICKS.fetch_add(1, Ordering::Relaxed);
    });
    assert_eq!(port.read_ready(), Ok(false));
    for b in 0..7u8 {
        assert!(isr.received(b));
    }
    assert!(
        !isr.rx_room(),
        "the queue is full: the board stops reading the UART"
    );
    let mut buf = [0u8; 5];
    assert_eq!(port.read(&mut buf), Ok(5));
    assert_eq!(buf, [0, 1, 2, 3, 4]);
    assert_eq!(
        KICKS.load(Ordering::Relaxed),
        1,
        "reading from a full queue kicks"
    );
    assert_eq!(port.read(&mut buf), Ok(2));
    assert_eq!(buf[..2], [5, 6]);
    assert_eq!(
        KICKS.load(Ordering::Relaxed),
        1,
        "not full any more: no kick"
    );
    assert_eq!(port.read_ready(), Ok(false));
    assert_eq!(port.read(&mut []), Ok(0));
}

#[test]
fn a_write_queues_what_fits_and_kicks_once_per_write() {
    static KICKS: AtomicU32 = AtomicU32::new(0);
    let (rxq, txq) = (Ring::<2>::new(), Ring::<7>::new());
    let stats = PortStats::new();
    let (mut port, mut isr) = QueuedSerial::split(&rxq, &txq, &stats, || {
        KICKS.fetch_add(1, Ordering::Relaxed);
    });
    assert_eq!(port.write(b"abcde"), Ok(5));
    assert_eq!(
        KICKS.load(Ordering::Relaxed),
        1,
        "one kick for the whole slice"
    );
    assert_eq!(port.write(b"fghij"), Ok(2), "the queue holds 7");
    assert_eq!(port.write_ready(), Ok(false));
    let mut block = [0u8; 16];
    assert_eq!(isr.take_to_send(&mut block), 7);
    assert_eq!(&block[..7], b"abcdefg");
    assert_eq!(port.counters().tx_bytes, 7);
    assert_eq!(port.write_ready(), Ok(true));
}

#[test]
fn a_batched_port_kicks_only_when_full_and_on_flush() {
    static KICKS: AtomicU32 = AtomicU32::new(0);
    let (rxq, txq) = (Ring::<2>::new(), Ring::<7>::new());
    let stats = PortStats::new();
    let (port, mut isr) = QueuedSerial::split(&rxq, &txq, &stats, || {
        KICKS.fetch_add(1, Ordering::Relaxed);
    });
    let mut port = port.batched();
    assert_eq!(port.write(b"abc"), Ok(3));
    assert_eq!(port.write(b"defgh"), Ok(4));
    assert_eq!(KICKS.load(Ordering::Relaxed), 0, "writes only queue");
    // Full: asking for room kicks the interrupt, which may make room at once.
    assert_eq!(port.write_ready(), Ok(false));
    assert_eq!(KICKS.load(Ordering::Relaxed), 1);
    // The main loop's flush after the poll (the `embedded_hal_nb` one: it does not wait).
    assert!(embedded_hal_nb::serial::Write::flush(&mut port).is_err());
    assert_eq!(KICKS.load(Ordering::Relaxed), 2);
    let (room, mut fifo) = (core::cell::Cell::new(16), Vec::new());
    let put = |b| {
        room.set(room.get() - 1);
        fifo.push(b);
    };
    assert_eq!(isr.send_while(|| room.get() > 0, put), 7);
    assert_eq!(fifo, b"abcdefg");
    assert_eq!(port.counters().tx_bytes, 7);
    assert!(embedded_hal_nb::serial::Write::flush(&mut port).is_ok());
}

/// Every way of cutting a stream into writes, and of taking it out (FIFO fills of every size,
/// DMA blocks of every size), through a small ring that wraps around many times: the bytes
/// come out whole and in order, and the counters agree.
#[test]
fn every_split_through_a_wrapping_ring_keeps_every_byte_in_order() {
    let input: Vec<u8> = (0..600u32).map(|i| (i * 31 + 7) as u8).collect();
    for write_len in 1..=9usize {
        for take_len in 1..=9usize {
            for fifo in [false, true] {
                let (rxq, txq) = (Ring::<2>::new(), Ring::<8>::new());
                let stats = PortStats::new();
                let (mut port, mut isr) = QueuedSerial::split(&rxq, &txq, &stats, || {});
                let (mut at, mut out) = (0, Vec::new());
                while out.len() < input.len() {
                    let chunk = &input[at..(at + write_len).min(input.len())];
                    if !chunk.is_empty() && port.write_ready() == Ok(true) {
                        at += port.write(chunk).unwrap();
                    }
                    if fifo {
                        let room = core::cell::Cell::new(take_len);
                        isr.send_while(
                            || room.get() > 0,
                            |b| {
                                room.set(room.get() - 1);
                                out.push(b);
                            },
                        );
                    } else {
                        let mut block = vec![0u8; take_len];
                        let n = isr.take_to_send(&mut block);
                        out.extend_from_slice(&block[..n]);
                    }
                    assert!(port.tx_space() <= 8);
                }
                assert_eq!(out, input, "writes of {write_len}, takes of {take_len}");
                assert_eq!(port.counters().tx_bytes, 600);
                assert!(!isr.tx_pending());
                assert_eq!(embedded_hal_nb::serial::Write::flush(&mut port), Ok(()));
            }
        }
    }
}

/// The receive side the same way: FIFO bursts of every size into a small ring, reads of every
/// size out; a full ring leaves the rest of a burst in the "UART" (nothing dropped) and the
/// next read kicks the handler.
#[test]
fn every_split_through_a_wrapping_rx_ring_keeps_every_byte_and_drops_none() {
    static KICKS: AtomicU32 = AtomicU32::new(0);
    let input: Vec<u8> = (0..500u32).map(|i| (i * 13 + 1) as u8).collect();
    for burst in 1..=12usize {
        for read_len in 1..=9usize {
            KICKS.store(0, Ordering::Relaxed);
            let (rxq, txq) = (Ring::<8>::new(), Ring::<2>::new());
            let stats = PortStats::new();
            let (mut port, mut isr) = QueuedSerial::split(&rxq, &txq, &stats, || {
                KICKS.fetch_add(1, Ordering::Relaxed);
            });
            let (mut uart, mut out) = (input.iter().copied().peekable(), Vec::new());
            let mut buf = vec![0u8; read_len];
            // Bounded: a handler that stores nothing fails the test instead of hanging it.
            for _ in 0..2 * input.len() {
                if out.len() >= input.len() {
                    break;
                }
                let mut left = burst;
                isr.receive_while(|| {
                    if left == 0 {
                        return None;
                    }
                    left -= 1;
                    uart.next().map(Ok)
                });
                if port.read_ready() == Ok(true) {
                    let n = port.read(&mut buf).unwrap();
                    out.extend_from_slice(&buf[..n]);
                }
            }
            assert_eq!(out, input, "bursts of {burst}, reads of {read_len}");
            let c = port.counters();
            assert_eq!((c.rx_bytes, c.rx_dropped), (500, 0));
            assert_eq!(port.rx_pending(), 0);
            if burst > 8 {
                assert!(KICKS.load(Ordering::Relaxed) > 0, "a full ring: kicked");
            }
        }
    }
}

/// A receive error takes no room in the ring and is counted; a full ring stops the handler
/// before it takes the next byte from the UART.
#[test]
fn receive_while_counts_errors_and_stops_when_full() {
    let (rxq, txq) = (Ring::<3>::new(), Ring::<2>::new());
    let stats = PortStats::new();
    let (mut port, mut isr) = QueuedSerial::split(&rxq, &txq, &stats, || {});
    let mut uart = [Ok(1), Err(()), Ok(2), Err(()), Ok(3), Ok(4)].into_iter();
    assert_eq!(isr.receive_while(|| uart.next()), 3);
    assert_eq!(uart.next(), Some(Ok(4)), "left in the UART");
    assert!(!isr.rx_room());
    let mut buf = [0u8; 8];
    assert_eq!(port.read(&mut buf), Ok(3));
    assert_eq!(buf[..3], [1, 2, 3]);
    let c = port.counters();
    assert_eq!((c.rx_bytes, c.rx_errors, c.rx_dropped), (3, 2, 0));
}

/// Receive errors anywhere in a burst, at every fill of a wrapping ring: each is counted once,
/// none takes a slot, and the bytes around them arrive in order; `receive_while` returns the
/// bytes it stored.
#[test]
fn errors_between_bytes_of_a_wrapping_rx_ring_are_counted_and_take_no_room() {
    for error_every in 1..=5usize {
        for burst in 1..=10usize {
            let uart_items: Vec<Result<u8, ()>> = (0..300usize)
                .map(|i| {
                    if i % (error_every + 1) == error_every {
                        Err(())
                    } else {
                        Ok(i as u8)
                    }
                })
                .collect();
            let want: Vec<u8> = uart_items.iter().filter_map(|r| r.ok()).collect();
            let errors = uart_items.len() - want.len();
            let (rxq, txq) = (Ring::<7>::new(), Ring::<2>::new());
            let stats = PortStats::new();
            let (mut port, mut isr) = QueuedSerial::split(&rxq, &txq, &stats, || {});
            let (mut uart, mut out, mut stored) =
                (uart_items.into_iter().peekable(), Vec::new(), 0);
            let mut buf = [0u8; 3];
            for _ in 0..600 {
                if uart.peek().is_none() && port.rx_pending() == 0 {
                    break;
                }
                let mut left = burst;
                stored += isr.receive_while(|| {
                    if left == 0 {
                        return None;
                    }
                    left -= 1;
                    uart.next()
                });
                if port.read_ready() == Ok(true) {
                    let n = port.read(&mut buf).unwrap();
                    out.extend_from_slice(&buf[..n]);
                }
            }
            assert_eq!(out, want, "an error every {error_every}, bursts of {burst}");
            assert_eq!(stored, want.len());
            let c = port.counters();
            assert_eq!(
                (c.rx_bytes as usize, c.rx_errors as usize, c.rx_dropped),
                (want.len(), errors, 0)
            );
        }
    }
}

/// `send_fifo` against a model of a 16-byte UART FIFO at every fill level, through a ring
/// that wraps at every position: it hands over exactly what the FIFO has room for (a block
/// while it is empty, then a byte while it has room), in order, says whether bytes are left,
/// and counts what it handed over.
#[test]
fn send_fifo_fills_a_fifo_of_any_level_through_a_wrapping_ring() {
    const FIFO: usize = 16;
    let input: Vec<u8> = (0..40u32).map(|i| (i * 37 + 11) as u8).collect();
    for offset in 0..32usize {
        for queued in 0..=24usize {
            for level in 0..=FIFO {
                let (rxq, txq) = (Ring::<2>::new(), Ring::<32>::new());
                let stats = PortStats::new();
                let (mut port, mut isr) = QueuedSerial::split(&rxq, &txq, &stats, || {});
                // Move the ring's positions to `offset`, so the queued bytes wrap there.
                for _ in 0..offset {
                    assert_eq!(port.write(&[0]), Ok(1));
                    assert_eq!(isr.next_to_send(), Some(0));
                }
                let mut at = 0;
                while at < queued {
                    // A ring of 32 takes 24 bytes at any position, in at most two writes.
                    assert_eq!(port.write_ready(), Ok(true), "offset {offset}");
                    at += port.write(&input[at..queued]).unwrap();
                }
                let before = port.counters().tx_bytes;
                let fill = core::cell::Cell::new(level);
                let mut out = Vec::new();
                let pending = isr.send_fifo(
                    FIFO,
                    || fill.get() == 0,
                    || fill.get() < FIFO,
                    |b| {
                        assert!(fill.get() < FIFO, "a byte put into a full FIFO");
                        fill.set(fill.get() + 1);
                        out.push(b);
                    },
                );
                let sent = queued.min(FIFO - level);
                let case = format!("offset {offset}, {queued} queued, FIFO at {level}");
                assert_eq!(out, input[..sent], "{case}");
                assert_eq!(pending, sent < queued, "{case}");
                assert_eq!(isr.tx_pending(), sent < queued, "{case}");
                assert_eq!(port.counters().tx_bytes - before, sent as u32, "{case}");
            }
        }
    }
}

/// `receive_batched` against a model, through a wrapping ring, for many random scripts of
/// bursts (with receive errors), publish requests, thresholds and reads: what the application
/// reads is the UART's bytes in order; a byte becomes visible exactly when the model says
/// (the threshold reached, the run of free ring full, or a publish request), never earlier;
/// the counters agree; nothing is dropped; and a full ring leaves bytes in the UART.
#[test]
fn receive_batched_publishes_when_the_model_says_and_keeps_every_byte_in_order() {
    struct Rng(u64);
    impl Rng {
        fn below(&mut self, n: u64) -> u64 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            self.0 % n
        }
    }
    let mut full_rings = 0;
    for seed in 1..=300u64 {
        let mut rng = Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15));
        let publish_at = 1 + rng.below(12) as usize;
        let (rxq, txq) = (Ring::<16>::new(), Ring::<2>::new());
        let stats = PortStats::new();
        let (mut port, mut isr) = QueuedSerial::split(&rxq, &txq, &stats, || {});
        let input: Vec<Result<u8, ()>> = (0..400u32)
            .map(|i| {
                if rng.below(9) == 0 {
                    Err(())
                } else {
                    Ok((i * 7 + seed as u32) as u8)
                }
            })
            .collect();
        let want: Vec<u8> = input.iter().filter_map(|r| r.ok()).collect();
        let mut uart = input.iter().copied().peekable();
        let (mut out, mut published) = (Vec::new(), 0usize);
        let mut buf = [0u8; 8];
        for step in 0..4_000 {
            if out.len() == want.len() {
                break;
            }
            let burst = rng.below(10) as usize;
            let publish = rng.below(4) == 0 || step > 3_000;
            let before = isr.unpublished();
            let mut taken = 0usize;
            let n = isr.receive_batched(publish_at, publish, || {
                if taken == burst {
                    return None;
                }
                taken += 1;
                uart.next()
            });
            published += n;
            let after = isr.unpublished();
            // Never more held than the threshold allows (a run of the ring that ends sooner
            // is published when full, so less may be published at a time).
            assert!(
                after < publish_at,
                "seed {seed}: {after} held at {publish_at}"
            );
            if n == 0 && !publish {
                // Nothing published: what was held, and the bytes just taken, are held.
                assert!(after >= before, "seed {seed}: held bytes vanished");
            }
            if publish && isr.rx_room() {
                assert_eq!(after, 0, "seed {seed}: a request publishes everything");
            }
            assert_eq!(port.rx_pending() + out.len(), published, "seed {seed}");
            full_rings += usize::from(isr.rx_held());
            if rng.below(3) == 0 && port.read_ready() == Ok(true) {
                let k = 1 + rng.below(buf.len() as u64) as usize;
                let n = port.read(&mut buf[..k]).unwrap();
                out.extend_from_slice(&buf[..n]);
            }
        }
        assert_eq!(out, want, "seed {seed}, publish at {publish_at}");
        // Receive errors after the last byte are still in the UART: take them.
        assert_eq!(isr.receive_batched(publish_at, true, || uart.next()), 0);
        let c = port.counters();
        assert_eq!(c.rx_bytes as usize, want.len(), "seed {seed}");
        assert_eq!(
            c.rx_errors as usize,
            input.len() - want.len(),
            "seed {seed}"
        );
        assert_eq!(c.rx_dropped, 0);
    }
    assert!(full_rings > 0, "the scripts fill the ring at times");
}

/// Bytes `receive_batched` holds come before those of a later `receive_while` or `received`:
/// both publish what is held first.
#[test]
fn the_byte_paths_publish_what_receive_batched_holds_first() {
    let (rxq, txq) = (Ring::<16>::new(), Ring::<2>::new());
    let stats = PortStats::new();
    let (mut port, mut isr) = QueuedSerial::split(&rxq, &txq, &stats, || {});
    let mut uart = [1, 2].into_iter().map(Ok);
    assert_eq!(isr.receive_batched(8, false, || uart.next()), 0);
    let mut more = [3].into_iter().map(Ok);
    assert_eq!(isr.receive_while(|| more.next()), 1);
    assert_eq!(isr.unpublished(), 0);
    let mut uart = [4].into_iter().map(Ok);
    assert_eq!(isr.receive_batched(8, false, || uart.next()), 0);
    assert!(isr.received(5));
    let mut buf = [0u8; 8];
    assert_eq!(port.read(&mut buf), Ok(5));
    assert_eq!(buf[..5], [1, 2, 3, 4, 5]);
    assert_eq!(port.counters().rx_bytes, 5);
}
