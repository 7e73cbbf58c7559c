#!/usr/bin/env bash
# The mutation score of the three protocol libraries: runs cargo-mutants (settings in
# .cargo/mutants.toml) and prints, per crate, the mutants caught, missed, unviable and timed
# out, and the score = caught / (caught + missed). Timeouts (a mutant that makes a test hang)
# are counted apart, in neither term: the score would only be higher with them as caught.
#
#   scripts/mutants.sh [options]
#     --crate NAME     only this crate (repeatable; default aeolus-proto, aydp-proto, aok-proto)
#     --shard K/N      only mutant i with i % N == K (round-robin: an unbiased sample)
#     --in-diff REV    only the mutants in lines that REV..HEAD changed in the crates' src/
#                      (CI: HEAD~1); nothing to do, and status 0, when there are none
#     --max N          with --in-diff: skip, with status 0 and a message, if more than N mutants
#     --jobs N         cargo-mutants jobs (default 2)
#     --out DIR        where mutants.out goes (default target/mutants)
#     --report DIR     only print the table of an earlier run's DIR/mutants.out
#     -- ARGS          pass ARGS on to cargo mutants (e.g. --shuffle, --timeout 60)
#
# A mutant the x86-64 tests miss is run again with the tests built for i686 (32-bit words, as
# on the firmware's Cortex-M), when that target is installed (scripts/setup.sh i686): the
# word-at-a-time paths under cfg(not(target_pointer_width = "64")) are compiled only there. A
# mutant caught there counts as caught; missed.txt then lists the mutants missed by both, and
# missed-x86_64.txt the first run's list.
#
# Exit status: 0 when no mutant was missed, 1 when one was (they are listed), 2 on a usage
# error or when cargo-mutants itself fails. Runs under `nice -n 19`. The mutant builds have no
# debug info and opt-level 1, the workspace's test profile (CARGO_PROFILE_{DEV,TEST}_DEBUG=0,
# _OPT_LEVEL=1): the same checks (debug assertions, overflow checks) as `cargo test`; at
# opt-level 0 the property tests ran 5-10 times slower and cost more than the builds saved.
set -euo pipefail
cd "$(dirname "$0")/.."

crates=()
shard=""
in_diff=""
max=""
jobs=2
out=target/mutants
report=""
extra=()
while [ $# -gt 0 ]; do
  case $1 in
    --crate) crates+=("$2"); shift 2 ;;
    --shard) shard=$2; shift 2 ;;
    --in-diff) in_diff=$2; shift 2 ;;
    --max) max=$2; shift 2 ;;
    --jobs) jobs=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --report) report=$2; shift 2 ;;
    --) shift; extra=("$@"); break ;;
    *) echo "mutants.sh: unknown argument '$1' (see the header of $0)" >&2; exit 2 ;;
  esac
