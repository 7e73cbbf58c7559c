//! The watchdog's supervisor (`sensor_box::supervisor`), as `firmware-embassy` runs it: a check
//! every 500 ms over the hearts of its tasks, the IWDG fed on `Verdict::Feed` only. Each test
//! runs the tasks on a simulated millisecond clock and a model of the watchdog (reset when no
//! feed came for its time-out), and checks that a box whose tasks all progress is never reset
//! and a box with a task that stops (or beats too rarely) is, with the task named.

use sensor_box::supervisor::{Heartbeat, Supervisor, Task, Verdict};

/// The check period of `firmware-embassy` (`links::FEED_MS`).
const PERIOD: u64 = 500;
/// The IWDG's time-out at the LSI's fastest (47 kHz), the shortest it may be, ms.
const WATCHDOG: u64 = 5_400;

/// What a run of the box did.
#[derive(Debug, Default)]
struct Run {
    /// The watchdog's time-out ran out: when, ms.
    reset_at: Option<u64>,
    /// The first verdict that was not `Feed`.
    first_stall: Option<(u64, Verdict)>,
    feeds: u32,
}

/// Runs `supervisor` from 1 ms to `until` ms: `step(now)` lets the tasks do what they do in
/// that millisecond (beat, wait, nothing); every `PERIOD` a check, and a feed on `Feed`. The
/// watchdog model resets the box when no feed came for `WATCHDOG` ms.
fn run<const N: usize>(
    supervisor: &mut Supervisor<'_, N>,
    until: u64,
    mut step: impl FnMut(u64),
) -> Run {
    let mut out = Run::default();
    let mut fed_at = 0;
    for now in 1..=until {
        step(now);
        if now % PERIOD == 0 {
            match supervisor.check(now) {
                Verdict::Feed => {
                    fed_at = now;
                    out.feeds += 1;
                }
                stall => {
                    out.first_stall.get_or_insert((now, stall));
                }
            }
        }
        if now - fed_at >= WATCHDOG {
            out.reset_at = Some(now);
            break;
        }
    }
    out
}

/// The tasks of `firmware-embassy` with their limits.
fn tasks<'a>(tick: &'a Heartbeat, pump: &'a Heartbeat, aok: &'a Heartbeat) -> [Task<'a>; 3] {
    [
        Task::new("tick", tick, 500),
        Task::new("aeolus pump", pump, 1_000),
        Task::new("aok", aok, 1_000),
    ]
}

#[test]
fn all_tasks_alive_feed_the_watchdog_for_an_hour() {
    let (tick, pump, aok) = (Heartbeat::new(), Heartbeat::new(), Heartbeat::new());
    let mut supervisor = Supervisor::new(tasks(&tick, &pump, &aok), PERIOD, 0);
    let out = run(&mut supervisor, 3_600_000, |now| {
        tick.beat();
        // The pump sends a burst every 20 ms and waits for work in between.
        if now % 20 == 0 {
            pump.resume();
        } else if now % 20 == 2 {
            pump.wait();
        }
        // The AOK task wakes every 250 ms at the latest.
        if now % 250 == 0 {
            aok.beat();
        }
    });
    assert_eq!(out.reset_at, None);
    assert_eq!(out.first_stall, None);
    assert_eq!(out.feeds, 7_200);
}

#[test]
fn a_task_that_stops_is_named_and_the_watchdog_resets_the_box() {
    let (tick, pump, aok) = (Heartbeat::new(), Heartbeat::new(), Heartbeat::new());
    let mut supervisor = Supervisor::new(tasks(&tick, &pump, &aok), PERIOD, 0);
    // The AOK task hangs at 10 s (say, in an await that never ends); the others go on.
    let out = run(&mut supervisor, 60_000, |now| {
        tick.beat();
        pump.beat();
        if now % 250 == 0 && now <= 10_000 {
            aok.beat();
        }
    });
    // Its last beat was seen by the check at 10 000; the first check more than 1 000 ms
    // later names it.
    assert_eq!(
        out.first_stall,
        Some((
            11_500,
            Verdict::Starve {
                task: "aok",
                silent_ms: 1_500
            }
        ))
    );
    // Not fed after 11 000: the watchdog resets the box at its time-out.
    assert_eq!(out.reset_at, Some(11_000 + WATCHDOG));
}

