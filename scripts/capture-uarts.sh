#!/usr/bin/env bash
# Records the sample captures in testdata/: the raw bytes of the firmware's three UARTs in
# QEMU (lm3s6965evb), from boot, cut at the end of the last whole message.
#
#   scripts/capture-uarts.sh                  writes testdata/qemu-uart{0-aeolus,1-aydp,2-aok}.bin
#   scripts/capture-uarts.sh --out DIR        somewhere else
#
#   UART0  AEOLUS  CAPTURE_AEOLUS_SECONDS  default 2 (full telemetry: about 60 KB/s)
#   UART1  AYDP    CAPTURE_SECONDS         default 5
#   UART2  AOK     CAPTURE_SECONDS         default 5
#
# QEMU listens on 127.0.0.1:CAPTURE_PORT..+2 (default 17900, away from the demo's 7000 and the
# tests' 17400..17569 and 17600..17769), starts the CPU when UART0 is connected (QEMU_WAIT=1, as the test
# harness does), and is stopped (its whole process group) when the recording ends. Each
# capture is then decoded with `protolink decode` and its summary line printed.
set -euo pipefail
cd "$(dirname "$0")/.."
out=testdata
while [ $# -gt 0 ]; do
  case "$1" in
    --out) [ $# -ge 2 ] || { echo "capture-uarts.sh: --out needs a folder" >&2; exit 2; }
           out=$2; shift 2 ;;
    -h|--help) sed -n '2,15p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "capture-uarts.sh: unknown argument '$1' (try --help)" >&2; exit 2 ;;
  esac
done
aeolus_secs=${CAPTURE_AEOLUS_SECONDS:-2}
other_secs=${CAPTURE_SECONDS:-5}
base=${CAPTURE_PORT:-17900}
bash scripts/setup.sh qemu defmt-print

echo "building the firmware (release, thumbv7m) and protolink ..." >&2
cargo qemu-build -q
cargo build -q --release -p protolink
elf=target/thumbv7m-none-eabi/release/sensor-box
protolink=target/release/protolink
log=target/capture-firmware.log
mkdir -p "$out" target
raw=$(mktemp -d target/capture.XXXXXX)

# In its own process group (setsid), so that stopping it stops QEMU and defmt-print too.
QEMU_WAIT=1 QEMU_UART0_PORT=$base QEMU_UART1_PORT=$((base + 1)) QEMU_UART2_PORT=$((base + 2)) \
  setsid scripts/qemu-run.sh "$elf" >"$log" 2>&1 &
qemu=$!
cleanup() {
  kill -TERM -- "-$qemu" 2>/dev/null || true
  wait "$qemu" 2>/dev/null || true
  rm -rf "$raw"
}
trap cleanup EXIT

echo "recording UART0 for ${aeolus_secs} s, UART1 and UART2 for ${other_secs} s (firmware log: $log) ..." >&2
python3 - "$base" "$aeolus_secs" "$other_secs" "$raw" <<'EOF'
import select, socket, sys, time
base, secs0, secs12, raw = int(sys.argv[1]), float(sys.argv[2]), float(sys.argv[3]), sys.argv[4]

def connect(port):
    deadline = time.monotonic() + 10
    while True:
        try:
            return socket.create_connection(("127.0.0.1", port), timeout=1)
        except OSError:
            if time.monotonic() > deadline:
                sys.exit(f"QEMU's port {port} is not up after 10 s")
            time.sleep(0.05)

# UART0 first: the CPU starts then, and QEMU creates UART1 and UART2's sockets after it.
socks = [connect(base)]
start = time.monotonic()
socks += [connect(base + 1), connect(base + 2)]
ends = [start + secs0, start + secs12, start + secs12]
data = [bytearray(), bytearray(), bytearray()]
open_ = {0, 1, 2}
while open_:
    now = time.monotonic()
    for i in list(open_):
        if now >= ends[i]:
            open_.discard(i)
    if not open_:
        break
    r, _, _ = select.select([socks[i] for i in open_], [], [], 0.05)
    for s in r:
        i = socks.index(s)
        chunk = s.recv(65536)
        if not chunk:
            open_.discard(i)
        else:
            data[i] += chunk
for i, d in enumerate(data):
    with open(f"{raw}/uart{i}.bin", "wb") as f:
        f.write(d)
EOF

# Cut each capture after its last whole message (the offset protolink reports a message at is
# its last byte), so only the stream's start can hold a partial frame (it does not: the
# recording starts at boot).
cut() {
  local in=$1 dst=$2; shift 2
  local end
  end=$("$protolink" decode "$@" --from "file:$in" --json |
        python3 -c 'import json,sys
end = 0
for line in sys.stdin:
    e = json.loads(line)
    if e.get("kind") == "message":
        end = e["offset"] + 1
print(end)')
  head -c "$end" "$in" >"$dst"
  printf '%-28s %7s bytes: ' "$dst" "$end"
  "$protolink" decode "$@" --from "file:$dst" | tail -1
}
cut "$raw/uart0.bin" "$out/qemu-uart0-aeolus.bin" --proto aeolus
cut "$raw/uart1.bin" "$out/qemu-uart1-aydp.bin" --proto aydp --profile spec
cut "$raw/uart2.bin" "$out/qemu-uart2-aok.bin" --proto aok --side device
