//! The AOK link as an async task: board-independent (any `embedded_io_async` reader that can
//! say whether bytes wait, `embassy-time` for the clock).
//!
//! ```text
//!   UART RX (DMA ring) --read--> held bytes --Receive--> AokLink::poll --> QueuedSerial --> pump_tx
//!   (a poll on every read, and at the link's own wake: next_wake_ms)
//! ```
//!
//! The link is driven as the blocking boards' main loop drives it: [`AokLink::poll`] after
//! bytes arrived, and at the instant [`AokLink::next_wake_ms`] names (the debug stream, a
//! motor test's lapse, the end of a burst), at the next millisecond at the earliest. Its noise
//! gate is inside the link and is kept as it is: a burst is obeyed only when a poll finds the
//! port empty [`GAP_MS`](sensor_box::aok_link::GAP_MS) after the last byte was taken. So a
//! poll at a timer wake first asks the reader whether bytes wait ([`ReadReady`]: the DMA ring
//! may hold bytes it has not yet signalled, with no idle line yet and the ring less than half
//! full) and takes them first: silence is observed, never inferred from a read that has not
//! returned. The store policy is the link's too (`Shared::request_store`); the store itself
//! is done by the tick ([`links::run`](crate::links::run)), as for the other links.
//!
//! A UART error (framing, noise, parity, overrun) is counted and reported to the link as an
//! error of its port (the link's `port_errors`; that poll observes no silence).
//!
//! [`AokLink::poll`]: sensor_box::aok_link::AokLink::poll
//! [`AokLink::next_wake_ms`]: sensor_box::aok_link::AokLink::next_wake_ms

use core::ops::Range;

use embassy_futures::select::{Either, select};
use embassy_time::{Instant, Timer};
use embedded_io::{ErrorKind, ErrorType, Write, WriteReady};
use embedded_io_async::{Read, ReadReady};
use sensor_box::aok_link::RX_BUDGET;
use sensor_box::port::Receive;
use sensor_box::supervisor::Heartbeat;

use crate::links::{Application, Port, RxErrors, Shared, now_ms};

/// The longest the AOK task sleeps without a poll, ms (the blocking boards cap the main
/// loop's sleep in the same way): its heart beats at least this often.
pub const MAX_SLEEP_MS: u64 = 250;

/// A reader that says whether a read began a burst: its receive side saw the line silent
/// ([`GAP_MS`](sensor_box::aok_link::GAP_MS)) before the read's first byte by its own clock,
/// however late the task read it (`sensor_box::port::Receive::burst_starts`). Such a reader
/// never returns a read that crosses such a point.
pub trait Bursts {
    /// Whether the last read began a burst. A reader with no clock of its own (a DMA ring)
    /// says `false`: the link then observes silence itself, by polling.
    fn began_burst(&self) -> bool;
}

/// The AOK link's port for one poll: the received bytes the task holds, lent through
/// [`Receive`]; whether the first of them begins a burst; a UART error to report; the TX
/// queue its pump drains.
struct AokPort<'a> {
    rx: &'a [u8],
    taken: usize,
    /// The held bytes begin a burst (until the link takes the first).
    starts: bool,
    error: bool,
    tx: &'a mut Port,
}

impl ErrorType for AokPort<'_> {
    type Error = ErrorKind;
}

impl Receive for AokPort<'_> {
    fn receive(&mut self, take: impl FnOnce(&[u8]) -> usize) -> Result<usize, ErrorKind> {
        if core::mem::take(&mut self.error) {
            return Err(ErrorKind::Other);
        }
        let rest = self.rx.get(self.taken..).unwrap_or(&[]);
        if rest.is_empty() {
            return Ok(0);
        }
        let n = take(rest).min(rest.len());
        self.taken += n;
        if n > 0 {
            self.starts = false;
        }
        Ok(n)
    }

    fn burst_starts(&self) -> bool {
        self.starts && self.taken < self.rx.len()
    }
}

impl Write for AokPort<'_> {
    fn write(&mut self, buf: &[u8]) -> Result<usize, ErrorKind> {
        self.tx.write(buf).map_err(|e| match e {})
    }

    fn flush(&mut self) -> Result<(), ErrorKind> {
        // The pump sends what is queued; nothing to wait for here.
        Ok(())
    }
}

impl WriteReady for AokPort<'_> {
    fn write_ready(&mut self) -> Result<bool, ErrorKind> {
        self.tx.write_ready().map_err(|e| match e {})
    }
}

/// AOK: reads `uart` into the AOK link and polls it on every read and at its wake time
/// (see the module docs). `heart` beats on every poll, at least every [`MAX_SLEEP_MS`].
pub async fn aok<R: Read + ReadReady + Bursts>(
    mut uart: R,
    shared: &Shared,
    errors: &RxErrors,
    heart: &Heartbeat,
) -> ! {
    let mut buf = [0u8; RX_BUDGET];
    // The bytes of `buf` read from the UART and not yet taken by the link.
    let mut held: Range<usize> = 0..0;
    // Whether the held bytes begin a burst (the reader said so before it read them).
    let mut starts = false;
    let mut error = false;
    loop {
        heart.beat();
        let now = now_ms();
        let wake = shared
            .with(|a| {
                let Application { app, aok_tx, .. } = a;
                let mut port = AokPort {
                    rx: buf.get(held.clone()).unwrap_or(&[]),
                    taken: 0,
                    starts,
                    error: core::mem::take(&mut error),
                    tx: aok_tx,
                };
                app.aok.poll(now, &mut port, &mut app.shared);
                held.start = held.start.saturating_add(port.taken).min(held.end);
                starts = port.starts;
                app.aok.next_wake_ms()
            })
            .unwrap_or(now);
        let soonest = now.saturating_add(1);
        if !held.is_empty() {
            // The link took no more (its TX queue lacked room for the answers): the rest
            // waits in `buf`, and the UART's ring, until the next millisecond's poll.
            Timer::at(Instant::from_millis(soonest)).await;
            continue;
        }
        let deadline = wake.max(soonest).min(now.saturating_add(MAX_SLEEP_MS));
        let read = match select(
            uart.read(&mut buf),
            Timer::at(Instant::from_millis(deadline)),
        )
        .await
        {
            Either::First(read) => read,
            // The link's wake: a read that waits for the idle line may not have returned
            // bytes the ring holds, so ask; an error is a read result too.
            Either::Second(()) => match uart.read_ready() {
                Ok(false) => continue,
                _ => uart.read(&mut buf).await,
            },
        };
        match read {
            Ok(n) => {
                held = 0..n.min(buf.len());
                starts = uart.began_burst();
            }
            Err(_) => {
                errors.bump();
                error = true;
                defmt::warn!("AOK: UART receive error");
            }
        }
    }
}
