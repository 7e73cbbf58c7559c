//! Line noise on the AOK UART commands nothing (issues 42 and 53): random bytes into UART2 of
//! the real firmware in QEMU (lm3s6965evb), flying and landed, continuous and in bursts, and the
//! box must neither reset, nor store, nor load, nor run a motor, nor toggle its debug stream,
//! nor hand the sticks to external control, nor change a parameter or the mission POI. Then
//! genuine commands, sent as `protolink aok` sends them (`aok_proto::Client`, one write per
//! command, with silence around it), are all obeyed.
//!
//! The noise, seeded ([`SEED`]), at 38 400 Bd's pace (3 840 bytes/s):
//!
//! | phase | the box | what | time |
//! |---|---|---|---|
//! | 1 | flying (the default at boot) | continuous | [`CONTINUOUS`] |
//! | 2 | flying | bursts of 20-200 bytes, then 5-200 ms of silence | [`BURSTS`] |
//! | 3 | landed (`a pause` over AEOLUS) | continuous | [`CONTINUOUS`] |
//! | 4 | landed | bursts | [`BURSTS`] |
//! | 5 | flying | [`GLITCHES`] glitches of 1-8 bytes, each one write with 10-40 ms of silence after it, then every one-bit-flip and lost-byte variant of [`FLIPPED`] | about 15 s |
//! | 6 | landed | as 5, with the variants of the motor tests [`FLIPPED_LANDED`] and one genuine motor-test frame alone | about 10 s |
//!
//! Phases 5 and 6 are the glitch and bit-flip models of `sensor-box/tests/all/noise.rs` through the
//! real UART (`docs/protocol-notes.md` PL41): in flight nothing may change but the debug stream
//! (`63 01`/`63 02` stay obeyed in flight, and are counted apart), and landed no motor may run.
//!
//! QEMU's UART model delivers the bytes of one socket write back to back, so the pace is kept
//! by the writes: [`CHUNK`] bytes every [`CHUNK`] byte times (10.4 ms), never fewer than
//! [`MIN_CHUNK`] bytes in one write (a burst's tail joins its last chunk). A write is the
//! shortest stretch of noise the box sees between two quiet gaps, and it is longer than any AOK
//! command (19 bytes at most), so no single write can be taken for one command that a PC sent
//! alone. Genuine commands have at least 100 ms of silence before them (twice the AOK link's
//! 50 ms idle limit for a partial frame) and after them.
//!
//! What counts is read from the firmware's defmt log (the lines `sensor-box/src/aok_link` logs
//! when it obeys), from the boot TOASTs on UART0, and from reading the parameters and the
//! mission POI back over AOK before and after the noise. The test prints every count.
//!
//! It takes about 100 s. Before the AOK line-noise gate (issue 42) the box obeys this noise and
//! the test fails: with this seed, a waypoint load from flash in flight; landed, a reset,
//! waypoint saves and loads, motor-test outputs and debug toggles.
//!
//! The lm3s6965evb boards: the blocking firmware and the async one (`firmware-embassy`'s QEMU
//! board, whose AOK task drives the same link and noise gate). Not the simulated STM32
//! (netduinoplus2): it takes a whole host core already and would double the run.

// The bit-flip and lost-byte variants, as `sensor-box/tests/all/noise.rs` makes them.
#[allow(dead_code)]
#[path = "../../../sensor-box/tests/all/common/genuine_aok.rs"]
mod genuine_aok;

