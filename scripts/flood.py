#!/usr/bin/env python3
"""Measures protolink under a loopback flood: peak RSS of `decode`, `sim` and `bridge`, and
the share of telemetry that `bridge` forwards while its UDP in-port is flooded.

    python3 scripts/flood.py                 10 s floods (about a minute in all)
    python3 scripts/flood.py --seconds 3     shorter floods
    python3 scripts/flood.py --bin PATH      an already-built protolink (no cargo build)

Runs (each protolink in a fresh process, its peak RSS read from /proc/PID/status VmHWM every
50 ms and from wait4's ru_maxrss at exit, the larger kept):

  decode stdin   `decode --proto aeolus --from -`, a producer writes random bytes mixed with
                 valid GYRO frames (and some with a bad CRC) into its stdin as fast as it can
  decode udp     `decode --proto aeolus --from udp:PORT`, flooded with 1400-byte datagrams
                 (garbage, and datagrams of packed valid frames)
  sim            `sim --udp-out P1 --udp-in P2`, P2 flooded with 1400-byte garbage; right after
                 the flood a COMMAND "a pause" goes to P2 and telemetry on P1 must stop
                 within 1 s (then "a resume" is sent)
  bridge         `bridge --uart tcp:...` against a fake UART that streams GYRO frames at a
                 known rate (1000 frames/s) while the bridge's --udp-in is flooded; counts the
                 distinct GYRO frames that come out on P1 and the bytes the fake UART got back.
                 Like a real UART, the fake one reads back at a baud rate (--uart-baud, 921600)
                 and drops what does not fit in its 4 KiB transmit buffer; a second run
                 (bridge-unthrottled) reads back as fast as it can.

Prints a Markdown table and exits 0: it is a measurement, not a test. Every address is
127.0.0.1; every loop ends by a deadline; a protolink whose RSS passes --rss-cap-mb is killed
(and reported as such) so that a runaway queue cannot take the machine down.
The script needs only Python 3 (stdlib).
"""

import argparse
import os
import random
import select
import signal
import socket
import struct
import subprocess
import sys
import threading
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
HOST = "127.0.0.1"
TARGET_RSS_MB = 50.0
TARGET_FORWARDED = 99.0
GYRO_ID = 62
COMMAND_ID = 11
TOAST_ID = 82
TELEMETRY_IDS = {51, 61, 62, 63, 64, 65, 66, 71, 72, 73}
DATAGRAM = 1400
UART_BUFFER = 4096

# ------------------------------------------------------------------ AEOLUS framing


def _crc_table():
    table = []
    for i in range(256):
        crc = i << 8
        for _ in range(8):
            crc = ((crc << 1) ^ (0x1021 if crc & 0x8000 else 0)) & 0xFFFF
        table.append(crc)
    return table


CRC_LUT = _crc_table()


def crc16(data):
    """The AEOLUS CRC (spec section 4.3): `crc = lut[crc >> 8] ^ (crc << 8) ^ byte`, init 0."""
    crc = 0
    for b in data:
        crc = CRC_LUT[crc >> 8] ^ ((crc << 8) & 0xFFFF) ^ b
    return crc


def check_crc_vectors():
    """Checks crc16 against the vectors made from the spec's C code; exits on a mismatch."""
    for path in (os.path.join(ROOT, "testdata/aeolus-crc.txt"),
                 os.path.join(ROOT, "../shared/vectors/aeolus-crc.txt")):
        if os.path.isfile(path):
            break
    else:
        print("flood.py: no aeolus-crc.txt vectors found; CRC unchecked", file=sys.stderr)
        return
    n = 0
    with open(path) as f:
        for line in f:
            line = line.strip()
            if not line or line.startswith("#"):
                continue
            data, want = line.split()
            data = b"" if data == "-" else bytes.fromhex(data)
            if crc16(data) != int(want, 16):
                sys.exit(f"flood.py: CRC mismatch on vector {line[:40]}...: "
                         f"computed {crc16(data):04x}")
            n += 1
    print(f"CRC checked against {n} vectors in {os.path.relpath(path, ROOT)}", file=sys.stderr)


def frame(msg_id, data):
    """One AEOLUS frame: flag, escaped ID + data + CRC (LSB first), flag."""
    body = bytes([msg_id]) + data
    crc = crc16(body)
    body += bytes([crc & 0xFF, crc >> 8])
    out = bytearray([0x7E])
    for b in body:
        if b in (0x7E, 0x7D):
            out += bytes([0x7D, b ^ 0x20])
        else:
            out.append(b)
    out.append(0x7E)
    return bytes(out)


