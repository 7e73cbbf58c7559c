//! Line noise must command nothing (issue 42): uniformly random bytes at the link's line rate,
//! or in bursts (the loose-cable model), through the real `AokLink` and `AydpLink` and their
//! real ports (`QueuedSerial`/`SerialIsr`, as the boards give them), polled every millisecond
//! with the bytes that arrived in that millisecond while the clock advances, for 24 simulated
//! hours a scenario. Every state-changing outcome is counted, and the target is zero of each.
//!
//! The scenarios (each its own test, so `cargo test` runs them on its threads):
//!
//! | scenario | bytes | line |
//! |---|---|---|
//! | AOK uniform, flying / landed | 331 776 000 a day each | 38 400 Bd 8N1, 3 840 bytes/s, back to back |
//! | AOK bursts, flying / landed | about 72.4 M a day each | 20..=200 bytes at line rate, then 5..=200 ms of silence |
//! | AYDP uniform | 995 328 000 a day | 115 200 Bd 8N1, 11 520 bytes/s, back to back |
//! | AYDP bursts | about 84.7 M a day | as AOK's bursts, at 115 200 Bd |
//!
//! What counts as a state change, AOK: a reset request (`shared.requests.reboot`), a store
//! request (`shared.requests.store`), a RAM parameter change, a parameter set loaded from flash,
//! a start-set change, a RAM waypoint change (slots 0..=30, 254, 255), a waypoint load from
//! flash, a motor-test output turned on (and the milliseconds it stayed on), external control
//! taken, a debug on/off toggle. To see a load from flash at all, the test keeps the flash
//! mirror (`shared.persisted.aok`) different from RAM: after boot and after every change it
//! seeds the sets and the flash waypoints with fresh marker values that no random frame
//! writes, so a load is exactly "RAM now equals the flash mirror". AYDP: system value updates
//! applied, direct-output messages applied, store configuration requested (with direct
//! control enabled at boot, so that a random direct-output frame would be obeyed).
//!
//! `NOISE_HOURS` (default 24) sets the simulated time of every scenario; each test prints its
//! figures (`cargo test -p sensor-box --test noise -- --nocapture`). The figures before the
//! AOK link's silence framing, and after, are in `docs/RELIABILITY.md` ("Line noise commands
//! nothing"). The whole file takes 155 to 165 s in a debug `cargo test` on two cores (the
//! test profile builds the box's crates with `opt-level = 3`).

use aok_proto::WaypointSlot;
use sensor_box::aok_link::{AokLink, ControlSource};
use sensor_box::aydp_link::AydpLink;
use sensor_box::serial::{PortStats, QueuedSerial, Ring, SerialIsr};
use sensor_box::state::StoredWaypoint;
use sensor_box::{Persisted, Shared};

/// xorshift64*, seeded: every figure is reproducible.
struct Rng(u64);

impl Rng {
    fn next_u64(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x >> 12;
        x ^= x << 25;
        x ^= x >> 27;
        self.0 = x;
        x.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    fn byte(&mut self) -> u8 {
        (self.next_u64() >> 56) as u8
    }
    /// Uniform in `lo..=hi`.
    fn between(&mut self, lo: u64, hi: u64) -> u64 {
        lo + self.next_u64() % (hi - lo + 1)
    }
}

/// How the noise arrives.
#[derive(Debug, Clone, Copy)]
enum Model {
    /// Back to back at the line rate, for ever.
    Uniform,
    /// 20..=200 bytes back to back, then 5..=200 ms of silence.
    Bursts,
}

/// The noise source: which byte arrives when. Time is in units of `1 / (1000 * rate)` s, so a
/// byte lasts 1 000 units and a millisecond `rate` units (`rate` in bytes a second).
struct Noise {
    rng: Rng,
    model: Model,
    rate: u64,
    next_at: u64,
    left_in_burst: u64,
    bytes: u64,
}

impl Noise {
    fn new(seed: u64, model: Model, rate: u64) -> Self {
        let mut n = Noise {
            rng: Rng(seed),
            model,
            rate,
            next_at: 0,
            left_in_burst: 0,
            bytes: 0,
        };
        n.left_in_burst = n.burst_len();
        n
    }

    fn burst_len(&mut self) -> u64 {
        match self.model {
            Model::Uniform => u64::MAX,
            Model::Bursts => self.rng.between(20, 200),
        }
    }

    /// Every byte that has arrived by the end of millisecond `ms`, into the UART's receive
    /// interrupt in one go (as a UART with a FIFO hands them over: one commit to the ring).
    fn arrive<const RX: usize, const TX: usize>(&mut self, ms: u64, isr: &mut SerialIsr<RX, TX>) {
        let mut fifo = [0u8; 64];
        let mut n = 0;
        self.arrived_by(ms, |b| {
            fifo[n] = b;
            n += 1;
        });
        let mut bytes = fifo[..n].iter();
        assert_eq!(
            isr.receive_while(|| bytes.next().map(|&b| Ok(b))),
            n,
            "RX ring full"
        );
    }

