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

step "cross-compile the libraries for thumbv6m, thumbv7m and thumbv7em (no features, defmt, embedded-io + embedded-io-async)"
for t in thumbv6m-none-eabi thumbv7m-none-eabi thumbv7em-none-eabihf; do
  for l in "${LIBS[@]}"; do
    cargo build -q -p "$l" --target "$t" --release
    cargo build -q -p "$l" --target "$t" --release --features defmt,embedded-io,embedded-io-async
  done
done

MSRV=$(sed -n 's/^rust-version = "\(.*\)"/\1/p' aeolus-proto/Cargo.toml)
step "MSRV: the libraries with Rust $MSRV exactly (host check with all features, thumbv6m build)"
for l in "${LIBS[@]}"; do
  cargo +"$MSRV" check -q -p "$l" --all-features
  cargo +"$MSRV" check -q -p "$l" --no-default-features
  cargo +"$MSRV" build -q -p "$l" --target thumbv6m-none-eabi --release --features embedded-io,embedded-io-async
done

step "panic-never: link-time proof that no panic path survives (checks/panic-never, thumbv7m and thumbv6m)"
if ! (cd checks/panic-never && cargo build -q --release && cargo build -q --release --target thumbv6m-none-eabi); then
  echo "FAILED panic-never check: a panic path is reachable from a decoder, typed parse or encoder."
  echo "The link error names the undefined symbol PANIC_PATH_REACHABLE_see_checks_panic_never;"
  echo "see checks/panic-never/src/main.rs for what it exercises."
  exit 1
fi

step "footprint binaries build for thumbv7m and thumbv6m (the figures: python3 scripts/footprint.py)"
(cd checks/footprint && for t in thumbv7m-none-eabi thumbv6m-none-eabi; do
  cargo build -q --release --target "$t" \
    --features aeolus-decode,aeolus-encode,aydp-decode,aydp-encode,aok-decode,aok-encode,aeolus-read,aydp-read,aok-read
done)

step "firmware: release builds for both boards, clippy on thumb"
cargo qemu-build -q
cargo stm32-build -q
cargo clippy -q -p firmware-example --release --target thumbv7m-none-eabi --features board-qemu --lib --bins -- -D warnings
cargo clippy -q -p firmware-example --release --target thumbv7em-none-eabihf --features board-stm32f411 --lib --bins -- -D warnings

step "rustdoc (warnings denied)"
RUSTDOCFLAGS="-D warnings" cargo doc -q --workspace --no-deps --all-features

step "host tests"
cargo test --workspace --all-features

step "fuzz smoke run: every cargo-fuzz target for ${FUZZ_SECONDS:-20} s"
FUZZ_JOBS="${FUZZ_JOBS:-$(nproc)}" scripts/fuzz.sh "${FUZZ_SECONDS:-20}"