def gyro(seq):
    """A GYRO frame (ID 62, 32 data bytes) whose timestamp is `seq` ms, so frames are counted
    one by one."""
    data = struct.pack("<B7xdfff4x", 1, float(seq), 0.01, -0.02, 0.03)
    return frame(GYRO_ID, data)


def command(text):
    """A COMMAND frame (ID 11): the text and its NUL."""
    return frame(COMMAND_ID, text.encode() + b"\0")


def deframe(buf):
    """The (id, data) of every frame with a good CRC (or none, 00 00) in `buf`."""
    out = []
    for part in buf.split(b"\x7e"):
        if len(part) < 3:
            continue
        raw = bytearray()
        esc = False
        bad = False
        for b in part:
            if esc:
                raw.append(b ^ 0x20)
                esc = False
            elif b == 0x7D:
                esc = True
            else:
                raw.append(b)
        if esc or len(raw) < 3:
            bad = True
        if bad:
            continue
        body, got = raw[:-2], raw[-2] | (raw[-1] << 8)
        if got == 0 or crc16(body) == got:
            out.append((body[0], bytes(body[1:])))
    return out


# ------------------------------------------------------------------ helpers


def free_port(kind=socket.SOCK_DGRAM):
    s = socket.socket(socket.AF_INET, kind)
    s.bind((HOST, 0))
    port = s.getsockname()[1]
    s.close()
    return port


def garbage_pool(rng, n=64, size=DATAGRAM):
    return [bytes(rng.getrandbits(8) for _ in range(size)) for _ in range(n)]


def mixed_stream(rng, size=1 << 20):
    """Random bytes mixed with valid GYRO frames and, now and then, one with a bad CRC."""
    out = bytearray()
    seq = 0
    noise = bytes(rng.getrandbits(8) for _ in range(4096))
    while len(out) < size:
        k = rng.randrange(0, 200)
        start = rng.randrange(0, len(noise) - k)
        out += noise[start:start + k]
        f = bytearray(gyro(seq))
        seq += 1
        if seq % 10 == 0:
            f[5] ^= 0x01  # a data byte: the CRC no longer matches
        out += f
    return bytes(out)


class Flooder:
    """A child process (this script, `_flood` mode) that sends UDP datagrams to 127.0.0.1:PORT
    as fast as it can for SECONDS; `join()` returns how many it sent."""

    def __init__(self, port, seconds, mode):
        self.proc = subprocess.Popen(
            [sys.executable, os.path.abspath(__file__), "_flood", str(port), str(seconds), mode],
            stdout=subprocess.PIPE, text=True)

    def join(self, timeout):
        try:
            out, _ = self.proc.communicate(timeout=timeout)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            out, _ = self.proc.communicate()
        try:
            return int(out.strip().split()[-1])
        except (ValueError, IndexError):
            return 0


def flood_main(port, seconds, mode):
    """The flooder process: garbage datagrams, or (mode "mixed") every other one packed with
    valid GYRO frames."""
    rng = random.Random(port)
    pool = garbage_pool(rng)
    if mode == "mixed":
        packed = b"".join(gyro(i) for i in range(30))[:DATAGRAM]
        packed = packed[:packed.rfind(b"\x7e") + 1]
        pool = [d for g in pool for d in (g, packed)]
    s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    s.connect((HOST, port))
    sent = 0
    deadline = time.monotonic() + seconds
    n = len(pool)
    while time.monotonic() < deadline:
        for i in range(256):
            try:
                s.send(pool[(sent + i) % n])
            except OSError:  # ECONNREFUSED while nobody listens yet, ENOBUFS
                pass
        sent += 256
    print(sent)


def status_kb(pid, field):
    try:
        with open(f"/proc/{pid}/status") as f:
            for line in f:
                if line.startswith(field + ":"):
                    return int(line.split()[1])
    except (OSError, ValueError):
        pass
    return 0


