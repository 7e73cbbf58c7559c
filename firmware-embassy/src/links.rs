//! The async glue between UARTs and the application: board-independent (any
//! `embedded_io_async` reader and writer, `embassy-time` for the clock).
//!
//! ```text
//!   UART RX (DMA ring) --> FrameReader --> AeolusLink::handle_frame / AydpLink::handle_frame
//!   UART RX (DMA ring) --> aok::aok --> AokLink::poll (on bytes and at its wake)
//!   ticker (1 ms)  --> AeolusLink::poll_tx, AydpLink::poll_tx, the store and reboot requests
//!   ticker --StoreJob--> store --> persist::store_in_async (the settings map, awaited)
//!   links --> QueuedSerial (TX queue) --kick--> pump_tx --> UART TX (DMA)
//! ```
//!
//! The protocol logic is the `sensor-box` crate, unchanged: the links decide what is sent
//! and when, and encode it into a TX queue exactly as on the blocking boards
//! ([`QueuedSerial`], with the same drop policies when it is full); here an async task moves
//! the queue to the UART in DMA chunks instead of a TXE interrupt moving it a byte at a time.
//! Only the RX side differs in shape: the protocol crates' async `FrameReader`s decode what
//! the DMA ring holds, and each frame is handed to the link's per-frame entry point.
//!
//! The watchdog is fed by one supervisor ([`supervise`]), and only while every task that must
//! make progress shows it within its limit (`sensor_box::supervisor`: a [`Heartbeat`] per
//! task, the verdict of [`Supervisor::check`]): the tick ([`run`]) beats on every tick, each
//! TX pump ([`pump_tx`]) after every transfer and waits ([`Heartbeat::wait`]) while it has
//! nothing to send, the AOK task ([`aok`](crate::aok::aok)) on every poll. The AEOLUS and AYDP
//! RX tasks wait for as long as nothing is received, so they have no heartbeat; a hang inside
//! one (or anywhere: the tasks share one executor) stops the tick's too.

use core::cell::RefCell;
use core::sync::atomic::{AtomicU32, Ordering};

use aeolus_proto::IoError;
use embassy_sync::blocking_mutex::raw::CriticalSectionRawMutex;
use embassy_sync::signal::Signal;
use embassy_time::{Duration, Instant, Timer};
use embedded_io_async::{Read, Write};
use firmware_example::{QueuedSerial, SerialIsr};
use sensor_box::persist::{self, Scratch};
use sensor_box::supervisor::{Heartbeat, Supervisor, Task, Verdict};
use sensor_box::{App, aeolus_link, aydp_link};

/// How often the links' TX halves run (the telemetry schedule's resolution), ms. The
/// blocking boards poll at least this often (SysTick at 1 kHz).
pub const TICK_MS: u64 = 1;
/// Period of the status log lines, ms.
pub const REPORT_MS: u64 = 5_000;
/// How long a reboot waits for the answer TOAST to leave UART0, ms (as the blocking boards).
pub const REBOOT_FLUSH_MS: u64 = 20;
/// Bytes the TX pump hands to one DMA transfer.
pub const TX_CHUNK: usize = 128;
/// Read buffer of the async frame readers: the most bytes one `read` takes from the ring.
pub const READ_BUF: usize = 64;

/// Room the AYDP TX queue must have before the link may write to it, bytes: the longest
/// reply (a normal system value update of a `char[40]`, 70 bytes) and the three 1 Hz messages
/// (7 + 43 + 31 bytes) each fit. The link's own policy for a full queue is to retry a byte
/// (it waits for the UART interrupt on the blocking boards); here nothing drains the queue
/// while the link runs, so the tasks wait for this room instead, and that policy never fires.
pub const AYDP_ROOM: usize = 128;
/// How long a task waits before it looks at the AYDP TX queue's room again, µs.
const ROOM_POLL_US: u64 = 500;

/// Bytes of each TX ring between a link and its pump, as on the blocking boards.
pub const TX_QUEUE: usize = 512;
/// Bytes of each port's RX ring: unused (the readers take the UARTs' bytes directly).
pub const UNUSED_RX_LEN: usize = 1;
/// A link's port: the TX ring its pump drains.
pub type Port = QueuedSerial<'static, UNUSED_RX_LEN, TX_QUEUE>;
/// The pump's half of a port.
pub type PortIsr = SerialIsr<'static, UNUSED_RX_LEN, TX_QUEUE>;

/// A wake-up for a TX pump: set by the port's `kick` whenever a link queues a byte.
pub type TxReady = Signal<CriticalSectionRawMutex, ()>;

