#!/usr/bin/env bash
# Runs every cargo-fuzz target for SECONDS each (default 20), seeding the corpora from the
# known-answer vectors, and prints the executions reached and the crashes found per target.
#   scripts/fuzz.sh [SECONDS] [TARGET...]
# FUZZ_JOBS=N runs N targets at a time (default 1; each takes one core).
set -euo pipefail
cd "$(dirname "$0")/.."
secs="${1:-20}"; shift || true
jobs="${FUZZ_JOBS:-1}"
command -v cargo-fuzz >/dev/null || cargo install --locked cargo-fuzz
rustup toolchain list | grep -q '^nightly' || rustup toolchain install nightly --profile minimal

python3 scripts/fuzz_seeds.py fuzz/corpus
targets=("$@")
[ ${#targets[@]} -gt 0 ] || mapfile -t targets < <(cd fuzz && cargo +nightly fuzz list)
# Build once, before any run starts (parallel runs would wait on each other's builds).
(cd fuzz && cargo +nightly fuzz build)

run_one() {
  local t=$1 log="fuzz/artifacts/$1.log"
  mkdir -p fuzz/artifacts "fuzz/corpus/$t"
  if (cd fuzz && cargo +nightly fuzz run "$t" -- -max_total_time="$secs" -max_len=4096 -print_final_stats=1 >"../$log" 2>&1); then
    echo 0 >"$log.status"
  else
    echo 1 >"$log.status"
  fi
}

running=0
for t in "${targets[@]}"; do
  run_one "$t" &
  running=$((running + 1))
  if [ "$running" -ge "$jobs" ]; then
    wait -n || true
    running=$((running - 1))
  fi
done
wait || true

printf '%-22s %12s %8s\n' target executions crashes
fail=0
for t in "${targets[@]}"; do
  log="fuzz/artifacts/$t.log"
  crashes=$(cat "$log.status" 2>/dev/null || echo 1)
  [ "$crashes" = 0 ] || fail=1
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || true)
  [ -n "$execs" ] || execs=$(grep -oE '^#[0-9]+' "$log" | tail -1 | tr -d '#')
  printf '%-22s %12s %8s\n' "$t" "${execs:-?}" "$crashes"
  [ "$crashes" = 0 ] || { echo "--- $t failed; last lines of $log:"; tail -30 "$log"; }
done
exit $fail