class Run:
    """One protolink process: started, watched (peak RSS), stopped by its deadline."""

    def __init__(self, binary, args, cap_mb, stdin=None):
        self.cmd = [binary] + args
        self.proc = subprocess.Popen(self.cmd, stdin=stdin, stdout=subprocess.PIPE,
                                     stderr=subprocess.PIPE)
        self.cap_kb = cap_mb * 1024
        self.peak_kb = 0
        self.killed_for_rss = False
        self.exit = None
        self.out_tail = b""
        self.err_tail = b""
        self.out_bytes = 0
        self._readers = [threading.Thread(target=self._drain, args=(self.proc.stdout, "out"),
                                          daemon=True),
                         threading.Thread(target=self._drain, args=(self.proc.stderr, "err"),
                                          daemon=True)]
        for t in self._readers:
            t.start()
        self.deadline = None
        self._watcher = threading.Thread(target=self._monitor, daemon=True)
        self._watcher.start()

    def _drain(self, pipe, which):
        """Reads everything (quickly, so the tool is never held up by its stdout) and keeps
        the last 4 KiB."""
        tail = b""
        while True:
            chunk = pipe.read1(1 << 20) if hasattr(pipe, "read1") else pipe.read(1 << 16)
            if not chunk:
                break
            if which == "out":
                self.out_bytes += len(chunk)
            tail = (tail + chunk)[-4096:]
            setattr(self, which + "_tail", tail)

    def _monitor(self):
        """From the start to the exit: the peak RSS (VmHWM, every 50 ms, and wait4's
        ru_maxrss at the exit), the RSS cap, and the deadline set by `watch` (SIGTERM, then
        SIGKILL 3 s later). Bounded: a process still running after 10 minutes is killed."""
        pid = self.proc.pid
        hard = time.monotonic() + 600
        term_sent = None
        while True:
            self.peak_kb = max(self.peak_kb, status_kb(pid, "VmHWM"))
            if status_kb(pid, "VmRSS") > self.cap_kb and not self.killed_for_rss:
                self.killed_for_rss = True
                os.kill(pid, signal.SIGKILL)
            wpid, status, usage = os.wait4(pid, os.WNOHANG)
            if wpid == pid:
                self.peak_kb = max(self.peak_kb, usage.ru_maxrss)  # KiB on Linux
                self.proc.returncode = os.waitstatus_to_exitcode(status)
                self.exit = self.proc.returncode
                return
            now = time.monotonic()
            deadline = min(self.deadline or hard, hard)
            if now > deadline and term_sent is None:
                os.kill(pid, signal.SIGTERM)
                term_sent = now
            elif term_sent is not None and now > term_sent + 3:
                os.kill(pid, signal.SIGKILL)
            time.sleep(0.05)

    @property
    def running(self):
        return self.exit is None

    def watch(self, timeout):
        """Waits for the exit (stopping the process after `timeout`); the exit status."""
        self.deadline = time.monotonic() + timeout
        self._watcher.join(timeout=timeout + 10)
        for t in self._readers:
            t.join(timeout=5)
        return self.exit

    @property
    def peak_mb(self):
        return self.peak_kb / 1024.0

    def last_line(self, which="out"):
        lines = getattr(self, which + "_tail").decode(errors="replace").strip().splitlines()
        return lines[-1] if lines else ""

    def note(self):
        """What went wrong, if anything, in a few words."""
        if self.killed_for_rss:
            return f"killed when its RSS passed {self.cap_kb // 1024} MB"
        if self.exit not in (0, None):
            err = self.last_line("err")
            return f"exit {self.exit}" + (f": {err[:120]}" if err else "")
        return ""


def seconds_arg(binary):
    """`--seconds` takes a number today and a duration with a unit (`2s`) after the rewrite;
    the first form the binary accepts."""
    for form in ("1", "1s"):
        p = subprocess.run([binary, "decode", "--proto", "aeolus", "--from", "file:/dev/null",
                            "--seconds", form], stdout=subprocess.DEVNULL,
                           stderr=subprocess.DEVNULL, timeout=30)
        if p.returncode != 2:
            return (lambda n: str(n)) if form == "1" else (lambda n: f"{n}s")
    return lambda n: str(n)


# ------------------------------------------------------------------ the runs


