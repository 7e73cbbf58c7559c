#!/usr/bin/env bash
# The main job: boots the sensor-box firmware in QEMU (lm3s6965evb) and shows its live AEOLUS
# telemetry with `protolink watch` (or `protolink web` with --web), while the firmware's defmt
# log goes to a file.
#
#   scripts/demo.sh                  runs until Ctrl-C
#   scripts/demo.sh --seconds 20     stops by itself after 20 s (or DEMO_SECONDS=20)
#   scripts/demo.sh --web            the same run in the browser: `protolink web` on
#                                    http://127.0.0.1:8080/ (DEMO_LISTEN=IP:PORT for another)
#   scripts/demo.sh --board embassy  the async firmware (firmware-embassy's QEMU board) in the
#                                    same machine instead of the blocking one (--board blocking)
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${DEMO_SECONDS:-}
view=watch
board=blocking
while [ $# -gt 0 ]; do
  case "$1" in
    --seconds) [ $# -ge 2 ] || { echo "demo.sh: --seconds needs a number" >&2; exit 2; }
               seconds=$2; shift 2 ;;
    --seconds=*) seconds=${1#--seconds=}; shift ;;
    --web) view=web; shift ;;
    --board) [ $# -ge 2 ] || { echo "demo.sh: --board needs blocking or embassy" >&2; exit 2; }
             board=$2; shift 2 ;;
    --board=*) board=${1#--board=}; shift ;;
    -h|--help) sed -n '2,11p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "demo.sh: unknown argument '$1' (try --help)" >&2; exit 2 ;;
  esac
done
case "$board" in
  blocking | embassy) ;;
  *) echo "demo.sh: unknown board '$board' (blocking or embassy)" >&2; exit 2 ;;
esac
# Progress on stderr: one line per step with the time since the start, and cargo's own
# progress (its bar on a terminal, a line per crate compiled otherwise) while it builds.
start=$(date +%s%3N)
note() { awk -v ms="$(($(date +%s%3N) - start))" -v msg="$*" 'BEGIN { printf "demo [%5.1f s] %s\n", ms / 1000, msg }' >&2; }
note "checking the toolchain, qemu-system-arm and defmt-print"
bash scripts/setup.sh qemu defmt-print

note "building the $board firmware (release, thumbv7m-none-eabi)"
if [ "$board" = embassy ]; then
  # Its own workspace; into target/embassy, where the QEMU tests build it too.
  (cd firmware-embassy && CARGO_TARGET_DIR=../target/embassy cargo qemu-build)
  elf=target/embassy/thumbv7m-none-eabi/release/sensor-box-embassy
else
  cargo qemu-build
  elf=target/thumbv7m-none-eabi/release/sensor-box
fi
note "building protolink (release)"
cargo build --release -p protolink
port=${QEMU_UART0_PORT:-7000}
log=${DEMO_LOG:-target/demo-firmware.log}

# UART0 waits for its client, so the watcher sees the boot TOAST too.
# In its own process group (setsid), so that the exit trap stops QEMU and defmt-print too,
# not just the script that started them.
note "booting the firmware in QEMU (lm3s6965evb)"
QEMU_WAIT=1 setsid scripts/qemu-run.sh "$elf" >"$log" 2>&1 &
qemu=$!
trap 'kill -TERM -- "-$qemu" 2>/dev/null; wait "$qemu" 2>/dev/null || true' EXIT
# Wait until QEMU listens (without connecting: the first client is the watcher).
hex=$(printf ':%04X ' "$port")
up="QEMU is up"
for i in $(seq 200); do
  grep -q "$hex.* 0A " /proc/net/tcp && break
  [ "$i" = 200 ] && up="QEMU is not listening after 10 s (see $log)"
  sleep 0.05
done
note "$up; protolink $view on UART0 (127.0.0.1:$port)${seconds:+ for $seconds s}"
echo "firmware log (defmt): $log; AYDP on 127.0.0.1:${QEMU_UART1_PORT:-7001}, AOK on 127.0.0.1:${QEMU_UART2_PORT:-7002}" >&2
args=("$view" --from "tcp:127.0.0.1:$port")
if [ "$view" = web ]; then
  listen=${DEMO_LISTEN:-127.0.0.1:8080}
  args+=(--listen "$listen")
  echo "open http://$listen/ in a browser: the simulated turn flies there (Ctrl-C to stop)" >&2
fi
[ -n "$seconds" ] && args+=(--seconds "$seconds")
target/release/protolink "${args[@]}"