done
[ ${#crates[@]} -gt 0 ] || crates=(aeolus-proto aydp-proto aok-proto)

# Prints the table of DIR/mutants.out; status 1 if a mutant was missed.
table() {
  local dir=$1/mutants.out
  local c caught missed unviable timeout all_missed=0
  printf '%-14s %7s %7s %9s %8s %7s\n' crate caught missed unviable timeout score
  for c in "${crates[@]}"; do
    caught=$(grep -c "^$c/" "$dir/caught.txt" || true)
    missed=$(grep -c "^$c/" "$dir/missed.txt" || true)
    unviable=$(grep -c "^$c/" "$dir/unviable.txt" || true)
    timeout=$(grep -c "^$c/" "$dir/timeout.txt" || true)
    all_missed=$((all_missed + missed))
    printf '%-14s %7d %7d %9d %8d %7s\n' "$c" "$caught" "$missed" "$unviable" "$timeout" \
      "$(awk -v c="$caught" -v m="$missed" 'BEGIN { if (c + m) printf "%.1f %%", 100 * c / (c + m); else print "-" }')"
  done
  if [ "$all_missed" -gt 0 ]; then
    echo "missed (no test failed with these mutations):"
    sed 's/^/  /' "$dir/missed.txt"
    return 1
  fi
}

if [ -n "$report" ]; then
  table "$report"
  exit $?
fi

# The version the figures in docs/RELIABILITY.md were measured with.
need_cargo_mutants() {
  command -v cargo-mutants >/dev/null || cargo install --locked cargo-mutants --version 27.1.0
}

args=(-j "$jobs" -o "$out")
for c in "${crates[@]}"; do args+=(-p "$c"); done
[ -z "$shard" ] || args+=(--shard "$shard" --sharding round-robin)
args+=("${extra[@]}")
if [ -n "$in_diff" ]; then
  if ! git rev-parse -q --verify "$in_diff^{commit}" >/dev/null; then
    echo "mutants: skipped: no commit '$in_diff' in this checkout (a shallow clone?)"
    exit 0
  fi
  mkdir -p "$out"
  diff_file=$out/in-diff.patch
  git diff "$in_diff" HEAD -- "${crates[@]/%//src}" >"$diff_file"
  if [ ! -s "$diff_file" ]; then
    echo "mutants: skipped: $in_diff..HEAD changes no library source (${crates[*]/%//src/})"
    exit 0
  fi
  args+=(--in-diff "$diff_file")
  need_cargo_mutants
  list=$(cargo mutants --list "${args[@]}") || { echo "mutants: cargo mutants --list failed"; exit 2; }
  n=$(grep -c . <<<"$list" || true)
  if [ "$n" -eq 0 ]; then
    echo "mutants: skipped: the library lines $in_diff..HEAD changes hold no mutant"
    exit 0
  fi
  if [ -n "$max" ] && [ "$n" -gt "$max" ]; then
    echo "mutants: skipped: $in_diff..HEAD changes lines with $n mutants, more than $max;"
    echo "run scripts/mutants.sh before the release (docs/RELIABILITY.md, \"Mutation score\")"
    exit 0
  fi
  echo "mutants: $n mutants in the lines $in_diff..HEAD changes"
fi

need_cargo_mutants
echo "cargo-mutants $(cargo mutants --version | awk '{ print $2 }'), $(date -u '+%Y-%m-%d %H:%M UTC')"
status=0
CARGO_PROFILE_DEV_DEBUG=0 CARGO_PROFILE_TEST_DEBUG=0 \
  CARGO_PROFILE_DEV_OPT_LEVEL=1 CARGO_PROFILE_TEST_OPT_LEVEL=1 nice -n 19 cargo mutants "${args[@]}" || status=$?
# cargo-mutants: 0 all caught, 2 missed, 3 timeouts, 4 the baseline failed, 1 a usage error.
case $status in
  0 | 2 | 3) ;;
  *) echo "mutants: cargo-mutants failed (status $status)"; exit 2 ;;
esac

# The missed mutants again, with the tests built and run for i686 (see the header).
dir=$out/mutants.out
if [ -s "$dir/missed.txt" ]; then
  if rustup target list --installed | grep -q '^i686-unknown-linux-gnu$'; then
    again=(-j "$jobs" -o "$out/i686")
    for c in "${crates[@]}"; do again+=(-p "$c"); done
    while IFS= read -r m; do
      again+=(-F "^$(printf '%s' "$m" | sed 's/[][\\^$.|?*+(){}]/\\&/g')\$")
    done <"$dir/missed.txt"
    echo "mutants: $(grep -c . "$dir/missed.txt") missed on x86-64, run again with the tests built for i686"
    status=0
    CARGO_PROFILE_DEV_DEBUG=0 CARGO_PROFILE_TEST_DEBUG=0 \
      CARGO_PROFILE_DEV_OPT_LEVEL=1 CARGO_PROFILE_TEST_OPT_LEVEL=1 nice -n 19 \
      cargo mutants "${again[@]}" --cargo-arg=--target=i686-unknown-linux-gnu || status=$?
    case $status in
      0 | 2 | 3) ;;
      *) echo "mutants: cargo-mutants failed on i686 (status $status)"; exit 2 ;;
    esac
    cp "$dir/missed.txt" "$dir/missed-x86_64.txt"
    for f in caught unviable timeout; do
      [ ! -s "$out/i686/mutants.out/$f.txt" ] || cat "$out/i686/mutants.out/$f.txt" >>"$dir/$f.txt"
    done
    cp "$out/i686/mutants.out/missed.txt" "$dir/missed.txt"
  else
    echo "mutants: the i686 target is not installed: missed mutants not run again at 32 bits (scripts/setup.sh i686)"
  fi
fi
table "$out"
