//! The PL011 driver's decisions, apart from its registers, wakers and ring: when the
//! interrupt wakes the reader and the writer, which interrupts it leaves on, and what a read,
//! a write and a flush do with what they find. Plain functions of register values and counts
//! (`core` only), so that `tests/tests/all/harness/pl011_wake.rs` runs them on the host
//! against a model of the UART, its ring and the two tasks; the driver ([`super`]) only reads
//! and writes the registers around them.

/// FR: the receive FIFO is empty.
pub const FR_RXFE: u32 = 1 << 4;
/// FR: the transmit FIFO is full.
pub const FR_TXFF: u32 = 1 << 5;
/// FR: the transmit FIFO is empty.
pub const FR_TXFE: u32 = 1 << 7;
/// IMSC, MIS and ICR: receive (the RX FIFO reached its level).
pub const INT_RX: u32 = 1 << 4;
/// IMSC, MIS and ICR: transmit (the TX FIFO drained to its level).
pub const INT_TX: u32 = 1 << 5;
/// IMSC, MIS and ICR: receive timeout (bytes below the level wait and the line is quiet).
pub const INT_RT: u32 = 1 << 6;

/// The interrupt mask `imsc` with `bits` set (`on`) or cleared, the other bits kept.
pub const fn mask(imsc: u32, bits: u32, on: bool) -> u32 {
    if on { imsc | bits } else { imsc & !bits }
}

/// What the interrupt does after it moved what the RX FIFO held into the ring.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AfterReceive {
    /// Wake the reader: bytes reached the ring, or receive errors were counted.
    pub wake_reader: bool,
    /// The interrupt mask to write: RX and receive timeout off while the ring is full and
    /// bytes wait in the FIFO (the reader's next read pends the interrupt), on otherwise.
    pub imsc: u32,
}

/// The receive half of the interrupt: `moved` bytes went into the ring, `new_errors` whether
/// receive errors were counted, `held` whether the ring filled with bytes still in the FIFO.
pub const fn after_receive(imsc: u32, moved: usize, new_errors: bool, held: bool) -> AfterReceive {
    AfterReceive {
        wake_reader: moved > 0 || new_errors,
        imsc: mask(imsc, INT_RX | INT_RT, !held),
    }
}

/// What the interrupt does for the writer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AfterTransmit {
    /// Wake the writer: it waits for room (its TX interrupt is on) and the FIFO has room.
    pub wake_writer: bool,
    /// The interrupt mask to write: TX off once the writer is woken (the TX interrupt stays
    /// raised while the FIFO has room), else unchanged.
    pub imsc: u32,
}

/// The transmit half of the interrupt, from the mask and FR. A writer that does not wait has
/// its TX interrupt off: the receive interrupts (on every received byte in QEMU) never wake
/// it.
pub const fn after_transmit(imsc: u32, fr: u32) -> AfterTransmit {
    let wake_writer = imsc & INT_TX != 0 && fr & FR_TXFF == 0;
    AfterTransmit {
        wake_writer,
        imsc: if wake_writer {
            mask(imsc, INT_TX, false)
        } else {
            imsc
        },
    }
}

/// What a read does with what it finds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Read {
    /// Report one error: receive errors were counted since the last one reported.
    Error,
    /// Take bytes from the ring.
    Take,
    /// Wait for the interrupt's wake (the waker is registered first).
    Wait,
}

/// A read: `pending` bytes in the ring, `errors` the port's receive-error count and
/// `errors_seen` that count as of the last error reported. An error comes before the bytes.
pub const fn read(pending: usize, errors: u32, errors_seen: u32) -> Read {
    if errors != errors_seen {
        Read::Error
    } else if pending > 0 {
        Read::Take
    } else {
        Read::Wait
    }
}

/// What a write or a flush does.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Write {
    /// Done: `n` bytes went into the FIFO (a flush: the FIFO is empty).
    Done(usize),
    /// Wait for the TX interrupt: write this mask (TX on) after the waker is registered.
    Wait(u32),
}

/// A write whose FIFO took `taken` bytes of a non-empty buffer: done, or (nothing taken, the
/// FIFO is full) wait with the TX interrupt on.
pub const fn write(imsc: u32, taken: usize) -> Write {
    match taken {
        0 => Write::Wait(mask(imsc, INT_TX, true)),
        n => Write::Done(n),
    }
}

/// A flush: done when FR says the TX FIFO is empty, else wait with the TX interrupt on.
pub const fn flush(imsc: u32, fr: u32) -> Write {
    if fr & FR_TXFE != 0 {
        Write::Done(0)
    } else {
        Write::Wait(mask(imsc, INT_TX, true))
    }
}