def run_decode_stdin(binary, secs, cap_mb, sec):
    rng = random.Random(1)
    chunk = mixed_stream(rng)
    run = Run(binary, ["decode", "--proto", "aeolus", "--from", "-", "--seconds", sec(secs)],
              cap_mb, stdin=subprocess.PIPE)
    fd = run.proc.stdin.fileno()
    os.set_blocking(fd, False)
    written = 0
    view = memoryview(chunk)
    pos = 0
    deadline = time.monotonic() + secs
    while time.monotonic() < deadline and run.running:
        _, w, _ = select.select([], [fd], [], 0.1)
        if not w:
            continue
        try:
            n = os.write(fd, view[pos:pos + 65536])
        except BlockingIOError:
            continue
        except (BrokenPipeError, OSError):
            break
        written += n
        pos = (pos + n) % len(chunk)
        if len(chunk) - pos < 65536:
            pos = 0
    try:
        run.proc.stdin.close()
    except OSError:
        pass
    run.watch(timeout=15)
    return {
        "what": f"decode --from - ({secs} s stdin flood)",
        "rss": run,
        "note": f"{written / 1e6:.0f} MB written; {run.out_bytes / 1e6:.0f} MB printed; "
                f"{summary_short(run.last_line())}",
    }


def summary_short(line):
    if not line.startswith("summary"):
        return "no summary line"
    fields = dict(kv.split("=", 1) for kv in line.split()[1:] if "=" in kv)
    return " ".join(f"{k}={fields[k]}" for k in ("bytes", "frames_ok", "checksum_errors")
                    if k in fields) or line[:80]


def run_decode_udp(binary, secs, cap_mb, sec):
    port = free_port()
    run = Run(binary, ["decode", "--proto", "aeolus", "--from", f"udp:{port}",
                       "--seconds", sec(secs + 1)], cap_mb)
    time.sleep(0.5)
    sent = Flooder(port, secs, "mixed").join(timeout=secs + 10)
    run.watch(timeout=15)
    return {
        "what": f"decode --from udp ({secs} s UDP flood)",
        "rss": run,
        "note": f"{sent} datagrams sent; {summary_short(run.last_line())}",
    }


class UdpCounter:
    """Receives on 127.0.0.1:PORT on a thread; keeps each datagram's arrival time and frames."""

    def __init__(self, port):
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 8 << 20)
        self.sock.bind((HOST, port))
        self.sock.settimeout(0.1)
        self.datagrams = 0
        self.frames = []  # (arrival, id, data)
        self.stop_at = None
        self.thread = threading.Thread(target=self._loop, daemon=True)
        self.thread.start()

    def _loop(self):
        hard_stop = time.monotonic() + 600
        while time.monotonic() < hard_stop and (self.stop_at is None
                                                or time.monotonic() < self.stop_at):
            try:
                d = self.sock.recv(65536)
            except socket.timeout:
                continue
            except OSError:
                break
            now = time.monotonic()
            self.datagrams += 1
            for msg_id, data in deframe(d):
                self.frames.append((now, msg_id, data))

    def stop(self):
        self.stop_at = time.monotonic()
        self.thread.join(timeout=5)
        self.sock.close()


def run_sim(binary, secs, cap_mb, sec):
    out_port, in_port = free_port(), free_port()
    rx = UdpCounter(out_port)
    run = Run(binary, ["sim", "--udp-out", f"{HOST}:{out_port}", "--udp-in", str(in_port),
                       "--seconds", sec(secs + 3)], cap_mb)
    time.sleep(0.5)
    before = sum(1 for f in rx.frames if f[1] in TELEMETRY_IDS)
    sent = Flooder(in_port, secs, "garbage").join(timeout=secs + 10)
    s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    t_cmd = time.monotonic()
    s.sendto(command("a pause"), (HOST, in_port))
    # Paused: no telemetry arrives between 1 s and 2 s after the command.
    time.sleep(2.0)
    late = [f for f in rx.frames if f[1] in TELEMETRY_IDS and f[0] > t_cmd + 1.0]
    last_tel = max((f[0] for f in rx.frames if f[1] in TELEMETRY_IDS), default=None)
    paused = run.running and not late
    s.sendto(command("a resume"), (HOST, in_port))
    s.close()
    run.watch(timeout=10)
    rx.stop()
    if paused:
        stopped = max(0.0, last_tel - t_cmd) if last_tel is not None else 0.0
        acted = f"yes: telemetry stopped {stopped:.2f} s after the command"
    elif run.killed_for_rss or (run.exit is not None and run.exit != 0):
        acted = "unknown (sim stopped before the check)"
    else:
        acted = f"no: {len(late)} telemetry frames 1..2 s after it"
    during = sum(1 for f in rx.frames if f[1] in TELEMETRY_IDS and f[0] <= t_cmd)
    toasts = [(f[0] - t_cmd, f[2].rstrip(b"\0").decode(errors="replace")) for f in rx.frames
              if f[1] == TOAST_ID and t_cmd < f[0] <= t_cmd + 2.0]
    answer = (f"TOAST \"{toasts[0][1]}\" {toasts[0][0]:.2f} s after it" if toasts
              else "no TOAST answer within 2 s")
    return {
        "what": f"sim, --udp-in flooded ({secs} s)",
        "rss": run,
        "note": f"{sent} datagrams sent; telemetry frames received {before} before, "
                f"{during - before} during the flood; \"a pause\" acted on: {acted}; {answer}",
        "paused": paused,
    }


