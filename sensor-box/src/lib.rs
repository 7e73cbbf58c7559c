//! The sensor box's behaviour: AEOLUS telemetry on UART0, AYDP on UART1, AOK on UART2.
//!
//! This crate is the box, without a board: it is generic over the serial ports
//! ([`port::Receive`] and `embedded_io::{Write, WriteReady}`, used without waiting: see [`port`]),
//! a flash store
//! (`embedded_storage::nor_flash::NorFlash`) and the time (`now_ms`, passed in), so the same
//! code runs on every board (`firmware-example`'s QEMU and STM32F411 boards, `firmware-embassy`),
//! in `protolink sim` on the desk, and in host tests with in-memory ports and a simulated clock.
//! It has no `unsafe` and no board crate.
//!
//! Structure:
//! - [`state`]: the data the links share ([`Shared`]), the [`Settings`] and the
//!   [`Persisted`] record kept in flash.
//! - [`persist`]: loading and storing the [`Persisted`] record (a `sequential-storage` map,
//!   one item per setting group, read back and generation-checked; the format 1-3 store
//!   migrated once), and [`store_policy`]: when a command may store it (not in flight,
//!   rate-limited across resets).
//! - [`telemetry`]: which AEOLUS messages are due when, built from the simulated flight
//!   (shared with `protolink sim`).
//! - [`aeolus_link`], [`aydp_link`], [`aok_link`]: one protocol on one UART each.
//! - [`port`]: reading received bytes in slices and queueing whole frames for transmit, the
//!   same way on every link; [`burst_marks`]: where the receive interrupt saw the line fall
//!   silent, so the AOK link frames its bursts by the line's silences even after a stall.
//! - [`serial`] (feature `bbqueue`, on by default): `QueuedSerial`, the interrupt-driven port
//!   of the blocking boards, and [`storage`]: `MemFlash`, NOR flash over a byte slice. The
//!   boards use them, and so do this crate's tests and examples.
//! - [`budget`]: where the CPU goes (per-category accounting, feature `cpu-budget`).
//! - [`supervisor`]: whether every task of a board still makes progress, and so whether the
//!   watchdog is fed (`firmware-embassy`'s tasks).
//! - [`log`]: `info!`/`warn!`/`error!`/`debug!` macros that go to `defmt` on the target
//!   (feature `defmt`) and compile to nothing on the host.
//!
//! The main loop calls [`App::poll_pending`] (or [`App::poll`]) after every wake; the flash is
//! written only from there.
//!
//! Features: `defmt` (log through defmt on `target_os = "none"`, `defmt::Format` on the
//! public types); `legacy` (default: the format 1-3 store read and migrated at boot);
//! `hardware-lm3s6965evb` and `hardware-stm32f411` name the board in AYDP
//! 0x0003 (the boards turn them on; on the host the name is `host`).
#![no_std]
#![forbid(unsafe_code)]
#![deny(missing_docs)]

pub mod aeolus_link;
pub mod aok_link;
pub mod aydp_link;
pub mod budget;
pub mod burst_marks;
pub mod log;
pub mod persist;
pub mod port;
#[cfg(feature = "bbqueue")]
pub mod serial;
pub mod state;
pub mod storage;
pub mod store_policy;
pub mod supervisor;
pub mod telemetry;

pub use state::{Persisted, Settings, Shared};

use embedded_io::{Write, WriteReady};
use embedded_storage::nor_flash::NorFlash;
use port::{Receive, Transmit};

/// Re-exported for the logging macros; not part of the API.
#[doc(hidden)]
#[cfg(all(feature = "defmt", target_os = "none"))]
pub use defmt as __defmt;

/// What the main loop must do after a poll.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(all(feature = "defmt", target_os = "none"), derive(defmt::Format))]
pub enum Control {
    /// Keep going.
    Run,
    /// Reset the MCU (warm reset: the flash store survives).
    Reboot,
}

/// The whole application.
pub struct App {
    /// State shared by the links.
    pub shared: Shared,
    /// AEOLUS on UART0.
    pub aeolus: aeolus_link::AeolusLink,
    /// AYDP on UART1.
    pub aydp: aydp_link::AydpLink,
    /// AOK on UART2.
    pub aok: aok_link::AokLink,
    /// Where the flash store's map and format 1-3 store lie.
    pub layout: persist::Layout,
}

