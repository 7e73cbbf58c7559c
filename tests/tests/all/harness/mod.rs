//! The QEMU harness of the end-to-end tests: boots the release sensor-box firmware in QEMU
//! through `scripts/qemu-run.sh` and connects to its three UART sockets. Every test listed in
//! [`on_every_board!`] runs on the three boards ([`Board`]): the default `lm3s6965evb`, the
//! STM32F411 board built with `qemu-stm32` in `netduinoplus2` (an STM32F405 model), and the
//! async firmware (`firmware-embassy`, its QEMU board) in `lm3s6965evb`.
//!
//! * Skipped only when `qemu-system-arm` is not installed (`scripts/setup.sh qemu` installs
//!   it; `.ci/run` does), through `protolink_tests::skip`: a failure under CI (`CI=true`), and
//!   outside CI a line in the skipped count of `scripts/test.sh`'s summary.
//! * The firmware is built by the harness itself (`cargo qemu-build` / `cargo
//!   stm32-qemu-build`, a no-op when `scripts/test.sh` has built it already), into
//!   `$CARGO_TARGET_DIR` (default `target/`); the async firmware by `cargo qemu-build` in
//!   `firmware-embassy/` (its own workspace), into `$CARGO_TARGET_DIR/embassy`.
//!   `SENSOR_BOX_ELF=path` (lm3s), `SENSOR_BOX_STM32_ELF=path` (STM32) and
//!   `SENSOR_BOX_EMBASSY_ELF=path` (the async firmware) boot a given ELF instead. [`protolink`] builds the
//!   host tool the same way.
//! * Every test boots its own QEMU on its own fixed ports ([`Ports`], moved by
//!   [`Ports::on`] for the STM32 and the async firmware's runs), far from the demo's 7000..7002. All the QEMU tests are
//!   in one test binary (`tests/all/`), whose tests run in parallel; at most [`qemu_jobs`]
//!   emulators run at once (`QEMU_JOBS`, 1 to 16, default 2), so that a few emulators, not
//!   every test of the binary, share the cores and disturb each other's timing; the simulated
//!   STM32 runs alone (it takes a whole host core, and beside another emulator on two cores it
//!   falls behind real time: AEOLUS frames short of the rate, an AOK burst cut by a late byte),
//!   and so does a test that floods all three UARTs ([`boot_alone`]). A test
//!   waits for its turn in [`boot`]. Each runs on its own ports, its own log file and its own
//!   temporary files, so any of them may run beside any other. QEMU is killed when the test
//!   ends, whether it passed or not ([`Qemu`]'s `Drop`), and the next test's turn comes then.
//!   The firmware's defmt log goes to `$CARGO_TARGET_DIR/qemu-firmware-PORT.log` (decoded when
//!   `defmt-print` is installed; on the STM32 it is read over RTT through QEMU's GDB stub, port
//!   UART0 + 3).
//!
//! A test that needs a firmware built with extra features of `firmware-example` or
//! `firmware-embassy` (such as the test-only `fault-hang`) gets its ELF from [`firmware_elf_with`], which builds it once and
//! copies it to its own path beside the default one, then boots it with [`boot_elf`]. No QEMU
//! runs during that build (it waits for the running ones and holds back the others), and the
//! other tests boot a copy of the default build (`sensor-box-default`), which it never
//! overwrites.
//!
//! To add a test: write `fn my_test(board: Board)`, add it to the file's [`on_every_board!`]
//! list, give it its own [`Ports`] (a new constant, added to [`Ports::ALL`]), then `let
//! Some(mut q) = boot(board, Ports::NEXT_ONE.on(board)) else { return };` and use `q.uart0` (an
//! [`Aeolus`] reader over the AEOLUS socket), `q.uart1` (AYDP) and `q.uart2` (AOK), plain
//! `TcpStream`s for the last two. Anything else it binds or writes must be its own too (a port
//! of its range, a file name with its board or ports in it): any other test may run beside it. To let `protolink` take a UART instead, close the harness's connection first
//! ([`Aeolus::disconnect`], `TcpStream::shutdown`): a QEMU UART socket serves one client at a
//! time.
#![allow(dead_code)]

mod pl011_wake;

use aeolus_proto::message::{Message, Text};
use aeolus_proto::{CrcMode, Decode, Decoder, max_encoded_len};
use std::fs::File;
use std::io::{ErrorKind, Read, Write};
use std::net::TcpStream;
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::sync::{Condvar, Mutex, MutexGuard, OnceLock};
use std::time::{Duration, Instant};

// ------------------------------------------------------------------ QEMU harness

/// The board a test boots, and the QEMU machine it runs in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Board {
    /// The default board: QEMU `lm3s6965evb` (Cortex-M3), `cargo qemu-build`.
    Lm3s6965evb,
    /// The STM32F411 board with its three simulation changes (`qemu-stm32`) in QEMU's
    /// `netduinoplus2` (STM32F405, Cortex-M4F), `cargo stm32-qemu-build`.
    Stm32f411,
    /// The async firmware (`firmware-embassy`, feature `board-qemu`) in QEMU `lm3s6965evb`,
    /// `cargo qemu-build` in `firmware-embassy/`.
    Embassy,
}