/// What the tasks share: the application and the TX halves of its three ports.
pub struct Application {
    /// The sensor-box application (settings, the links, the simulated flight).
    pub app: App,
    /// Where the AEOLUS link queues its frames (drained by a [`pump_tx`] to its UART).
    pub aeolus_tx: Port,
    /// Where the AYDP link queues its messages (drained by a [`pump_tx`] to its UART).
    pub aydp_tx: Port,
    /// Where the AOK link queues its replies and debug frames (drained by a [`pump_tx`] to
    /// its UART).
    pub aok_tx: Port,
    /// The AEOLUS reader's decoder counters as of its last frame.
    pub aeolus_rx: aeolus_proto::Stats,
    /// The AYDP reader's decoder counters as of its last message.
    pub aydp_rx: aydp_proto::Stats,
}

/// The [`Application`], shared by the tasks of one executor. Every access is a short
/// synchronous closure, never held across an `await`.
pub struct Shared(RefCell<Application>);

impl Shared {
    /// Wraps the application.
    pub const fn new(app: Application) -> Self {
        Shared(RefCell::new(app))
    }

    /// Runs `f` on the application. `None` only if called from inside another `with`
    /// (nothing does; it is not a panic path).
    pub fn with<R>(&self, f: impl FnOnce(&mut Application) -> R) -> Option<R> {
        self.0.try_borrow_mut().ok().map(|mut a| f(&mut a))
    }
}

/// Receive errors a UART reported to a reader (overrun, framing, noise, parity), wrapping.
pub struct RxErrors(AtomicU32);

impl RxErrors {
    /// Zero.
    pub const fn new() -> Self {
        RxErrors(AtomicU32::new(0))
    }

    /// One more.
    pub fn bump(&self) {
        self.0.store(
            self.0.load(Ordering::Relaxed).wrapping_add(1),
            Ordering::Relaxed,
        );
    }

    /// The count.
    pub fn get(&self) -> u32 {
        self.0.load(Ordering::Relaxed)
    }
}

/// How often the supervisor looks at the heartbeats and feeds the watchdog, ms. With the
/// longest stall of the executor (a 128 KiB sector erase, up to 4 s by the data sheet;
/// `embassy-stm32` erases at x32 parallelism), feeds are at most 4.5 s apart: below the IWDG's
/// 8 s time-out at the LSI's fastest (47 kHz: 5.4 s).
pub const FEED_MS: u64 = 500;
/// The longest the tick ([`run`]) may show no progress, ms; it beats every [`TICK_MS`].
pub const TICK_SILENCE_MS: u64 = 500;
/// The longest a TX pump ([`pump_tx`]) may show no progress while it has bytes to send, ms;
/// one transfer of [`TX_CHUNK`] bytes lasts 33 ms at 38 400 Bd.
pub const PUMP_SILENCE_MS: u64 = 1_000;
/// The longest the AOK task may show no progress, ms; it polls at least every
/// [`MAX_SLEEP_MS`](crate::aok::MAX_SLEEP_MS).
pub const AOK_SILENCE_MS: u64 = 1_000;

/// The watchdog's supervisor over the tasks that must show progress, `hearts` in this order:
/// the tick ([`run`]), the AEOLUS, AYDP and AOK TX pumps ([`pump_tx`]) and the AOK task, each
/// with its limit. Every [`FEED_MS`] a [`Supervisor::check`], and `feed` on [`Verdict::Feed`]
/// only. A stall is logged once, with the task's name; the verdict stays, and the watchdog
/// resets the box at its time-out.
pub async fn supervise(hearts: &[Heartbeat; 5], mut feed: impl FnMut()) -> ! {
    let [tick, aeolus, aydp, aok_pump, aok] = hearts;
    let mut supervisor = Supervisor::new(
        [
            Task::new("tick", tick, TICK_SILENCE_MS),
            Task::new("AEOLUS TX pump", aeolus, PUMP_SILENCE_MS),
            Task::new("AYDP TX pump", aydp, PUMP_SILENCE_MS),
            Task::new("AOK TX pump", aok_pump, PUMP_SILENCE_MS),
            Task::new("AOK", aok, AOK_SILENCE_MS),
        ],
        FEED_MS,
        now_ms(),
    );
    let mut logged = false;
    loop {
        Timer::after_millis(FEED_MS).await;
        match supervisor.check(now_ms()) {
            Verdict::Feed => feed(),
            Verdict::Starve { task, silent_ms } => {
                if !core::mem::replace(&mut logged, true) {
                    defmt::error!(
                        "watchdog: {=str} shows no progress for {=u64} ms: not fed, the box resets",
                        task,
                        silent_ms
                    );
                }
            }
        }
    }
}