    /// Every byte that has arrived by the end of millisecond `ms`.
    fn arrived_by(&mut self, ms: u64, mut put: impl FnMut(u8)) {
        let end = (ms + 1) * self.rate;
        while self.next_at < end {
            put(self.rng.byte());
            self.bytes += 1;
            self.next_at += 1000;
            self.left_in_burst -= 1;
            if self.left_in_burst == 0 {
                let silence_ms = self.rng.between(5, 200);
                self.next_at += silence_ms * self.rate;
                self.left_in_burst = self.burst_len();
            }
        }
    }
}

fn hours() -> u64 {
    std::env::var("NOISE_HOURS")
        .ok()
        .and_then(|h| h.parse().ok())
        .unwrap_or(24)
}

fn ports<const RX: usize, const TX: usize>()
-> (QueuedSerial<'static, RX, TX>, SerialIsr<'static, RX, TX>) {
    let rx = Box::leak(Box::new(Ring::<RX>::new()));
    let tx = Box::leak(Box::new(Ring::<TX>::new()));
    let stats = Box::leak(Box::new(PortStats::new()));
    QueuedSerial::split(rx, tx, stats, || {})
}

/// Every state-changing outcome of AOK noise.
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq)]
struct AokTally {
    resets: u64,
    stores: u64,
    parameter_changes: u64,
    set_loads: u64,
    start_set_changes: u64,
    ram_waypoint_changes: u64,
    waypoint_loads: u64,
    motor_runs: u64,
    motor_on_ms: u64,
    external_taken: u64,
    debug_toggles: u64,
}

impl AokTally {
    fn changes(&self) -> u64 {
        self.resets
            + self.stores
            + self.parameter_changes
            + self.set_loads
            + self.start_set_changes
            + self.ram_waypoint_changes
            + self.waypoint_loads
            + self.motor_runs
            + self.external_taken
            + self.debug_toggles
    }
}

/// The RAM waypoints the link holds: slots 0..=30, then 254 and 255.
fn ram_waypoints(link: &AokLink, shared: &Shared) -> [StoredWaypoint; 33] {
    let mut out = [StoredWaypoint::default(); 33];
    for (i, w) in out.iter_mut().enumerate() {
        let wire = match i {
            0..=30 => i as u8,
            31 => 254,
            _ => 255,
        };
        *w = link.waypoint(WaypointSlot::from_wire(wire).unwrap(), shared);
    }
    out
}

/// Fresh marker values in the flash mirror's sets and waypoints (generation `generation`): no
/// random frame writes them, and they differ from what RAM holds.
fn seed_flash(shared: &mut Shared, generation: u32) {
    let g = generation as i32;
    for (i, set) in shared.persisted.aok.sets.iter_mut().enumerate() {
        for (j, v) in set.iter_mut().enumerate() {
            *v = 0x5e70_0000 ^ (g << 12) ^ ((i as i32) << 6) ^ j as i32;
        }
    }
    for (i, w) in shared.persisted.aok.waypoints.iter_mut().enumerate() {
        *w = StoredWaypoint {
            lon: 0x3a70_0000 ^ (g << 8) ^ i as i32,
            lat: -0x3a70_0000 ^ g,
            action1: 0x8000_0000 | generation,
            action2: 0x4000_0000 | generation,
        };
    }
}