#[test]
fn the_tick_stopping_is_named_even_while_the_others_wait() {
    let (tick, pump, aok) = (Heartbeat::new(), Heartbeat::new(), Heartbeat::new());
    pump.wait();
    let mut supervisor = Supervisor::new(tasks(&tick, &pump, &aok), PERIOD, 0);
    let out = run(&mut supervisor, 60_000, |now| {
        if now < 3_000 {
            tick.beat();
        }
        aok.beat();
    });
    assert_eq!(
        out.first_stall,
        Some((
            3_500 + PERIOD,
            Verdict::Starve {
                task: "tick",
                silent_ms: 1_000
            }
        ))
    );
    assert!(out.reset_at.is_some());
}

#[test]
fn a_task_that_beats_too_rarely_is_not_fed_every_other_check() {
    let (tick, pump, aok) = (Heartbeat::new(), Heartbeat::new(), Heartbeat::new());
    let mut supervisor = Supervisor::new(tasks(&tick, &pump, &aok), PERIOD, 0);
    // The AOK task beats every 1 600 ms, above its 1 000 ms limit: two checks of three or
    // four see no beat since the one before, and a supervisor that fed whenever a task beat
    // since its last look would feed the watchdog often enough for the box never to reset.
    let out = run(&mut supervisor, 60_000, |now| {
        tick.beat();
        pump.beat();
        if now % 1_600 == 1 {
            aok.beat();
        }
    });
    let Some((at, Verdict::Starve { task, silent_ms })) = out.first_stall else {
        panic!("no stall found: {out:?}");
    };
    assert_eq!(task, "aok");
    assert!(silent_ms > 1_000, "{silent_ms}");
    assert!(at <= 10_000, "found only at {at}");
    let reset = out.reset_at.expect("the watchdog must reset the box");
    assert!(reset <= at + WATCHDOG, "reset at {reset}");
}

#[test]
fn a_task_just_within_its_limit_is_fed() {
    let (tick, pump, aok) = (Heartbeat::new(), Heartbeat::new(), Heartbeat::new());
    let mut supervisor = Supervisor::new(tasks(&tick, &pump, &aok), PERIOD, 0);
    // Every 1 500 ms, seen by every third check: silent 1 000 ms at a check at most, the
    // limit.
    let out = run(&mut supervisor, 600_000, |now| {
        tick.beat();
        pump.beat();
        if now % 1_500 == 1 {
            aok.beat();
        }
    });
    assert_eq!(out.first_stall, None);
    assert_eq!(out.reset_at, None);
}

#[test]
fn a_stall_is_final_even_when_the_task_comes_back() {
    let tick = Heartbeat::new();
    let mut supervisor = Supervisor::new([Task::new("tick", &tick, 500)], PERIOD, 0);
    tick.beat();
    assert_eq!(supervisor.check(500), Verdict::Feed);
    assert_eq!(supervisor.check(1_000), Verdict::Feed);
    let stall = Verdict::Starve {
        task: "tick",
        silent_ms: 1_000,
    };
    assert_eq!(supervisor.check(1_500), stall);
    for now in (2_000..20_000).step_by(500) {
        tick.beat();
        assert_eq!(supervisor.check(now), stall, "at {now}");
    }
}

#[test]
fn a_counter_that_wraps_is_progress() {
    // Each heart wraps between two checks; each must count as progress.
    let tick = Heartbeat::starting_at(u32::MAX - 2);
    let pump = Heartbeat::starting_at(u32::MAX);
    let aok = Heartbeat::starting_at(u32::MAX - 249);
    let mut supervisor = Supervisor::new(tasks(&tick, &pump, &aok), PERIOD, 0);
    let out = run(&mut supervisor, 10_000, |_| {
        tick.beat();
        pump.beat();
        aok.beat();
    });
    assert_eq!(out.first_stall, None);
    assert_eq!(out.reset_at, None);
    assert_eq!(tick.beats(), 9_997);
    // One beat from u32::MAX to 0, between two checks: progress.
    let heart = Heartbeat::starting_at(u32::MAX);
    let mut supervisor = Supervisor::new([Task::new("wrap", &heart, 500)], PERIOD, 0);
    assert_eq!(supervisor.check(500), Verdict::Feed);
    heart.beat();
    assert_eq!(heart.beats(), 0);
    for now in [1_000, 1_500] {
        assert_eq!(supervisor.check(now), Verdict::Feed, "at {now}");
    }
    assert_eq!(
        supervisor.check(2_000),
        Verdict::Starve {
            task: "wrap",
            silent_ms: 1_000
        }
    );
}