impl Board {
    /// The machine name for `scripts/qemu-run.sh --machine`.
    pub fn machine(self) -> &'static str {
        match self {
            Board::Lm3s6965evb | Board::Embassy => "lm3s6965evb",
            Board::Stm32f411 => "netduinoplus2",
        }
    }

    /// How the firmware names itself in its boot log line (`board::NAME`).
    pub fn log_name(self) -> &'static str {
        match self {
            Board::Lm3s6965evb => "on qemu-lm3s6965evb: booting",
            Board::Stm32f411 => "on stm32f411 (simulated: QEMU netduinoplus2): booting",
            Board::Embassy => "on qemu-lm3s6965evb-embassy: booting",
        }
    }

    /// The cargo alias that builds this board's firmware (in [`Board::build_dir`]).
    fn build_alias(self) -> &'static str {
        match self {
            Board::Lm3s6965evb | Board::Embassy => "qemu-build",
            Board::Stm32f411 => "stm32-qemu-build",
        }
    }

    /// The target triple and the board feature of its firmware build (what its alias passes).
    fn target_and_feature(self) -> (&'static str, &'static str) {
        match self {
            Board::Lm3s6965evb | Board::Embassy => ("thumbv7m-none-eabi", "board-qemu"),
            Board::Stm32f411 => ("thumbv7em-none-eabihf", "qemu-stm32"),
        }
    }

    /// Where its build runs: the workspace root, or `firmware-embassy/` (its own workspace).
    fn build_dir(self) -> PathBuf {
        match self {
            Board::Lm3s6965evb | Board::Stm32f411 => workspace_root(),
            Board::Embassy => workspace_root().join("firmware-embassy"),
        }
    }

    /// The target directory of its build: the workspace's, or `embassy/` inside it for the
    /// async firmware (its own workspace and lock file, nothing shared with the root's builds).
    fn build_target_dir(self) -> PathBuf {
        match self {
            Board::Lm3s6965evb | Board::Stm32f411 => target_dir(),
            Board::Embassy => target_dir().join("embassy"),
        }
    }

    /// Where that alias puts the ELF, under [`Board::build_target_dir`].
    fn elf_path(self) -> &'static str {
        match self {
            Board::Lm3s6965evb => "thumbv7m-none-eabi/release/sensor-box",
            Board::Stm32f411 => "thumbv7em-none-eabihf/release/sensor-box",
            Board::Embassy => "thumbv7m-none-eabi/release/sensor-box-embassy",
        }
    }

    /// The package and binary of its firmware build.
    fn package_and_bin(self) -> (&'static str, &'static str) {
        match self {
            Board::Lm3s6965evb | Board::Stm32f411 => ("firmware-example", "sensor-box"),
            Board::Embassy => ("firmware-embassy", "sensor-box-embassy"),
        }
    }

    /// The environment variable that names a prebuilt ELF for this board.
    fn elf_env(self) -> &'static str {
        match self {
            Board::Lm3s6965evb => "SENSOR_BOX_ELF",
            Board::Stm32f411 => "SENSOR_BOX_STM32_ELF",
            Board::Embassy => "SENSOR_BOX_EMBASSY_ELF",
        }
    }

    /// Every board, in the order [`on_every_board!`] runs them.
    pub const ALL: [Board; 3] = [Board::Lm3s6965evb, Board::Stm32f411, Board::Embassy];
}

/// Defines, for each `fn name(board: Board)` listed, a module `name` with one `#[test]` per
/// board: `FILE::name::lm3s6965evb`, `FILE::name::stm32f411_in_netduinoplus2` and
/// `FILE::name::embassy_in_lm3s6965evb` (run one board with `cargo test ... --
/// ::lm3s6965evb`, `-- stm32f411` or `-- embassy`). Comes with the harness's glob import (`use
/// crate::harness::*;`). `on_every_board!(lm3s6965evb: name, ...)` defines the two tests on
/// that chip only, the blocking board's and the async firmware's, for a test whose file says
/// why the simulated STM32 cannot run it.
macro_rules! on_every_board {
    (lm3s6965evb: $($name:ident),* $(,)?) => {
        $(
            mod $name {
                #[test]
                fn lm3s6965evb() {
                    super::$name(super::Board::Lm3s6965evb)
                }

                #[test]
                fn embassy_in_lm3s6965evb() {
                    super::$name(super::Board::Embassy)
                }
            }
        )*
    };
    ($($name:ident),* $(,)?) => {
        $(
            mod $name {
                #[test]
                fn lm3s6965evb() {
                    super::$name(super::Board::Lm3s6965evb)
                }

                #[test]
                fn stm32f411_in_netduinoplus2() {
                    super::$name(super::Board::Stm32f411)
                }

                #[test]
                fn embassy_in_lm3s6965evb() {
                    super::$name(super::Board::Embassy)
                }
            }
        )*
    };
}
pub(crate) use on_every_board;

/// The three TCP ports of one QEMU instance (UART0, UART1, UART2).
#[derive(Debug, Clone, Copy)]
pub struct Ports(pub u16);

impl Ports {
    /// `qemu_firmware::aeolus_telemetry_crc_rates_and_commands`.
    pub const AEOLUS: Ports = Ports(17_400);
    /// `qemu_firmware::aydp_setting_survives_store_and_reboot`.
    pub const AYDP: Ports = Ports(17_410);
    /// `qemu_firmware::aok_parameter_and_waypoint`.
    pub const AOK: Ports = Ports(17_420);
    /// `protolink_e2e::bridge_carries_telemetry_and_commands_over_udp`.
    pub const BRIDGE: Ports = Ports(17_430);
    /// `protolink_e2e::protolink_aydp_set_get_store`.
    pub const CLI_AYDP: Ports = Ports(17_440);
    /// `protolink_e2e::protolink_aok_get_set_waypoint`.
    pub const CLI_AOK: Ports = Ports(17_450);
    /// `protolink_help::every_help_example_runs_against_the_firmware` (UART ports, then the
    /// UDP ports of its examples at +5..+9).
    pub const CLI_HELP: Ports = Ports(17_460);
    /// `soak::hostile_soak` (both lm3s6965evb boards).
    pub const SOAK: Ports = Ports(17_470);
    /// `web_qemu::the_page_flies_the_firmwares_turn` (UART ports, then the bridge's UDP ports
    /// at +5 and +6 and the page at +7).
    pub const WEB: Ports = Ports(17_480);
    /// `realtime_flood::every_rate_and_every_answer_under_a_flood_on_all_three_uarts` (both
    /// lm3s6965evb boards).
    pub const REALTIME: Ports = Ports(17_490);
    /// `nmea_qemu::an_app_reads_the_firmwares_flight_as_nmea` (UART ports, then the NMEA
    /// server at +7).
    pub const NMEA: Ports = Ports(17_500);
    /// `gdl90_qemu::an_efb_reads_the_firmwares_flight_as_stratux_ahrs` (UART ports, then the
    /// EFB's UDP port at +7).
    pub const GDL90: Ports = Ports(17_510);
    /// `watchdog_qemu::a_hung_loop_is_reset_and_keeps_its_settings`.
    pub const WATCHDOG: Ports = Ports(17_520);
    /// `noise_qemu::line_noise_on_the_aok_uart_commands_nothing`.
    pub const NOISE: Ports = Ports(17_530);
    /// `capture_qemu::a_capture_of_the_firmware_dissects_in_tshark_as_decode_reads_it_and_replays`
    /// (UART ports, then UDP at +5..+8).
    pub const CAPTURE: Ports = Ports(17_540);
    /// `box_clock::the_boxs_clock_keeps_the_hosts_time`.
    pub const BOX_CLOCK: Ports = Ports(17_550);
    /// `readme_examples::every_readme_example_runs_as_written` (UART ports, then the EFB's port
    /// at +7 and the page at +8; the box's UDP stays on 5001/5002, as the READMEs show).
    pub const README: Ports = Ports(17_560);