/// `hours` of noise into a fresh AOK link; its tally and the bytes sent.
fn aok_noise(model: Model, flying: bool, seed: u64, hours: u64) -> (AokTally, u64) {
    let (mut port, mut isr) = ports::<1024, 1024>();
    let mut shared = Shared::new(Persisted::default(), 0);
    let mut link = AokLink::new(&shared);
    shared.paused = !flying;
    let mut generation = 1;
    seed_flash(&mut shared, generation);

    let mut t = AokTally::default();
    let mut params = *link.parameters();
    let mut waypoints = ram_waypoints(&link, &shared);
    let mut start_set = shared.persisted.aok.start_set;
    let mut debug_on = link.debug_enabled();
    let mut motors_on = false;
    let mut external = false;
    let mut frames_ok = link.decoder_stats().frames_ok;
    let mut noise = Noise::new(seed, model, 3_840);
    let mut sink = [0u8; 256];

    for ms in 0..hours * 3_600_000 {
        noise.arrive(ms, &mut isr);
        link.poll(ms, &mut port, &mut shared);
        while isr.take_to_send(&mut sink) == sink.len() {}

        if std::mem::take(&mut shared.requests.reboot) {
            t.resets += 1;
        }
        if std::mem::take(&mut shared.requests.store) {
            t.stores += 1;
        }
        if link.debug_enabled() != debug_on {
            debug_on = !debug_on;
            t.debug_toggles += 1;
        }
        let on = link.motor_outputs().iter().any(|&v| v != 0);
        if on {
            t.motor_on_ms += 1;
            if !motors_on {
                t.motor_runs += 1;
            }
        }
        motors_on = on;
        let ext = link.control_source() == ControlSource::External;
        if ext && !external {
            t.external_taken += 1;
        }
        external = ext;

        // The rest changes only when the decoder accepted a frame.
        let ok = link.decoder_stats().frames_ok;
        if ok == frames_ok {
            continue;
        }
        frames_ok = ok;
        let mut reseed = false;
        if *link.parameters() != params {
            params = *link.parameters();
            if shared.persisted.aok.sets.contains(&params) {
                t.set_loads += 1;
            } else {
                t.parameter_changes += 1;
            }
        }
        if shared.persisted.aok.sets.contains(&params) {
            reseed = true; // a load, or a save of RAM into a set
        }
        if shared.persisted.aok.start_set != start_set {
            start_set = shared.persisted.aok.start_set;
            t.start_set_changes += 1;
        }
        let now = ram_waypoints(&link, &shared);
        let flash = &shared.persisted.aok.waypoints;
        let like_flash = now[..31] == flash[..31] && now[31] == flash[31];
        if now != waypoints {
            waypoints = now;
            if like_flash {
                t.waypoint_loads += 1;
            } else {
                t.ram_waypoint_changes += 1;
            }
        }
        if like_flash || reseed {
            generation += 1;
            seed_flash(&mut shared, generation);
        }
    }
    (t, noise.bytes)
}

fn aok_scenario(name: &str, model: Model, flying: bool, seed: u64) {
    let h = hours();
    let started = std::time::Instant::now();
    let (t, bytes) = aok_noise(model, flying, seed, h);
    println!(
        "AOK {name}, {h} h, {bytes} bytes, {:.1} s: {t:?}",
        started.elapsed().as_secs_f64()
    );
    assert_eq!(
        t.changes(),
        0,
        "AOK {name}: noise changed the box's state: {t:?}"
    );
    assert_eq!(t.motor_on_ms, 0, "AOK {name}: a motor ran: {t:?}");
}

#[test]
fn aok_uniform_noise_flying_commands_nothing() {
    aok_scenario("uniform flying", Model::Uniform, true, 0x0a0c_0001);
}

#[test]
fn aok_uniform_noise_landed_commands_nothing() {
    aok_scenario("uniform landed", Model::Uniform, false, 0x0a0c_0002);
}

#[test]
fn aok_burst_noise_flying_commands_nothing() {
    aok_scenario("bursts flying", Model::Bursts, true, 0x0a0c_0003);
}

#[test]
fn aok_burst_noise_landed_commands_nothing() {
    aok_scenario("bursts landed", Model::Bursts, false, 0x0a0c_0004);
}

/// Every state-changing outcome of AYDP noise.
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq)]
struct AydpTally {
    updates_applied: u64,
    direct_applied: u64,
    stores_requested: u64,
}

fn aydp_noise(model: Model, seed: u64, hours: u64) -> (AydpTally, u64) {
    let (mut port, mut isr) = ports::<1024, 1024>();
    let mut shared = Shared::new(Persisted::default(), 0);
    shared.direct_control = true;
    let mut link = AydpLink::new(0);
    let mut noise = Noise::new(seed, model, 11_520);
    let mut sink = [0u8; 256];
    let mut stores = 0;
    for ms in 0..hours * 3_600_000 {
        noise.arrive(ms, &mut isr);
        link.poll(ms, &mut port, &mut shared);
        while isr.take_to_send(&mut sink) == sink.len() {}
        if std::mem::take(&mut shared.requests.store) {
            stores += 1;
        }
    }
    let c = link.counters();
    let t = AydpTally {
        updates_applied: u64::from(c.updates_applied),
        direct_applied: u64::from(c.direct_applied),
        stores_requested: u64::from(c.stores_requested).max(stores),
    };
    (t, noise.bytes)
}

fn aydp_scenario(name: &str, model: Model, seed: u64) {
    let h = hours();
    let started = std::time::Instant::now();
    let (t, bytes) = aydp_noise(model, seed, h);
    println!(
        "AYDP {name}, {h} h, {bytes} bytes, {:.1} s: {t:?}",
        started.elapsed().as_secs_f64()
    );
    assert_eq!(
        t,
        AydpTally::default(),
        "AYDP {name}: noise changed the box's state"
    );
}

#[test]
fn aydp_uniform_noise_commands_nothing() {
    aydp_scenario("uniform", Model::Uniform, 0x0a7d_0001);
}

#[test]
fn aydp_burst_noise_commands_nothing() {
    aydp_scenario("bursts", Model::Bursts, 0x0a7d_0002);
}