/// Milliseconds since boot (the application's clock).
pub fn now_ms() -> u64 {
    Instant::now().as_millis()
}

/// AEOLUS RX: decodes what `uart` delivers and hands every frame, or every frame the
/// decoder dropped, to [`aeolus_link::AeolusLink::handle_frame`]. Answers go out with the
/// next tick. A UART error is counted in `errors` and reading goes on (the driver restarts
/// its DMA ring on the next read).
///
/// Back-pressure, as the blocking link's "decode only while one longest answer still fits":
/// a frame is handed over only while the link's TX queue has room for one longest answer
/// ([`aeolus_link::TX_RESERVE`]); else the task waits for the tick to move the queue into
/// the port (the received bytes wait in the UART's ring meanwhile). Without it a burst of
/// commands already received (40 in one read of the ring) was handled in one go, and the
/// answers beyond the queue's 512 bytes were dropped.
pub async fn aeolus_rx<R: Read>(uart: R, shared: &Shared, errors: &RxErrors) -> ! {
    let mut reader = aeolus_proto::embedded_io_async::FrameReader::<
        R,
        { aeolus_link::RX_FRAME },
        READ_BUF,
    >::new(uart, aeolus_proto::Decoder::new());
    loop {
        let result = reader.read().await;
        if result.is_ok() {
            while shared
                .with(|a| aeolus_link::TX_QUEUE.saturating_sub(a.app.aeolus.tx_pending()))
                .unwrap_or(0)
                < aeolus_link::TX_RESERVE
            {
                Timer::after_micros(ROOM_POLL_US).await;
            }
        }
        let now = now_ms();
        let frame = match result {
            Ok(ref frame) => Ok(frame),
            Err(IoError::Protocol(e)) => Err(e),
            Err(IoError::Transport(_)) => {
                errors.bump();
                defmt::warn!("AEOLUS: UART receive error");
                continue;
            }
            // A UART never ends; these cannot come.
            Err(_) => continue,
        };
        shared.with(|a| a.app.aeolus.handle_frame(frame, now, &mut a.app.shared));
        drop(result);
        let stats = reader.decoder().stats();
        shared.with(|a| a.aeolus_rx = stats);
    }
}

/// AYDP RX: decodes what `uart` delivers and hands every message to
/// [`aydp_link::AydpLink::handle_frame`], whose replies go straight into the AYDP TX queue.
/// Register 0x0300 reports the decoder counters as of just after the message before the
/// request (the blocking boards: just before the request's last byte; the two differ only by
/// errors and discarded bytes between the two messages).
pub async fn aydp_rx<R: Read>(uart: R, shared: &Shared, errors: &RxErrors) -> ! {
    let mut reader = aydp_proto::embedded_io_async::FrameReader::<
        R,
        { aydp_link::DECODER_CAPACITY },
        READ_BUF,
    >::new(uart, aydp_proto::Decoder::new(aydp_proto::Profile::Spec));
    loop {
        let stats = reader.decoder().stats();
        match reader.read().await {
            Ok(frame) => {
                // Back-pressure: a flood of requests waits here (the DMA ring goes on
                // filling) rather than its replies being dropped by the link's TX queue.
                while shared.with(|a| a.aydp_tx.tx_space()).unwrap_or(0) < AYDP_ROOM {
                    Timer::after_micros(ROOM_POLL_US).await;
                }
                let now = now_ms();
                shared.with(|a| {
                    let Application { app, aydp_tx, .. } = a;
                    app.aydp
                        .handle_frame(Ok(&frame), &stats, now, aydp_tx, &mut app.shared);
                });
            }
            Err(aydp_proto::IoError::Protocol(e)) => {
                let now = now_ms();
                shared.with(|a| {
                    let Application { app, aydp_tx, .. } = a;
                    app.aydp
                        .handle_frame(Err(e), &stats, now, aydp_tx, &mut app.shared);
                });
            }
            Err(aydp_proto::IoError::Transport(_)) => {
                errors.bump();
                defmt::warn!("AYDP: UART receive error");
            }
            Err(_) => {}
        }
        let stats = reader.decoder().stats();
        shared.with(|a| a.aydp_rx = stats);
    }
}

/// Moves what the links queued on one port to `uart`, [`TX_CHUNK`] bytes per write (one DMA
/// transfer each); sleeps on `ready` while the queue is empty. `heart` beats after every
/// transfer, and waits ([`Heartbeat::wait`]) while the pump sleeps.
pub async fn pump_tx<W: Write>(
    mut isr: PortIsr,
    mut uart: W,
    ready: &TxReady,
    heart: &Heartbeat,
) -> ! {
    let mut chunk = [0u8; TX_CHUNK];
    loop {
        let n = isr.take_to_send(&mut chunk);
        if n == 0 {
            heart.wait();
            ready.wait().await;
            heart.resume();
            continue;
        }
        if uart.write_all(chunk.get(..n).unwrap_or(&[])).await.is_err() {
            defmt::warn!("UART transmit error: {=usize} bytes lost", n);
        }
        heart.beat();
    }
}

