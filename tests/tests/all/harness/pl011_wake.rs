//! The async firmware's PL011 driver decisions (`firmware-embassy/src/qemu/pl011/wake.rs`,
//! compiled here as it is) on the host: each rule on its own, then the rules driving a model
//! of QEMU's PL011 (its 16-byte FIFOs, the RX interrupt raised when the FIFO goes from empty
//! to one byte and cleared by ICR, the TX interrupt raised while the TX FIFO is at its level),
//! the driver's receive ring with `sensor-box`'s hold-and-kick, a reader and a writer, in
//! random orders. Every received byte must reach the reader and every byte written must leave,
//! with no wake-up lost, and the receive interrupts must never wake a writer that is not
//! waiting.

#[path = "../../../../firmware-embassy/src/qemu/pl011/wake.rs"]
#[allow(dead_code)]
mod wake;

use protolink_tests::rng::Rng;
use wake::*;

#[test]
fn the_receive_interrupt_wakes_on_bytes_or_errors_and_masks_while_the_ring_is_full() {
    let on = INT_RX | INT_RT | INT_TX;
    assert_eq!(
        after_receive(on, 3, false, false),
        AfterReceive {
            wake_reader: true,
            imsc: on
        }
    );
    assert!(after_receive(on, 0, true, false).wake_reader);
    assert!(!after_receive(on, 0, false, false).wake_reader);
    // Held: RX and the receive timeout off, the writer's TX interrupt untouched.
    assert_eq!(after_receive(on, 5, false, true).imsc, INT_TX);
    // The next interrupt after the reader's kick turns them on again.
    assert_eq!(after_receive(INT_TX, 7, false, false).imsc, on);
}

#[test]
fn the_interrupt_wakes_the_writer_only_when_it_waits_and_the_fifo_has_room() {
    let waiting = INT_RX | INT_RT | INT_TX;
    assert_eq!(
        after_transmit(waiting, 0),
        AfterTransmit {
            wake_writer: true,
            imsc: INT_RX | INT_RT
        }
    );
    assert_eq!(
        after_transmit(waiting, FR_TXFF),
        AfterTransmit {
            wake_writer: false,
            imsc: waiting
        }
    );
    // An idle writer (TX off) is not woken by a receive interrupt, even with an empty FIFO.
    assert!(!after_transmit(INT_RX | INT_RT, FR_TXFE).wake_writer);
}

#[test]
fn a_read_reports_an_error_before_bytes_and_waits_on_an_empty_ring() {
    assert_eq!(read(4, 2, 1), Read::Error);
    assert_eq!(read(4, 2, 2), Read::Take);
    assert_eq!(read(0, 2, 2), Read::Wait);
    assert_eq!(read(0, 0, u32::MAX), Read::Error);
}

#[test]
fn a_write_or_flush_waits_with_the_tx_interrupt_on() {
    assert_eq!(write(INT_RX, 0), Write::Wait(INT_RX | INT_TX));
    assert_eq!(write(INT_RX, 9), Write::Done(9));
    assert_eq!(flush(INT_RX, FR_TXFE), Write::Done(0));
    assert_eq!(flush(INT_RX, 0), Write::Wait(INT_RX | INT_TX));
}

const FIFO: usize = 16;
/// TX interrupt level: one-eighth of the FIFO.
const TX_LEVEL: usize = 2;

/// QEMU's PL011, the driver's ring and its two tasks, stepped by the rules of `wake`.
#[derive(Default)]
struct Model {
    ring_len: usize,
    imsc: u32,
    /// QEMU's raised interrupt bits (`int_level`).
    level: u32,
    /// The NVIC's pending bit (the reader's kick).
    pended: bool,
    rx_fifo: Vec<bool>,
    /// The ring's bytes; `held`: the interrupt left bytes in the FIFO (sensor-box's rx_held).
    ring: usize,
    held: bool,
    errors: u32,
    errors_seen: u32,
    reader_waits: bool,
    reader_woken: bool,
    received: usize,
    errors_reported: u32,
    tx_fifo: usize,
    to_write: usize,
    written: usize,
    left: usize,
    writer_waits: bool,
    writer_woken: bool,
    idle_writer_wakes: u32,
}

impl Model {
    fn new(ring_len: usize, to_write: usize) -> Self {
        Model {
            ring_len,
            imsc: INT_RX | INT_RT,
            to_write,
            ..Model::default()
        }
    }

    /// A byte (or a receive error) arrives, if the FIFO has room (else QEMU keeps it).
    fn arrive(&mut self, error: bool) -> bool {
        if self.rx_fifo.len() == FIFO {
            return false;
        }
        self.rx_fifo.push(error);
        if self.rx_fifo.len() == 1 {
            self.level |= INT_RX;
        }
        true
    }

    fn tx_level(&self) -> u32 {
        if self.tx_fifo <= TX_LEVEL { INT_TX } else { 0 }
    }

    fn interrupt_due(&self) -> bool {
        self.pended || (self.level | self.tx_level()) & self.imsc != 0
    }

