//! Where the CPU goes: per-category time accounting for the `cpu-budget` feature.
//!
//! The code under measurement marks what it is doing with [`span`] (or [`enter`] and
//! [`leave`] around an interrupt handler). The account is a single "current category" and the
//! time it started: every switch charges the time since the previous switch to the category
//! that was running, so nesting (an interrupt inside the main loop, the flight simulation
//! inside the telemetry) charges each instant to exactly one category, and the categories add
//! up to the whole elapsed time. Whatever runs outside any span is [`Category::Other`].
//!
//! The clock is SysTick's current value (the boards' 1 ms SysTick): a switch reads it and
//! counts its decrease since the last switch, adding one period when it wrapped. That needs a
//! switch at least once per period, which the SysTick handler itself provides (it is a span).
//! Under QEMU with `-icount shift=0` SysTick counts instructions (`docs/BENCHMARKS.md`,
//! "Firmware CPU budget"), so the account is deterministic.
//!
//! Without the feature, or on a host build, [`span`] is a plain call and nothing is counted:
//! the normal firmware carries none of this.

/// What the CPU is doing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(all(feature = "defmt", target_os = "none"), derive(defmt::Format))]
#[repr(u8)]
pub enum Category {
    /// Anything outside a span: the main loop's own glue.
    Other,
    /// Asleep in `wfi` (plus the `wfi` itself).
    Idle,
    /// The SysTick handler (the millisecond clock).
    Tick,
    /// The flight simulation (`Shared::flight_state`).
    FlightSim,
    /// The telemetry schedule, building the messages and encoding them into the link's queue.
    Telemetry,
    /// Handing encoded bytes to the port (the links' writes into the UART's TX queue).
    TxQueue,
    /// UART interrupts, transmit side.
    TxIrq,
    /// UART interrupts, receive side (and the handler's entry).
    RxIrq,
    /// The AEOLUS link's reading, deframing and handling (UART0).
    AeolusRx,
    /// The AYDP link: reading, decoding, handling and its periodic messages (UART1).
    Aydp,
    /// The AOK link: reading, decoding, handling and its debug frames (UART2).
    Aok,
}

impl Category {
    /// Number of categories.
    pub const COUNT: usize = 11;

    /// Every category, in index order.
    pub const ALL: [Category; Category::COUNT] = [
        Category::Other,
        Category::Idle,
        Category::Tick,
        Category::FlightSim,
        Category::Telemetry,
        Category::TxQueue,
        Category::TxIrq,
        Category::RxIrq,
        Category::AeolusRx,
        Category::Aydp,
        Category::Aok,
    ];

    /// A short name for logs and tables.
    ///
    /// ```
    /// use sensor_box::budget::Category;
    /// assert_eq!(Category::TxIrq.name(), "tx-irq");
    /// ```
    pub const fn name(self) -> &'static str {
        match self {
            Category::Other => "other",
            Category::Idle => "idle",
            Category::Tick => "systick",
            Category::FlightSim => "flight-sim",
            Category::Telemetry => "telemetry",
            Category::TxQueue => "tx-queue",
            Category::TxIrq => "tx-irq",
            Category::RxIrq => "rx-irq",
            Category::AeolusRx => "aeolus-rx",
            Category::Aydp => "aydp",
            Category::Aok => "aok",
        }
    }
}

/// The account at one instant: per category, the SysTick counts charged to it and how many
/// times it was entered.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Snapshot {
    /// SysTick counts, per [`Category`] (indexed by its discriminant).
    pub ticks: [u64; Category::COUNT],
    /// Spans of each category (switches into it).
    pub entries: [u32; Category::COUNT],
    /// Spans entered while each category was current (its interrupts and inner spans). Each
    /// span costs its category and its parent about one switch of the account each, which a
    /// reader subtracts with the measured cost of a switch.
    pub nested: [u32; Category::COUNT],
}

/// Runs `f` charged to `category` (its interrupts excepted), then goes back to what ran before.
///
/// ```
/// use sensor_box::budget::{Category, span};
/// assert_eq!(span(Category::FlightSim, || 2 + 2), 4);
/// ```
#[inline(always)]
pub fn span<R>(category: Category, f: impl FnOnce() -> R) -> R {
    let previous = enter(category);
    let r = f();
    leave(previous);
    r
}

