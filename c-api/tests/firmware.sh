#!/usr/bin/env bash
# The C firmware test and the C link-time no-panic proof of libprotolink_c.a (run by
# scripts/test.sh). Needs arm-none-eabi-gcc, picolibc and qemu-system-arm (setup.sh c qemu).
#
# 1. c-api/tests/firmware/main.c, built with Debian's arm-none-eabi-gcc and picolibc for the
#    Cortex-M3 and linked with the thumbv7m archive, boots in QEMU lm3s6965evb, decodes the
#    three UART captures of testdata/ (built into the image) and prints its counters over
#    semihosting; they must equal the Rust decoders' (protolink decode --json).
# 2. The same program, with every exported pl_* function kept as a link root, linked against
#    the archive built with the `panic-never` feature for thumbv7m and thumbv6m: its panic
#    handler calls a symbol defined nowhere, so the link fails if any panic path survives.
set -euo pipefail
cd "$(dirname "$0")/../.."
out=target/c-api-fw
mkdir -p "$out"
cargo build -q -p protolink-c --release --target thumbv7m-none-eabi
protolink=$(scripts/protolink-bin.sh)

# The lm3s6965: 256 KiB of flash at 0, 64 KiB of RAM at 0x20000000 (picolibc's picolibc.ld).
cflags=(-std=c11 -Wall -Wextra -Werror -pedantic -Os -mthumb --specs=picolibc.specs
  --oslib=semihost --crt0=semihost -Wl,--defsym=__flash=0 -Wl,--defsym=__flash_size=256K
  -Wl,--defsym=__ram=0x20000000 -Wl,--defsym=__ram_size=64K -Wl,--no-warn-execstack
  -Ic-api/include -Itestdata)
src=(c-api/tests/firmware/main.c c-api/tests/firmware/capture.S)

arm-none-eabi-gcc -mcpu=cortex-m3 "${cflags[@]}" "${src[@]}" \
  target/thumbv7m-none-eabi/release/libprotolink_c.a -o "$out/c-firmware.elf"
arm-none-eabi-size "$out/c-firmware.elf"
timeout 120 qemu-system-arm -M lm3s6965evb -nographic -monitor none -serial none \
  -semihosting-config enable=on,target=native -kernel "$out/c-firmware.elf" >"$out/qemu.log" 2>&1
cat "$out/qemu.log"
python3 - "$out/qemu.log" "$protolink" <<'PY'
import json, subprocess, sys

got = {}
for line in open(sys.argv[1]):
    words = line.split()
    if words and words[0] in ("aeolus", "aydp", "aok"):
        got[words[0]] = {k: int(v) for k, v in (w.split("=") for w in words[1:])}
runs = {"aeolus": (["--proto", "aeolus"], "testdata/qemu-uart0-aeolus.bin"),
        "aydp": (["--proto", "aydp", "--profile", "spec"], "testdata/qemu-uart1-aydp.bin"),
        "aok": (["--proto", "aok", "--side", "device"], "testdata/qemu-uart2-aok.bin")}
bad = []
for proto, (args, path) in runs.items():
    out = subprocess.run([sys.argv[2], "decode", *args, "--from", f"file:{path}",
                          "--json"], capture_output=True, text=True, check=True).stdout.splitlines()
    events = [json.loads(l) for l in out]
    want = next(e["counters"] for e in events if e["kind"] == "summary")
    want["messages"] = sum(e["kind"] == "message" for e in events)
    if proto not in got:
        bad.append(f"{proto}: the firmware printed no counters")
        continue
    for key, value in got[proto].items():
        if want.get(key) != value:
            bad.append(f"{proto} {key}: C firmware {value}, Rust decoder {want.get(key)}")
    print(f"{proto}: {len(got[proto])} counters, C firmware in QEMU == Rust decoder"
          if not any(b.startswith(proto) for b in bad) else f"{proto}: DIFFERENT")
for b in bad:
    print(b, file=sys.stderr)
sys.exit(1 if bad else 0)
PY

# Every exported function a link root: the whole C API is in the proof, not just what main
# calls.
roots=$(grep -oE '\bpl_[a-z0-9_]+\(' c-api/include/protolink.h | tr -d '(' | sort -u | sed 's/^/-Wl,--undefined=/')
n=$(echo "$roots" | wc -l)
for target in thumbv7m-none-eabi:cortex-m3 thumbv6m-none-eabi:cortex-m0; do
  t=${target%%:*} cpu=${target#*:}
  cargo build -q -p protolink-c --release --target "$t" --features panic-never \
    --target-dir target/c-api-panic-never
  # shellcheck disable=SC2086
  if ! arm-none-eabi-gcc -mcpu="$cpu" "${cflags[@]}" $roots "${src[@]}" \
    "target/c-api-panic-never/$t/release/libprotolink_c.a" -o "$out/panic-never-$t.elf"; then
    echo "FAILED: a panic path is reachable from a C API function on $t: the link names"
    echo "PANIC_PATH_REACHABLE_in_libprotolink; see c-api/tests/firmware.sh."
    exit 1
  fi
  echo "panic-never ($t, $cpu): a C program with all $n pl_* functions linked; no panic path"
done
