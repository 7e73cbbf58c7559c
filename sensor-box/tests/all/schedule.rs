//! The schedule against a model of its rules that passes over every kind on every call (no
//! shortcut for the milliseconds with nothing due): the same kinds, the same next due
//! instants and the same skipped count, under interval changes (shortened, lengthened,
//! turned off and on), stalls, restarts and iterators dropped early.

use sensor_box::state::Intervals;
use sensor_box::telemetry::{Kind, Telemetry};

/// The rules of `Telemetry::take`, one pass over every kind per call.
#[derive(Clone)]
struct Model {
    next: [u64; Kind::COUNT],
    skipped: u32,
}

impl Model {
    fn due(&mut self, now: u64, intervals: &Intervals, take: usize) -> Vec<Kind> {
        let mut out = Vec::new();
        for kind in Kind::ALL {
            if out.len() == take {
                break;
            }
            let next = &mut self.next[kind.index()];
            let interval = u64::from(kind.interval_ms(intervals));
            if interval == 0 {
                *next = u64::MAX;
                continue;
            }
            if *next == u64::MAX {
                *next = now;
            }
            *next = (*next).min(now + interval);
            if now < *next {
                continue;
            }
            let instants = (now - *next) / interval + 1;
            if instants > Telemetry::MAX_LATE {
                let drop = instants - Telemetry::MAX_LATE;
                *next += drop * interval;
                self.skipped += drop as u32;
            }
            *next += interval;
            out.push(kind);
        }
        out
    }
}

/// xorshift64: a reproducible stream of test choices.
fn rng(state: &mut u64) -> u64 {
    *state ^= *state << 13;
    *state ^= *state >> 7;
    *state ^= *state << 17;
    *state
}

#[test]
fn the_quiet_shortcut_changes_nothing() {
    for seed in 1..=40u64 {
        let mut r = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15);
        let mut t = Telemetry::new(0);
        let mut m = Model {
            next: [0; Kind::COUNT],
            skipped: 0,
        };
        let mut iv = Intervals::SPEC;
        let mut now = 0u64;
        for _ in 0..20_000 {
            match rng(&mut r) % 1000 {
                // A stall of up to 200 ms.
                0..=4 => now += rng(&mut r) % 200,
                // An interval changed (0: off).
                5..=9 => {
                    let v = [0, 1, 3, 5, 7, 50, 92, 829][(rng(&mut r) % 8) as usize];
                    match rng(&mut r) % 6 {
                        0 => iv.imu_ms = v,
                        1 => iv.pressure_ms = v,
                        2 => iv.gps_ms = v,
                        3 => iv.temp_ms = v,
                        4 => iv.wind_ms = v,
                        _ => iv.info_ms = v,
                    }
                }
                10 => {
                    t.restart(now);
                    m.next = [now; Kind::COUNT];
                }
                _ => {}
            }
            // Mostly a full pass; sometimes the caller stops early.
            let take = if rng(&mut r).is_multiple_of(50) {
                (rng(&mut r) % 3) as usize
            } else {
                usize::MAX
            };
            // A caller that sleeps until `next_due` is awake whenever a kind is due, also
            // right after a change of the intervals (before any pass has seen it).
            if !m.clone().due(now, &iv, usize::MAX).is_empty() {
                assert!(
                    t.next_due(&iv) <= now,
                    "seed {seed} at {now} ms: would sleep"
                );
            }
            let got: Vec<Kind> = t.due(now, &iv).take(take).collect();
            assert_eq!(got, m.due(now, &iv, take), "seed {seed} at {now} ms");
            for kind in Kind::ALL {
                assert_eq!(t.next_due_ms(kind), m.next[kind.index()], "seed {seed}");
            }
            assert_eq!(t.skipped(), m.skipped);
            // Never later than the earliest due instant: a caller that sleeps until then
            // misses nothing; after a complete pass, exactly that instant.
            let earliest = m.next.iter().copied().min().unwrap_or(u64::MAX);
            if take == usize::MAX {
                assert_eq!(t.next_due(&iv), earliest, "seed {seed} at {now} ms");
            } else {
                assert!(t.next_due(&iv) <= earliest, "seed {seed} at {now} ms");
            }
            now += 1 + rng(&mut r) % 2;
        }
    }
}