    /// Every test's ports, by the constant's name: each test owns UART0's port and the 9 above
    /// it ([`Ports::RANGE`]) on each board, and no two tests' ranges meet on any board
    /// (`the_tests_ports_never_meet`).
    pub const ALL: [(&str, Ports); 17] = [
        ("AEOLUS", Ports::AEOLUS),
        ("AYDP", Ports::AYDP),
        ("AOK", Ports::AOK),
        ("BRIDGE", Ports::BRIDGE),
        ("CLI_AYDP", Ports::CLI_AYDP),
        ("CLI_AOK", Ports::CLI_AOK),
        ("CLI_HELP", Ports::CLI_HELP),
        ("SOAK", Ports::SOAK),
        ("WEB", Ports::WEB),
        ("REALTIME", Ports::REALTIME),
        ("NMEA", Ports::NMEA),
        ("GDL90", Ports::GDL90),
        ("WATCHDOG", Ports::WATCHDOG),
        ("NOISE", Ports::NOISE),
        ("CAPTURE", Ports::CAPTURE),
        ("BOX_CLOCK", Ports::BOX_CLOCK),
        ("README", Ports::README),
    ];

    /// The ports a test may use from UART0's: the UARTs (+0..+2), the STM32's GDB stub (+3)
    /// and its own UDP and TCP ports (+5..+9).
    pub const RANGE: u16 = 10;

    /// How much higher the STM32 runs' ports are ([`Ports::on`]): above every lm3s6965evb
    /// range, so that the two boards' runs of all the tests can be up at the same time.
    pub const STM32_OFFSET: u16 = 200;

    /// How much higher the async firmware's runs' ports are ([`Ports::on`]): above every
    /// STM32 range.
    pub const EMBASSY_OFFSET: u16 = 400;
}

impl Ports {
    /// The TCP port of UART `n`.
    pub fn uart(self, n: u16) -> u16 {
        self.0 + n
    }

    /// The same test's ports on `board`: the STM32 runs are [`Ports::STM32_OFFSET`] higher and
    /// the async firmware's [`Ports::EMBASSY_OFFSET`], so that the boards' runs of a test,
    /// which may run at the same time, and a QEMU still closing from one board never hold
    /// another's ports. Each test's range is
    /// [`Ports::RANGE`] ports: UART0..UART2, the GDB stub (+3, STM32) and the test's own UDP
    /// and TCP ports (+5..+9).
    pub fn on(self, board: Board) -> Ports {
        match board {
            Board::Lm3s6965evb => self,
            Board::Stm32f411 => Ports(self.0 + Ports::STM32_OFFSET),
            Board::Embassy => Ports(self.0 + Ports::EMBASSY_OFFSET),
        }
    }
}

#[test]
fn the_tests_ports_never_meet() {
    let mut ranges: Vec<(u16, String)> = Ports::ALL
        .iter()
        .flat_map(|&(name, p)| Board::ALL.map(|b| (p.on(b).0, format!("{name} on {b:?}"))))
        .collect();
    ranges.sort();
    for pair in ranges.windows(2) {
        let ((a, first), (b, second)) = (&pair[0], &pair[1]);
        assert!(
            a + Ports::RANGE <= *b,
            "{first} uses ports {a}..{} and {second} starts at {b}: give each test its own range",
            a + Ports::RANGE
        );
    }
}

/// How many QEMUs run at once: `QEMU_JOBS` (1 to 16), 2 when it is not set.
pub fn qemu_jobs() -> usize {
    static JOBS: OnceLock<usize> = OnceLock::new();
    *JOBS.get_or_init(|| {
        let Some(v) = std::env::var_os("QEMU_JOBS") else {
            return 2;
        };
        match v.to_str().and_then(|s| s.trim().parse::<usize>().ok()) {
            Some(n) if (1..=16).contains(&n) => n,
            _ => panic!(
                "QEMU_JOBS is {v:?}, but it must be a number from 1 to 16 (how many QEMUs the \
                 tests run at once; 2 when it is not set)"
            ),
        }
    })
}

/// The QEMUs running now, counted against [`qemu_jobs`] (see the module docs), and the
/// firmware builds waiting for the cores ([`Turn::take_all`]).
struct Turns {
    running: usize,
    builds_waiting: usize,
}

static TURNS: Mutex<Turns> = Mutex::new(Turns {
    running: 0,
    builds_waiting: 0,
});
/// Signalled when a QEMU or a build is done, so that a waiting test may go on.
static FREED: Condvar = Condvar::new();

/// A turn to run one QEMU (taken in [`boot`], waiting while [`qemu_jobs`] run) or, from
/// [`Turn::take_all`], every turn; given back on drop.
struct Turn {
    taken: usize,
}

