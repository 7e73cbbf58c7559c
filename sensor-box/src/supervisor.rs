//! Whether every task of a board still makes progress, and so whether the watchdog is fed.
//!
//! A board that runs its jobs as tasks (`firmware-embassy`: a tick, the UART pumps, the AOK
//! link) cannot feed its watchdog from one main loop: one task may hang (wait for a transfer
//! that never ends, spin in a loop that yields) while the others, and the one feeding the
//! watchdog, go on. So every task that must make progress owns a [`Heartbeat`], and one
//! supervisor looks at all of them every few hundred milliseconds ([`Supervisor::check`]) and
//! feeds the watchdog only when each has shown progress recently enough ([`Verdict::Feed`]).
//!
//! | rule | why |
//! |---|---|
//! | progress: the heart's beat count changed since the last check, or the task waits with nothing to do ([`Heartbeat::wait`]) | a task that waits for input or work is not hung; the count is compared for change only, so its wrap is progress too |
//! | a task is stalled when the check that last saw it progress is more than its `max_silence_ms` ago ([`Task::new`]) | each task has its own rhythm: a 1 ms tick, a pump that waits for work, a link that wakes at least every 250 ms |
//! | a stall is final: every later check answers [`Verdict::Starve`] with the same task | a task that beats too rarely would otherwise be fed every other check and never reset |
//! | a check that comes late (more than the check period after the last) does not charge the delay to any task | the executor was blocked (a flash erase blocks it for up to 4 s), not the tasks; a hang that blocks the executor blocks the supervisor too, and the watchdog's own time-out resets the box |
//!
//! The module holds no board types: the hearts are atomics a task bumps, the time is passed
//! in (ms since boot), and the verdict says what to do with the watchdog. The board owns the
//! watchdog and the timer that runs the checks.
//!
//! ```
//! use sensor_box::supervisor::{Heartbeat, Supervisor, Task, Verdict};
//!
//! static TICK: Heartbeat = Heartbeat::new();
//! static PUMP: Heartbeat = Heartbeat::new();
//! let mut supervisor = Supervisor::new(
//!     [Task::new("tick", &TICK, 500), Task::new("pump", &PUMP, 1_000)],
//!     500, // a check every 500 ms
//!     0,   // now, ms since boot
//! );
//! TICK.beat();
//! PUMP.wait(); // nothing to send
//! assert_eq!(supervisor.check(500), Verdict::Feed);
//! PUMP.resume(); // work arrived (a beat), and the pump hangs in its transfer
//! for now in [1_000, 1_500, 2_000] {
//!     TICK.beat();
//!     assert_eq!(supervisor.check(now), Verdict::Feed); // last seen at 1 000: not too long yet
//! }
//! TICK.beat();
//! let stalled = Verdict::Starve { task: "pump", silent_ms: 1_500 };
//! assert_eq!(supervisor.check(2_500), stalled);
//! TICK.beat();
//! PUMP.beat(); // too late: the watchdog resets the box
//! assert_eq!(supervisor.check(3_000), stalled);
//! ```

use core::sync::atomic::{AtomicBool, AtomicU32, Ordering};

/// A task's sign of progress: a count of beats and whether the task waits with nothing to
/// do. Only the task itself writes it (a plain load and store, so it builds on cores without
/// atomic read-modify-write); the supervisor reads it.
#[derive(Debug, Default)]
pub struct Heartbeat {
    beats: AtomicU32,
    waiting: AtomicBool,
}

impl Heartbeat {
    /// No beat yet, not waiting.
    ///
    /// ```
    /// let heart = sensor_box::supervisor::Heartbeat::new();
    /// assert_eq!(heart.beats(), 0);
    /// ```
    pub const fn new() -> Self {
        Self::starting_at(0)
    }

    /// A heart whose count starts at `beats` (a count carried over, or a test of the wrap).
    ///
    /// ```
    /// let heart = sensor_box::supervisor::Heartbeat::starting_at(u32::MAX);
    /// heart.beat();
    /// assert_eq!(heart.beats(), 0); // it wraps
    /// ```
    pub const fn starting_at(beats: u32) -> Self {
        Heartbeat {
            beats: AtomicU32::new(beats),
            waiting: AtomicBool::new(false),
        }
    }

    /// The task made progress: one more beat (wrapping).
    ///
    /// ```
    /// let heart = sensor_box::supervisor::Heartbeat::new();
    /// heart.beat();
    /// assert_eq!(heart.beats(), 1);
    /// ```
    pub fn beat(&self) {
        let beats = self.beats.load(Ordering::Relaxed).wrapping_add(1);
        self.beats.store(beats, Ordering::Relaxed);
    }

    /// The task waits with nothing to do (for input, or for work another task hands it):
    /// progress for as long as it waits, until [`Heartbeat::resume`].
    ///
    /// ```
    /// let heart = sensor_box::supervisor::Heartbeat::new();
    /// heart.wait();
    /// assert!(heart.is_waiting());
    /// ```
    pub fn wait(&self) {
        self.waiting.store(true, Ordering::Relaxed);
    }

    /// The task has work again: it no longer waits, and this is a beat.
    ///
    /// ```
    /// let heart = sensor_box::supervisor::Heartbeat::new();
    /// heart.wait();
    /// heart.resume();
    /// assert_eq!((heart.is_waiting(), heart.beats()), (false, 1));
    /// ```
    pub fn resume(&self) {
        self.waiting.store(false, Ordering::Relaxed);
        self.beat();
    }

    /// The beats so far (wrapping).
    ///
    /// ```
    /// assert_eq!(sensor_box::supervisor::Heartbeat::new().beats(), 0);
    /// ```
    pub fn beats(&self) -> u32 {
        self.beats.load(Ordering::Relaxed)
    }

