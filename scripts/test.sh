#!/usr/bin/env bash
# Runs every test and check of the project. This is the command the README
# gives and the one .ci/run calls.
#
# The steps run in order, except the host tests (the test binaries, the Python tests and
# Miri), which run in the background from the firmware step's end, beside the steps that
# follow it (those at nice 10), up to the fuzz smoke run. Each step prints how long it took.
# The run ends with one summary: the time of every step and of the background's parts, the
# QEMU tests run, the fuzz executions and crashes, and as the very last line
# `tests: N passed, M failed, K skipped` (the sums of every `cargo test` "test result:" line
# and of pytest's last line for the Python package, less the tests that skipped for a missing
# tool, counted apart), which CI reads. Under CI=true a missing tool fails its tests instead of
# skipping them. The summary is printed on failure too (after the background's tests end),
# and the exit status is then the failing step's. The outputs it is computed from are kept in
# target/test-logs/.
set -euo pipefail
cd "$(dirname "$0")/.."

# frame-io: the embedded-io readers and writers the three protocol crates share.
LIBS=(frame-io aeolus-proto aydp-proto aok-proto)
logs=target/test-logs
mkdir -p "$logs"
test_log=$logs/cargo-test.log
fuzz_log=$logs/fuzz.log
# pytest's output of the Python package's tests (scripts/test-python.sh): its last line's counts
# go into the summary beside cargo's.
py_log=$logs/python.log
# One line per test that returned early because a tool was missing (tests/src/skip.rs writes
# it; under CI=true such a test fails instead). Cargo counts those tests as passed: the
# summary takes them out and shows them on a line of their own.
skip_log=$logs/skipped.log
: >"$test_log"
: >"$fuzz_log"
: >"$py_log"
: >"$skip_log"
# CI builds everything once on a fresh clone, so incremental state is dead weight there, and the
# debug builds keep line tables only (backtraces still name file and line). On a fresh clone a
# whole CI run left target/ at 4.7 GB (debug/ 3.0 GB) with these settings and the removals
# below, 9.0 GB (debug/ 6.6 GB) without them. The per-byte check's x86 build goes under target/
# and is removed after the check. Locally nothing changes, so a run of this script does not make
# the next `cargo test` rebuild the workspace.
if [ "${CI:-}" = true ]; then
  export CARGO_INCREMENTAL=0 CARGO_PROFILE_DEV_DEBUG=line-tables-only CARGO_PROFILE_TEST_DEBUG=line-tables-only
  export BENCH_TARGET_DIR="$PWD/target/bench-check"
fi
# The teed steps keep cargo's colours on a terminal (the summary strips them).
[ -t 1 ] && [ -z "${CARGO_TERM_COLOR:-}" ] && export CARGO_TERM_COLOR=always

