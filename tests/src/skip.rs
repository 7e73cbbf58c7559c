//! Skipping a test because a tool it needs is missing, never silently.
//!
//! Under CI (`CI=true`, as `.ci/run` runs) a skip fails the test: CI installs every tool, so
//! a missing one is a broken set-up, not a reason to pass. Outside CI the test returns early
//! after saying why on standard error, and adds a line to `target/test-logs/skipped.log`,
//! which `scripts/test.sh` counts and shows on its own line of the summary, so a green run
//! never hides a suite that did not run.

use std::io::Write;
use std::path::{Path, PathBuf};

/// The file `scripts/test.sh` reads: one line per skipped test, `file::test: reason` (the
/// test's file's module in its crate's `tests/all/` binary, then the test's own name).
pub fn log_path() -> PathBuf {
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../target"));
    let target = if target.is_relative() {
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("..")
            .join(target)
    } else {
        target
    };
    target.join("test-logs/skipped.log")
}

/// Whether this run is CI's (`CI=true`).
pub fn under_ci() -> bool {
    std::env::var("CI").as_deref() == Ok("true")
}

/// Records that the calling test is skipped for `reason` (a sentence naming what is missing
/// and how to install it); under CI, fails the test with that reason instead.
///
/// The caller returns at once after this.
pub fn skip(reason: &str) {
    // `file::test`: in a crate's one integration-test binary (`tests/all/`), the test's own
    // name, which begins with its file's module (`qemu_firmware::aok_parameter_and_waypoint::
    // lm3s6965evb`); in any other binary, the binary's name without cargo's hash, then the
    // test's.
    let binary = std::env::current_exe()
        .ok()
        .and_then(|p| p.file_stem().map(|s| s.to_string_lossy().into_owned()))
        .map(|s| {
            s.rsplit_once('-')
                .map_or(s.clone(), |(name, _)| name.to_owned())
        })
        .unwrap_or_default();
    let name = std::thread::current()
        .name()
        .unwrap_or("an unnamed test")
        .to_owned();
    let test = if binary == "all" {
        name
    } else {
        format!("{binary}::{name}")
    };
    assert!(
        !under_ci(),
        "{test} cannot run under CI (CI=true), where every skip fails: {reason}"
    );
    eprintln!("SKIPPED: {test}: {reason}");
    let path = log_path();
    let recorded = path
        .parent()
        .map_or(Ok(()), std::fs::create_dir_all)
        .and_then(|()| {
            std::fs::OpenOptions::new()
                .create(true)
                .append(true)
                .open(&path)
        })
        // One write of the whole line: the tests of a binary run in parallel, and `writeln!`
        // writes a line in pieces, which two tests skipping at once interleaved.
        .and_then(|mut f| f.write_all(format!("{test}: {reason}\n").as_bytes()));
    if let Err(e) = recorded {
        eprintln!(
            "(the skip could not be recorded in {}: {e})",
            path.display()
        );
    }
}