impl Turn {
    fn turns() -> MutexGuard<'static, Turns> {
        TURNS.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// One QEMU's turn, once fewer than [`qemu_jobs`] run and no build waits; `alone`: every
    /// turn, once no other QEMU runs (the simulated STM32, which takes a whole host core and
    /// falls behind real time beside another emulator on a two-core host, and the floods:
    /// [`boot_alone`]).
    fn take(alone: bool) -> Turn {
        let jobs = qemu_jobs();
        let want = if alone { jobs } else { 1 };
        let mut turns = Turn::turns();
        while turns.running + want > jobs || turns.builds_waiting > 0 {
            turns = FREED.wait(turns).unwrap_or_else(|e| e.into_inner());
        }
        turns.running += want;
        Turn { taken: want }
    }

    /// Every turn, once no QEMU runs: for a firmware build, which would disturb a running
    /// emulator's timing. QEMUs not yet started wait for it.
    fn take_all() -> Turn {
        let jobs = qemu_jobs();
        let mut turns = Turn::turns();
        turns.builds_waiting += 1;
        while turns.running > 0 {
            turns = FREED.wait(turns).unwrap_or_else(|e| e.into_inner());
        }
        turns.builds_waiting -= 1;
        turns.running = jobs;
        Turn { taken: jobs }
    }
}

impl Drop for Turn {
    fn drop(&mut self) {
        let mut turns = Turn::turns();
        turns.running -= self.taken;
        drop(turns);
        FREED.notify_all();
    }
}

/// The firmware builds: one at a time, so that the default ELF is never copied while a build
/// with other features ([`firmware_elf_with`]) has taken its place.
static BUILD: Mutex<()> = Mutex::new(());

pub fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("tests/ is inside the workspace")
        .to_path_buf()
}

pub fn target_dir() -> PathBuf {
    std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .map(|p| {
            if p.is_relative() {
                workspace_root().join(p)
            } else {
                p
            }
        })
        .unwrap_or_else(|| workspace_root().join("target"))
}

pub fn qemu_installed() -> bool {
    Command::new("qemu-system-arm")
        .arg("--version")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

/// The board's release firmware ELF, built once per test run.
pub fn firmware_elf(board: Board) -> &'static Path {
    static LM3S: OnceLock<PathBuf> = OnceLock::new();
    static STM32: OnceLock<PathBuf> = OnceLock::new();
    static EMBASSY: OnceLock<PathBuf> = OnceLock::new();
    let cell = match board {
        Board::Lm3s6965evb => &LM3S,
        Board::Stm32f411 => &STM32,
        Board::Embassy => &EMBASSY,
    };
    cell.get_or_init(|| {
        if let Some(elf) = std::env::var_os(board.elf_env()) {
            return PathBuf::from(elf);
        }
        let _build = BUILD.lock().unwrap_or_else(|e| e.into_inner());
        let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
        let alias = board.build_alias();
        let status = Command::new(cargo)
            .arg(alias)
            .current_dir(board.build_dir())
            .env("CARGO_TARGET_DIR", board.build_target_dir())
            .status()
            .unwrap_or_else(|e| panic!("run `cargo {alias}`: {e}"));
        assert!(status.success(), "`cargo {alias}` failed");
        // A copy that the tests boot: a build with other features (`firmware_elf_with`, for a
        // test that may run beside them) overwrites the built ELF for a while.
        let built = board.build_target_dir().join(board.elf_path());
        let copy = built.with_file_name("sensor-box-default");
        std::fs::copy(&built, &copy).expect("copy the firmware ELF");
        copy
    })
}

/// The board's release firmware built with the extra `features` of `firmware-example`, copied
/// to `sensor-box-FEATURES` beside the default ELF (so the default one, which the other tests
/// boot, is rebuilt by the next `cargo qemu-build` from cargo's cache, not overwritten for
/// good). Built each time it is called: call it once per test. The tests that boot the default
/// build boot [`firmware_elf`]'s copy of it, which this never touches.
pub fn firmware_elf_with(board: Board, features: &[&str]) -> PathBuf {
    let _build = BUILD.lock().unwrap_or_else(|e| e.into_inner());
    // No QEMU runs while it builds (the tests that wait for a turn start after it).
    let _cores = Turn::take_all();
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let (target, feature) = board.target_and_feature();
    let (package, bin) = board.package_and_bin();
    let all = std::iter::once(feature)
        .chain(features.iter().copied())
        .collect::<Vec<_>>()
        .join(",");
    let mut build = Command::new(&cargo);
    build
        .args(["build", "-p", package, "--bin", bin, "--release"])
        .args(["--target", target, "--features", &all]);
    if board == Board::Embassy {
        // Its default feature is the STM32 board.
        build.arg("--no-default-features");
    }
    let status = build
        .current_dir(board.build_dir())
        .env("CARGO_TARGET_DIR", board.build_target_dir())
        .status()
        .unwrap_or_else(|e| panic!("build the firmware with {all}: {e}"));
    assert!(status.success(), "the firmware build with {all} failed");
    let built = board.build_target_dir().join(board.elf_path());
    let copy = built.with_file_name(format!("{bin}-{}", features.join("-")));
    std::fs::copy(&built, &copy).expect("copy the firmware ELF");
    // The default ELF back in its place (cargo has it cached: a copy, no compile).
    let status = Command::new(&cargo)
        .arg(board.build_alias())
        .current_dir(board.build_dir())
        .env("CARGO_TARGET_DIR", board.build_target_dir())
        .status()
        .expect("run the default firmware build");
    assert!(status.success(), "the default firmware build failed");
    copy
}