now_ms() { date +%s%3N; }
secs() { awk -v ms="$1" 'BEGIN { s = ms / 1000; if (s < 60) printf "%.1f s", s; else printf "%d min %02d s", s / 60, s % 60 }'; }
run_start=$(now_ms)
free_space() {
  echo "$(df -h --output=avail target 2>/dev/null | tail -n 1 | tr -d ' ') free for target/, $(df -h --output=avail "${TMPDIR:-/tmp}" 2>/dev/null | tail -n 1 | tr -d ' ') for ${TMPDIR:-/tmp}"
}
mkdir -p target
echo "free space at the start: $(free_space)"
current=""
step_start=0
timings=()
end_step() {
  [ -n "$current" ] || return 0
  local d=$(($(now_ms) - step_start))
  printf -- '--> %s: %s\n' "$current" "$(secs "$d")"
  local short=${current%%:*}
  timings+=("$(printf '%12s  %s' "$(secs "$d")" "${short%% (*}")")
  current=""
}
step() {
  end_step
  current=$1
  step_start=$(now_ms)
  printf '\n==> %s\n' "$*"
}

# The logs without the colour escapes that cargo and pytest write on a terminal.
plain() { sed 's/\x1b\[[0-9;]*[A-Za-z]//g' "$@"; }

# From pytest's last summary line ("3 failed, 150 passed, 2 skipped in 9.1s"), the number before
# WORD (errors count as failed); a SKIPPED line of scripts/test-python.sh counts as one skipped.
pytest_count() {
  plain "$py_log" | awk -v word="$1" '
    /^SKIPPED python\/tests/ { skip = 1 }
    /^(=+ )?[0-9]+ [a-z]+[ ,]/ && / in [0-9.]+s/ { line = $0 }
    END {
      n = 0
      k = split(line, f, /[ ,=]+/)
      for (i = 2; i <= k; i++) {
        if (f[i] ~ "^" word || (word == "failed" && f[i] ~ /^errors?$/)) n += f[i - 1]
      }
      if (word == "skipped") n += skip
      print n + 0
    }'
}

# Sums, over every "test result:" line of the cargo test output, the number before WORD
# (passed, failed).
count() {
  plain "$test_log" | awk -v word="$1" '
    /^test result:/ { for (i = 2; i <= NF; i++) if ($i ~ "^" word) n += $(i - 1) }
    END { print n + 0 }'
}

# After a failure, what CI shows of the run is its end: the failed tests by name (at most 20,
# from the cargo and pytest logs) and the first error lines of the logs; the summary then gives
# the free space where builds and temporary files go. (A CI run once failed 407 tests of the
# host step, exactly as many as six crates have doc tests, and its end named none of them.)
failures() {
  local names errors
  names=$(plain "$test_log" "$py_log" |
    grep -E '^test .* \.\.\. FAILED$|^FAILED python/' | sed -E 's/^test (.*) \.\.\. FAILED$/\1/' || true)
  if [ -n "$names" ]; then
    echo "failed tests ($(grep -c . <<<"$names"); the first 20):"
    head -n 20 <<<"$names" | sed 's/^/  /'
  fi
  errors=$(plain "$test_log" "$py_log" |
    grep -E '^error(\[E[0-9]+\])?:|No space left|Too many open files|Cannot allocate memory|Permission denied' |
    awk '!seen[$0]++' | head -n 8 || true)
  if [ -n "$errors" ]; then
    echo "first distinct error lines of the logs:"
    sed 's/^/  /' <<<"$errors"
  fi
}

# The modules of protolink-tests (tests/tests/all/) whose tests boot the firmware in QEMU.
qemu_modules='box_clock|capture_qemu|gdl90_qemu|nmea_qemu|noise_qemu|protolink_e2e|protolink_help|qemu_firmware|readme_examples|realtime_flood|soak|watchdog_qemu|web_qemu'

summary() {
  local status=$? failed_step=$current
  trap - EXIT
  set +e
  end_step
  # The host tests still running in the background: their results count, unless the run was
  # interrupted (then they are stopped with their emulators).
  if [ -n "${host_pid:-}" ]; then
    if [ "$status" -gt 128 ]; then
      kill -TERM -- "-$host_pid" 2>/dev/null
      host_pid=""
    else
      echo "(waiting for the host tests in the background)"
      join_host_tests >/dev/null
    fi
  fi
  local passed failed qemu qemu_skipped skipped fuzz_targets fuzz_execs fuzz_crashes
  skipped=$(grep -c . "$skip_log" || true)
  qemu_skipped=$(grep -cE "^($qemu_modules)::" "$skip_log" || true)
  passed=$(($(count passed) - skipped + $(pytest_count passed)))
  failed=$(($(count failed) + $(pytest_count failed)))
  qemu=$(($(plain "$test_log" | grep -cE "^test ($qemu_modules)::[^ ]* \.\.\. ok$" || true) - qemu_skipped))
  # fuzz.sh's table: "target executions crashes", one line per target.
  read -r fuzz_targets fuzz_execs fuzz_crashes < <(awk '
    $1 == "target" && $2 == "executions" { t = 1; next }
    t && NF == 3 && $3 ~ /^[0-9]+$/ { n++; c += $3; if ($2 ~ /^[0-9]+$/) e += $2; else u++ }
    END { printf "%d %d%s %d\n", n, e, (u ? "+" : ""), c }' "$fuzz_log")
  printf '\n==> summary (%s in all)\n' "$(secs $(($(now_ms) - run_start)))"
  printf '%s\n' "${timings[@]}"
  echo "QEMU tests run: $qemu passed, $qemu_skipped skipped (the modules ${qemu_modules//|/, } of tests/tests/all/)"
  if [ "$skipped" -gt 0 ]; then
    echo "SKIPPED: $skipped tests did not run, for a missing tool ($skip_log):"
    sed 's/^/  /' "$skip_log"
  fi
  echo "Python tests (python/tests, $py_log): $(pytest_count passed) passed, $(pytest_count failed) failed, $(pytest_count skipped) skipped"
  grep '^SKIPPED python/tests' "$py_log" || true
  skipped=$((skipped + $(pytest_count skipped)))
  if [ "$fuzz_targets" -gt 0 ]; then
    echo "fuzz: $fuzz_execs executions over $fuzz_targets targets, $fuzz_crashes crashes"
  else
    echo "fuzz: not run"
  fi
  if [ "$status" != 0 ]; then
    echo "FAILED: step '$failed_step' (exit status $status)"
    failures
  fi
  echo "free space at the end: $(free_space)"
  echo "tests: $passed passed, $failed failed, $skipped skipped"
  exit "$status"
}
trap summary EXIT

# The tools of the later steps install in the background from here, beside the steps up to the
# firmware's, which need only the toolchains (.ci/run installs them first) and python3: on a
# fresh machine the installs wait on the network and dpkg, and compile the crates.io tools.
# The host tests wait for them (join_setup).
setup_log=$logs/setup.log
setup_components=(qemu defmt-print tshark chromium i686 c bench python gpsd fuzz)
[ "${CI:-}" = true ] && setup_components+=(mutants)
step "setup, in the background: qemu-system-arm, defmt-print, tshark, chromium, i686, the C tools, valgrind, python3 with pynmea2, maturin, pytest, hypothesis, pandas and pymavlink, gpsd with gpspipe, cargo-fuzz, and in CI cargo-mutants (the QEMU, tshark, browser, 32-bit, C, callgrind, NMEA, Python, gpsd and fuzz checks must run, never skip, in CI)"
if command -v python3 >/dev/null; then
  setup_start=$(now_ms)
  rm -f "$logs/setup.end"
  { status=0; bash scripts/setup.sh "${setup_components[@]}" >"$setup_log" 2>&1 || status=$?
    now_ms >"$logs/setup.end"; exit "$status"; } &
  setup_pid=$!
else
  # This script's own helpers need python3: all of the setup first.
  bash scripts/setup.sh "${setup_components[@]}"
fi
# Waits for the background setup; its output, and a failure, end the run.
join_setup() {
  [ -n "${setup_pid:-}" ] || return 0
  local status=0 end
  wait "$setup_pid" || status=$?
  setup_pid=""
  end=$(cat "$logs/setup.end" 2>/dev/null || now_ms)
  timings+=("$(printf '%12s  %s' "$(secs $((end - setup_start)))" "setup, in the background from the start")")
  if [ "$status" != 0 ]; then
    cat "$setup_log"
    echo "FAILED: scripts/setup.sh ${setup_components[*]} (exit status $status; $setup_log)"
    return "$status"
  fi
}

step "docs: every relative path named in Markdown or a doc comment exists (scripts/check-paths.py)"
python3 scripts/check-paths.py

step "docs: no stale name of a removed type or method outside the CHANGELOGs (scripts/check-words.py)"
python3 scripts/check-words.py

step "surface: at most 200 public items in each protocol crate (scripts/surface.py)"
python3 scripts/surface.py

step "format"
cargo fmt --all -- --check
(cd firmware-embassy && cargo fmt -- --check)

step "clippy (all targets, warnings denied)"
cargo clippy --workspace --all-targets --all-features -- -D warnings
# The host tool's library as other crates take it (host-tool/README.md, "Features"): with no
# feature at all, and with the Python extension's (python/Cargo.toml). The full build above
# never sees these sets; a check (no code generated) proves they compile.
cargo clippy -q -p protolink --no-default-features --lib -- -D warnings
cargo clippy -q -p protolink-python -- -D warnings

# Every test binary (one per crate), the `protolink` binary that the C library's checks, the
# Python tests and the QEMU harness run ($PROTOLINK) and the Python extension
# ($PROTOLINK_PYTHON_SO): the host tool and its dependencies are compiled once, here. What
# `cargo test --no-run` builds (libraries, binaries, tests, examples, the `test` profile), plus
# the libraries as such, among them the extension. Every feature but those that turn on defmt
# (scripts/test-features.py says why); PYO3_BUILD_EXTENSION_MODULE as maturin sets it (the
# extension does not link libpython).
step "test build: every crate's tests, the protolink binary and the Python extension (cargo build --profile test)"
test_build=$logs/test-build.json
test_features=$(python3 scripts/test-features.py)
PYO3_BUILD_EXTENSION_MODULE=1 cargo build -q --profile test --workspace --features "$test_features" \
  --lib --bins --tests --examples --message-format=json-render-diagnostics >"$test_build"
export PROTOLINK="$PWD/${CARGO_TARGET_DIR:-target}/debug/protolink"
export PROTOLINK_PYTHON_SO="$PWD/${CARGO_TARGET_DIR:-target}/debug/libprotolink_python.so"

step "firmware: sensor-box and the boards: release builds for both boards (and the simulated STM32, and the async firmware's QEMU board), clippy on thumb"
# The box's behaviour on its own, as each board builds it (no features, defmt + the hardware name).
for t in thumbv7m-none-eabi thumbv7em-none-eabihf; do
  cargo build -q -p sensor-box --target "$t" --release
  cargo build -q -p sensor-box --target "$t" --release --features defmt,hardware-stm32f411
  cargo clippy -q -p sensor-box --release --target "$t" --features defmt -- -D warnings
done
cargo qemu-build -q
cargo stm32-build -q
cargo clippy -q -p firmware-example --release --target thumbv7m-none-eabi --features board-qemu --lib --bins -- -D warnings
cargo clippy -q -p firmware-example --release --target thumbv7em-none-eabihf --features board-stm32f411 --lib --bins -- -D warnings
# The STM32 board in QEMU netduinoplus2 (the QEMU tests boot it); built last, so this is the
# ELF at target/thumbv7em-none-eabihf/release/sensor-box when the tests run.
cargo clippy -q -p firmware-example --release --target thumbv7em-none-eabihf --features qemu-stm32 --lib --bins -- -D warnings
cargo stm32-qemu-build -q
# The async firmware's QEMU board (firmware-embassy, its own workspace; the QEMU tests boot it
# as their third board): built into target/embassy, where the harness builds it too, and its
# clippy with the test-only fault-hang (the watchdog test's build) and with cpu-budget as well.
(cd firmware-embassy && export CARGO_TARGET_DIR=../target/embassy &&
  cargo qemu-build -q &&
  cargo clippy -q --release --target thumbv7m-none-eabi --no-default-features --features board-qemu,fault-hang -- -D warnings &&
  cargo clippy -q --release --target thumbv7m-none-eabi --no-default-features --features cpu-budget -- -D warnings)

# The executables of the test build run as cargo would run them (in their package's directory,
# a `Running` line first), but by this script: a second `cargo test` over part of the workspace
# would resolve other features for shared dependencies and compile them again
# (scripts/test-binaries.py). Every binary runs whatever fails (the summary counts every
# failure).
run_binaries() { # LIST LOG [ARGS]: each "dir<TAB>exe<TAB>label" line of LIST run with ARGS, output
  # to LOG; status 1 if one failed
  local list=$1 log=$2 dir exe label status=0
  shift 2
  while IFS=$'\t' read -r dir exe label; do
    printf '     Running %s (%s)\n' "$label" "$exe"
    (cd "$dir" && "$exe" "$@") || status=1
  done <"$list" >>"$log" 2>&1
  return "$status"
}

# The host tests run in the background from here, beside the steps up to the fuzz build, in
# two lanes: the QEMU tests (modules of protolink-tests' binary, QEMU_JOBS emulators at a time,
# four test threads), which mostly wait for the emulated box, then Miri over the C library; and
# the other crates' binaries, then the Python tests, which mostly compute or wait on their own
# links. They need the firmware ELFs of the step above (no step below writes them) and the
# test build. The steps below, and Miri, run at a lower priority (nice 10), so that the
# emulated boxes and the tests' timing get the cores first and the builds take what is left.
# Their output goes to $host_log ($py_log, $miri_log); "host tests" below waits for them and
# shows it.
host_log=$logs/host-tests.log
qemu_log=$logs/protolink-tests.log
miri_log=$logs/miri.log
host_times=$logs/host-tests.times
host_part() { # NAME COMMAND...: runs COMMAND, appends "ms<TAB>NAME" to $host_times
  local name=$1 t0 status=0
  shift
  t0=$(now_ms)
  "$@" || status=$?
  printf '%s\t%s\n' "$(($(now_ms) - t0))" "$name" >>"$host_times"
  return "$status"
}
# The QEMU lane: the QEMU tests, then (at nice 10, as the other lane) Miri over the C library's
# tests, every unsafe block they reach (its own target directory, target/miri): the QEMU tests
# mostly wait for the emulated boxes, and the other lane's Python tests are as long. What
# failed goes to $logs/qemu-lane.failed, a line each.
qemu_lane() {
  local status=0
  : >"$logs/qemu-lane.failed"
  host_part "QEMU tests (protolink-tests)" run_binaries "$logs/binaries-qemu.txt" "$qemu_log" --test-threads=4 ||
    { echo "protolink-tests" >>"$logs/qemu-lane.failed"; status=1; }
  renice -n 10 -p "$BASHPID" >/dev/null
  host_part "Miri (protolink-c's tests)" cargo +nightly miri test -q -p protolink-c >"$miri_log" 2>&1 ||
    { echo "Miri over protolink-c ($miri_log)" >>"$logs/qemu-lane.failed"; status=1; }
  return "$status"
}
host_tests() {
  local failed=() qemu_pid
  python3 scripts/test-binaries.py "$test_build" --only protolink-tests >"$logs/binaries-qemu.txt"
  python3 scripts/test-binaries.py "$test_build" --except protolink-tests >"$logs/binaries-rest.txt"
  qemu_lane &
  qemu_pid=$!
  # The rest of this lane at nice 10, as the foreground's later steps: the emulated boards run
  # in real time (their UART gaps, their sensors' freshness), so on two cores the QEMU lane
  # started above keeps nice 0 and is not starved by the other tests.
  renice -n 10 -p "$BASHPID" >/dev/null
  host_part "the other crates' test binaries" run_binaries "$logs/binaries-rest.txt" "$host_log" ||
    failed+=("the other crates' test binaries")
  # The Python package (python/): python/protolink with the test build's extension
  # (target/py-pkg), its pytest and hypothesis tests against `protolink decode --json` in a
  # venv (scripts/test-python.sh runs this alone; with --wheel it builds the wheel as the
  # README does): the package equals protolink decode field for field, round trips, random
  # bytes, to_frames, python -m protolink decode, live links.
  host_part "python (pytest python/tests)" scripts/test-python.sh >"$py_log" 2>&1 ||
    failed+=("the Python tests ($py_log)")
  wait "$qemu_pid" || mapfile -t -O "${#failed[@]}" failed <"$logs/qemu-lane.failed"
  cat "$qemu_log" >>"$host_log"
  now_ms >"$logs/host-tests.end"
  printf '%s\n' "${failed[@]}" >"$logs/host-tests.failed"
  [ ${#failed[@]} -eq 0 ]
}
step "waiting for the setup (in the background since the start)"
join_setup
: >"$host_log"
: >"$qemu_log"
: >"$miri_log"
: >"$host_times"
rm -f "$logs/host-tests.end" "$logs/host-tests.failed"
host_start=$(now_ms)
# Its own process group (job control on for the `&`), so that an interrupted run can stop it
# with the emulators it started.
set -m
host_tests &
host_pid=$!
set +m
# Waits for the background host tests, adds their output to $test_log and their times to the
# summary, shows their results; status 1 when one of them failed.
join_host_tests() {
  [ -n "${host_pid:-}" ] || return 0
  local status=0 end ms name
  wait "$host_pid" || status=$?
  host_pid=""
  cat "$host_log" >>"$test_log"
  end=$(cat "$logs/host-tests.end" 2>/dev/null || now_ms)
  timings+=("$(printf '%12s  %s' "$(secs $((end - host_start)))" "host tests, in the background from the firmware step's end (its parts below)")")
  while IFS=$'\t' read -r ms name; do
    timings+=("$(printf '%12s    %s' "$(secs "$ms")" "$name")")
  done <"$host_times"
  plain "$host_log" | grep -E '^test result:|^     Running|FAILED|panicked' | tail -n 60
  echo "python: $(plain "$py_log" | tail -n 1)"
  echo "Miri: $(plain "$miri_log" | grep -E '^test result:' | tail -n 1)"
  if [ "$status" != 0 ]; then
    echo "FAILED: $(paste -sd ';' "$logs/host-tests.failed" 2>/dev/null) ($host_log)"
    return 1
  fi
}
echo
echo "==> host tests started in the background (protolink-tests with QEMU_JOBS=${QEMU_JOBS:-2} emulators at a time, then Miri; beside them the other crates' tests, then the Python tests; $host_log)"
renice -n 10 -p $$ >/dev/null || echo "renice: the steps below run at the host tests' priority"

# A build of the libraries for thumb proves nothing a check does not: panic-never, footprint, the C
# library and the firmware build them for thumb below. Only thumbv6m is checked here, the
# strictest (no compare-and-swap, no unaligned access): the firmware step above has already built
# them for thumbv7m and thumbv7em, with defmt and with embedded-io-async (sensor-box's defmt
# builds, both boards, the async firmware's QEMU board), and the C library builds them for both.
step "thumb check: the libraries for thumbv6m (no features; defmt, embedded-io + embedded-io-async)"
thumbs=(--target thumbv6m-none-eabi)
lib_args=()
for l in "${LIBS[@]}"; do lib_args+=(-p "$l"); done
cargo check -q "${thumbs[@]}" "${lib_args[@]}" -p gdl90-proto
with=$(for l in "${LIBS[@]}"; do printf '%s/defmt,%s/embedded-io,%s/embedded-io-async,' "$l" "$l" "$l"; done)
# gdl90-proto has no embedded-io features yet: defmt only.
cargo check -q "${thumbs[@]}" "${lib_args[@]}" -p gdl90-proto --features "${with}gdl90-proto/defmt"

MSRV=$(sed -n 's/^rust-version = "\(.*\)"/\1/p' aeolus-proto/Cargo.toml)
step "MSRV: the libraries with Rust $MSRV exactly (host check with all features and with none, thumbv6m check)"
cargo +"$MSRV" check -q "${lib_args[@]}" -p gdl90-proto --all-features
cargo +"$MSRV" check -q "${lib_args[@]}" -p gdl90-proto --no-default-features
msrv_with=$(for l in "${LIBS[@]}"; do printf '%s/embedded-io,%s/embedded-io-async,' "$l" "$l"; done)
cargo +"$MSRV" check -q "${lib_args[@]}" -p gdl90-proto --target thumbv6m-none-eabi --features "${msrv_with%,}"

step "publish dry run: every library packages and builds as crates.io would see it"
# gdl90-proto depends on aeolus-proto, and the three protocol crates on frame-io, which are not
# on crates.io: cargo resolves them from the packages of this same run (cargo >= 1.90 packages
# workspace members together). Cargo extracts those packages under registry/src/-<hash>/ and
# reuses an extraction of the same name and version on the next run, even when the package has
# changed since (seen: gdl90-proto verified against an aeolus-proto of an earlier run, without
# a field added since): the extractions of this workspace's own crates go first.
for c in frame-io aeolus-proto aydp-proto aok-proto gdl90-proto; do
  rm -rf "${CARGO_HOME:-$HOME/.cargo}"/registry/src/-*/"$c"-0.1.0
done
# The same for the verify builds, which go to the target directory: cargo takes a registry
# package as never changing, so an rlib of an earlier run's aeolus-proto 0.1.0 is reused when the
# profile matches (seen: gdl90-proto verified against an aeolus-proto without EncodeError). They
# get a target directory of their own, emptied first.
rm -rf target/package target/publish-check
CARGO_TARGET_DIR=target/publish-check cargo publish --dry-run -q --allow-dirty -p frame-io -p aeolus-proto -p aydp-proto -p aok-proto -p gdl90-proto
rm -rf target/publish-check

step "panic-never: link-time proof that no panic path survives (checks/panic-never, thumbv7m and thumbv6m)"
if ! (cd checks/panic-never && cargo build -q --release && cargo build -q --release --target thumbv6m-none-eabi); then
  echo "FAILED panic-never check: a panic path is reachable from a decoder, typed parse or encoder."
  echo "The link error names the undefined symbol PANIC_PATH_REACHABLE_see_checks_panic_never;"
  echo "see checks/panic-never/src/main.rs for what it exercises."
  exit 1
fi

# The C library (c-api/): one archive for C firmware, its cbindgen header, and its tests.
step "C library: libprotolink_c.a for thumbv6m, thumbv7m, thumbv7em; header drift; host C test (ASan+UBSan) against protolink; C firmware in QEMU; C panic-never link (thumbv7m, thumbv6m); Miri runs with the host tests"
for t in thumbv6m-none-eabi thumbv7m-none-eabi thumbv7em-none-eabihf; do
  cargo build -q -p protolink-c --release --target "$t"
done
RUSTC_BOOTSTRAP=1 cbindgen -q --config c-api/cbindgen.toml --crate protolink-c --output target/protolink.h.fresh
if ! diff -u c-api/include/protolink.h target/protolink.h.fresh; then
  echo "FAILED: c-api/include/protolink.h differs from what cbindgen generates from c-api/src."
  echo "Regenerate it: RUSTC_BOOTSTRAP=1 cbindgen --config c-api/cbindgen.toml --crate protolink-c --output c-api/include/protolink.h"
  exit 1
fi
bash c-api/tests/host.sh
bash c-api/tests/firmware.sh

step "footprint binaries build for thumbv7m and thumbv6m (the figures: python3 scripts/footprint.py)"
(cd checks/footprint && for t in thumbv7m-none-eabi thumbv6m-none-eabi; do
  cargo build -q --release --target "$t" \
    --features aeolus-decode,aeolus-encode,aydp-decode,aydp-encode,aok-decode,aok-encode,aeolus-read,aydp-read,aok-read
done)

# The Cortex-M3 instruction counts are exact (QEMU -icount), so they can guard themselves: a
# per-byte figure more than 3 % above docs/BENCHMARKS.md's published table fails the run.
step "per-byte regression check: the x86-64 (callgrind) and Cortex-M3 (-icount) counts against the published tables (scripts/bench-check.py)"
python3 scripts/bench-check.py
# CI: the two builds it measured (about 0.4 GB and more) are not used again.
if [ "${CI:-}" = true ]; then rm -rf "$BENCH_TARGET_DIR" checks/cm3-bench/target; fi

# Its own workspace (embassy-stm32, its own Cargo.lock and target/): the STM32F411 board is
# built, not run (no board; QEMU has no model of the F411's DMA and RCC, see
# firmware-embassy/README.md). Its QEMU board is built in the firmware step and run by the
# QEMU tests.
step "firmware-embassy: STM32F411 embassy board, release build and clippy (warnings denied)"
(cd firmware-embassy && cargo build -q --release && cargo clippy -q --release -- -D warnings)
# CI: its target/ (about 0.6 GB) is not used again.
if [ "${CI:-}" = true ]; then rm -rf firmware-embassy/target; fi

step "rustdoc (warnings denied), each crate once"
RUSTDOCFLAGS="-D warnings" cargo doc -q --workspace --exclude protolink --no-deps --all-features
# The host tool's library is mostly crate-private: its maintainers' docs (the public items
# among them), every link checked.
RUSTDOCFLAGS="-D warnings" cargo doc -q -p protolink --no-deps --all-features --document-private-items

step "doc tests (every crate's, the test build's features)"
PYO3_BUILD_EXTENSION_MODULE=1 cargo test --workspace --features "$test_features" --doc --no-fail-fast >>"$test_log" 2>&1 ||
  { plain "$test_log" | grep -E '^test result:|FAILED|panicked' | tail -n 20; exit 1; }
plain "$test_log" | grep -E '^test result:' | tail -n 10

# The word-at-a-time paths of the decoders and the CRC have a 32-bit form (the firmware's
# Cortex-M) and a 64-bit one (the host): x86-64 tests alone never run the firmware's.
step "the protocol libraries' tests on i686 (32-bit words, as on the firmware)"
cargo test --target i686-unknown-linux-gnu -p frame-io -p aeolus-proto -p aydp-proto -p aok-proto -p gdl90-proto --all-features 2>&1 | tee -a "$test_log"

# CI only: every exclusion of .cargo/mutants.toml names exactly one mutant; the mutants in the
# library lines the last commit changed are run, and a missed or timed-out one fails the step
# and is listed. Nothing to run when the commit changes no library source; a commit touching
# more than 40 mutants, or a checkout without HEAD~1, fails (scripts/mutants.sh, CI=true).
if [ "${CI:-}" = true ]; then
  step "mutants: every exclusion names exactly one mutant; the last commit's library changes (scripts/mutants.sh --in-diff HEAD~1, at most 40)"
  scripts/mutants.sh --check-exclusions
  scripts/mutants.sh --in-diff HEAD~1 --max 40 --out target/mutants-ci
fi

# The fuzz targets built here, beside the host tests: scripts/fuzz.sh's own build below finds
# them done.
step "fuzz build"
(cd fuzz && cargo +nightly fuzz build)

step "waiting for the host tests (in the background since the firmware step)"
join_host_tests
renice -n 0 -p $$ >/dev/null 2>&1 || true

step "fuzz smoke run: every cargo-fuzz target for ${FUZZ_SECONDS:-20} s"
FUZZ_JOBS="${FUZZ_JOBS:-$(nproc)}" scripts/fuzz.sh "${FUZZ_SECONDS:-20}" 2>&1 | tee "$fuzz_log"
