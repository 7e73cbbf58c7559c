#!/usr/bin/env bash
# Cortex-M3 instruction counts of the protocol crates: builds checks/cm3-bench once per
# protocol (the 64 KiB inputs of all three do not fit in 256 KiB of flash together), runs each
# build twice in QEMU's lm3s6965evb with -icount shift=0 (one instruction = 1 ns of virtual
# time), times every function with SysTick, and prints a Markdown table of instructions per
# byte.
#
#   scripts/cm3-bench.sh            print the table (and the method) to stdout
#
# `python3 scripts/bench.py` runs it and puts its table into docs/BENCHMARKS.md (the x86-64
# column is read from the x86 section of the same run, X86_DOC below).
#
# Environment:
#   CARGO_TARGET_DIR   where to build (default: checks/cm3-bench/target)
#   CM3_OPT_LEVEL      override the crate's release opt-level ("s", like the root workspace)
#   CM3_TIMEOUT        seconds allowed per QEMU run (default 60; a run takes well under 1 s)
#   X86_DOC            the page whose x86-64 table gives the side-by-side column
#                      (default docs/BENCHMARKS.md; scripts/bench.py passes its fresh section)
#
# Fails (exit 1) if a build or run fails, if a result differs from the x86 bench's on the
# same input, or if the two runs of a build do not print exactly the same counts.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
crate=checks/cm3-bench
protocols=(aeolus aydp aok)

for arg in "$@"; do
  case "$arg" in
    -h | --help)
      sed -n '2,19p' "$0" | sed 's/^# \{0,1\}//'
      exit 0
      ;;
    *)
      echo "cm3-bench.sh: unknown argument '$arg' (try --help)" >&2
      exit 2
      ;;
  esac
done

die() {
  echo "cm3-bench.sh: $*" >&2
  exit 1
}

command -v qemu-system-arm >/dev/null ||
  die "qemu-system-arm is missing: install it with 'scripts/setup.sh qemu' (Debian package qemu-system-arm)"
command -v cargo >/dev/null || die "cargo is missing: install rustup, then run 'scripts/setup.sh'"
# rustc from inside the crate, so rust-toolchain.toml picks the same toolchain cargo will use.
sysroot=$(cd "$crate" && rustc --print sysroot) || die "rustc does not run (see 'scripts/setup.sh')"
[ -d "$sysroot/lib/rustlib/thumbv7m-none-eabi" ] ||
  die "the thumbv7m-none-eabi target is missing from $(basename "$sysroot"): run 'rustup target add thumbv7m-none-eabi' (or 'scripts/setup.sh')"

target_dir=${CARGO_TARGET_DIR:-$root/$crate/target}
[ -n "${CM3_OPT_LEVEL:-}" ] && export CARGO_PROFILE_RELEASE_OPT_LEVEL=$CM3_OPT_LEVEL
opt_level=${CM3_OPT_LEVEL:-$(sed -n '/^\[profile.release\]/,/^\[/s/^opt-level *= *"\{0,1\}\([^"]*\)"\{0,1\}/\1/p' "$crate/Cargo.toml")}
timeout_s=${CM3_TIMEOUT:-60}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# llvm-size and llvm-objdump of the llvm-tools component (rust-toolchain.toml); optional.
tools="$sysroot/lib/rustlib/$(cd "$crate" && rustc -vV | sed -n 's/^host: //p')/bin"
size_tool="$tools/llvm-size"
objdump_tool="$tools/llvm-objdump"
flash_notes=()
for p in "${protocols[@]}"; do
  echo "cm3-bench.sh: building the $p harness (release, opt-level $opt_level, lto)" >&2
  (cd "$crate" && CARGO_TARGET_DIR=$target_dir cargo build -q --release --features "$p") ||
    die "the $p build failed (if the link failed for lack of FLASH, the inputs no longer fit in 256 KiB)"
  cp "$target_dir/thumbv7m-none-eabi/release/cm3-bench" "$work/$p.elf"
  if [ -x "$size_tool" ]; then
    # Flash = vector table + .text + .rodata (the inputs are in .rodata).
    flash=$("$size_tool" -A "$work/$p.elf" | awk '$1 == ".vector_table" || $1 == ".text" || $1 == ".rodata" { s += $2 } END { print s }')
    flash_notes+=("$p $flash")
  fi
