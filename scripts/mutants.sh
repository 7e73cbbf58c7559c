#!/usr/bin/env bash
# The mutation score of the three protocol libraries and frame-io: runs cargo-mutants (settings
# in .cargo/mutants.toml) and prints, per crate, the mutants caught, missed, unviable and timed
# out, and the score = caught / (caught + missed + timeout). A timeout (a mutant with which a
# test hangs, cargo-mutants' status 3) is not counted as caught: no test failed, and the
# hang may be the harness's rather than a test's finding. It is listed, and fails the run,
# like a missed mutant.
#
#   scripts/mutants.sh [options]
#     --crate NAME     only this crate (repeatable; default frame-io, aeolus-proto, aydp-proto,
#                      aok-proto)
#     --shard K/N      only mutant i with i % N == K (round-robin: an unbiased sample)
#     --in-diff REV    only the mutants in lines that REV..HEAD changed in the crates' src/
#                      (CI: HEAD~1); nothing to do, and status 0, when there are none
#     --max N          with --in-diff: do not run more than N mutants (status 0 and a message;
#                      under CI=true, status 1: CI never passes a run it could not make)
#     --check-exclusions  only check that every pattern of exclude_re in .cargo/mutants.toml
#                      matches exactly one mutant (status 1, and the patterns listed, if not)
#     --jobs N         cargo-mutants jobs (default 2)
#     --out DIR        where mutants.out goes (default target/mutants)
#     --report DIR     only print the table of an earlier run's DIR/mutants.out
#     --again FILE     only the mutants named in FILE (one cargo-mutants name a line, e.g. an
#                      earlier run's missed.txt or timeout.txt), matched by file, function and
#                      mutation but not line and column: the lines may have moved since
#     -- ARGS          pass ARGS on to cargo mutants (e.g. --shuffle, --timeout 60)
#
# A mutant the x86-64 tests miss is run again with the tests built for i686 (32-bit words, as
# on the firmware's Cortex-M), when that target is installed (scripts/setup.sh i686): the
# word-at-a-time paths under cfg(not(target_pointer_width = "64")) are compiled only there. A
# mutant caught there counts as caught; missed.txt then lists the mutants missed by both, and
# missed-x86_64.txt the first run's list.
#
# Exit status: 0 when no mutant was missed or timed out, 1 when one was (they are listed) or
# when, under CI=true, the run could not be made (no REV in a shallow clone, more than --max
# mutants), 2 on a usage error or when cargo-mutants itself fails. Runs under `nice -n 19`. The mutant builds have no
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
again_file=""
check_exclusions=""
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
    --again) again_file=$2; shift 2 ;;
    --check-exclusions) check_exclusions=1; shift ;;
    --) shift; extra=("$@"); break ;;
    *) echo "mutants.sh: unknown argument '$1' (see the header of $0)" >&2; exit 2 ;;
  esac