impl App {
    /// Boots the application: loads the persisted record from `flash` laid out as
    /// [`persist::Layout::for_flash`] says (defaults and a logged warning if it is missing or
    /// corrupt), starts the simulated flight at `now_ms`.
    pub fn new<F: NorFlash>(flash: &mut F, now_ms: u64) -> Self {
        let layout = persist::Layout::for_flash(flash);
        Self::with_layout(flash, layout, now_ms)
    }

    /// [`App::new`] with the board's flash layout: the record ([`persist::boot`]), the
    /// store policy's debt resumed and the corrupt items counted.
    ///
    /// ```
    /// use sensor_box::storage::MemFlash;
    /// use sensor_box::{App, persist::Layout};
    /// let mut mem = [0xFFu8; 8192];
    /// let mut flash = MemFlash::new(&mut mem);
    /// let app = App::with_layout(&mut flash, Layout::halves(8192, 1024), 0);
    /// assert_eq!(app.shared.counters.corrupt_items, 0);
    /// ```
    pub fn with_layout<F: NorFlash>(flash: &mut F, layout: persist::Layout, now_ms: u64) -> Self {
        let boot = persist::boot(flash, &layout);
        let mut shared = Shared::new(boot.record, now_ms);
        shared.counters.corrupt_items = boot.corrupt_items;
        shared.store_policy = store_policy::StorePolicy::resumed(boot.store_debt_ms, now_ms);
        let aok = aok_link::AokLink::new(&shared);
        App {
            aeolus: aeolus_link::AeolusLink::new(now_ms),
            aydp: aydp_link::AydpLink::new(now_ms),
            aok,
            shared,
            layout,
        }
    }

    /// Runs every link once: decodes what arrived, answers, and sends what is due at
    /// `now_ms`. Writes the flash when a link asked for it. [`App::poll_pending`] with every
    /// port marked as having received.
    pub fn poll<U0, U1, U2, F>(
        &mut self,
        now_ms: u64,
        uart0: &mut U0,
        uart1: &mut U1,
        uart2: &mut U2,
        flash: &mut F,
    ) -> Control
    where
        U0: Receive + Transmit + Write + WriteReady,
        U1: Receive + Write + WriteReady,
        U2: Receive + Write + WriteReady,
        F: NorFlash,
    {
        self.poll_pending(now_ms, [true; 3], uart0, uart1, uart2, flash)
    }

    /// Runs only the links that have work: the link of each port whose `received` flag is set
    /// (the board's UART interrupt sets it when it moved bytes into the port), and any link
    /// whose own timer is due, whose TX queue is waiting for room, or that left received bytes
    /// in its port ([`AeolusLink::has_work`](aeolus_link::AeolusLink::has_work) and its
    /// twins). A wake caused by one UART costs the other links a few comparisons. Writes the
    /// flash when a link asked for it.
    ///
    /// ```
    /// use sensor_box::serial::{PortStats, QueuedSerial, Ring};
    /// use sensor_box::storage::MemFlash;
    /// use sensor_box::App;
    /// let (r, t) = ([const { Ring::<64>::new() }; 3], [const { Ring::<512>::new() }; 3]);
    /// let s = [const { PortStats::new() }; 3];
    /// let (mut u0, _i0) = QueuedSerial::split(&r[0], &t[0], &s[0], || {});
    /// let (mut u1, _i1) = QueuedSerial::split(&r[1], &t[1], &s[1], || {});
    /// let (mut u2, _i2) = QueuedSerial::split(&r[2], &t[2], &s[2], || {});
    /// let mut mem = [0xFFu8; 4096];
    /// let mut flash = MemFlash::new(&mut mem);
    /// let mut app = App::new(&mut flash, 0);
    /// app.poll_pending(0, [false; 3], &mut u0, &mut u1, &mut u2, &mut flash); // boot: all due
    /// assert!(!app.aydp.has_work(1)); // the next heartbeat is due at 1000
    /// assert!(!app.aok.has_work(1)); // the next debug value at 20
    /// assert!(!app.aeolus.has_work(1, &app.shared)); // PRESSURE is next due at 5
    /// assert_eq!(app.next_wake_ms(), 5); // so the main loop may sleep until then
    /// ```
    pub fn poll_pending<U0, U1, U2, F>(
        &mut self,
        now_ms: u64,
        received: [bool; 3],
        uart0: &mut U0,
        uart1: &mut U1,
        uart2: &mut U2,
        flash: &mut F,
    ) -> Control
    where
        U0: Receive + Transmit + Write + WriteReady,
        U1: Receive + Write + WriteReady,
        U2: Receive + Write + WriteReady,
        F: NorFlash,
    {
        use budget::{Category, span};
        let [rx0, rx1, rx2] = received;
        if rx0 || self.aeolus.has_work(now_ms, &self.shared) {
            self.aeolus.poll(now_ms, uart0, &mut self.shared);
        }
        if rx1 || self.aydp.has_work(now_ms) {
            span(Category::Aydp, || {
                self.aydp.poll(now_ms, uart1, &mut self.shared)
            });
        }
        if rx2 || self.aok.has_work(now_ms) {
            span(Category::Aok, || {
                self.aok.poll(now_ms, uart2, &mut self.shared)
            });
        }
        if self.shared.requests.store || self.shared.requests.reboot {
            self.service_requests(flash)
        } else {
            Control::Run
        }
    }

