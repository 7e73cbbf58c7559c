#!/usr/bin/env bash
# The main job: boots the sensor-box firmware in QEMU (lm3s6965evb) and shows its live AEOLUS
# telemetry with `protolink watch`, while the firmware's defmt log goes to a file.
#
#   scripts/demo.sh              runs until Ctrl-C
#   DEMO_SECONDS=20 scripts/demo.sh    stops by itself after 20 s
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh qemu defmt-print

echo "building the firmware (release, thumbv7m) and protolink ..." >&2
cargo qemu-build -q
cargo build -q --release -p protolink
elf=target/thumbv7m-none-eabi/release/sensor-box
port=${QEMU_UART0_PORT:-7000}
log=${DEMO_LOG:-target/demo-firmware.log}

# UART0 waits for its client, so the watcher sees the boot TOAST too.
QEMU_WAIT=1 scripts/qemu-run.sh "$elf" >"$log" 2>&1 &
qemu=$!
trap 'kill "$qemu" 2>/dev/null; wait "$qemu" 2>/dev/null || true' EXIT
# Wait until QEMU listens (without connecting: the first client is the watcher).
hex=$(printf ':%04X ' "$port")
for _ in $(seq 200); do
  grep -q "$hex.* 0A " /proc/net/tcp && break
  sleep 0.05
done
echo "firmware log (defmt): $log; AYDP on 127.0.0.1:${QEMU_UART1_PORT:-7001}, AOK on 127.0.0.1:${QEMU_UART2_PORT:-7002}" >&2
args=(watch --from "tcp:127.0.0.1:$port")
[ -n "${DEMO_SECONDS:-}" ] && args+=(--seconds "$DEMO_SECONDS")
target/release/protolink "${args[@]}"