#[cfg(all(feature = "cpu-budget", target_os = "none"))]
mod account {
    use super::{Category, Snapshot};
    use core::cell::Cell;
    use cortex_m::interrupt::{Mutex, free};
    use cortex_m::peripheral::SYST;

    /// Cells, not a `RefCell`: a switch is on every measured path, so it must be short.
    struct Account {
        current: Cell<Category>,
        last: Cell<u32>,
        period: Cell<u32>,
        ticks: [Cell<u64>; Category::COUNT],
        entries: [Cell<u32>; Category::COUNT],
        nested: [Cell<u32>; Category::COUNT],
    }

    static ACCOUNT: Mutex<Account> = Mutex::new(Account {
        current: Cell::new(Category::Other),
        last: Cell::new(0),
        period: Cell::new(0),
        ticks: [const { Cell::new(0) }; Category::COUNT],
        entries: [const { Cell::new(0) }; Category::COUNT],
        nested: [const { Cell::new(0) }; Category::COUNT],
    });

    fn bump(cell: Option<&Cell<u32>>) {
        if let Some(c) = cell {
            c.set(c.get().wrapping_add(1));
        }
    }

    impl Account {
        /// Charges the time since the last switch to the current category and makes `next`
        /// current.
        #[inline(always)]
        fn switch(&self, next: Category) -> Category {
            let now = SYST::get_current();
            let last = self.last.replace(now);
            let elapsed = if now <= last {
                last - now
            } else {
                // SysTick reloaded in between (it counts down).
                last.wrapping_add(self.period.get()).wrapping_sub(now)
            };
            let current = self.current.replace(next);
            if let Some(t) = self.ticks.get(current as usize) {
                t.set(t.get().wrapping_add(u64::from(elapsed)));
            }
            current
        }
    }

    pub fn start() {
        free(|cs| {
            let a = ACCOUNT.borrow(cs);
            a.period.set(SYST::get_reload().wrapping_add(1));
            a.last.set(SYST::get_current());
            a.current.set(Category::Other);
            for c in a.ticks.iter() {
                c.set(0);
            }
            for c in a.entries.iter().chain(a.nested.iter()) {
                c.set(0);
            }
        });
    }

    pub fn enter(category: Category) -> Category {
        free(|cs| {
            let a = ACCOUNT.borrow(cs);
            if a.period.get() == 0 {
                return a.current.get();
            }
            let previous = a.switch(category);
            bump(a.entries.get(category as usize));
            bump(a.nested.get(previous as usize));
            previous
        })
    }

    pub fn leave(previous: Category) {
        free(|cs| {
            let a = ACCOUNT.borrow(cs);
            if a.period.get() != 0 {
                a.switch(previous);
            }
        });
    }

    pub fn snapshot() -> Snapshot {
        free(|cs| {
            let a = ACCOUNT.borrow(cs);
            if a.period.get() != 0 {
                a.switch(a.current.get());
            }
            Snapshot {
                ticks: core::array::from_fn(|i| a.ticks.get(i).map_or(0, Cell::get)),
                entries: core::array::from_fn(|i| a.entries.get(i).map_or(0, Cell::get)),
                nested: core::array::from_fn(|i| a.nested.get(i).map_or(0, Cell::get)),
            }
        })
    }
}

#[cfg(not(all(feature = "cpu-budget", target_os = "none")))]
mod account {
    use super::{Category, Snapshot};

    pub fn start() {}

    #[inline(always)]
    pub fn enter(_: Category) -> Category {
        Category::Other
    }

    #[inline(always)]
    pub fn leave(_: Category) {}

    pub fn snapshot() -> Snapshot {
        Snapshot::default()
    }
}

/// Starts the account from zero (SysTick must already run). Before it, nothing is counted.
pub fn start() {
    account::start();
}

/// Switches to `category`; returns the category to give [`leave`] afterwards. For interrupt
/// handlers, which cannot wrap their body in [`span`] as easily.
#[inline(always)]
pub fn enter(category: Category) -> Category {
    account::enter(category)
}

/// Goes back to `previous` (what [`enter`] returned).
#[inline(always)]
pub fn leave(previous: Category) {
    account::leave(previous);
}

/// The account so far (all zero without the feature).
///
/// ```
/// assert_eq!(sensor_box::budget::snapshot().ticks.iter().sum::<u64>(), 0);
/// ```
pub fn snapshot() -> Snapshot {
    account::snapshot()
}