    /// The driver's interrupt handler (`pl011::on_interrupt`).
    fn interrupt(&mut self) {
        self.pended = false;
        self.level &= !(INT_RX | INT_RT | INT_TX);
        let (mut moved, mut new_errors) = (0, false);
        while !self.rx_fifo.is_empty() && self.ring < self.ring_len {
            if self.rx_fifo.remove(0) {
                self.errors += 1;
                new_errors = true;
            } else {
                self.ring += 1;
                moved += 1;
            }
        }
        let held = !self.rx_fifo.is_empty();
        self.held |= held;
        let after = after_receive(self.imsc, moved, new_errors, held);
        self.imsc = after.imsc;
        if after.wake_reader {
            self.reader_woken = true;
        }
        let fr = if self.tx_fifo == FIFO { FR_TXFF } else { 0 }
            | if self.tx_fifo == 0 { FR_TXFE } else { 0 };
        let after = after_transmit(self.imsc, fr);
        self.imsc = after.imsc;
        if after.wake_writer {
            if !self.writer_waits {
                self.idle_writer_wakes += 1;
            }
            self.writer_woken = true;
        }
    }

    /// One poll of the reader (`Rx::read`): registers, then decides.
    fn read(&mut self, rng: &mut Rng) {
        match read(self.ring, self.errors, self.errors_seen) {
            Read::Error => {
                self.errors_seen = self.errors;
                self.errors_reported += 1;
                self.reader_waits = false;
            }
            Read::Take => {
                let n = 1 + rng.below(self.ring.min(64) as u64) as usize;
                self.ring -= n;
                self.received += n;
                self.reader_waits = false;
                if std::mem::take(&mut self.held) {
                    self.pended = true;
                }
            }
            Read::Wait => {
                self.reader_waits = true;
                self.reader_woken = false;
            }
        }
    }

    /// One poll of the writer (`Tx::write`) while it has bytes to write.
    fn write(&mut self, rng: &mut Rng) {
        let want = (self.to_write - self.written).min(1 + rng.below(128) as usize);
        let taken = want.min(FIFO - self.tx_fifo);
        match write(self.imsc, taken) {
            Write::Done(n) => {
                self.tx_fifo += n;
                self.written += n;
                self.writer_waits = false;
            }
            Write::Wait(imsc) => {
                self.imsc = imsc;
                self.writer_waits = true;
                self.writer_woken = false;
            }
        }
    }

    fn reader_runs(&self) -> bool {
        !self.reader_waits || self.reader_woken
    }

    fn writer_runs(&self) -> bool {
        self.written < self.to_write && (!self.writer_waits || self.writer_woken)
    }
}

/// Runs `bytes` arrivals (one in `error_every` an error) and a `to_write`-byte write in random
/// orders; returns the model after everything that can still happen has happened.
fn run(seed: u64, ring_len: usize, bytes: usize, error_every: usize, to_write: usize) -> Model {
    let mut rng = Rng::new(seed);
    let mut m = Model::new(ring_len, to_write);
    let mut arrived = 0;
    for _ in 0..1_000_000 {
        let line_busy = arrived < bytes;
        let mut choices = Vec::new();
        if line_busy {
            choices.push(0);
        }
        if m.interrupt_due() {
            choices.push(1);
        }
        if m.reader_runs() {
            choices.push(2);
        }
        if m.writer_runs() {
            choices.push(3);
        }
        if m.tx_fifo > 0 {
            choices.push(4);
        }
        let Some(&step) = choices.get(rng.below(choices.len() as u64) as usize) else {
            break;
        };
        match step {
            0 => {
                let error = error_every > 0 && rng.below(error_every as u64) == 0;
                if m.arrive(error) {
                    arrived += 1;
                }
            }
            1 => m.interrupt(),
            2 => m.read(&mut rng),
            3 => m.write(&mut rng),
            _ => {
                m.tx_fifo -= 1;
                m.left += 1;
            }
        }
    }
    m
}

#[test]
fn the_rules_lose_no_byte_and_no_wake_up_in_random_orders() {
    for seed in 0..300u64 {
        let ring_len = [1, 2, 16, 64][seed as usize % 4];
        let errors = if seed % 3 == 0 { 0 } else { 7 };
        let m = run(seed, ring_len, 600, errors, 500);
        assert_eq!(
            m.received as u32 + m.errors,
            600,
            "seed {seed}: bytes stuck (ring {}, FIFO {}, IMSC {:#x}, held {})",
            m.ring,
            m.rx_fifo.len(),
            m.imsc,
            m.held
        );
        assert_eq!(
            m.errors_seen, m.errors,
            "seed {seed}: an error not reported"
        );
        assert!(
            m.errors_reported <= m.errors && (m.errors == 0) == (m.errors_reported == 0),
            "seed {seed}: {} errors reported for {}",
            m.errors_reported,
            m.errors
        );
        assert!(
            m.reader_waits,
            "seed {seed}: the reader did not come to rest"
        );
        assert_eq!(
            (m.written, m.left),
            (500, 500),
            "seed {seed}: the writer stalled (IMSC {:#x})",
            m.imsc
        );
        assert_eq!(
            m.idle_writer_wakes, 0,
            "seed {seed}: an idle writer was woken"
        );
    }
}