def run_bridge(binary, secs, cap_mb, sec, baud, rate=1000):
    """`bridge` against a fake UART: a TCP server that sends GYRO frames at `rate` per second
    (frame k's timestamp is k ms, so each one is counted once) and reads back what the bridge
    writes to it at `baud` (bits/s, 10 per byte; 0: as fast as it can). Like a real UART, it
    never waits to send: a frame that does not fit in its 4 KiB transmit buffer (the bridge is
    not reading) is dropped."""
    uart = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    uart.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    # Small socket buffers, so that a bridge that stops reading is felt within milliseconds
    # (set on the listener, the accepted socket inherits them).
    uart.setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, UART_BUFFER)
    uart.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4 * UART_BUFFER)
    uart.bind((HOST, 0))
    uart.listen(1)
    uart.settimeout(10)
    uart_port = uart.getsockname()[1]
    out_port, in_port = free_port(), free_port()
    rx = UdpCounter(out_port)
    nominal = rate * secs
    frames = [gyro(i) for i in range(nominal)]
    state = {"sent": 0, "dropped": 0, "back": 0, "start": None, "error": None}

    def fake_uart():
        try:
            conn, _ = uart.accept()
        except OSError as e:
            state["error"] = f"the bridge never connected ({e})"
            return
        conn.setblocking(False)
        pending = b""
        start = time.monotonic()
        state["start"] = start
        end = start + secs
        hold = end + 4  # stays connected until the bridge's own --seconds ends it
        next_frame = 0
        read_budget = 0.0
        last = start
        while True:
            now = time.monotonic()
            if now >= hold:
                break
            due = min(nominal, int((now - start) * rate) + 1)
            while next_frame < due:
                f = frames[next_frame]
                next_frame += 1
                if len(pending) + len(f) <= UART_BUFFER:
                    pending += f
                    state["sent"] += 1
                else:
                    state["dropped"] += 1
            if baud:
                read_budget = min(read_budget + (now - last) * baud / 10, 4096)
            last = now
            want_read = not baud or read_budget >= 1
            r, w, _ = select.select([conn] if want_read else [], [conn] if pending else [],
                                    [], 0.001)
            if r:
                try:
                    d = conn.recv(int(read_budget) if baud else 1 << 20)
                except (BlockingIOError, InterruptedError):
                    d = None
                except OSError:
                    break
                if d == b"":
                    break
                if d:
                    state["back"] += len(d)
                    read_budget -= len(d)
            if w and pending:
                try:
                    n = conn.send(pending)
                    pending = pending[n:]
                except (BlockingIOError, InterruptedError):
                    pass
                except OSError:
                    break
            if not r and not w and not pending and next_frame >= nominal and not want_read:
                time.sleep(0.001)
        conn.close()

    server = threading.Thread(target=fake_uart, daemon=True)
    server.start()
    run = Run(binary, ["bridge", "--uart", f"tcp:{HOST}:{uart_port}",
                       "--udp-out", f"{HOST}:{out_port}", "--udp-in", str(in_port),
                       "--seconds", sec(secs + 2)], cap_mb)
    time.sleep(0.3)
    sent = Flooder(in_port, secs, "garbage").join(timeout=secs + 10)
    run.watch(timeout=15)
    server.join(timeout=10)
    uart.close()
    time.sleep(0.2)
    rx.stop()
    first = {}
    for t, i, data in rx.frames:
        if i == GYRO_ID and len(data) == 32:
            seq = int(struct.unpack_from("<d", data, 8)[0])
            first.setdefault(seq, t)
    start = state["start"] or 0.0
    late = sum(1 for seq, t in first.items() if t - (start + seq / rate) > 1.0)
    forwarded = 100.0 * len(first) / nominal if nominal else 0.0
    speed = f"{baud} baud" if baud else "full speed"
    note = (f"{len(first)} of {nominal} GYRO frames ({rate}/s for {secs} s) out on --udp-out in "
            f"{rx.datagrams} datagrams, {late} of them more than 1 s late; the fake UART sent "
            f"{state['sent']} and dropped {state['dropped']} (its 4 KiB buffer full); "
            f"{sent} flood datagrams sent, {state['back'] / 1e6:.1f} MB written back to the "
            f"fake UART")
    if state["error"]:
        note += "; " + state["error"]
    return {"what": f"bridge, --udp-in flooded ({secs} s), fake UART reads at {speed}",
            "rss": run, "note": note, "forwarded": forwarded,
            "fw_what": f"bridge (fake UART reads at {speed}): telemetry forwarded"}