done

# Checks of the calibration against the disassembly: the length of a function's loop (when it
# has exactly one backward branch), for the nop loop and the AEOLUS CRC.
loop_len() {
  [ -x "$objdump_tool" ] || return 0
  "$objdump_tool" -d --no-show-raw-insn --demangle "$1" | awk -v sym="$2" '
    function hex(s,    i, v) {
      s = tolower(s); sub(/^0x/, "", s); v = 0
      for (i = 1; i <= length(s); i++) v = v * 16 + index("0123456789abcdef", substr(s, i, 1)) - 1
      return v
    }
    /^[0-9a-f]+ </ { inside = index($0, "<" sym "::") > 0; n = 0; next }
    inside && !/^ +[0-9a-f]+:/ { inside = 0 }
    inside {
      a = $1; sub(/:$/, "", a); addr[++n] = hex(a)
      if ($2 ~ /^(b|b[a-z][a-z]|b\.w|b[a-z][a-z]\.w|cbn?z)$/ && match($0, /0x[0-9a-f]+ </)) {
        t = hex(substr($0, RSTART, RLENGTH - 2))
        if (t < addr[n]) { back++; len = 0; for (i = 1; i <= n; i++) if (addr[i] >= t) len++ }
      }
    }
    END { if (back == 1) print len }'
}
crc_loop=$(loop_len "$work/aeolus.elf" cm3_bench::measured::aeolus_crc)
nop_loop=$(loop_len "$work/aeolus.elf" cm3_bench::nop_loop)

for p in "${protocols[@]}"; do
  for run in 1 2; do
    echo "cm3-bench.sh: running $p in QEMU (-icount shift=0), run $run of 2" >&2
    status=0
    timeout "$timeout_s" qemu-system-arm \
      -machine lm3s6965evb -cpu cortex-m3 -icount shift=0 \
      -semihosting-config enable=on,target=native \
      -display none -monitor none -serial none \
      -kernel "$work/$p.elf" >"$work/$p.$run.out" 2>"$work/$p.$run.err" || status=$?
    # QEMU's lm3s6965evb prints this at reset, before the firmware runs: not ours.
    grep -v '^Timer with period zero, disabling$' "$work/$p.$run.err" >&2 || true
    [ "$status" = 124 ] && die "$p: QEMU did not exit within ${timeout_s} s (CM3_TIMEOUT)"
    [ "$status" = 0 ] || die "$p: the harness failed (exit status $status); its output:
$(cat "$work/$p.$run.out")"
    grep -q '^done ' "$work/$p.$run.out" || die "$p: the harness did not finish"
  done
  cmp -s "$work/$p.1.out" "$work/$p.2.out" ||
    die "$p: two runs of the same binary printed different counts (not deterministic):
$(diff "$work/$p.1.out" "$work/$p.2.out")"
done

qemu_version=$(qemu-system-arm --version | sed -n '1s/^QEMU emulator version //p')
rustc_version=$(cd "$crate" && rustc --version | awk '{ print $2 }')
# The x86 bench's optimisation level: its bench profile's, else its release profile's, else
# Cargo's default for both (3).
profile_opt() { sed -n "/^\[profile.$1\]/,/^\[/s/^opt-level *= *\"\{0,1\}\([^\"]*\)\"\{0,1\}/\1/p" bench/Cargo.toml; }
x86_opt=$(profile_opt bench)
[ -n "$x86_opt" ] || x86_opt=$(profile_opt release)
[ -n "$x86_opt" ] || x86_opt=3

# Turns the harness's lines into the Markdown document. Labels (and the x86 figures beside
# them) follow docs/BENCHMARKS.md; a key the harness prints but this table does not know is
# still reported, under its own name.
cat "$work"/aeolus.1.out "$work"/aydp.1.out "$work"/aok.1.out | awk \
  -v date="$(date -u +%Y-%m-%d)" -v qemu="$qemu_version" -v rustc="$rustc_version" \
  -v opt="$opt_level" -v flash="${flash_notes[*]:-}" -v x86doc="${X86_DOC:-$root/docs/BENCHMARKS.md}" \
  -v x86opt="$x86_opt" -v crcloop="$crc_loop" -v noploop="$nop_loop" '
