#!/usr/bin/env bash
# Runs every cargo-fuzz target for SECONDS each (default 20), seeding the corpora from the
# known-answer vectors, and prints the executions reached and the crashes found per target.
#   scripts/fuzz.sh [SECONDS] [TARGET...]
set -euo pipefail
cd "$(dirname "$0")/.."
secs="${1:-20}"; shift || true
command -v cargo-fuzz >/dev/null || cargo install --locked cargo-fuzz
rustup toolchain list | grep -q '^nightly' || rustup toolchain install nightly --profile minimal

python3 scripts/fuzz_seeds.py fuzz/corpus
targets=("$@")
[ ${#targets[@]} -gt 0 ] || mapfile -t targets < <(cd fuzz && cargo +nightly fuzz list)

printf '%-22s %12s %8s\n' target executions crashes
fail=0
for t in "${targets[@]}"; do
  log="fuzz/artifacts/$t.log"; mkdir -p fuzz/artifacts "fuzz/corpus/$t"
  if (cd fuzz && cargo +nightly fuzz run "$t" -- -max_total_time="$secs" -max_len=4096 -print_final_stats=1 >"../$log" 2>&1); then
    crashes=0
  else
    crashes=1; fail=1
  fi
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || true)
  [ -n "$execs" ] || execs=$(grep -oE '^#[0-9]+' "$log" | tail -1 | tr -d '#')
  printf '%-22s %12s %8s\n' "$t" "${execs:-?}" "$crashes"
  [ "$crashes" = 0 ] || { echo "--- $t failed; last lines of $log:"; tail -30 "$log"; }
done
exit $fail