    /// The earliest instant at which [`App::poll_pending`] has something to do without a
    /// received byte: the earliest of the three links' `next_wake_ms` (0: at once). A main
    /// loop may sleep until then, or until a UART wakes a link.
    ///
    /// ```
    /// use sensor_box::serial::{PortStats, QueuedSerial, Ring};
    /// use sensor_box::storage::MemFlash;
    /// use sensor_box::App;
    /// let (r, t) = ([const { Ring::<64>::new() }; 3], [const { Ring::<512>::new() }; 3]);
    /// let s = [const { PortStats::new() }; 3];
    /// let (mut u0, _i0) = QueuedSerial::split(&r[0], &t[0], &s[0], || {});
    /// let (mut u1, _i1) = QueuedSerial::split(&r[1], &t[1], &s[1], || {});
    /// let (mut u2, _i2) = QueuedSerial::split(&r[2], &t[2], &s[2], || {});
    /// let mut mem = [0xFFu8; 4096];
    /// let mut flash = MemFlash::new(&mut mem);
    /// let mut app = App::new(&mut flash, 0);
    /// assert_eq!(app.next_wake_ms(), 0); // boot: every link has its first messages due
    /// app.poll_pending(0, [false; 3], &mut u0, &mut u1, &mut u2, &mut flash);
    /// assert_eq!(app.next_wake_ms(), 5); // PRESSURE
    /// ```
    pub fn next_wake_ms(&self) -> u64 {
        self.aeolus
            .next_wake_ms(&self.shared)
            .min(self.aydp.next_wake_ms())
            .min(self.aok.next_wake_ms())
    }

    /// What the links asked the main loop for, done after they ran: writes the flash when a
    /// link asked for a store (an unchanged record is not written; the outcome is counted in
    /// [`Counters`](state::Counters), a failure logged), and says whether to reboot.
    /// [`App::poll`] ends with it; a board that runs the links itself (one task per link, as
    /// `firmware-embassy` does) calls it after them.
    ///
    /// ```
    /// use sensor_box::storage::MemFlash;
    /// use sensor_box::{App, Control};
    /// let mut mem = [0xFFu8; 4096];
    /// let mut flash = MemFlash::new(&mut mem);
    /// let mut app = App::new(&mut flash, 0);
    /// app.shared.requests.reboot = true;
    /// assert_eq!(app.service_requests(&mut flash), Control::Reboot);
    /// assert_eq!(app.service_requests(&mut flash), Control::Run);
    /// ```
    pub fn service_requests<F: NorFlash>(&mut self, flash: &mut F) -> Control {
        if core::mem::take(&mut self.shared.requests.store) {
            let debt = self.shared.store_policy.debt_ms();
            let outcome = persist::store_in(flash, &self.layout, &self.shared.persisted, debt);
            if outcome.is_err() {
                crate::warn!("flash store: write failed; settings kept in RAM only");
            }
            self.shared.counters.count_store(&outcome);
        }
        if core::mem::take(&mut self.shared.requests.reboot) {
            Control::Reboot
        } else {
            Control::Run
        }
    }
}