/// The `protolink` binary: `$PROTOLINK` when set (`scripts/test.sh` sets it to the binary of
/// its test build, so that the host tool is compiled once per run), else the debug build,
/// made once per test run (`cargo build -p protolink`).
pub fn protolink() -> &'static Path {
    static BIN: OnceLock<PathBuf> = OnceLock::new();
    BIN.get_or_init(|| {
        if let Some(path) = std::env::var_os("PROTOLINK") {
            let path = PathBuf::from(path);
            assert!(path.is_file(), "PROTOLINK={} is not a file", path.display());
            return path;
        }
        let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
        let status = Command::new(cargo)
            .args(["build", "-q", "-p", "protolink", "--bin", "protolink"])
            .current_dir(workspace_root())
            .env("CARGO_TARGET_DIR", target_dir())
            .status()
            .expect("run `cargo build -p protolink`");
        assert!(status.success(), "`cargo build -p protolink` failed");
        target_dir().join("debug/protolink")
    })
}

/// A running QEMU and the sockets of its three UARTs. Dropping it kills QEMU.
pub struct Qemu {
    /// UART0: AEOLUS.
    pub uart0: Aeolus,
    /// UART1: AYDP.
    pub uart1: TcpStream,
    /// UART2: AOK.
    pub uart2: TcpStream,
    process: Process,
    board: Board,
    /// This QEMU's turn among the [`qemu_jobs`] that may run at once: given back last, once
    /// QEMU is gone.
    _turn: Turn,
}

/// `scripts/qemu-run.sh` and what it started (QEMU, defmt-print), in their own process group.
struct Process {
    child: Child,
    log: PathBuf,
}

/// Boots `board`'s release firmware in QEMU on `ports` and connects to its three UARTs;
/// `None` when `qemu-system-arm` is missing: the test is then skipped through
/// `protolink_tests::skip::skip`, which fails it under CI.
///
/// QEMU runs in wait mode (`QEMU_WAIT=1`): the CPU starts only once UART0 is connected, so
/// the first bytes read from it are the boot TOAST.
pub fn boot(board: Board, ports: Ports) -> Option<Qemu> {
    boot_with(board, ports, false)
}

/// [`boot`], with `-icount shift=0` when `icount` (`QEMU_ICOUNT=1`): the virtual clock then
/// advances by 1 ns per executed instruction while the CPU runs and with the host's clock
/// while it sleeps, so the box's own clock is never late however slowly the host emulates it.
/// The simulated STM32 takes about a whole host core on a slow host and then falls behind real
/// time (SysTick ticks coalesce and the schedule skips late slots, as it must on a late CPU);
/// a test that judges the schedule in the box's clock boots it this way.
pub fn boot_with(board: Board, ports: Ports, icount: bool) -> Option<Qemu> {
    boot_as(board, ports, icount, board == Board::Stm32f411)
}

/// [`boot`], with no other emulator beside it: for a test that holds the box to the host's
/// clock under the heaviest load (three UARTs flooded), where a second emulator on a two-core
/// host would take the core the box needs.
pub fn boot_alone(board: Board, ports: Ports) -> Option<Qemu> {
    boot_as(board, ports, false, true)
}

fn boot_as(board: Board, ports: Ports, icount: bool, alone: bool) -> Option<Qemu> {
    if !qemu_installed() {
        skip_without_qemu();
        return None;
    }
    // Every board's firmware is built before any QEMU runs (the first test to get here builds
    // it, the others wait): a build on the same cores would disturb a running emulator.
    for b in Board::ALL {
        firmware_elf(b);
    }
    start(board, ports, icount, alone, firmware_elf(board))
}

/// [`boot`] with a given ELF of `board` (from [`firmware_elf_with`]); `None` when
/// `qemu-system-arm` is missing.
pub fn boot_elf(board: Board, ports: Ports, elf: &Path) -> Option<Qemu> {
    if !qemu_installed() {
        skip_without_qemu();
        return None;
    }
    start(board, ports, false, board == Board::Stm32f411, elf)
}

fn skip_without_qemu() {
    protolink_tests::skip::skip(
        "qemu-system-arm is not installed, so the firmware cannot be booted \
         (scripts/setup.sh qemu installs it)",
    );
}

fn start(board: Board, ports: Ports, icount: bool, alone: bool, elf: &Path) -> Option<Qemu> {
    assert!(elf.is_file(), "no firmware at {}", elf.display());
    let turn = Turn::take(alone);

    let log = target_dir().join(format!("qemu-firmware-{}.log", ports.0));
    let out = File::create(&log).expect("create the QEMU log file");
    let err = out.try_clone().expect("clone the log file handle");
    let defmt_print = Command::new("defmt-print")
        .arg("--version")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    let child = Command::new(workspace_root().join("scripts/qemu-run.sh"))
        .args(["--machine", board.machine()])
        .arg(elf)
        .env("QEMU_UART0_PORT", ports.uart(0).to_string())
        .env("QEMU_UART1_PORT", ports.uart(1).to_string())
        .env("QEMU_UART2_PORT", ports.uart(2).to_string())
        .env("QEMU_WAIT", "1")
        .env("QEMU_ICOUNT", if icount { "1" } else { "0" })
        .env("QEMU_DEFMT", if defmt_print { "1" } else { "0" })
        .stdin(Stdio::null())
        .stdout(out)
        .stderr(err)
        // Its own process group, so that Drop stops the script, QEMU and defmt-print.
        .process_group(0)
        .spawn()
        .expect("start scripts/qemu-run.sh");
    // From here on, a panic drops `process`, which kills QEMU.
    let mut process = Process { child, log };
    // QEMU creates UART1 and UART2's sockets only after a client took UART0 (wait mode).
    let uart0 = Aeolus::new(process.connect(ports.uart(0)));
    let uart1 = process.connect(ports.uart(1));
    let uart2 = process.connect(ports.uart(2));
    Some(Qemu {
        uart0,
        uart1,
        uart2,
        process,
        board,
        _turn: turn,
    })
}

impl Qemu {
    /// Where the firmware's log goes.
    pub fn log(&self) -> &Path {
        &self.process.log
    }

    /// Stops QEMU; the firmware's whole log.
    pub fn stop(self) -> String {
        if self.board == Board::Stm32f411 {
            // The STM32 log is copied out of the RTT buffer every 200 ms (scripts/rtt-gdb.py):
            // give the last lines one more poll before QEMU goes.
            std::thread::sleep(Duration::from_millis(500));
        }
        let log = self.process.log.clone();
        drop(self);
        std::fs::read_to_string(&log).unwrap_or_default()
    }
}

