#!/usr/bin/env bash
# Boots a sensor-box ELF in QEMU's lm3s6965evb (Cortex-M3) and runs it until
# stopped (Ctrl-C) or until the firmware exits through semihosting.
#
#   scripts/qemu-run.sh ELF            (cargo's runner for thumbv7m-none-eabi)
#
# The three UARTs are TCP servers on 127.0.0.1 (connect with nc, python or
# `protolink ... tcp:127.0.0.1:PORT`):
#
#   UART0  AEOLUS  $QEMU_UART0_PORT  default 7000
#   UART1  AYDP    $QEMU_UART1_PORT  default 7001
#   UART2  AOK     $QEMU_UART2_PORT  default 7002
#
# Environment:
#   QEMU_UART0_PORT, QEMU_UART1_PORT, QEMU_UART2_PORT   the ports above
#   QEMU_WAIT=1      QEMU does not start the CPU until a client has connected
#                    to UART0 (wait=on), so a test sees the boot output.
#   QEMU_ICOUNT=1    -icount shift=0: one instruction = 1 ns of virtual time,
#                    deterministic instruction counts (time no longer follows
#                    the host clock).
#   QEMU_DEFMT=0     print the raw semihosting stream instead of piping it
#                    through `defmt-print -e ELF` (default 1).
#   QEMU_EXTRA       extra QEMU arguments (word-split).
#
# The defmt log (semihosting, stdout) is decoded by defmt-print; QEMU's own
# messages go to stderr. The exit code is QEMU's (the firmware's semihosting
# exit code).
set -euo pipefail

if [ $# -lt 1 ]; then
  echo "usage: $0 ELF [extra qemu args...]" >&2
  exit 2
fi
elf=$1
shift
command -v qemu-system-arm >/dev/null || {
  echo "qemu-system-arm is missing: run 'scripts/setup.sh qemu'" >&2
  exit 127
}

p0=${QEMU_UART0_PORT:-7000}
p1=${QEMU_UART1_PORT:-7001}
p2=${QEMU_UART2_PORT:-7002}
wait0=off
[ "${QEMU_WAIT:-0}" = 1 ] && wait0=on

args=(
  -machine lm3s6965evb -cpu cortex-m3
  -display none -monitor none
  -semihosting-config enable=on,target=native
  -serial "tcp:127.0.0.1:${p0},server=on,wait=${wait0}"
  -serial "tcp:127.0.0.1:${p1},server=on,wait=off"
  -serial "tcp:127.0.0.1:${p2},server=on,wait=off"
  -kernel "$elf"
)
[ "${QEMU_ICOUNT:-0}" = 1 ] && args+=(-icount shift=0)
# shellcheck disable=SC2206
[ -n "${QEMU_EXTRA:-}" ] && args+=(${QEMU_EXTRA})
args+=("$@")

echo "qemu-run: $(basename "$elf") on lm3s6965evb; UART0 127.0.0.1:${p0} (wait=${wait0}), UART1 :${p1}, UART2 :${p2}" >&2

if [ "${QEMU_DEFMT:-1}" = 1 ]; then
  command -v defmt-print >/dev/null || {
    echo "defmt-print is missing: run 'scripts/setup.sh defmt-print' (or QEMU_DEFMT=0)" >&2
    exit 127
  }
  # QEMU's stdout carries only the semihosting stream (no -nographic, no
  # monitor), so it is pure defmt frames.
  set +e
  qemu-system-arm "${args[@]}" | defmt-print -e "$elf"
  status=("${PIPESTATUS[@]}")
  set -e
  exit "${status[0]}"
else
  exec qemu-system-arm "${args[@]}"
fi