use crate::harness::*;
use aok_proto::WaypointSlot;
use aok_proto::{Client, Command, Motor, MotorTest, Waypoint};
use protolink_tests::rng::Rng;
use std::io::{ErrorKind, Read, Write};
use std::net::TcpStream;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// The noise's seed.
const SEED: u64 = 0x4E01_5E42;
/// The AOK line's rate, bytes per second (38 400 Bd, 10 bits a byte).
const BYTES_PER_S: f64 = 3_840.0;
/// Bytes per write of continuous noise (10.4 ms of the line).
const CHUNK: usize = 40;
/// The fewest bytes one write of noise carries: more than the longest AOK command (19).
const MIN_CHUNK: usize = 20;
/// Each continuous phase.
const CONTINUOUS: Duration = Duration::from_secs(20);
/// Each burst phase.
const BURSTS: Duration = Duration::from_secs(12);
/// Silence before and after a genuine command (and after the noise).
const QUIET: Duration = Duration::from_millis(150);
/// Glitches per glitch phase.
const GLITCHES: usize = 300;
/// Genuine commands whose one-bit-flip and lost-byte variants are sent in flight: read
/// waypoint 9 (`63 09` a bit away), read parameter 7 (`63 07`), load waypoints, save
/// waypoints, set parameter 12 to 1500, a motor test.
const FLIPPED: [&[u8]; 6] = [
    &[0x67, 0x09],
    &[0x67, 0x07],
    &[0x63, 0x09],
    &[0x63, 0x08],
    &[0x73, 0x0c, 0x00, 0x00, 0x05, 0xdc, 0xd5],
    &[0x31, 0x28, 0x19],
];
/// The motor tests whose variants are sent landed: motor 1 = 40, motor 12 = 32.
const FLIPPED_LANDED: [&[u8]; 2] = [&[0x31, 0x28, 0x19], &[0x43, 0x20, 0x63]];

/// What the box logs when it obeys a state-changing AOK command (`sensor-box/src/aok_link`),
/// and what it logs when an AOK reply did not fit (reported, not a state change).
const OBEYED: [(&str, &str); 10] = [
    ("reset", "AOK reset requested"),
    ("parameter set saved", "AOK parameters saved to set"),
    ("start set stored", "AOK start set"),
    ("waypoints saved", "AOK waypoints saved to flash"),
    ("waypoints loaded", "AOK waypoints loaded from flash"),
    ("parameter set loaded", "AOK parameters loaded from set"),
    ("motor test output", "AOK motor test: motor"),
    ("debug on", "AOK debug on"),
    ("debug off", "AOK debug off"),
    ("external control", "AOK external control takes over"),
];
const REPLY_DROPPED: &str = "AOK: TX queue full, reply dropped";

#[test]
fn line_noise_on_the_aok_uart_commands_nothing() {
    line_noise_commands_nothing(Board::Lm3s6965evb);
}

#[test]
fn line_noise_on_the_aok_uart_of_the_async_firmware_commands_nothing() {
    line_noise_commands_nothing(Board::Embassy);
}

