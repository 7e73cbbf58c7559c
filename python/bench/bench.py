#!/usr/bin/env python3
"""Messages per second of `protolink.aeolus.Decoder.feed` beside pymavlink's `parse_buffer`,
and of the columns (`protolink.to_frames`, `protolink export` to Parquet), in one run (the
figures are in docs/BENCHMARKS.md, "Python").

    python3 python/bench/bench.py            # 100 MB each; about two minutes
    python3 python/bench/bench.py --mb 10    # a quicker look

The AEOLUS stream is testdata/qemu-uart0-aeolus.bin (2 s of the firmware's telemetry in QEMU)
repeated to at least --mb megabytes. The MAVLink stream is as long: MAVLink 2 messages of the
common dialect, one for each AEOLUS message in the same order, the nearest in content (GYRO,
ACCEL and MAGNET as SCALED_IMU, SCALED_IMU2 and SCALED_IMU3, ATTITUDE as ATTITUDE, COMPASS as
VFR_HUD, PRESSURE as SCALED_PRESSURE, GPS as GPS_RAW_INT, TEMP as SCALED_PRESSURE2, WIND as
WIND_COV, TOAST as STATUSTEXT, AEOLUSINFO as AUTOPILOT_VERSION), with the AEOLUS values.

Both are fed in 64 KiB pieces, as a file or a socket is read, and every message is counted.
pymavlink runs twice, each in its own process: pure Python (its C `mavnative` is never used:
only `mavutil` with `native=True` loads it; and `fastcrc`, the Rust CRC pymavlink 2.4.41+
uses when installed, is blocked, so its own Python CRC runs), and as installed (with fastcrc).
protolink's rates: `feed` alone (messages made; their fields become Python objects when first
read), `feed` then `name` and one field of each message, and `feed` then `to_dict()` of each
(every field a Python object, as pymavlink's messages hold them). Each protolink figure is the
best of --repeat runs (the machine is shared); each pymavlink figure one run of the whole
stream.

The columns: `protolink.to_frames` of the AEOLUS stream written as a file (one DataFrame per
message type, every field a column), each run in a process of its own, with its peak RSS above
that process's after its imports; beside it pymavlink's pure-Python `parse_buffer` with every
field of every message read (`getattr` of each of its `_fieldnames`). Then `protolink export`
(target/release/protolink, or $PROTOLINK) of ten copies of the file, 1 GB, to Parquet, with
its peak RSS.
"""

import argparse
import json
import os
import pathlib
import platform
import subprocess
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parents[2]
SAMPLE = ROOT / "testdata" / "qemu-uart0-aeolus.bin"
CHUNK = 65536


