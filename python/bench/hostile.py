#!/usr/bin/env python3
"""Hostile inputs to the Python package (issue 44): the figures of docs/RELIABILITY.md,
"Hostile inputs: Python".

    python3 python/bench/hostile.py              # about a minute; --mb 111 as measured
    python3 python/bench/hostile.py --mb 20      # a quicker look

With the `protolink` package of the Python that runs it (scripts/test-python.sh --wheel installs
it into target/py-venv; `target/py-venv/bin/python python/bench/hostile.py`), and the
`protolink` binary of $PROTOLINK or target/release/ to record the capture. Each figure is
measured in a child process of its own:

- sigint feed: `aeolus.Decoder().feed(data)` of testdata/qemu-uart0-aeolus.bin repeated to
  --mb megabytes; SIGINT is sent (os.kill) --after seconds into the call, in one child per
  value; the latency is the time from the kill to the child's `except KeyboardInterrupt`
  (both read the wall clock of this machine), and the child prints how many bytes the
  decoder had consumed.
- sigint feed_iter: the same, iterating `feed_iter(data)`.
- sigint to_frames: the same, for `protolink.to_frames` of a pcapng recorded from that data.
- peak RSS: VmHWM of a child that feeds the data with `feed` (a list of every message),
  or with `feed_iter` (one piece at a time), counting the messages; and of one that only
  builds the data, the baseline.
- peak RSS of to_frames: VmHWM of a child that runs `to_frames` of a pcapng recorded from
  30 MB of the sample (a dict per row before issue 44, a list per column after).
- cut capture: a pcapng of the data cut in the middle of its last block, read with
  `to_frames`: the GYRO rows it gives (or the exception it raises).
"""

import argparse
import os
import pathlib
import signal
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parents[2]
SAMPLE = ROOT / "testdata" / "qemu-uart0-aeolus.bin"

# The child's prologue: the data, then "ready" on stdout once the long call is about to start.
MAKE_DATA = """
import os, sys, time
import protolink
def peak():
    # VmHWM, the high-water mark of this process's own memory, in KiB (ru_maxrss would start
    # at the parent's RSS, inherited at fork).
    for line in open("/proc/self/status"):
        if line.startswith("VmHWM:"):
            return int(line.split()[1])
sample = open({sample!r}, "rb").read()
data = sample * max(1, {mb} * 1_000_000 // len(sample))
"""

SIGINT_FEED = MAKE_DATA + """
d = protolink.aeolus.Decoder()
print("ready", flush=True)
start = time.time()
try:
    events = d.feed(data)
    print("finished", time.time(), d.bytes_fed, len(data), flush=True)
except KeyboardInterrupt:
    print("interrupted", time.time(), d.bytes_fed, len(data), flush=True)
"""

SIGINT_FEED_ITER = SIGINT_FEED.replace("events = d.feed(data)", "for m in d.feed_iter(data): pass")

SIGINT_FRAMES = """
import sys, time
import protolink
print("ready", flush=True)
try:
    frames = protolink.to_frames({path!r})
    print("finished", time.time(), sum(len(f) for f in frames.values()), 0, flush=True)
except KeyboardInterrupt:
    print("interrupted", time.time(), 0, 0, flush=True)
"""

PEAK = MAKE_DATA + """
d = protolink.aeolus.Decoder()
if {how!r} == "feed":
    n = len(d.feed(data))
elif {how!r} == "feed_iter":
    n = sum(1 for _ in d.feed_iter(data))
else:
    n = 0
print(n, peak(), flush=True)
"""

FRAMES_PEAK = """
import protolink
frames = protolink.to_frames({path!r})
for line in open("/proc/self/status"):
    if line.startswith("VmHWM:"):
        print(sum(len(f) for f in frames.values()), int(line.split()[1]), flush=True)
"""

CUT = """
import warnings
import protolink
with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always")
    try:
        frames = protolink.to_frames({path!r})
        print("GYRO rows", len(frames.get("GYRO", [])), "warnings:", [str(w.message) for w in caught])
    except OSError as e:
        print("raised", type(e).__name__, e)
"""


