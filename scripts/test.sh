#!/usr/bin/env bash
# Runs every test and check of the project. This is the command the README
# gives and the one .ci/run calls.
set -euo pipefail
cd "$(dirname "$0")/.."
# qemu-system-arm and defmt-print: the QEMU tests must run, never skip, in CI.
bash scripts/setup.sh qemu defmt-print

LIBS=(aeolus-proto aydp-proto aok-proto)
step() { printf '\n==> %s\n' "$*"; }

step "format"
cargo fmt --all -- --check

step "clippy (all targets, warnings denied)"
cargo clippy --workspace --all-targets --all-features -- -D warnings

step "cross-compile the libraries for both thumb targets (default and defmt features)"
for t in thumbv7m-none-eabi thumbv7em-none-eabihf; do
  for l in "${LIBS[@]}"; do
    cargo build -q -p "$l" --target "$t" --release
    cargo build -q -p "$l" --target "$t" --release --features defmt
  done
done

step "panic-never: link-time proof that no panic path survives (checks/panic-never)"
if ! (cd checks/panic-never && cargo build -q --release); then
  echo "FAILED panic-never check: a panic path is reachable from a decoder, typed parse or encoder."
  echo "The link error names the undefined symbol PANIC_PATH_REACHABLE_see_checks_panic_never;"
  echo "see checks/panic-never/src/main.rs for what it exercises."
  exit 1
fi

step "firmware: release builds for both boards (and the simulated STM32), clippy on thumb"
cargo qemu-build -q
cargo stm32-build -q
cargo clippy -q -p firmware-example --release --target thumbv7m-none-eabi --features board-qemu --lib --bins -- -D warnings
cargo clippy -q -p firmware-example --release --target thumbv7em-none-eabihf --features board-stm32f411 --lib --bins -- -D warnings
# The STM32 board in QEMU netduinoplus2 (the QEMU tests boot it); built last, so this is the
# ELF at target/thumbv7em-none-eabihf/release/sensor-box when the tests run.
cargo clippy -q -p firmware-example --release --target thumbv7em-none-eabihf --features qemu-stm32 --lib --bins -- -D warnings
cargo stm32-qemu-build -q

step "rustdoc (warnings denied)"
RUSTDOCFLAGS="-D warnings" cargo doc -q --workspace --no-deps --all-features

step "host tests"
cargo test --workspace --all-features

step "fuzz smoke run: every cargo-fuzz target for ${FUZZ_SECONDS:-20} s"
FUZZ_JOBS="${FUZZ_JOBS:-$(nproc)}" scripts/fuzz.sh "${FUZZ_SECONDS:-20}"
