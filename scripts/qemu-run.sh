#!/usr/bin/env bash
# Boots a sensor-box ELF in QEMU and runs it until stopped (Ctrl-C) or until
# the firmware exits through semihosting.
#
#   scripts/qemu-run.sh [--machine M] ELF [extra qemu args...]
#
#   M = lm3s6965evb     the default board (Cortex-M3); cargo's runner for
#                       thumbv7m-none-eabi (`cargo qemu`)
#   M = netduinoplus2   STM32F405 model (Cortex-M4F) for the STM32F411 board
#                       built with `qemu-stm32` (`cargo stm32-qemu`)
#
# The three UARTs are TCP servers on 127.0.0.1 (connect with nc, python or
# `protolink ... tcp:127.0.0.1:PORT`), the same ports on both machines:
#
#   UART0  AEOLUS  $QEMU_UART0_PORT  default 7000   lm3s UART0, STM32 USART2
#   UART1  AYDP    $QEMU_UART1_PORT  default 7001   lm3s UART1, STM32 USART1
#   UART2  AOK     $QEMU_UART2_PORT  default 7002   lm3s UART2, STM32 USART6
#
# On netduinoplus2 QEMU's serial indexes are 0 = USART1, 1 = USART2,
# 2 = USART3, 3 = UART4, 4 = UART5, 5 = USART6 (`info qtree`); the unused ones
# are `null`. The STM32 firmware logs over RTT (defmt-rtt): QEMU's GDB stub
# listens on 127.0.0.1:$QEMU_GDB_PORT (default UART0's port + 3) and
# scripts/rtt-gdb.py reads the RTT buffer through it, as a probe would.
#
# Environment:
#   QEMU_MACHINE     the machine, as --machine (the option wins)
#   QEMU_UART0_PORT, QEMU_UART1_PORT, QEMU_UART2_PORT   the ports above
#   QEMU_GDB_PORT    netduinoplus2 only: the GDB stub's port (RTT log)
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

machine=${QEMU_MACHINE:-lm3s6965evb}
if [ "${1:-}" = --machine ]; then
  machine=${2:?--machine needs a value}
  shift 2
fi
if [ $# -lt 1 ]; then
  echo "usage: $0 [--machine lm3s6965evb|netduinoplus2] ELF [extra qemu args...]" >&2
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

uart() { echo "tcp:127.0.0.1:$1,server=on,wait=$2"; }
case "$machine" in
  lm3s6965evb)
    rtt=0
    args=(
      -machine lm3s6965evb -cpu cortex-m3
      -semihosting-config enable=on,target=native
      -serial "$(uart "$p0" "$wait0")"
      -serial "$(uart "$p1" off)"
      -serial "$(uart "$p2" off)"
    )
    ;;
  netduinoplus2)
    rtt=1
    pg=${QEMU_GDB_PORT:-$((p0 + 3))}
    # USART2 (AEOLUS) must be created first: with wait=on QEMU blocks at that
    # socket, and the others must not be up before it (the tests connect in order).
    # -serial binds in index order, so USART2 goes in with -chardev instead.
    args=(
      -machine netduinoplus2
      -chardev "socket,id=usart2,host=127.0.0.1,port=${p0},server=on,wait=${wait0}"
      -serial "$(uart "$p1" off)"
      -serial chardev:usart2
      -serial null -serial null -serial null
      -serial "$(uart "$p2" off)"
      -gdb "tcp:127.0.0.1:${pg}"
    )
    ;;
  *)
    echo "unknown machine '$machine' (lm3s6965evb or netduinoplus2)" >&2
    exit 2
    ;;
esac
args+=(-display none -monitor none -kernel "$elf")
[ "${QEMU_ICOUNT:-0}" = 1 ] && args+=(-icount shift=0)
# shellcheck disable=SC2206
[ -n "${QEMU_EXTRA:-}" ] && args+=(${QEMU_EXTRA})
args+=("$@")

echo "qemu-run: $(basename "$elf") on ${machine}; UART0 127.0.0.1:${p0} (wait=${wait0}), UART1 :${p1}, UART2 :${p2}" >&2

if [ "$rtt" = 1 ]; then
  command -v python3 >/dev/null || {
    echo "python3 is missing: it reads the RTT log (scripts/rtt-gdb.py)" >&2
    exit 127
  }
  if [ "${QEMU_DEFMT:-1}" = 1 ]; then
    command -v defmt-print >/dev/null || {
      echo "defmt-print is missing: run 'scripts/setup.sh defmt-print' (or QEMU_DEFMT=0)" >&2
      exit 127
    }
  fi
  # QEMU and the RTT reader (with defmt-print) in the background; a signal to
  # this script (Ctrl-C, kill) stops both. The reader ends when QEMU does.
  qemu-system-arm "${args[@]}" &
  qemu=$!
  here=$(dirname "$0")
  if [ "${QEMU_DEFMT:-1}" = 1 ]; then
    python3 "$here/rtt-gdb.py" "$elf" "$pg" "$qemu" | defmt-print -e "$elf" &
  else
    python3 "$here/rtt-gdb.py" "$elf" "$pg" "$qemu" &
  fi
  reader=$!
  trap 'kill "$qemu" 2>/dev/null; exit 130' INT TERM
  set +e
  wait "$qemu"
  status=$?
  wait "$reader"
  set -e
  exit "$status"
fi

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