def sigint(code: str, after: float) -> str:
    child = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True, cwd=ROOT.parent)
    assert child.stdout is not None
    line = child.stdout.readline()
    if line.strip() != "ready":
        child.wait()
        return f"the child did not start: {line!r}"
    time.sleep(after)
    sent = time.time()
    os.kill(child.pid, signal.SIGINT)
    stdout, stderr = child.communicate()
    out = stdout.split()
    if len(out) < 4:
        last = (stderr.strip().splitlines() or ["nothing on stderr"])[-1]
        return f"no answer from the child (exit status {child.returncode}): {last}"
    what, at, fed, total = out[0], float(out[1]), int(out[2]), int(out[3])
    consumed = f", {fed:,} of {total:,} bytes consumed" if total else ""
    return f"{what} {at - sent:.3f} s after the SIGINT{consumed}"


def peak(how: str, mb: int) -> str:
    code = PEAK.format(sample=str(SAMPLE), mb=mb, how=how)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT.parent)
    if out.returncode != 0:
        return f"failed: {out.stderr.strip().splitlines()[-1]}"
    n, kib = out.stdout.split()
    return f"{int(kib) / 1024:.0f} MiB peak RSS, {int(n):,} messages"


def protolink_binary() -> str:
    return os.environ.get("PROTOLINK") or str(ROOT / "target" / "release" / "protolink")


def record(raw: pathlib.Path, out: pathlib.Path) -> None:
    subprocess.run([protolink_binary(), "record", "--from", f"file:{raw}", "--proto", "aeolus",
                    "--out", str(out)], check=True, capture_output=True)


def last_block_start(path: pathlib.Path) -> int:
    """The offset of the last block of a little-endian pcapng (each block's length is at 4..8)."""
    data = path.read_bytes()
    at = 0
    while True:
        n = int.from_bytes(data[at + 4:at + 8], "little")
        if at + n >= len(data):
            return at
        at += n


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--mb", type=int, default=111, help="megabytes of AEOLUS stream (default 111)")
    ap.add_argument("--after", default="0.5,1,2,3",
                    help="seconds into the call the SIGINT is sent, one child each (default 0.5,1,2,3)")
    args = ap.parse_args()
    import protolink  # noqa: F401  (fails early without the package)

    afters = [float(a) for a in args.after.split(",")]
    print(f"python {sys.version.split()[0]}, {args.mb} MB of AEOLUS, SIGINT {args.after} s into each call")
    for after in afters:
        print(f"sigint feed      {after} s:", sigint(SIGINT_FEED.format(sample=str(SAMPLE), mb=args.mb), after))
    for after in afters:
        print(f"sigint feed_iter {after} s:", sigint(SIGINT_FEED_ITER.format(sample=str(SAMPLE), mb=args.mb), after))
    with tempfile.TemporaryDirectory() as tmp:
        raw = pathlib.Path(tmp) / "stream.bin"
        sample = SAMPLE.read_bytes()
        raw.write_bytes(sample * max(1, args.mb * 1_000_000 // len(sample)))
        cap = pathlib.Path(tmp) / "flight.pcapng"
        record(raw, cap)
        raw.unlink()
        for after in afters:
            print(f"sigint to_frames {after} s:", sigint(SIGINT_FRAMES.format(path=str(cap)), after))
        print("peak baseline:    ", peak("none", args.mb))
        print("peak feed:        ", peak("feed", args.mb))
        print("peak feed_iter:   ", peak("feed_iter", args.mb))
        medium = pathlib.Path(tmp) / "medium.bin"
        medium.write_bytes(sample * (30_000_000 // len(sample)))
        medium_cap = pathlib.Path(tmp) / "medium.pcapng"
        record(medium, medium_cap)
        out = subprocess.run([sys.executable, "-c", FRAMES_PEAK.format(path=str(medium_cap))],
                             capture_output=True, text=True, cwd=ROOT.parent).stdout.split()
        print(f"peak to_frames:    {int(out[1]) / 1024:.0f} MiB peak RSS, {int(out[0]):,} rows of 30 MB")
        small = pathlib.Path(tmp) / "small.pcapng"
        record(SAMPLE, small)
        cut = pathlib.Path(tmp) / "cut.pcapng"
        start = last_block_start(small)
        data = small.read_bytes()
        cut.write_bytes(data[:start + 20])
        code = CUT.format(path=str(small))
        whole = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True).stdout.strip()
        code = CUT.format(path=str(cut))
        out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
        print(f"cut capture:       {len(data)} B cut to {start + 20} B, 20 B into its last block (at byte {start})")
        print("  whole:          ", whole)
        print("  cut:            ", (out.stdout + out.stderr).strip())


if __name__ == "__main__":
    main()