# ------------------------------------------------------------------ report


def table(results, secs):
    rows = ["| what | peak RSS (MB) | target | met? | notes |", "| --- | --- | --- | --- | --- |"]
    for r in results:
        run = r["rss"]
        mb = run.peak_mb
        met = "no" if run.killed_for_rss or mb > TARGET_RSS_MB else "yes"
        shown = f"> {mb:.0f}" if run.killed_for_rss else f"{mb:.1f}"
        note = "; ".join(x for x in (run.note(), r["note"]) if x)
        rows.append(f"| {r['what']} | {shown} | {TARGET_RSS_MB:.0f} MB | {met} | {note} |")
        if "forwarded" in r:
            fw = r["forwarded"]
            rows.append(f"| {r['fw_what']} | {fw:.1f} % | "
                        f"{TARGET_FORWARDED:.0f} % | {'yes' if fw >= TARGET_FORWARDED else 'no'} "
                        f"| distinct GYRO frames out on --udp-out while the bridge ran, share "
                        f"of the nominal count |")
    return "\n".join(rows)


def main():
    if len(sys.argv) == 5 and sys.argv[1] == "_flood":
        flood_main(int(sys.argv[2]), float(sys.argv[3]), sys.argv[4])
        return 0
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seconds", type=int, default=10, help="flood length (default 10)")
    ap.add_argument("--bin", help="protolink binary to measure (default: build the release one)")
    ap.add_argument("--rss-cap-mb", type=int, default=4096,
                    help="kill a protolink whose RSS passes this (default 4096)")
    ap.add_argument("--uart-baud", type=int, default=921600,
                    help="how fast the bridge's fake UART reads back what the bridge writes to "
                         "it (default 921600; the bridge-unthrottled run reads at full speed)")
    ap.add_argument("--only", nargs="*",
                    choices=["decode-stdin", "decode-udp", "sim", "bridge", "bridge-unthrottled"],
                    help="run only these")
    args = ap.parse_args()
    secs = max(1, args.seconds)
    check_crc_vectors()
    binary = args.bin
    if not binary:
        env = dict(os.environ)
        env.setdefault("CARGO_BUILD_JOBS", "1")
        print("building: cargo build --release -p protolink", file=sys.stderr)
        subprocess.run(["cargo", "build", "-q", "--release", "-p", "protolink"], cwd=ROOT,
                       env=env, check=True)
        binary = os.path.join(ROOT, "target/release/protolink")
    sec = seconds_arg(binary)
    runs = [("decode-stdin", run_decode_stdin), ("decode-udp", run_decode_udp),
            ("sim", run_sim),
            ("bridge", lambda *a: run_bridge(*a, baud=args.uart_baud)),
            ("bridge-unthrottled", lambda *a: run_bridge(*a, baud=0))]
    results = []
    for name, fn in runs:
        if args.only and name not in args.only:
            continue
        t0 = time.monotonic()
        print(f"{name}: {secs} s flood ...", file=sys.stderr, flush=True)
        r = fn(binary, secs, args.rss_cap_mb, sec)
        print(f"{name}: done in {time.monotonic() - t0:.1f} s, peak RSS {r['rss'].peak_mb:.1f} MB",
              file=sys.stderr, flush=True)
        results.append(r)
    print(f"\nprotolink under a {secs} s loopback flood ({os.path.relpath(binary, ROOT)}):\n")
    print(table(results, secs))
    return 0


if __name__ == "__main__":
    sys.exit(main())