#[test]
fn a_task_waiting_for_work_is_alive_and_named_once_it_hangs_with_work() {
    let (tick, pump, aok) = (Heartbeat::new(), Heartbeat::new(), Heartbeat::new());
    let mut supervisor = Supervisor::new(tasks(&tick, &pump, &aok), PERIOD, 0);
    // The pump waits for 30 s with nothing to send, then work comes and its transfer never
    // ends (a DMA that does not complete).
    let out = run(&mut supervisor, 60_000, |now| {
        tick.beat();
        aok.beat();
        if now == 1 {
            pump.wait();
        }
        if now == 30_000 {
            pump.resume();
        }
    });
    assert_eq!(
        out.first_stall,
        Some((
            31_500,
            Verdict::Starve {
                task: "aeolus pump",
                silent_ms: 1_500
            }
        ))
    );
    assert_eq!(out.reset_at, Some(31_000 + WATCHDOG));
}

#[test]
fn a_task_that_never_beats_from_boot_is_named() {
    let (tick, pump, aok) = (Heartbeat::new(), Heartbeat::new(), Heartbeat::new());
    let mut supervisor = Supervisor::new(tasks(&tick, &pump, &aok), PERIOD, 0);
    let out = run(&mut supervisor, 60_000, |_| {
        tick.beat();
        aok.beat();
    });
    assert_eq!(
        out.first_stall,
        Some((
            1_500,
            Verdict::Starve {
                task: "aeolus pump",
                silent_ms: 1_500
            }
        ))
    );
    assert_eq!(out.reset_at, Some(1_000 + WATCHDOG));
}

#[test]
fn the_first_stalled_task_of_the_table_is_named() {
    let (a, b) = (Heartbeat::new(), Heartbeat::new());
    let mut supervisor = Supervisor::new(
        [Task::new("a", &a, 500), Task::new("b", &b, 500)],
        PERIOD,
        0,
    );
    assert_eq!(supervisor.check(500), Verdict::Feed);
    assert_eq!(
        supervisor.check(1_000),
        Verdict::Starve {
            task: "a",
            silent_ms: 1_000
        }
    );
}

#[test]
fn a_blocked_executor_is_not_charged_to_the_tasks() {
    let (tick, pump, aok) = (Heartbeat::new(), Heartbeat::new(), Heartbeat::new());
    let mut supervisor = Supervisor::new(tasks(&tick, &pump, &aok), PERIOD, 0);
    for now in (500..=5_000).step_by(500) {
        tick.beat();
        pump.beat();
        aok.beat();
        assert_eq!(supervisor.check(now), Verdict::Feed);
    }
    // The tick starts a sector erase at 5 100 that blocks the executor for 4 s: the tick
    // beat before it, the pump and the AOK task last beat at 5 000 and could not run since.
    tick.beat();
    // The supervisor's timer, due at 5 500, runs at 9 100 before any other task.
    assert_eq!(supervisor.check(9_100), Verdict::Feed);
    // The tasks run again.
    tick.beat();
    pump.beat();
    aok.beat();
    assert_eq!(supervisor.check(9_600), Verdict::Feed);
    // A task that hangs across the stall is still named, its limit after the stall.
    let mut supervisor = Supervisor::new(tasks(&tick, &pump, &aok), PERIOD, 0);
    tick.beat();
    pump.beat();
    aok.beat();
    assert_eq!(supervisor.check(500), Verdict::Feed);
    tick.beat();
    assert_eq!(supervisor.check(4_500), Verdict::Feed); // blocked 3.5 s
    tick.beat();
    assert_eq!(supervisor.check(5_000), Verdict::Feed); // silent 1 000 (blocked time not counted)
    tick.beat();
    assert_eq!(
        supervisor.check(5_500),
        Verdict::Starve {
            task: "aeolus pump",
            silent_ms: 1_500
        }
    );
}