def aeolus_stream(mb):
    sample = SAMPLE.read_bytes()
    copies = -(-int(mb * 1_000_000) // len(sample))
    return sample * copies, copies


def mavlink_stream(size, sample_messages):
    """MAVLink 2 bytes, at least `size` long, one message per AEOLUS message of the sample."""
    from pymavlink.dialects.v20 import common as mav

    link = mav.MAVLink(None, srcSystem=1, srcComponent=1)

    def scaled(cls, m, t):
        x = [int(v * 1000) if abs(v) < 30 else 0 for v in (m["x"], m["y"], m["z"])]
        return cls(t, x[0], x[1], x[2], x[1], x[2], x[0], x[2], x[0], x[1], 2150)

    def convert(m):
        t = int(m.get("timestamp_ms", 0)) & 0xFFFFFFFF
        n = m["name"]
        if n == "GYRO":
            return scaled(mav.MAVLink_scaled_imu_message, m, t)
        if n == "ACCEL":
            return scaled(mav.MAVLink_scaled_imu2_message, m, t)
        if n == "MAGNET":
            return scaled(mav.MAVLink_scaled_imu3_message, m, t)
        if n == "ATTITUDE":
            return mav.MAVLink_attitude_message(t, m["roll_rad"], m["pitch_rad"], m["yaw_rad"],
                                                m["slip_ball"], m["turn_coordinator"], m["qz"])
        if n == "COMPASS":
            return mav.MAVLink_vfr_hud_message(30.5, 31.25, int(m["heading_deg"]) % 360, 55, 1000.5, 0.25)
        if n == "PRESSURE":
            return mav.MAVLink_scaled_pressure_message(t, m["static_mbar"], m["pitot_mbar"], 2150, 2150)
        if n == "GPS":
            return mav.MAVLink_gps_raw_int_message(
                t * 1000, 3, int(m["latitude_deg"] * 1e7), int(m["longitude_deg"] * 1e7),
                int(m["altitude_m"] * 1000), 90, 150, int(m["ground_speed_mps"] * 100), 9000,
                m["satellites"], 1000000, 1500, 2500, 300, 1000, 9000)
        if n == "TEMP":
            return mav.MAVLink_scaled_pressure2_message(t, 1013.25, 0.5, int(m["celsius"] * 100), 2150)
        if n == "WIND":
            return mav.MAVLink_wind_cov_message(t * 1000, m["speed_mps"], m["direction_deg"], 0.5,
                                                1.0, 1.0, 1000.0, 1.5, 2.5)
        if n == "TOAST":
            return mav.MAVLink_statustext_message(6, m["text"].encode(), 1, 0)
        if n == "AEOLUSINFO":
            return mav.MAVLink_autopilot_version_message(
                0xFFFF, 0x03080000, 1, 1, 1, [1] * 8, [2] * 8, [3] * 8, 0x1209, 0x5741,
                0x7CDD907E7D0A, [m["model"]] * 18)
        raise ValueError(n)

    one = b"".join(convert(m).pack(link) for m in sample_messages)
    copies = -(-size // len(one))
    return one * copies, copies


def rate(run, repeat):
    best = None
    for _ in range(repeat):
        start = time.perf_counter()
        n = run()
        took = time.perf_counter() - start
        best = took if best is None else min(best, took)
    return n, best


def protolink_rates(data, repeat):
    import protolink

    def feed():
        d = protolink.aeolus.Decoder()
        n = 0
        for i in range(0, len(data), CHUNK):
            n += len(d.feed(data[i:i + CHUNK]))
        return n

    def feed_and_read():
        d = protolink.aeolus.Decoder()
        n = 0
        for i in range(0, len(data), CHUNK):
            for m in d.feed(data[i:i + CHUNK]):
                m.name
                getattr(m, "timestamp_ms", None)
                n += 1
        return n

    def feed_and_to_dict():
        d = protolink.aeolus.Decoder()
        n = 0
        for i in range(0, len(data), CHUNK):
            for m in d.feed(data[i:i + CHUNK]):
                m.to_dict()
                n += 1
        return n

    out = {}
    for label, fn in (("feed", feed), ("feed + name and one field", feed_and_read),
                      ("feed + to_dict()", feed_and_to_dict)):
        n, took = rate(fn, repeat)
        out[label] = (n, took)
    return out


def pymavlink_rate(path, pure, fields=False):
    """Runs in its own process: pymavlink's parse_buffer over the file at `path` (`fields`:
    and every field of every message read)."""
    if pure:
        sys.modules["fastcrc"] = None  # pymavlink falls back to its Python CRC
    from pymavlink.dialects.v20 import common as mav
    from pymavlink.generator import mavcrc

    data = pathlib.Path(path).read_bytes()
    link = mav.MAVLink(None)
    start = time.perf_counter()
    n = 0
    for i in range(0, len(data), CHUNK):
        got = link.parse_buffer(data[i:i + CHUNK])
        if got:
            n += len(got)
            if fields:
                for m in got:
                    for f in m._fieldnames:
                        getattr(m, f)
    took = time.perf_counter() - start
    assert "pymavlink.mavnative" not in sys.modules
    bad = link.total_receive_errors
    return {"messages": n, "seconds": took, "crc": mavcrc.x25crc.__name__, "bad": bad}


def frames_run(path):
    """Runs in its own process: `to_frames` of the AEOLUS file at `path`, once; its time, rows,
    columns, the frames' size and the peak RSS above the process's after the imports."""
    import resource

    import pandas  # noqa: F401  (imported before the baseline, as an analyst's script has it)
    import pyarrow  # noqa: F401
    import protolink

    base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    start = time.perf_counter()
    frames = protolink.to_frames(path, proto="aeolus")
    took = time.perf_counter() - start
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return {"seconds": took, "rows": sum(len(f) for f in frames.values()),
            "columns": sum(len(f.columns) for f in frames.values()),
            "frames_mb": sum(int(f.memory_usage(deep=True).sum()) for f in frames.values()) / 1e6,
            "peak_mb": (peak - base) * 1024 / 1e6}


def columns_bench(aeolus, expected, repeat, mav_file, mav_expected):
    """to_frames of a 100 MB capture beside pymavlink reading every field, and export of ten
    such captures (1 GB) to Parquet by `protolink export`."""
    path = ROOT / "target" / "bench-aeolus.bin"
    path.write_bytes(aeolus)
    runs = []
    for _ in range(repeat):
        out = subprocess.run([sys.executable, __file__, "--frames", str(path)], check=True, capture_output=True,
                             text=True).stdout
        runs.append(json.loads(out))
        assert runs[-1]["rows"] == expected, runs[-1]
    best = min(runs, key=lambda r: r["seconds"])
    out = subprocess.run([sys.executable, __file__, "--peer", "pure-fields", "--file", str(mav_file)],
                         check=True, capture_output=True, text=True).stdout
    peer = json.loads(out)
    assert peer["messages"] == mav_expected and peer["bad"] == 0, peer
    out_dir = ROOT / "target" / "bench-export"
    export_runs = []
    for _ in range(repeat):
        subprocess.run(["rm", "-rf", str(out_dir)], check=True)
        out = subprocess.run([sys.executable, __file__, "--export", str(out_dir), "--file", str(path)],
                             check=True, capture_output=True, text=True).stdout
        run = json.loads(out)
        written = sum(f.stat().st_size for f in out_dir.rglob("*.parquet"))
        export_runs.append((run["seconds"], written, run["line"], run["peak_mb"]))
    path.unlink()
    took, written, line, rss = min(export_runs)
    assert line.startswith(f"export: 10 sources, {10 * len(aeolus)} bytes, {10 * expected} rows"), line
    subprocess.run(["rm", "-rf", str(out_dir)], check=True)
    return best, peer, (took, written, rss)


def export_run(out_dir, path):
    """Runs in its own process: `protolink export` of ten copies of the file at `path` (1 GB)
    into `out_dir`; its time, last line and peak RSS (the only child of this process)."""
    import resource

    binary = os.environ.get("PROTOLINK") or str(ROOT / "target" / "release" / "protolink")
    start = time.perf_counter()
    run = subprocess.run([binary, "export", "--out", out_dir, "--proto", "aeolus", *[path] * 10],
                         check=True, capture_output=True, text=True)
    took = time.perf_counter() - start
    peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss * 1024 / 1e6
    return {"seconds": took, "line": run.stdout.splitlines()[-1], "peak_mb": peak}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mb", type=float, default=100.0, help="stream length in megabytes (default 100)")
    ap.add_argument("--repeat", type=int, default=3, help="protolink runs per figure (the best is kept)")
    ap.add_argument("--peer", choices=["pure", "installed", "pure-fields"], help=argparse.SUPPRESS)
    ap.add_argument("--file", help=argparse.SUPPRESS)
    ap.add_argument("--frames", help=argparse.SUPPRESS)
    ap.add_argument("--export", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.peer:
        print(json.dumps(pymavlink_rate(args.file, args.peer != "installed", args.peer == "pure-fields")))
        return
    if args.frames:
        print(json.dumps(frames_run(args.frames)))
        return
    if args.export:
        print(json.dumps(export_run(args.export, args.file)))
        return

    import pymavlink
    import protolink

    aeolus, copies = aeolus_stream(args.mb)
    sample = [dict(m.to_dict(), name=m.name) for m in protolink.aeolus.Decoder().feed(SAMPLE.read_bytes())]
    mavlink, mcopies = mavlink_stream(len(aeolus), sample)
    expected = len(sample) * copies
    print(f"command: python3 python/bench/bench.py --mb {args.mb:g} --repeat {args.repeat}")
    print(f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores; "
          f"Python {platform.python_version()}; pymavlink {pymavlink.__version__}; protolink {protolink.__version__}")
    print(f"AEOLUS:  {len(aeolus):,} bytes, {expected:,} messages ({len(aeolus) / expected:.1f} bytes each)")
    mav_expected = len(sample) * mcopies
    print(f"MAVLink: {len(mavlink):,} bytes, {mav_expected:,} messages ({len(mavlink) / mav_expected:.1f} bytes each)")

    mav_file = ROOT / "target" / "bench-mavlink.bin"
    mav_file.parent.mkdir(exist_ok=True)
    mav_file.write_bytes(mavlink)
    peers = {}
    for peer in ("pure", "installed"):
        out = subprocess.run([sys.executable, __file__, "--peer", peer, "--file", str(mav_file)],
                             check=True, capture_output=True, text=True).stdout
        peers[peer] = json.loads(out)
        assert peers[peer]["messages"] == mav_expected and peers[peer]["bad"] == 0, peers[peer]
    frames, fields_peer, (export_s, export_bytes, export_rss) = columns_bench(
        aeolus, expected, args.repeat, mav_file, mav_expected)
    mav_file.unlink()

    ours = protolink_rates(aeolus, args.repeat)
    for label, (n, _) in ours.items():
        assert n == expected, (label, n, expected)

    pure = peers["pure"]["messages"] / peers["pure"]["seconds"]
    installed = peers["installed"]["messages"] / peers["installed"]["seconds"]
    print()
    print(f"| decoder | messages/s | MB/s | vs pymavlink pure Python | vs pymavlink + fastcrc |")
    print(f"| --- | ---: | ---: | ---: | ---: |")
    for label, (n, took) in ours.items():
        r = n / took
        print(f"| protolink.aeolus.Decoder: {label} | {r:,.0f} | {len(aeolus) / took / 1e6:.1f} "
              f"| {r / pure:.1f}x | {r / installed:.1f}x |")
    for peer, label in (("pure", f"pymavlink parse_buffer, pure Python ({peers['pure']['crc']})"),
                        ("installed", f"pymavlink parse_buffer as installed ({peers['installed']['crc']}, fastcrc)")):
        p = peers[peer]
        r = p["messages"] / p["seconds"]
        print(f"| {label} | {r:,.0f} | {len(mavlink) / p['seconds'] / 1e6:.1f} | {r / pure:.1f}x | {r / installed:.1f}x |")

    print()
    fr = expected / frames["seconds"]
    fp = fields_peer["messages"] / fields_peer["seconds"]
    print("| columns | seconds | messages/s | MB/s | vs pymavlink pure Python, every field read | memory |")
    print("| --- | ---: | ---: | ---: | ---: | --- |")
    print(f"| protolink.to_frames, {len(aeolus) / 1e6:.0f} MB AEOLUS file to {frames['columns']} columns in "
          f"DataFrames per type | {frames['seconds']:.2f} | {fr:,.0f} | {len(aeolus) / frames['seconds'] / 1e6:.1f} "
          f"| {fr / fp:.1f}x | peak RSS +{frames['peak_mb']:.0f} MB, the frames {frames['frames_mb']:.0f} MB |")
    print(f"| pymavlink parse_buffer, pure Python, every field read (getattr) | {fields_peer['seconds']:.2f} | "
          f"{fp:,.0f} | {len(mavlink) / fields_peer['seconds'] / 1e6:.1f} | 1.0x | |")
    print(f"| protolink export, 10 x {len(aeolus) / 1e6:.0f} MB AEOLUS files to Parquet (snappy) | {export_s:.2f} | "
          f"{10 * expected / export_s:,.0f} | {10 * len(aeolus) / export_s / 1e6:.1f} | | peak RSS {export_rss:.0f} MB, "
          f"{export_bytes / 1e6:.0f} MB written |")


if __name__ == "__main__":
    main()