function kv(line, key,    n, i, parts, pair) {
  n = split(line, parts, " ")
  for (i = 1; i <= n; i++) {
    split(parts[i], pair, "=")
    if (pair[1] == key) return pair[2]
  }
  return ""
}
function trim(s) { sub(/^[ \t]+/, "", s); sub(/[ \t]+$/, "", s); return s }
function note(v, target) {
  if (target == "") return ""
  if (v <= target) return "target " target ": met"
  return sprintf("target %s: missed by %.0f%%", target, (v / target - 1) * 100)
}
BEGIN {
  order = "aeolus_crc crc_crate_xmodem aeolus_deframe aeolus_decode aeolus_deframe_slice aeolus_decode_slice aydp_decode aydp_decode_feed aok_pc_decode aok_pc_decode_feed aok_device_decode aok_device_decode_feed aeolus_encode aydp_encode aok_encode"
  label["aeolus_crc"] = "AEOLUS CRC alone (section 4.3, const table)"
  label["crc_crate_xmodem"] = "peer: `crc` crate, CRC-16/XMODEM table"; extra["crc_crate_xmodem"] = "same bytes"
  label["aeolus_deframe"] = "AEOLUS deframe, `feed` one byte a call"; target["aeolus_deframe"] = 20
  label["aeolus_decode"] = "AEOLUS full decode (deframe + typed parse), `feed` one byte a call"; target["aeolus_decode"] = 20
  label["aeolus_deframe_slice"] = "AEOLUS deframe, `feed`"; target["aeolus_deframe_slice"] = 10
  label["aeolus_decode_slice"] = "AEOLUS full decode (deframe + typed parse), `feed`"; target["aeolus_decode_slice"] = 10
  label["aydp_decode"] = "AYDP decode (Spec, typed parse), `feed` one byte a call"; target["aydp_decode"] = 15
  label["aydp_decode_feed"] = "AYDP decode (Spec, typed parse), `feed`"; target["aydp_decode_feed"] = 5
  label["aok_pc_decode"] = "AOK PC side (device'"'"'s debug frames), `feed` one byte a call"; target["aok_pc_decode"] = 15
  label["aok_pc_decode_feed"] = "AOK PC side (device'"'"'s debug frames), `feed`"; target["aok_pc_decode_feed"] = 8
  label["aok_device_decode"] = "AOK device side (PC'"'"'s commands), `feed` one byte a call"; target["aok_device_decode"] = 15
  label["aok_device_decode_feed"] = "AOK device side (PC'"'"'s commands), `feed`"; target["aok_device_decode_feed"] = 8
  label["aeolus_encode"] = "AEOLUS encode (typed message to escaped frame), per output byte"; target["aeolus_encode"] = 10
  label["aydp_encode"] = "AYDP encode (expedited), per output byte"; target["aydp_encode"] = 15
  label["aok_encode"] = "AOK encode (debug frames), per output byte"; target["aok_encode"] = 15
  # x86 figures (callgrind) from docs/BENCHMARKS.md, by label; blank if not found.
  while ((getline line < x86doc) > 0) {
    # Only the x86 table: the Cortex-M3 table below it has the same labels.
    if (line ~ /^## Cortex-M3/) break
    if (line !~ /^\|/) continue
    nf = split(line, cell, "|")
    if (nf >= 6) x86[trim(cell[2])] = trim(cell[5])
  }
  close(x86doc)
}
/^cm3-bench protocol=/ { runs++ }
/^calibration / {
  ins = kv($0, "delay_instructions"); t = kv($0, "delay_ticks")
  nop_n = kv($0, "nop_iterations"); nop_t = kv($0, "nop_ticks")
  if (ipt == "") { ipt = ins / t; cal = $0 } else if (ins / t != ipt) bad = bad "calibration differs between builds; "
}
/^overhead / {
  oh = kv($0, "ticks")
  if (kv($0, "repeat") != oh) bad = bad "overhead repeat differs; "
  overhead[runs] = oh
}
/^row / {
  k = kv($0, "key")
  if (!(k in label)) { label[k] = k; order = order " " k }
  bytes[k] = kv($0, "bytes"); per[k] = kv($0, "per"); calls[k] = kv($0, "calls")
  ticks[k] = kv($0, "ticks"); rep = kv($0, "repeat")
  oh_ticks[k] = overhead[runs] * calls[k]
  rows++
  if (rep == ticks[k]) same++
  else if (rep - ticks[k] <= calls[k] && ticks[k] - rep <= calls[k]) near++
  else bad = bad k " repeat differs by more than one tick per window; "
}
/^done / { wraps += kv($0, "wraps") }
END {
  if (bad != "") { print "cm3-bench.sh: " bad > "/dev/stderr"; exit 1 }
  printf "# Cortex-M3 instruction counts (QEMU lm3s6965evb, `-icount shift=0`, SysTick)\n\n"
  printf "Regenerated by `scripts/cm3-bench.sh` (run by `scripts/bench.py`). Last run:\n"
  printf "%s, QEMU %s, rustc %s; thumbv7m-none-eabi, release,\n", date, qemu, rustc
  printf "opt-level \"%s\", LTO, one codegen unit (the workspace'"'"'s release profile). The libraries are\n", opt
  printf "measured as they were in the working tree at that time.\n\n"
  printf "Each input is the x86 bench'"'"'s own stream (`bench/src/lib.rs`, built on the host by the\n"
  printf "harness'"'"'s build script), at least 64 KiB of valid frames, read from flash; the measured\n"
  printf "functions are the x86 bench'"'"'s (the `bench-kernels` crate, linked by both). Decoders are divided by input bytes,\n"
  printf "encoders by output bytes. Every result (frames, sums, CRCs, encoded bytes) is checked against\n"
  printf "the x86 bench'"'"'s on the same input. The x86-64 column is `docs/BENCHMARKS.md`'"'"'s figure\n"
  printf "(callgrind; the x86 bench builds at opt-level %s). These are executed instructions, not\n", x86opt
  printf "cycles: on a real Cortex-M3, loads, taken branches and flash wait states add cycles.\n\n"
  printf "| what | instructions | bytes | instr/byte | x86-64 instr/byte | note |\n"
  printf "| --- | ---: | ---: | ---: | ---: | --- |\n"
  n = split(order, keys, " ")
  for (i = 1; i <= n; i++) {
    k = keys[i]
    if (!(k in ticks)) continue
    ins = (ticks[k] - oh_ticks[k]) * ipt
    v = ins / bytes[k]
    value[k] = v
    nt = note(v, target[k])
    if (extra[k] != "") nt = (nt == "" ? extra[k] : nt "; " extra[k])
    printf "| %s | %d | %d | %.1f | %s | %s |\n", label[k], ins, bytes[k], v, x86[label[k]], nt
  }
  printf "\n"
  if (("aeolus_crc" in value) && ("aeolus_decode_slice" in value)) {
    r = value["aeolus_decode_slice"] / value["aeolus_crc"]
    printf "AEOLUS full decode (`feed`) / CRC alone = %.2f (target 2.2: %s).\n", r, (r <= 2.2 ? "met" : "missed")
  }
  if (("aeolus_crc" in value) && ("aeolus_decode" in value)) {
    r = value["aeolus_decode"] / value["aeolus_crc"]
    printf "AEOLUS full decode (`feed` one byte a call) / CRC alone = %.2f (target 2.2: %s).\n", r, (r <= 2.2 ? "met" : "missed")
  }
  # Total input: each distinct decoder stream once (the AEOLUS rows share one stream).
  total_in = 0; streams = 0
  split("aeolus_crc aydp_decode aok_pc_decode aok_device_decode", sk, " ")
  for (i = 1; i <= 4; i++) if (sk[i] in bytes) { total_in += bytes[sk[i]]; streams++ }
  total_out = 0
  split("aeolus_encode aydp_encode aok_encode", ek, " ")
  for (i = 1; i <= 3; i++) if (ek[i] in bytes) total_out += bytes[ek[i]]
  printf "Total input: %d bytes decoded (%d streams), %d bytes encoded.\n\n", total_in, streams, total_out

  printf "## Method\n\n"
  printf "`checks/cm3-bench` is a `no_std` binary for thumbv7m-none-eabi (cortex-m-rt, semihosting\n"
  printf "output and exit) run in QEMU'"'"'s lm3s6965evb with `-icount shift=0`: virtual time advances by\n"
  printf "exactly 1 ns per executed instruction, so SysTick, clocked from the core clock, counts\n"
  printf "instructions at a fixed rate that does not depend on the host or its load. SysTick reloads at\n"
  printf "2^24 - 1 and its exception counts the periods, so a long window cannot wrap unseen (periods\n"
  printf "during the runs: %d). One build per protocol: the inputs of all three do not fit in 256 KiB\n", wraps
  printf "of flash together.\n\n"
  printf "**Calibration.** `cortex_m::asm::delay(n)` runs exactly n + 1 iterations of `subs; bne`\n"
  printf "(its inline assembly), so two delays differ by exactly twice the difference of their\n"
  printf "arguments in instructions: %d instructions took %d ticks, so\n", kv(cal, "delay_instructions"), kv(cal, "delay_ticks")
  printf "**1 tick = %.3f instructions** (SysTick'"'"'s core clock in this QEMU model is %.1f MHz, against\n", ipt, 1000 / ipt
  printf "one instruction per ns). Cross-checks against the disassembly (llvm-objdump):"
  printf " a loop around one\n`nop`"
  if (noploop != "") printf " is %d instructions per iteration there, and SysTick gives", noploop
  else printf " comes out at"
  printf " %.3f\n(%d iterations, %d ticks)", nop_t * ipt / nop_n, nop_n, nop_t
  if (noploop != "" && nop_t * ipt / nop_n != noploop) printf " (**they disagree**)"
  if (crcloop != "" && ("aeolus_crc" in ticks)) {
    pred = crcloop * bytes["aeolus_crc"]; meas = ticks["aeolus_crc"] * ipt; diff = meas - pred
    printf "; the AEOLUS CRC'"'"'s loop is %d instructions, one byte per\n", crcloop
    printf "iteration: %d x %d = %d instructions, against %d measured\n", crcloop, bytes["aeolus_crc"], pred, meas
    printf "(%s%d: the call and the tick resolution)", (diff >= 0 ? "+" : "-"), (diff >= 0 ? diff : -diff)
    if (diff < -ipt || diff > ipt + 64) printf " (**they disagree**: the loop may not take one byte per iteration)"
  }
  printf ". Resolution: one tick (%.0f instructions) per measured window.\n\n", ipt
  printf "**Overhead.** Every window starts on a tick edge (the harness spins until SysTick\n"
  printf "changes), then reads the counter before and after the measured closure. The same window\n"
  printf "around an empty closure measures %d ticks (its own code is a few instructions, under one\n", overhead[1]
  printf "tick); that is subtracted from every window. Encoders are timed in batches (their messages\n"
  printf "and output do not fit in 64 KiB of RAM at once): only the encoder call is in the window.\n\n"
  printf "**Determinism.** Every figure is measured twice in the same run: %d of %d rows gave the\n", same, rows
  printf "same tick count both times (%d differed by at most one tick per window). Every build ran twice\n", near
  printf "in separate QEMU processes, and the two outputs are identical byte for byte (the script\n"
  printf "fails otherwise).\n"
  if (flash != "") {
    nfl = split(flash, fl, " ")
    printf "\nFlash used (vector table + .text + .rodata, inputs included) of 262144 B:"
    for (i = 1; i + 1 <= nfl; i += 2) printf "%s %s %d B", (i > 1 ? "," : ""), fl[i], fl[i + 1]
    printf ".\n"
  }
}' >"$work/table.md" || die "could not build the table from the harness output"

cat "$work/table.md"
