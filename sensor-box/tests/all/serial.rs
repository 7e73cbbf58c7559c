//! QueuedSerial: the application's port over the interrupt handler's queues.

use core::sync::atomic::{AtomicU32, Ordering};
use embedded_hal_nb::serial::{Read, Write};
use sensor_box::serial::{PortStats, QueuedSerial, Ring};

static KICKS: AtomicU32 = AtomicU32::new(0);
fn kick() {
    KICKS.fetch_add(1, Ordering::Relaxed);
}

#[test]
fn rx_bytes_arrive_in_order_and_empty_is_would_block() {
    let (rxq, txq) = (Ring::<64>::new(), Ring::<64>::new());
    let stats = PortStats::new();
    let (mut port, mut isr) = QueuedSerial::split(&rxq, &txq, &stats, || {});
    assert_eq!(port.read(), Err(nb::Error::WouldBlock));
    for b in 0..50u8 {
        assert!(isr.received(b));
    }
    assert_eq!(port.rx_pending(), 50);
    let got: Vec<u8> = core::iter::from_fn(|| port.read().ok()).collect();
    assert_eq!(got, (0..50).collect::<Vec<u8>>());
    assert_eq!(port.read(), Err(nb::Error::WouldBlock));
    assert_eq!(port.counters().rx_bytes, 50);
}

#[test]
fn full_rx_queue_drops_and_counts() {
    let (rxq, txq) = (Ring::<8>::new(), Ring::<8>::new());
    let stats = PortStats::new();
    let (mut port, mut isr) = QueuedSerial::split(&rxq, &txq, &stats, || {});
    let stored = (0..10u8).filter(|b| isr.received(*b)).count();
    assert_eq!(stored, 8); // an empty ring of N holds N
    let c = port.counters();
    assert_eq!((c.rx_bytes, c.rx_dropped), (8, 2));
    // The stored bytes are the first eight, untouched.
    let got: Vec<u8> = core::iter::from_fn(|| port.read().ok()).collect();
    assert_eq!(got, vec![0, 1, 2, 3, 4, 5, 6, 7]);
    isr.receive_error();
    assert_eq!(port.counters().rx_errors, 1);
}

#[test]
fn tx_queues_kicks_and_would_block_when_full() {
    KICKS.store(0, Ordering::Relaxed);
    let (rxq, txq) = (Ring::<4>::new(), Ring::<4>::new());
    let stats = PortStats::new();
    let (mut port, mut isr) = QueuedSerial::split(&rxq, &txq, &stats, kick);
    assert_eq!(port.tx_space(), 4);
    assert_eq!(port.flush(), Ok(()));
    for b in [10u8, 11, 12, 13] {
        assert_eq!(port.write(b), Ok(()));
    }
    assert_eq!(port.write(14), Err(nb::Error::WouldBlock));
    assert_eq!(
        KICKS.load(Ordering::Relaxed),
        5,
        "every write pends the interrupt"
    );
    assert_eq!(port.flush(), Err(nb::Error::WouldBlock));
    assert!(isr.tx_pending());
    assert_eq!(isr.next_to_send(), Some(10));
    // Wrapping around keeps one byte free between the write and the read position.
    assert_eq!(port.write(14), Err(nb::Error::WouldBlock));
    assert_eq!(isr.next_to_send(), Some(11));
    assert_eq!(port.write(14), Ok(()));
    let sent: Vec<u8> = core::iter::from_fn(|| isr.next_to_send()).collect();
    assert_eq!(sent, vec![12, 13, 14]);
    assert!(!isr.tx_pending());
    assert_eq!(port.flush(), Ok(()));
    assert_eq!(port.counters().tx_bytes, 5);
}

/// Interleaved traffic: the "interrupt" receives while the application
/// echoes; nothing is lost or reordered while the queues have room.
#[test]
fn echo_loop_keeps_every_byte() {
    let (rxq, txq) = (Ring::<32>::new(), Ring::<32>::new());
    let stats = PortStats::new();
    let (mut port, mut isr) = QueuedSerial::split(&rxq, &txq, &stats, || {});
    let input: Vec<u8> = (0..5000u32).map(|i| (i * 7 + 3) as u8).collect();
    let mut wire = Vec::new();
    for chunk in input.chunks(13) {
        for &b in chunk {
            assert!(isr.received(b));
        }
        while let Ok(b) = port.read() {
            nb::block!(port.write(b)).unwrap();
            // The UART takes bytes as fast as the application queues them.
            if let Some(out) = isr.next_to_send() {
                wire.push(out);
            }
        }
    }
    wire.extend(core::iter::from_fn(|| isr.next_to_send()));
    assert_eq!(wire, input);
    assert_eq!(port.counters().rx_dropped, 0);
}

static RX_KICKS: AtomicU32 = AtomicU32::new(0);
fn rx_kick() {
    RX_KICKS.fetch_add(1, Ordering::Relaxed);
}

#[test]
fn reading_from_a_full_rx_queue_kicks_the_interrupt() {
    // A board that holds bytes in its UART FIFO while the queue is full (QEMU) must be told
    // when there is room again; reading from a queue that is not near full costs no kick.
    let (rxq, txq) = (Ring::<8>::new(), Ring::<8>::new());
    let stats = PortStats::new();
    let (mut port, mut isr) = QueuedSerial::split(&rxq, &txq, &stats, rx_kick);
    while isr.rx_room() {
        assert!(isr.received(1));
    }
    assert_eq!(port.rx_pending(), 8);
    assert_eq!(port.read(), Ok(1));
    assert_eq!(RX_KICKS.load(Ordering::Relaxed), 1, "room again: kicked");
    assert_eq!(port.read(), Ok(1));
    assert!(isr.rx_room());
    assert_eq!(port.read(), Ok(1));
    assert_eq!(
        RX_KICKS.load(Ordering::Relaxed),
        1,
        "the handler found room since: no kick"
    );
    assert_eq!(port.counters().rx_dropped, 0);
}
