//! Where the receive side saw the line fall silent: the burst marks a UART interrupt handler
//! leaves for a link that frames commands by silence.
//!
//! A link observes silence itself when it polls often enough (the AOK link, [`GAP_MS`]). When
//! the main loop stalls (a flash erase blocks it for up to seconds), the interrupt handler
//! still takes every byte into the RX ring, and the link later finds the bytes of several
//! commands at once, with nothing to say where one ended. The handler, told the time by its
//! board ([`SerialIsr::at`](crate::serial::SerialIsr::at)), marks the position of the first
//! byte after [`GAP_MS`] of silence by its own clock; the port lends no slice across a mark
//! and says when the next byte begins a burst ([`Receive::burst_starts`]); the link ends the
//! open burst there as if it had seen the silence itself. The marks are as strict as the
//! link's own observation: whole milliseconds of the same clock, two of them.
//!
//! The marks live in a ring of [`MARKS`] positions; when it is full a new mark is dropped, the
//! bursts on both sides of it merge, and the gate discards them: never a command obeyed that
//! silence did not frame.
//!
//! [`GAP_MS`]: crate::aok_link::GAP_MS
//! [`Receive::burst_starts`]: crate::port::Receive::burst_starts

use core::sync::atomic::{AtomicU32, Ordering};

/// Marks the ring holds: a PC polling through a 1.5 s store stall sends about 8 commands.
pub const MARKS: usize = 16;

/// The burst marks of one port: positions in the received byte stream (the wrapping count of
/// bytes received before the mark) written by the interrupt handler, read by the application.
#[derive(Debug)]
pub struct BurstMarks {
    at: [AtomicU32; MARKS],
    /// Marks written, wrapping (the handler's).
    written: AtomicU32,
    /// Marks read, wrapping (the application's).
    read: AtomicU32,
}

impl Default for BurstMarks {
    fn default() -> Self {
        Self::new()
    }
}

impl BurstMarks {
    /// No mark (usable in a `static`).
    ///
    /// ```
    /// static MARKS: sensor_box::burst_marks::BurstMarks = sensor_box::burst_marks::BurstMarks::new();
    /// assert_eq!(MARKS.pending(), 0);
    /// ```
    pub const fn new() -> Self {
        BurstMarks {
            at: [const { AtomicU32::new(0) }; MARKS],
            written: AtomicU32::new(0),
            read: AtomicU32::new(0),
        }
    }

    /// Marks waiting to be passed by the application.
    ///
    /// ```
    /// let marks = sensor_box::burst_marks::BurstMarks::new();
    /// marks.push(3);
    /// assert_eq!(marks.pending(), 1);
    /// ```
    pub fn pending(&self) -> usize {
        let written = self.written.load(Ordering::Acquire);
        written.wrapping_sub(self.read.load(Ordering::Relaxed)) as usize
    }

    /// The handler's side: a burst begins at stream position `position`. Dropped when the ring
    /// is full (see the module doc).
    pub fn push(&self, position: u32) {
        let written = self.written.load(Ordering::Relaxed);
        let read = self.read.load(Ordering::Acquire);
        if written.wrapping_sub(read) as usize >= MARKS {
            return;
        }
        if let Some(slot) = self.at.get(written as usize % MARKS) {
            slot.store(position, Ordering::Relaxed);
        }
        self.written
            .store(written.wrapping_add(1), Ordering::Release);
    }

    /// The application's side, with `taken` bytes of the stream taken: drops the marks it has
    /// passed and returns (whether the next byte begins a burst, how many bytes at most may be
    /// taken before the next mark after it, `None` for no limit).
    ///
    /// ```
    /// let marks = sensor_box::burst_marks::BurstMarks::new();
    /// marks.push(0);
    /// marks.push(2);
    /// assert_eq!(marks.next(0), (true, Some(2)));
    /// assert_eq!(marks.next(1), (false, Some(1)));
    /// assert_eq!(marks.next(2), (true, None));
    /// assert_eq!(marks.next(3), (false, None));
    /// assert_eq!(marks.pending(), 0);
    /// ```
    pub fn next(&self, taken: u32) -> (bool, Option<usize>) {
        let written = self.written.load(Ordering::Acquire);
        let mut read = self.read.load(Ordering::Relaxed);
        let mut starts = false;
        let mut limit = None;
        let mut i = read;
        while i != written {
            let at = self
                .at
                .get(i as usize % MARKS)
                .map_or(taken, |a| a.load(Ordering::Relaxed));
            let ahead = at.wrapping_sub(taken) as i32;
            if ahead < 0 {
                // Passed: dropped (only marks before every later one are passed).
                read = i.wrapping_add(1);
            } else if ahead == 0 {
                starts = true;
            } else {
                limit = Some(ahead as usize);
                break;
            }
            i = i.wrapping_add(1);
        }
        self.read.store(read, Ordering::Release);
        (starts, limit)
    }
}