/// The stack high-water mark the firmware logged after its first boot (`booted: App N bytes,
/// stack high-water N bytes`), bytes.
pub fn boot_stack_high_water(log: &str) -> Option<usize> {
    let line = log.lines().find(|l| l.contains("booted: App"))?;
    let rest = line.split("stack high-water ").nth(1)?;
    rest.split_whitespace().next()?.parse().ok()
}

impl Process {
    /// Connects to `port`, retrying while QEMU starts (10 s at most).
    fn connect(&mut self, port: u16) -> TcpStream {
        let deadline = Instant::now() + Duration::from_secs(10);
        loop {
            match TcpStream::connect(("127.0.0.1", port)) {
                Ok(s) => {
                    s.set_nodelay(true).ok();
                    return s;
                }
                Err(e) => {
                    if let Ok(Some(status)) = self.child.try_wait() {
                        panic!(
                            "QEMU exited ({status}) before port {port} was up; log: {}",
                            self.log.display()
                        );
                    }
                    assert!(
                        Instant::now() < deadline,
                        "port {port} not up after 10 s ({e}); log: {}",
                        self.log.display()
                    );
                    std::thread::sleep(Duration::from_millis(50));
                }
            }
        }
    }
}

impl Drop for Process {
    fn drop(&mut self) {
        let group = format!("-{}", self.child.id());
        let _ = Command::new("kill").args(["-TERM", "--", &group]).status();
        let deadline = Instant::now() + Duration::from_secs(3);
        while Instant::now() < deadline {
            if let Ok(Some(_)) = self.child.try_wait() {
                return;
            }
            std::thread::sleep(Duration::from_millis(20));
        }
        let _ = Command::new("kill").args(["-KILL", "--", &group]).status();
        let _ = self.child.wait();
    }
}

// ------------------------------------------------------------------ AEOLUS reader

/// One frame received on UART0.
#[derive(Debug, Clone)]
pub struct Frame {
    /// Message ID.
    pub id: u8,
    /// Message data.
    pub data: Vec<u8>,
}

impl Frame {
    pub fn msg(&self) -> Option<Message<'_>> {
        Message::parse(self.id, &self.data).ok()
    }

    pub fn toast(&self) -> Option<String> {
        match self.msg()? {
            Message::Toast(t) => Some(String::from_utf8_lossy(t.as_bytes()).into_owned()),
            _ => None,
        }
    }

    /// The timestamp (ms since boot) of a telemetry message.
    pub fn timestamp(&self) -> Option<f64> {
        self.msg()?.timestamp_ms()
    }

    pub fn is_telemetry(&self) -> bool {
        TELEMETRY.iter().any(|t| t.id == self.id)
    }
}

/// The UART0 socket and everything decoded from it so far, with a strict decoder: a frame
/// without a CRC or with a wrong one is counted, never delivered.
#[derive(Default)]
pub struct Aeolus {
    stream: Option<TcpStream>,
    decoder: Decoder<{ aeolus_proto::MAX_FIXED_FRAME }>,
    /// Every frame received, in order.
    pub frames: Vec<Frame>,
    /// Every byte received.
    pub bytes: usize,
    /// Every byte sent (commands and raw bytes, once flushed).
    pub sent: usize,
    outgoing: Vec<u8>,
}

impl Aeolus {
    fn new(stream: TcpStream) -> Self {
        stream
            .set_read_timeout(Some(Duration::from_millis(20)))
            .expect("set a read timeout");
        Aeolus {
            stream: Some(stream),
            decoder: Decoder::strict(),
            ..Aeolus::default()
        }
    }

    /// Reads and decodes for `d`; returns the index of the first frame read.
    pub fn read_for(&mut self, d: Duration) -> usize {
        let first = self.frames.len();
        let deadline = Instant::now() + d;
        while Instant::now() < deadline {
            self.read_some();
        }
        first
    }

    /// Reads until a frame satisfying `want` arrives (within `timeout`); its index.
    pub fn read_until(&mut self, timeout: Duration, want: impl Fn(&Frame) -> bool) -> usize {
        let mut checked = self.frames.len();
        let deadline = Instant::now() + timeout;
        loop {
            if let Some(i) = self.frames[checked..].iter().position(&want) {
                return checked + i;
            }
            checked = self.frames.len();
            assert!(
                Instant::now() < deadline,
                "nothing wanted within {timeout:?}"
            );
            self.read_some();
        }
    }

    fn read_some(&mut self) {
        let mut buf = [0u8; 4096];
        let stream = self.stream.as_mut().expect("connected");
        match stream.read(&mut buf) {
            Ok(0) => panic!("QEMU closed UART0"),
            Ok(n) => {
                self.bytes += n;
                let frames = &mut self.frames;
                self.decoder.feed(&buf[..n], |event| {
                    if let Ok(f) = event {
                        frames.push(Frame {
                            id: f.id(),
                            data: f.data().to_vec(),
                        });
                    }
                });
            }
            Err(e) if matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut) => {}
            Err(e) => panic!("UART0: {e}"),
        }
    }

    /// Lands the box: "a pause", answered by TOAST "AEOLUS paused" (the box refuses a flash
    /// store in flight, `sensor_box::store_policy`).
    pub fn land(&mut self) {
        self.command("a pause");
        let ack = self.read_until(Duration::from_secs(2), |f| f.toast().is_some());
        assert_eq!(
            self.frames[ack].toast().as_deref(),
            Some("AEOLUS paused"),
            "the answer to \"a pause\""
        );
    }

    /// Sends a COMMAND.
    pub fn command(&mut self, text: &str) {
        self.queue_command(text);
        self.flush_commands();
    }

    /// Adds a COMMAND to what [`Aeolus::flush_commands`] sends in one write.
    pub fn queue_command(&mut self, text: &str) {
        let msg = Message::Command(Text::new(text).expect("short command"));
        let mut buf = vec![0u8; max_encoded_len(msg.buffer_len())];
        let n = msg.encode(&mut buf, CrcMode::Compute).expect("encode");
        self.outgoing.extend_from_slice(&buf[..n]);
    }

    /// Sends the queued COMMANDs in one write.
    pub fn flush_commands(&mut self) {
        let stream = self.stream.as_mut().expect("connected");
        stream.write_all(&self.outgoing).expect("send to UART0");
        self.sent += self.outgoing.len();
        self.outgoing.clear();
    }

    /// Queues raw bytes (garbage, a SETTIME) for [`Aeolus::flush_commands`].
    pub fn queue_raw(&mut self, bytes: &[u8]) {
        self.outgoing.extend_from_slice(bytes);
    }

    /// Closes the socket, so that another client (`protolink bridge`) can take UART0. QEMU
    /// drops what the UART sends while no client is connected.
    pub fn disconnect(&mut self) {
        self.stream = None;
    }

    /// The decoder's counters.
    pub fn stats(&self) -> aeolus_proto::Stats {
        self.decoder.stats()
    }
}