done
[ ${#crates[@]} -gt 0 ] || crates=(frame-io aeolus-proto aydp-proto aok-proto)

# Prints the table of DIR/mutants.out; status 1 if a mutant was missed or timed out.
table() {
  local dir=$1/mutants.out
  local c caught missed unviable timeout all_missed=0 all_timeout=0 status=0
  printf '%-14s %7s %7s %9s %8s %7s\n' crate caught missed unviable timeout score
  for c in "${crates[@]}"; do
    caught=$(grep -c "^$c/" "$dir/caught.txt" 2>/dev/null || true)
    missed=$(grep -c "^$c/" "$dir/missed.txt" 2>/dev/null || true)
    unviable=$(grep -c "^$c/" "$dir/unviable.txt" 2>/dev/null || true)
    timeout=$(grep -c "^$c/" "$dir/timeout.txt" 2>/dev/null || true)
    all_missed=$((all_missed + missed))
    all_timeout=$((all_timeout + timeout))
    printf '%-14s %7d %7d %9d %8d %7s\n' "$c" "$caught" "$missed" "$unviable" "$timeout" \
      "$(awk -v c="$caught" -v m="$missed" -v t="$timeout" 'BEGIN { if (c + m + t) printf "%.1f %%", 100 * c / (c + m + t); else print "-" }')"
  done
  if [ "$all_missed" -gt 0 ]; then
    echo "missed (no test failed with these mutations):"
    sed 's/^/  /' "$dir/missed.txt"
    status=1
  fi
  if [ "$all_timeout" -gt 0 ]; then
    echo "timed out (not counted as caught: no test failed, one hung):"
    sed 's/^/  /' "$dir/timeout.txt"
    status=1
  fi
  return $status
}

# Under CI=true a run that could not be made fails; elsewhere it is skipped with the reason.
cannot_run() {
  echo "mutants: $*"
  if [ "${CI:-}" = true ]; then
    echo "mutants: FAILED: under CI a mutation run that cannot be made is a failure, not a skip"
    exit 1
  fi
  exit 0
}

if [ -n "$report" ]; then
  table "$report"
  exit $?
fi

# Every exclusion must name one mutant, so that it can neither hide a second one nor go stale
# unnoticed: list every mutant without the config's exclusions, and match each pattern.
if [ -n "$check_exclusions" ]; then
  command -v cargo-mutants >/dev/null || cargo install --locked cargo-mutants --version 27.1.0
  all=$(mktemp)
  trap 'rm -f "$all"' EXIT
  list_args=(--list --no-config --all-features)
  for c in "${crates[@]}"; do list_args+=(-p "$c"); done
  cargo mutants "${list_args[@]}" >"$all" || { echo "mutants: cargo mutants --list failed"; exit 2; }
  python3 - "$all" <<'PY'
import re, sys, tomllib
mutants = open(sys.argv[1]).read().splitlines()
patterns = tomllib.load(open(".cargo/mutants.toml", "rb"))["exclude_re"]
bad = 0
for p in patterns:
    hits = [m for m in mutants if re.search(p, m)]
    if len(hits) != 1:
        bad += 1
        print(f"exclusion {p!r} matches {len(hits)} mutants (it must match exactly one):")
        for m in hits:
            print(f"  {m}")
print(f"mutants: {len(patterns)} exclusions checked against {len(mutants)} mutants, {bad} not matching exactly one")
sys.exit(1 if bad else 0)
PY
  exit $?
fi

# The version the figures in docs/RELIABILITY.md were measured with.
need_cargo_mutants() {
  command -v cargo-mutants >/dev/null || cargo install --locked cargo-mutants --version 27.1.0
}

args=(-j "$jobs" -o "$out")
for c in "${crates[@]}"; do args+=(-p "$c"); done
[ -z "$shard" ] || args+=(--shard "$shard" --sharding round-robin)
if [ -n "$again_file" ]; then
  [ -s "$again_file" ] || { echo "mutants: --again $again_file: no such file, or empty"; exit 2; }
  while IFS= read -r m; do
    [ -n "$m" ] || continue
    # FILE:LINE:COL: MUTATION -> ^FILE:\d+:\d+: MUTATION$ (the rest escaped).
    file=${m%%:*}
    rest=${m#*:*:*: }
    args+=(-F "^$(printf '%s' "$file" | sed 's/[][\\^$.|?*+(){}]/\\&/g'):[0-9]+:[0-9]+: $(printf '%s' "$rest" | sed 's/[][\\^$.|?*+(){}]/\\&/g')\$")
  done <"$again_file"
fi
args+=("${extra[@]}")
if [ -n "$in_diff" ]; then
  if ! git rev-parse -q --verify "$in_diff^{commit}" >/dev/null; then
    cannot_run "not run: no commit '$in_diff' in this checkout (a shallow clone?)"
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
    cannot_run "not run: $in_diff..HEAD changes lines with $n mutants, more than $max" \
      "(run scripts/mutants.sh --in-diff $in_diff without --max; docs/RELIABILITY.md, \"Mutation score\")"
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