/// The flash store's hand-over from the tick ([`run`]) to the store task ([`store`]): the tick
/// asks for a store when a link asked for one; the store task writes the record as the
/// application holds it when the store starts. Asks that come while a store runs are served by
/// one more store.
pub struct StoreJob {
    ask: Signal<CriticalSectionRawMutex, ()>,
    asked: AtomicU32,
    done: AtomicU32,
}

impl StoreJob {
    /// Nothing asked.
    pub const fn new() -> Self {
        StoreJob {
            ask: Signal::new(),
            asked: AtomicU32::new(0),
            done: AtomicU32::new(0),
        }
    }

    /// One more store, after the ones asked before.
    fn request(&self) {
        self.asked.store(
            self.asked.load(Ordering::Relaxed).wrapping_add(1),
            Ordering::Relaxed,
        );
        self.ask.signal(());
    }

    /// Whether a store asked for has not finished yet.
    fn busy(&self) -> bool {
        self.asked.load(Ordering::Relaxed) != self.done.load(Ordering::Relaxed)
    }
}

/// The telemetry schedule and the links' TX halves, every [`TICK_MS`]: AEOLUS telemetry and
/// answers, the AYDP heartbeat, position and fix quality; then the requests the links made: a
/// store goes to the store task ([`StoreJob`]), a reboot waits for the stores asked before it
/// and returns [`REBOOT_FLUSH_MS`] later, for the answer to leave; the board resets. The tick
/// goes on while a store runs. `heart` beats on every tick. `board` says what the board adds
/// to the status lines every [`REPORT_MS`].
///
/// With the test-only feature `fault-hang`, the first unknown AEOLUS command stops the tick
/// after the tick that sends its answer (the other tasks run on): the supervisor then starves
/// the watchdog, which resets the box.
pub async fn run(
    shared: &Shared,
    rx_errors: [&RxErrors; 3],
    heart: &Heartbeat,
    job: &StoreJob,
    board: BoardReport,
) {
    let mut tick = Instant::now();
    let mut next_report = now_ms().saturating_add(REPORT_MS);
    let mut reboot = false;
    loop {
        heart.beat();
        let now = now_ms();
        let requests = shared.with(|a| {
            let Application {
                app,
                aeolus_tx,
                aydp_tx,
                ..
            } = a;
            app.aeolus.poll_tx(now, aeolus_tx, &app.shared);
            // Without room the 1 Hz messages wait for a later tick (their grid is kept).
            if aydp_tx.tx_space() >= AYDP_ROOM {
                app.aydp.poll_tx(now, aydp_tx, &app.shared);
            }
            let requests = &mut app.shared.requests;
            (
                core::mem::take(&mut requests.store),
                core::mem::take(&mut requests.reboot),
            )
        });
        if let Some((store, reboot_asked)) = requests {
            if store {
                job.request();
            }
            if reboot_asked && !reboot {
                reboot = true;
                defmt::info!("reboot requested: warm reset after the stores asked before it");
            }
        }
        #[cfg(feature = "fault-hang")]
        if shared
            .with(|a| a.app.aeolus.counters().unknown_commands != 0)
            .unwrap_or(false)
        {
            defmt::info!("fault-hang: the main loop hangs (the 1 ms tick stops)");
            core::future::pending::<()>().await;
        }
        if reboot && !job.busy() {
            Timer::after_millis(REBOOT_FLUSH_MS).await;
            return;
        }
        if now >= next_report {
            next_report = now.saturating_add(REPORT_MS);
            shared.with(|a| report(now, a, rx_errors, board));
        }
        // The next tick; after a stall (a flash erase blocks the executor for a second or
        // more) one tick at once, not a burst of the missed ones (the schedule catches up by
        // its own rules).
        tick = tick
            .saturating_add(Duration::from_millis(TICK_MS))
            .max(Instant::now());
        Timer::at(tick).await;
    }
}