    /// Whether the task waits with nothing to do.
    ///
    /// ```
    /// assert!(!sensor_box::supervisor::Heartbeat::new().is_waiting());
    /// ```
    pub fn is_waiting(&self) -> bool {
        self.waiting.load(Ordering::Relaxed)
    }
}

/// One task the supervisor watches: its name (for the verdict and the log), its heart, and
/// the longest it may go without progress.
#[derive(Debug, Clone, Copy)]
pub struct Task<'a> {
    name: &'static str,
    heart: &'a Heartbeat,
    max_silence_ms: u64,
}

impl<'a> Task<'a> {
    /// The task `name`, stalled once the check that last saw `heart` progress is more than
    /// `max_silence_ms` ago.
    ///
    /// ```
    /// use sensor_box::supervisor::{Heartbeat, Task};
    /// static TICK: Heartbeat = Heartbeat::new();
    /// let task = Task::new("tick", &TICK, 500);
    /// assert_eq!(task.name(), "tick");
    /// ```
    pub const fn new(name: &'static str, heart: &'a Heartbeat, max_silence_ms: u64) -> Self {
        Task {
            name,
            heart,
            max_silence_ms,
        }
    }

    /// The task's name.
    ///
    /// ```
    /// use sensor_box::supervisor::{Heartbeat, Task};
    /// assert_eq!(Task::new("pump", &Heartbeat::new(), 1_000).name(), "pump");
    /// ```
    pub const fn name(&self) -> &'static str {
        self.name
    }
}

/// What the watchdog's owner does after a check.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(all(feature = "defmt", target_os = "none"), derive(defmt::Format))]
pub enum Verdict {
    /// Every task showed progress within its limit: feed the watchdog.
    Feed,
    /// `task` showed none for `silent_ms` (more than its limit; the first such task in the
    /// table): do not feed it, now or later; the watchdog's time-out resets the box.
    Starve {
        /// The stalled task's name.
        task: &'static str,
        /// How long it had shown no progress when the stall was found, ms (stalls of the
        /// whole executor not counted).
        silent_ms: u64,
    },
}

/// What a check last saw of one heart.
#[derive(Debug, Clone, Copy)]
struct Seen {
    beats: u32,
    /// When a check last saw progress, moved on by the executor stalls since.
    at_ms: u64,
}

/// The watchdog's supervisor for `N` tasks: [`Supervisor::check`] every `period_ms`, and
/// feed the watchdog on [`Verdict::Feed`] only.
#[derive(Debug)]
pub struct Supervisor<'a, const N: usize> {
    tasks: [Task<'a>; N],
    seen: [Seen; N],
    period_ms: u64,
    last_check_ms: u64,
    stalled: Option<Verdict>,
}

impl<'a, const N: usize> Supervisor<'a, N> {
    /// Watches `tasks` from `now_ms` (each has its limit from then to show progress), with a
    /// check every `period_ms`.
    ///
    /// ```
    /// use sensor_box::supervisor::{Heartbeat, Supervisor, Task, Verdict};
    /// static TICK: Heartbeat = Heartbeat::new();
    /// let mut supervisor = Supervisor::new([Task::new("tick", &TICK, 500)], 500, 0);
    /// assert_eq!(supervisor.check(500), Verdict::Feed); // within its first 500 ms
    /// ```
    pub fn new(tasks: [Task<'a>; N], period_ms: u64, now_ms: u64) -> Self {
        let seen = tasks.map(|task| Seen {
            beats: task.heart.beats(),
            at_ms: now_ms,
        });
        Supervisor {
            tasks,
            seen,
            period_ms,
            last_check_ms: now_ms,
            stalled: None,
        }
    }

    /// Looks at every heart at `now_ms` (ms since boot, from the same clock as
    /// [`Supervisor::new`]'s) and says whether to feed the watchdog. Once a task has stalled,
    /// every later check names it.
    ///
    /// ```
    /// use sensor_box::supervisor::{Heartbeat, Supervisor, Task, Verdict};
    /// static TICK: Heartbeat = Heartbeat::new();
    /// let mut supervisor = Supervisor::new([Task::new("tick", &TICK, 500)], 500, 0);
    /// assert_eq!(supervisor.check(500), Verdict::Feed);
    /// // No beat since boot, checked on time: stalled at the second check.
    /// assert_eq!(
    ///     supervisor.check(1_000),
    ///     Verdict::Starve { task: "tick", silent_ms: 1_000 }
    /// );
    /// ```
    pub fn check(&mut self, now_ms: u64) -> Verdict {
        // The part of the wait since the last check beyond the period: the executor (or the
        // whole CPU) was blocked, so no task could show progress; nobody is charged for it.
        let late = now_ms
            .saturating_sub(self.last_check_ms)
            .saturating_sub(self.period_ms);
        self.last_check_ms = now_ms;
        let mut verdict = Verdict::Feed;
        for (task, seen) in self.tasks.iter().zip(self.seen.iter_mut()) {
            let beats = task.heart.beats();
            if beats != seen.beats || task.heart.is_waiting() {
                *seen = Seen {
                    beats,
                    at_ms: now_ms,
                };
                continue;
            }
            seen.at_ms = seen.at_ms.saturating_add(late).min(now_ms);
            let silent_ms = now_ms.saturating_sub(seen.at_ms);
            if silent_ms > task.max_silence_ms && verdict == Verdict::Feed {
                verdict = Verdict::Starve {
                    task: task.name,
                    silent_ms,
                };
            }
        }
        if let Some(stalled) = self.stalled {
            return stalled;
        }
        if verdict != Verdict::Feed {
            self.stalled = Some(verdict);
        }
        verdict
    }
}