// ------------------------------------------------------------------ the periodic messages

/// The periodic messages and their spec intervals (figure 1c), ms.
pub struct Periodic {
    /// Message ID.
    pub id: u8,
    /// Name in the spec.
    pub name: &'static str,
    /// Spec interval, ms.
    pub interval_ms: f64,
}

pub const TELEMETRY: [Periodic; 10] = [
    Periodic {
        id: 62,
        name: "GYRO",
        interval_ms: 7.0,
    },
    Periodic {
        id: 63,
        name: "ACCEL",
        interval_ms: 7.0,
    },
    Periodic {
        id: 64,
        name: "MAGNET",
        interval_ms: 7.0,
    },
    Periodic {
        id: 71,
        name: "ATTITUDE",
        interval_ms: 7.0,
    },
    Periodic {
        id: 72,
        name: "COMPASS",
        interval_ms: 7.0,
    },
    Periodic {
        id: 61,
        name: "PRESSURE",
        interval_ms: 5.0,
    },
    Periodic {
        id: 66,
        name: "GPS",
        interval_ms: 92.0,
    },
    Periodic {
        id: 65,
        name: "TEMP",
        interval_ms: 829.0,
    },
    Periodic {
        id: 73,
        name: "WIND",
        interval_ms: 1000.0,
    },
    Periodic {
        id: 51,
        name: "AEOLUSINFO",
        interval_ms: 1000.0,
    },
];

// ------------------------------------------------------------------ protolink runs

/// The longest one `protolink` run may take before the test fails (never a hang).
pub const RUN_LIMIT: Duration = Duration::from_secs(30);

/// A turn at UDP 63093, ForeFlight's fixed discovery port, which `protolink gdl90 --discover`
/// binds on every interface: taken around such a run (an example of `protolink_help` and of
/// `readme_examples`, which may run at the same time), `None` for any other run. The turn is a
/// lock on one file in the temporary folder, held until the file is dropped, so that it holds
/// across processes too: host-tool's `gdl90` tests, which run beside these in CI, take the same
/// file's lock around their `--discover` runs.
pub fn discovery_port_turn<S: AsRef<str>>(args: &[S]) -> Option<std::fs::File> {
    args.iter()
        .any(|a| a.as_ref().starts_with("--discover"))
        .then(|| {
            let path = std::env::temp_dir().join("protolink-tests-udp-63093.lock");
            let file = std::fs::OpenOptions::new()
                .create(true)
                .truncate(false)
                .write(true)
                .open(&path)
                .expect("the discovery port's lock file");
            file.lock().expect("the discovery port's lock");
            file
        })
}

/// A `protolink` command whose state (`gdl90`'s ownship file, `$XDG_STATE_HOME`) stays in
/// `target/test-state`, never in the user's home.
pub fn protolink_command() -> Command {
    let mut c = Command::new(protolink());
    c.env("XDG_STATE_HOME", target_dir().join("test-state"));
    c
}

pub fn spawn_protolink<S: AsRef<std::ffi::OsStr>>(args: &[S]) -> Child {
    protolink_command()
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start protolink")
}

/// Waits for a run (killing it after [`RUN_LIMIT`]), reading its pipes meanwhile.
pub fn finish(mut child: Child) -> Output {
    let mut out = child.stdout.take().expect("stdout");
    let mut err = child.stderr.take().expect("stderr");
    let out = std::thread::spawn(move || {
        let mut v = Vec::new();
        let _ = out.read_to_end(&mut v);
        v
    });
    let err = std::thread::spawn(move || {
        let mut v = Vec::new();
        let _ = err.read_to_end(&mut v);
        v
    });
    let started = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().expect("wait") {
            break s;
        }
        if started.elapsed() > RUN_LIMIT {
            let _ = child.kill();
            let _ = child.wait();
            panic!("protolink ran longer than {RUN_LIMIT:?}");
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    Output {
        status,
        stdout: out.join().expect("stdout reader"),
        stderr: err.join().expect("stderr reader"),
    }
}

// ------------------------------------------------------------------ AYDP and AOK helpers

/// Sends one AYDP message (profile `Spec`, expedited) on UART1.
pub fn aydp_send(port: &mut TcpStream, msg: &aydp_proto::Message<'_>) {
    let mut buf = [0u8; 128];
    let n = aydp_proto::Encoder::new(aydp_proto::Profile::Spec)
        .encode(msg, None, &mut buf)
        .expect("encode");
    port.write_all(&buf[..n]).expect("write UART1");
}

/// Reads UART1 until a system value update for `address` arrives; returns its data.
pub fn aydp_read_value(port: &mut TcpStream, address: u16, timeout: Duration) -> Option<Vec<u8>> {
    let mut d = aydp_proto::Decoder::<256>::new(aydp_proto::Profile::Spec);
    let end = Instant::now() + timeout;
    port.set_read_timeout(Some(Duration::from_millis(50)))
        .ok()?;
    let mut buf = [0u8; 512];
    while Instant::now() < end {
        let n = match port.read(&mut buf) {
            Ok(0) => return None,
            Ok(n) => n,
            Err(e) if matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut) => continue,
            Err(e) => panic!("UART1: {e}"),
        };
        let mut found = None;
        d.feed(&buf[..n], |ev| {
            if let Ok(Ok(aydp_proto::Message::SystemValueUpdate(u))) = ev.map(|f| f.message())
                && u.address == address
            {
                found = Some(u.data.to_vec());
            }
        });
        if found.is_some() {
            return found;
        }
    }
    None
}