fn line_noise_commands_nothing(board: Board) {
    let Some(mut q) = boot(board, Ports::NOISE.on(board)) else {
        return;
    };
    let log_path = q.log().display().to_string();
    let first = q.uart0.read_until(Duration::from_secs(10), |_| true);
    assert_eq!(
        q.uart0.frames[first].toast().as_deref(),
        Some("AEOLUS on"),
        "log: {log_path}"
    );
    let started = Instant::now();
    let mut rng = Rng::new(SEED);
    let uart2 = q.uart2.try_clone().expect("clone UART2");
    let (to_uart0, commands) = mpsc::channel::<String>();
    let stop = AtomicBool::new(false);

    let (before, after_flying, after_landed, genuine) = std::thread::scope(|s| {
        // UART0 is read all along (telemetry must not back up into QEMU), and takes the
        // AEOLUS commands of the test.
        let u0 = &mut q.uart0;
        let stop = &stop;
        let reader = s.spawn(move || {
            while !stop.load(Ordering::Relaxed) {
                while let Ok(c) = commands.try_recv() {
                    u0.command(&c);
                }
                u0.read_for(Duration::from_millis(20));
            }
        });

        let mark = |n| {
            to_uart0.send(mark(n)).expect("UART0 reader");
            std::thread::sleep(QUIET);
        };
        let before = read_state(&uart2);
        mark(1);
        noise(&uart2, &mut rng, CONTINUOUS, false);
        noise(&uart2, &mut rng, BURSTS, true);
        mark(2);
        let after_flying = read_state(&uart2);
        mark(5);
        glitches(&uart2, &mut rng, &FLIPPED);
        mark(6);
        let after_glitches = read_state(&uart2);
        // In flight: a parameter settable in flight, set and read back.
        let flying_set = genuine_set_parameter(&uart2, 12, 1500);

        to_uart0.send("a pause".into()).expect("UART0 reader");
        std::thread::sleep(QUIET);
        mark(3);
        noise(&uart2, &mut rng, CONTINUOUS, false);
        noise(&uart2, &mut rng, BURSTS, true);
        mark(4);
        let after_landed = read_state(&uart2);
        mark(7);
        glitches(&uart2, &mut rng, &FLIPPED_LANDED);
        // One genuine motor-test frame alone: it arms motor 3, it does not run it.
        writes(&uart2, [(vec![0x33, 0x28, 0x1b], QUIET)].into_iter());
        mark(8);
        // Landed (again, if the noise reset the box, which boots flying): the state-changing
        // commands a PC sends.
        to_uart0.send("a pause".into()).expect("UART0 reader");
        std::thread::sleep(QUIET);
        let landed = genuine_landed(&uart2);
        std::thread::sleep(QUIET);
        stop.store(true, Ordering::Relaxed);
        reader.join().expect("UART0 reader");
        (
            before,
            (after_flying, after_glitches),
            after_landed,
            (flying_set, landed),
        )
    });
    let (after_flying, after_glitches) = after_flying;
    let boot_toasts = q
        .uart0
        .frames
        .iter()
        .filter(|f| f.toast().as_deref() == Some("AEOLUS on"))
        .count();
    println!("{:.1} s", started.elapsed().as_secs_f64());
    let log = q.stop();

    // The log in its phases, between the marks: the flying noise, the landed noise, then
    // the genuine landed commands.
    let at = |n: usize| log.find(&marker_line(n)).unwrap_or(log.len());
    let flying_log = log.get(at(1)..at(2)).unwrap_or_default();
    let landed_log = log.get(at(3)..at(4)).unwrap_or_default();
    let glitch_flying_log = log.get(at(5)..at(6)).unwrap_or_default();
    let glitch_landed_log = log.get(at(7)..at(8)).unwrap_or_default();
    let genuine_log = log.get(at(8)..).unwrap_or_default();

    println!("what the noise made the box do (flying | landed):");
    let mut obeyed = 0;
    for (what, line) in OBEYED {
        let (f, l) = (
            obeyed_lines(flying_log, line),
            obeyed_lines(landed_log, line),
        );
        println!("{what:>22}: {f:5} | {l:5}");
        obeyed += f + l;
    }
    let boots = log.matches(board.log_name()).count();
    println!(
        "{:>22}: {boots} boot lines, {boot_toasts} boot TOASTs",
        "boots"
    );
    println!(
        "{:>22}: {:5} | {:5}",
        "replies dropped",
        flying_log.matches(REPLY_DROPPED).count(),
        landed_log.matches(REPLY_DROPPED).count()
    );
    println!(
        "{:>22}: refused in flight {}",
        "motor tests",
        flying_log.matches("AOK motor test refused: flying").count()
    );
    println!("what glitches and flipped bits made the box do (flying | landed):");
    let (mut glitch_flying, mut glitch_motor) = (0, 0);
    for (what, line) in OBEYED {
        let (f, l) = (
            obeyed_lines(glitch_flying_log, line),
            obeyed_lines(glitch_landed_log, line),
        );
        println!("{what:>22}: {f:5} | {l:5}");
        if !what.starts_with("debug") {
            glitch_flying += f;
        }
        if what == "motor test output" {
            glitch_motor += l;
        }
    }
    println!(
        "{:>22}: {:5} | {:5}",
        "refused in flight",
        glitch_flying_log.matches("refused: flying").count(),
        glitch_landed_log.matches("refused: flying").count()
    );
    println!("parameters and mission POI before: {before:?}");
    println!("after the flying noise: {after_flying:?}");
    println!("after the landed noise: {after_landed:?}");
    println!("genuine commands: {genuine:?}");
    println!("firmware log: {log_path}");

    assert_eq!(obeyed, 0, "state-changing commands obeyed from noise");
    assert_eq!(
        (boots, boot_toasts),
        (1, 1),
        "the box reset during the noise"
    );
    assert_eq!(
        after_flying, before,
        "the noise in flight changed the state"
    );
    assert_eq!(
        glitch_flying, 0,
        "glitches or flipped bits changed a flying box's state"
    );
    assert_eq!(
        after_glitches, before,
        "glitches or flipped bits in flight changed the state"
    );
    assert_eq!(glitch_motor, 0, "a glitch or a flipped bit ran a motor");
    // Landed, the state is the one before with the genuine in-flight parameter set.
    let mut expected = before;
    if let Some(p) = expected.params.as_mut().and_then(|p| p.get_mut(12)) {
        *p = 1500;
    }
    assert_eq!(
        after_landed, expected,
        "the noise on the ground changed the state"
    );
    assert_eq!(genuine.0, Some(1500), "a parameter set in flight");
    let (saved, motor) = genuine.1;
    assert!(saved, "save set 1 sent");
    assert!(motor, "motor test sent");
    assert!(genuine_log.contains("AOK parameters saved to set 1"));
    assert!(genuine_log.contains("AOK motor test: motor 1 0 -> 50"));
}