/// The store task: on each [`StoreJob`] ask, stores the application's record and the store
/// policy's debt into the settings map with [`persist::store_in_async`] (the map's writes,
/// reads and erases awaited on `flash`'s async driver; see its docs for the parts that use the
/// blocking one), and counts the outcome as `App::service_requests` does (stores written,
/// unchanged, failed; a failure logged, the settings kept in RAM). The record is copied out
/// first: the links go on changing theirs while the store awaits.
pub async fn store<F>(mut flash: F, shared: &Shared, job: &StoreJob) -> !
where
    F: embedded_storage::nor_flash::NorFlash + embedded_storage_async::nor_flash::NorFlash,
{
    let mut scratch = Scratch::new();
    loop {
        job.ask.wait().await;
        let asked = job.asked.load(Ordering::Relaxed);
        let taken = shared.with(|a| {
            let s = &a.app.shared;
            (
                s.persisted.clone(),
                s.store_policy.debt_ms(),
                a.app.layout.clone(),
            )
        });
        if let Some((record, debt_ms, layout)) = taken {
            let done =
                persist::store_in_async(&mut flash, &layout, &record, debt_ms, &mut scratch).await;
            match done {
                Ok(stored) => defmt::info!("flash store: {}", stored),
                Err(e) => {
                    defmt::warn!("flash store: {}: settings kept in RAM only", e)
                }
            }
            shared.with(|a| a.app.shared.counters.count_store(&done));
        }
        job.done.store(asked, Ordering::Relaxed);
    }
}

/// What a board adds to the status lines ([`run`]).
#[derive(Clone, Copy)]
pub struct BoardReport {
    /// The stack's high-water mark and size, bytes, when the board can tell.
    pub stack: Option<fn() -> (usize, usize)>,
    /// Whether the ports' counters count the received bytes (an interrupt-driven UART's
    /// handler does; a DMA ring's reader bypasses them): then a line per port, `UARTn: rx ..
    /// dropped .. errors .. tx ..`, in the blocking boards' words.
    pub port_rx: bool,
}

/// The periodic status lines. They name the links, not the UARTs (which UART carries which
/// link is the board's).
fn report(now: u64, a: &Application, rx_errors: [&RxErrors; 3], board: BoardReport) {
    match board.stack.map(|f| f()) {
        Some((high_water, size)) => defmt::info!(
            "uptime {=u64} ms, stack high-water {=usize} of {=usize} bytes",
            now,
            high_water,
            size
        ),
        None => defmt::info!("uptime {=u64} ms", now),
    }
    let [aeolus_errors, aydp_errors, aok_errors] = rx_errors;
    let (t0, t1, t2) = (
        a.aeolus_tx.counters(),
        a.aydp_tx.counters(),
        a.aok_tx.counters(),
    );
    if board.port_rx {
        for (i, c) in [&t0, &t1, &t2].into_iter().enumerate() {
            defmt::info!(
                "UART{=usize}: rx {=u32} dropped {=u32} errors {=u32} tx {=u32}",
                i,
                c.rx_bytes,
                c.rx_dropped,
                c.rx_errors,
                c.tx_bytes
            );
        }
    }
    let c = a.app.aeolus.counters();
    let rx = &a.aeolus_rx;
    defmt::info!(
        "AEOLUS: telemetry {=u32} frames, toasts {=u32}, tx dropped {=u32}, late skipped {=u32}; tx {=u32} bytes, rx ok {=u32} crc errors {=u32} uart errors {=u32} commands {=u32} unknown {=u32} settime {=u32}; paused {=bool}",
        c.telemetry_total(),
        c.toasts,
        c.tx_dropped,
        a.app.aeolus.telemetry().skipped(),
        t0.tx_bytes,
        rx.frames_delivered(),
        rx.checksum_errors,
        aeolus_errors.get(),
        c.commands,
        c.unknown_commands,
        c.settime,
        a.app.shared.paused
    );
    let y = a.app.aydp.counters();
    let s = &a.aydp_rx;
    defmt::info!(
        "AYDP: tx {=u32} bytes, tx dropped {=u32}; rx ok {=u32} checksum errors {=u32} uart errors {=u32}; applied {=u32} rejected {=u32} answered {=u32}",
        t1.tx_bytes,
        y.tx_dropped,
        s.frames_ok,
        s.checksum_errors,
        aydp_errors.get(),
        y.updates_applied,
        y.rejected,
        y.requests_answered
    );
    let k = a.app.aok.counters();
    let d = a.app.aok.decoder_stats();
    defmt::info!(
        "AOK: commands {=u32}, rx errors {=u32}, uart errors {=u32}, cut by a quiet line {=u32}, bursts discarded {=u32}, replies dropped {=u32}; tx {=u32} bytes",
        d.frames_ok,
        k.rx_errors,
        aok_errors.get(),
        d.abandoned,
        k.bursts_discarded,
        k.replies_dropped,
        t2.tx_bytes
    );
}
