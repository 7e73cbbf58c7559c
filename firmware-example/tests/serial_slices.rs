//! QueuedSerial through `embedded_io`: slices in and out of the queues, and when the
//! interrupt is kicked. Each test counts its kicks in its own static (tests run in parallel).

use core::sync::atomic::{AtomicU32, Ordering};
use embedded_io::{Read, ReadReady, Write, WriteReady};
use firmware_example::{PortStats, QueuedSerial};
use heapless::spsc::Queue;

#[test]
fn a_read_drains_what_is_queued_in_order_and_a_full_queue_kicks_once() {
    static KICKS: AtomicU32 = AtomicU32::new(0);
    let (mut rxq, mut txq) = (Queue::<u8, 8>::new(), Queue::<u8, 4>::new());
    let stats = PortStats::new();
    let (mut port, mut isr) = QueuedSerial::split(&mut rxq, &mut txq, &stats, || {
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
    let (mut rxq, mut txq) = (Queue::<u8, 2>::new(), Queue::<u8, 8>::new());
    let stats = PortStats::new();
    let (mut port, mut isr) = QueuedSerial::split(&mut rxq, &mut txq, &stats, || {
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
    let (mut rxq, mut txq) = (Queue::<u8, 2>::new(), Queue::<u8, 8>::new());
    let stats = PortStats::new();
    let (port, mut isr) = QueuedSerial::split(&mut rxq, &mut txq, &stats, || {
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