/// The lines of `log` that say the box obeyed (`line`); a motor test's lapse back to 0 is the
/// end of one obeyed, not another.
fn obeyed_lines(log: &str, line: &str) -> usize {
    log.lines()
        .filter(|l| l.contains(line) && !l.contains("(lapsed)"))
        .count()
}

/// The AEOLUS command that marks the end of noise phase `n` in the log (an unknown command,
/// logged with its length; the lengths of the two marks differ).
fn mark(n: usize) -> String {
    format!("a end of noise{}", "!".repeat(n))
}

fn marker_line(n: usize) -> String {
    format!("AEOLUS: unknown command ({} bytes)", mark(n).len())
}

/// Sends uniformly random bytes for `span`, continuous or in bursts, while another thread
/// drains what the box sends back on UART2.
fn noise(uart2: &TcpStream, rng: &mut Rng, span: Duration, bursts: bool) {
    draining(uart2, |out| {
        let start = Instant::now();
        let mut next = start;
        while start.elapsed() < span {
            let run = if bursts {
                20 + rng.below(181) as usize
            } else {
                CHUNK
            };
            let mut left = run;
            while left > 0 {
                let n = if left < CHUNK + MIN_CHUNK {
                    left
                } else {
                    CHUNK
                };
                out.write_all(&rng.bytes(n)).expect("write UART2");
                left -= n;
                next += Duration::from_secs_f64(n as f64 / BYTES_PER_S);
                sleep_until(next);
            }
            if bursts {
                next += Duration::from_millis(5 + rng.below(196));
                sleep_until(next);
            }
        }
    });
}

fn sleep_until(t: Instant) {
    if let Some(d) = t.checked_duration_since(Instant::now()) {
        std::thread::sleep(d);
    }
}

/// A PC's AOK client on UART2 (firmware 0.35: bulk reads).
fn client(uart2: &TcpStream) -> Client<NbSerial> {
    let stream = uart2.try_clone().expect("clone UART2");
    stream.set_nonblocking(true).expect("nonblocking");
    Client::new(NbSerial::new(stream), emulated_aok_config())
}

fn now() -> impl FnMut() -> u32 {
    let t0 = Instant::now();
    move || t0.elapsed().as_millis() as u32
}

/// The state noise must not change: the 32 RAM parameters and the mission POI (slot 31 in
/// flash), read with genuine commands; `None` where a read failed.
#[derive(Debug, PartialEq)]
struct State {
    params: Option<Vec<i32>>,
    mission_poi: Option<Waypoint>,
}