/// Requests the value at `address` on UART1 and waits up to 3 s for it.
pub fn request(port: &mut TcpStream, address: u16) -> Option<Vec<u8>> {
    let req =
        aydp_proto::Message::SystemControl(aydp_proto::SystemControl::RequestData { address });
    aydp_send(port, &req);
    aydp_read_value(port, address, Duration::from_secs(3))
}

/// AYDP's simulated airspeed (0x0110, f32): the setting the store tests change.
pub const AIRSPEED: u16 = 0x0110;

/// Sets the airspeed to `mps` over UART1 (from a different value), reads it back, lands the box
/// (a store is refused in flight) and sends "store configuration", then leaves the box 300 ms
/// to write its flash. `log` names the firmware log in the failure messages.
pub fn store_airspeed(q: &mut Qemu, mps: f32, log: &str) {
    let value = mps.to_le_bytes();
    let before = request(&mut q.uart1, AIRSPEED).expect("the airspeed readable");
    assert_ne!(
        before, value,
        "the airspeed is not already {mps}; log: {log}"
    );
    let set = aydp_proto::Message::SystemValueUpdate(aydp_proto::SystemValueUpdate {
        address: AIRSPEED,
        mode: aydp_proto::UpdateMode::Single,
        data: &value,
    });
    aydp_send(&mut q.uart1, &set);
    assert_eq!(
        request(&mut q.uart1, AIRSPEED).as_deref(),
        Some(&value[..]),
        "the airspeed read back; log: {log}"
    );
    q.uart0.land();
    aydp_send(
        &mut q.uart1,
        &aydp_proto::Message::SystemControl(aydp_proto::SystemControl::StoreConfiguration),
    );
    std::thread::sleep(Duration::from_millis(300));
}

/// The AOK client's settings against an emulated box. The defaults (a reply within 1 s, a
/// partial frame abandoned after a 50 ms gap) suit a real board; QEMU is a host process, and
/// under the parallel test load it can stall for longer mid-reply, so the client waits 10 s
/// for a reply and 500 ms inside one.
pub fn emulated_aok_config() -> aok_proto::Config {
    aok_proto::Config {
        timeout_ms: 10_000,
        quiet_ms: 500,
        ..aok_proto::Config::new(aok_proto::FirmwareVersion::new(0, 35))
    }
}

/// An AOK request to an emulated box, sent once more if the box did not answer. The box obeys
/// a command only when its bytes come as one burst (`sensor_box::aok_link::GAP_MS`), and the
/// STM32's emulated USART takes one byte at a time from QEMU: under the parallel test load
/// QEMU can hand the bytes of one write over further apart than that, and the box rightly
/// drops the command (the lm3s6965's 16-byte FIFO takes the same write whole). The requests sent this way set or
/// read a value, so the second one asks the same; a box that never answers fails both.
pub fn aok_once_more<T>(
    mut request: impl FnMut() -> Result<T, aok_proto::ClientError>,
) -> Result<T, aok_proto::ClientError> {
    match request() {
        Err(aok_proto::ClientError::Timeout) => request(),
        other => other,
    }
}

/// A TCP socket as an `embedded-hal-nb` serial port, for `aok_proto::Client`.
///
/// The bytes the client writes are held until it flushes at the end of a frame and go out in
/// one `write`, as a PC's serial driver sends them: a frame written a byte at a time reaches
/// QEMU in pieces that a loaded host may deliver to the guest more than the box's
/// `sensor_box::aok_link::GAP_MS` apart, and the box rightly drops a frame so split.
pub struct NbSerial {
    stream: TcpStream,
    out: Vec<u8>,
}

impl NbSerial {
    /// The client's side of `stream` (set it non-blocking first).
    pub fn new(stream: TcpStream) -> Self {
        NbSerial {
            stream,
            out: Vec::new(),
        }
    }
}

impl embedded_hal_nb::serial::ErrorType for NbSerial {
    type Error = core::convert::Infallible;
}

impl embedded_hal_nb::serial::Read<u8> for NbSerial {
    fn read(&mut self) -> nb::Result<u8, Self::Error> {
        let mut b = [0u8; 1];
        match self.stream.read(&mut b) {
            Ok(1) => Ok(b[0]),
            _ => Err(nb::Error::WouldBlock),
        }
    }
}

impl embedded_hal_nb::serial::Write<u8> for NbSerial {
    fn write(&mut self, word: u8) -> nb::Result<(), Self::Error> {
        self.out.push(word);
        Ok(())
    }
    fn flush(&mut self) -> nb::Result<(), Self::Error> {
        if !self.out.is_empty() {
            write_all_nonblocking(&mut self.stream, &self.out);
            self.out.clear();
        }
        Ok(())
    }
}

/// All of `bytes` into a non-blocking socket, waiting out `WouldBlock`.
fn write_all_nonblocking(stream: &mut TcpStream, mut bytes: &[u8]) {
    while !bytes.is_empty() {
        match stream.write(bytes) {
            Ok(0) => panic!("UART socket closed"),
            Ok(n) => bytes = bytes.get(n..).unwrap_or(&[]),
            Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => {
                std::thread::sleep(Duration::from_millis(1));
            }
            Err(e) => panic!("write to the UART socket: {e}"),
        }
    }
}