fn read_state(uart2: &TcpStream) -> State {
    let mut c = client(uart2);
    let mut now = now();
    let params = (|| {
        let mut v = c.bulk_read(0, &mut now).ok()?.to_vec();
        std::thread::sleep(QUIET);
        v.extend(c.bulk_read(16, &mut now).ok()?);
        Some(v)
    })();
    std::thread::sleep(QUIET);
    let mission_poi = c.read_waypoint(WaypointSlot::MissionPoi, &mut now).ok();
    std::thread::sleep(QUIET);
    State {
        params,
        mission_poi,
    }
}

/// In flight: parameter `number` set to `value`, then read back.
fn genuine_set_parameter(uart2: &TcpStream, number: u8, value: i32) -> Option<i32> {
    let mut c = client(uart2);
    let mut now = now();
    c.set_parameter(number, value, &mut now).ok()?;
    std::thread::sleep(QUIET);
    let back = c.read_parameter(number, &mut now).ok();
    std::thread::sleep(QUIET);
    back
}

/// Landed: save the parameters to set 1 and a motor-test value, sent twice 100 ms apart as a PC
/// holding a test does (a motor at rest runs from its second frame; neither command has a
/// reply, the log shows them). Whether each was sent.
fn genuine_landed(uart2: &TcpStream) -> (bool, bool) {
    let mut c = client(uart2);
    let mut now = now();
    let saved = c.run(Command::SaveSet(1), &mut now).is_ok();
    std::thread::sleep(QUIET);
    let test = MotorTest {
        motor: Motor::new(1).expect("motor 1"),
        value: 50,
    };
    let first = c.motor_test(test, &mut now).is_ok();
    std::thread::sleep(Duration::from_millis(100));
    let motor = first && c.motor_test(test, &mut now).is_ok();
    (saved, motor)
}

/// [`GLITCHES`] glitches of 1-8 random bytes, each one write with 10-40 ms of silence after
/// it, then every one-bit-flip and lost-byte variant of each of `genuine`, each one write with
/// 40 ms of silence after it.
fn glitches(uart2: &TcpStream, rng: &mut Rng, genuine: &[&[u8]]) {
    let mut all = Vec::new();
    for _ in 0..GLITCHES {
        let n = 1 + rng.below(8) as usize;
        let silence = Duration::from_millis(10 + rng.below(31));
        all.push((rng.bytes(n), silence));
    }
    for bytes in genuine {
        for v in genuine_aok::variants(bytes) {
            all.push((v, Duration::from_millis(40)));
        }
    }
    writes(uart2, all.into_iter());
}

/// Sends each write with the silence after it, while another thread drains what the box sends
/// back on UART2.
fn writes(uart2: &TcpStream, all: impl Iterator<Item = (Vec<u8>, Duration)>) {
    draining(uart2, |out| {
        for (bytes, silence) in all {
            out.write_all(&bytes).expect("write UART2");
            std::thread::sleep(silence);
        }
    });
}

/// Runs `send` with a handle on UART2 while another thread drains what the box sends back,
/// then drains for [`QUIET`] more (what the box still sends, before the next commands).
fn draining(uart2: &TcpStream, send: impl FnOnce(&mut TcpStream)) {
    let mut out = uart2.try_clone().expect("clone UART2");
    let mut back = uart2.try_clone().expect("clone UART2");
    back.set_read_timeout(Some(Duration::from_millis(20)))
        .expect("timeout");
    let stop = AtomicBool::new(false);
    std::thread::scope(|s| {
        s.spawn(|| {
            let mut buf = [0u8; 4096];
            while !stop.load(Ordering::Relaxed) {
                match back.read(&mut buf) {
                    Ok(0) => break,
                    Ok(_) => {}
                    Err(e) if matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut) => {}
                    Err(e) => panic!("UART2: {e}"),
                }
            }
        });
        send(&mut out);
        std::thread::sleep(QUIET);
        stop.store(true, Ordering::Relaxed);
    });
}
