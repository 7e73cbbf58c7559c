#!/usr/bin/env python3
"""The sensor-box firmware's CPU budget, measured in QEMU (lm3s6965evb) with -icount shift=0.

Builds the firmware with the `cpu-budget` feature (firmware-example), which accounts SysTick
counts per category (sensor-box's `budget` module) over a window of the box's clock and then
exits through semihosting, and boots it in these scenarios:

  telemetry   figure 1c telemetry on UART0, AYDP and AOK idle (nothing received);
              -icount shift=0,sleep=off: deterministic, run twice and compared
  flood       the same, while UART<k> (--flood-uart, default 0) receives random bytes paced
              at its line rate by this script (host time); -icount shift=0 (sleep on, so the
              virtual clock follows the host while the CPU sleeps): not deterministic, the
              bytes' arrival depends on the host
  realtime    the normal build (`cargo qemu-build`, no icount, as `cargo qemu` runs) under the
              same flood: telemetry frames and late-skipped slots from its 5 s log lines

Prints a markdown section (the "Firmware CPU budget" section of docs/BENCHMARKS.md) on stdout.

  python3 scripts/budget.py [--seconds N] [--flood-uart K] [--no-flood] [--elf ELF]

python3 stdlib only; QEMU's sockets on 127.0.0.1 (ports 17800.. by default, BUDGET_PORT).
"""
import argparse, os, random, re, signal, socket, subprocess, threading, time

root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TARGET = "thumbv7m-none-eabi"
CORE_HZ_REFERENCE = 50_000_000
# The `cpu-budget` builds' core clock in QEMU (SYSDIV 0): what SysTick counts.
CORE_HZ_BUDGET = 200_000_000
BAUD = [921_600, 115_200, 38_400]
DESCRIPTION = {
    "flight-sim": "flight simulation (`Shared::flight_state`, fixed point)",
    "telemetry": "schedule, message building and AEOLUS encoding into the port's TX ring (or the link's queue)",
    "tx-queue": "links' writes of queued bytes into the UART TX rings",
    "tx-irq": "UART interrupts, TX side",
    "rx-irq": "UART interrupts, entry and RX side",
    "aeolus-rx": "AEOLUS link: reading UART0, deframing, handling",
    "aydp": "AYDP link: reading, decoding, handling, its periodic messages",
    "aok": "AOK link: reading, decoding, handling, its debug frames",
    "systick": "SysTick handler (the 1 ms clock)",
    "other": "main loop glue (poll calls, clock reads, the 5 s log)",
}


METHOD = """**Method.** The code marks what it does with `sensor_box::budget::span` (the links, the flight
simulation, the telemetry, the writes into the UART queues) and the interrupt handlers with
`enter`/`leave`; the account keeps one current category and charges the SysTick counts since the
previous switch to it, so nesting charges every instant to exactly one category and the categories
add up to the whole window. The `cpu-budget` build sets the lm3s6965's RCC SYSDIV to 0, which QEMU's
model turns into a 200 MHz core clock: with `-icount shift=0` (1 instruction = 1 ns of virtual
time) one SysTick count is 5 instructions (the log's calibration: `cortex_m::asm::delay`, two
lengths, their difference), against 80 at the reset clock. Each span costs its category and its
parent about one switch of the account each (measured at boot over 2000 switches); that cost is
subtracted and shown as "(account)". **Idle** is not measured from QEMU: under icount the
virtual clock jumps over `wfi` (with `sleep=off` straight to the next timer), so the virtual time
spent asleep says nothing about a real part. The table's idle is 50 MHz minus the busy
instructions (the instructions the firmware needs per second of its own clock on any Cortex-M3);
the virtual time in `wfi` is given beside it only as a check that the emulated CPU was never
saturated. Without the feature, `span` is a plain call: the normal build carries none of it.
"""


def build(features, seconds, target_dir=None):
    env = dict(os.environ, BUDGET_SECONDS=str(seconds), CARGO_BUILD_JOBS=os.environ.get("CARGO_BUILD_JOBS", "1"))
    cmd = ["cargo", "build", "-q", "-p", "firmware-example", "--bin", "sensor-box", "--release",
           "--target", TARGET, "--features", features]
    if target_dir:
        env["CARGO_TARGET_DIR"] = target_dir
    subprocess.run(cmd, cwd=root, env=env, check=True)
    base = target_dir or os.path.join(root, "target")
    return os.path.join(base, TARGET, "release", "sensor-box")


def boot(elf, icount, port, timeout):
    env = dict(os.environ, QEMU_UART0_PORT=str(port), QEMU_UART1_PORT=str(port + 1),
               QEMU_UART2_PORT=str(port + 2), QEMU_WAIT="0")
    env.pop("QEMU_ICOUNT", None)
    if icount:
        env["QEMU_EXTRA"] = "-icount " + icount
    # Its own process group: stopping it stops QEMU and defmt-print too, not only the script.
    return subprocess.Popen([os.path.join(root, "scripts", "qemu-run.sh"), elf], cwd=root, env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True,
                            start_new_session=True)


def stop(q):
    if q.poll() is None:
        try:
            os.killpg(q.pid, signal.SIGTERM)
        except ProcessLookupError:
            pass
        try:
            q.wait(timeout=5)
        except subprocess.TimeoutExpired:
            os.killpg(q.pid, signal.SIGKILL)
            q.wait()


def connect(port, deadline):
    while time.time() < deadline:
        try:
            return socket.create_connection(("127.0.0.1", port), timeout=1)
        except OSError:
            time.sleep(0.05)
    raise RuntimeError(f"no QEMU socket on {port}")


class Flood:
    """UART0 read and discarded; UART<k> fed random bytes at its line rate (10 bits a byte)."""

    def __init__(self, port, uart, seconds):
        self.stop = threading.Event()
        self.sent = 0
        deadline = time.time() + 10
        self.sinks = [connect(port + i, deadline) for i in range(3)]
        self.threads = [threading.Thread(target=self.drain, args=(s,), daemon=True) for s in self.sinks]
        self.threads.append(threading.Thread(target=self.feed, args=(self.sinks[uart], BAUD[uart] // 10, seconds),
                                             daemon=True))
        for t in self.threads:
            t.start()

    def drain(self, s):
        s.settimeout(0.2)
        while not self.stop.is_set():
            try:
                if not s.recv(65536):
                    return
            except socket.timeout:
                continue
            except OSError:
                return

    def feed(self, s, rate, seconds):
        rng = random.Random(14)
        t0 = time.time()
        while not self.stop.is_set() and time.time() - t0 < seconds:
            due = int(rate * (time.time() - t0)) - self.sent
            if due > 0:
                try:
                    s.sendall(rng.randbytes(due))
                except OSError:
                    return
                self.sent += due
            time.sleep(0.005)

    def close(self):
        self.stop.set()
        for s in self.sinks:
            try:
                s.close()
            except OSError:
                pass


def run(elf, icount, port, flood_uart=None, seconds=10, timeout=600):
    q = boot(elf, icount, port, timeout)
    flood = None
    try:
        if flood_uart is not None:
            flood = Flood(port, flood_uart, seconds + 30)
        out, _ = q.communicate(timeout=timeout)
    finally:
        if flood:
            flood.close()
        stop(q)
    return out, (flood.sent if flood else 0)


def parse(log):
    r = {"cat": {}, "tel": {}, "uart": {}}
    for line in log.splitlines():
        if m := re.search(r"budget: calibration (\d+) instructions = (\d+) counts; (\d+) switches = (\d+) counts", line):
            r["ipc"] = int(m[1]) / int(m[2])
            r["switch"] = int(m[4]) * r["ipc"] / int(m[3])
        elif m := re.search(r"budget: window (\d+) ms, systick period (\d+)", line):
            r["window_ms"], r["period"] = int(m[1]), int(m[2])
        elif m := re.search(r"budget: category (\S+) counts (\d+) entries (\d+) nested (\d+)", line):
            r["cat"][m[1]] = (int(m[2]), int(m[3]), int(m[4]))
        elif m := re.search(r"budget: telemetry late-skipped (\d+)", line):
            r["skipped"] = int(m[1])
        elif m := re.search(r"budget: telemetry (\S+) (\d+)", line):
            r["tel"][m[1]] = int(m[2])
        elif m := re.search(r"budget: UART(\d) rx (\d+) dropped (\d+) errors (\d+) tx (\d+)", line):
            r["uart"][int(m[1])] = tuple(int(x) for x in m.groups()[1:])
    if "window_ms" not in r:
        raise RuntimeError("no budget report in the log:\n" + log[-3000:])
    return r


def table(r, label):
    """Markdown rows: per category, instructions per second of the box's clock, net of the
    account's own cost (one switch per span charged to the category and one to its parent)."""
    ipc, sw, secs = r["ipc"], r["switch"], r["window_ms"] / 1000
    rows, busy, overhead = [], 0.0, 0.0
    for name, (counts, entries, nested) in r["cat"].items():
        if name == "idle":
            continue
        raw = counts * ipc
        cost = sw * (entries + nested)
        net = max(raw - cost, 0.0) / secs
        overhead += cost / secs
        busy += net
        rows.append((name, net, entries / secs))
    rows.sort(key=lambda x: -x[1])
    total_counts = sum(c for c, _, _ in r["cat"].values())
    idle_virtual = r["cat"]["idle"][0] / total_counts
    out = [f"| {label}: category | what | instructions / s | share of 50 MHz | spans / s |",
           "| --- | --- | ---: | ---: | ---: |"]
    for name, net, spans in rows:
        out.append(f"| {name} | {DESCRIPTION.get(name, '')} | {net:,.0f} | {100 * net / CORE_HZ_REFERENCE:.2f} % | {spans:,.0f} |")
    out.append(f"| **busy** | sum of the above | **{busy:,.0f}** | **{100 * busy / CORE_HZ_REFERENCE:.2f} %** | |")
    out.append(f"| idle | 50 MHz minus busy | {CORE_HZ_REFERENCE - busy:,.0f} | {100 - 100 * busy / CORE_HZ_REFERENCE:.2f} % | |")
    out.append(f"| (account) | the measurement's own switches, subtracted above | {overhead:,.0f} | {100 * overhead / CORE_HZ_REFERENCE:.2f} % | |")
    notes = (f"Window {r['window_ms']} ms of the box's clock; 1 SysTick count = {ipc:.3f} instructions "
             f"(calibrated), one switch of the account = {sw:.1f} instructions; in QEMU's virtual time "
             f"the CPU slept in `wfi` {100 * idle_virtual:.2f} % of the window.")
    return out, busy, notes


def net_rates(r):
    """Per category: (instructions / s net of the account's switches, spans / s)."""
    ipc, sw, secs = r["ipc"], r["switch"], r["window_ms"] / 1000
    return {name: (max(counts * ipc - sw * (entries + nested), 0.0) / secs, entries / secs)
            for name, (counts, entries, nested) in r["cat"].items()}


# Instructions of the QEMU board's RX interrupt per received byte inside `receive_batched`'s
# loop (FR read and test, DR read, error test, store, pointer step, end test, branch), counted in
# `arm-none-eabi-objdump -d` of the cpu-budget build's `service`; see docs/BENCHMARKS.md. The
# rest of the interrupt's account is charged per interrupt, including the ring's grant and
# commit, which the handler pays once per run of WAKE_BYTES (a share of it per interrupt).
IRQ_LOOP = 11

# Issue 29's targets, per received byte in the flood scenario and per wake of an idle link.
TARGET_LINK, TARGET_BOX, TARGET_IRQ, TARGET_IDLE_WAKE = 20, 40, 10, 20
# Issue 29's quiet budget: figure 1c telemetry, AYDP and AOK idle, as a share of 50 MHz.
TARGET_QUIET = 0.04
# The real part's RX FIFO interrupt level (IFLS: 1/2 full, 8 of 16 bytes; QEMU ignores it).
FIFO_LEVEL = 8


def per_byte(r, u, irq_loop, quiet):
    """The flood's figures per received byte and per wake, against the targets. `irq_loop`:
    instructions of the RX interrupt's per-byte loop (from the disassembly), to split its
    cost into a fixed part per interrupt and a part per byte; `quiet`: the quiet run, whose
    busy instructions a second are the telemetry's load (the same with or without a flood)."""
    secs = r["window_ms"] / 1000
    rate = net_rates(r)
    quiet_busy = sum(v for k, (v, _) in net_rates(quiet).items() if k != "idle")
    rx = r["uart"][u][0] / secs
    if rx <= 0:
        return ["No byte was received in the window."]
    busy = sum(v for k, (v, _) in rate.items() if k != "idle")
    link = rate.get("aeolus-rx", (0, 0))[0] if u == 0 else rate.get(["", "aydp", "aok"][u], (0, 0))[0]
    irq, irqs = rate.get("rx-irq", (0, 0))
    wakes = rate.get("idle", (0, 0))[1]
    fixed = max(irq - irq_loop * rx, 0.0) / irqs if irqs else 0.0
    amortised = fixed / FIFO_LEVEL + irq_loop
    verdict = lambda v, t: f"{'met' if v <= t else 'missed'} (target at most {t})"
    name = ["the AEOLUS link (read, decode, handle)", "the AYDP link", "the AOK link"][u]
    out = [f"Per received byte ({rx:,.0f} B/s of the box's clock; {irqs:,.0f} RX interrupts/s, "
           f"{rx / irqs if irqs else 0:.1f} bytes each; {wakes:,.0f} main-loop wakes/s, "
           f"{rx / wakes if wakes else 0:.1f} bytes each):", ""]
    link_spans = rate.get(["aeolus-rx", "aydp", "aok"][u], (0, 0))[1]
    if link_spans:
        out.append(f"- {name}: **{link / rx:.1f}** instructions per byte: {verdict(link / rx, TARGET_LINK)}.")
    else:
        # A build that marks no span of the link (the async firmware: its reader decodes in its
        # task, counted in "other") has no figure for it alone.
        out.append(f"- {name}: not charged apart in this build (no span of it): its reading and "
                   f"decoding are in \"other\" and in the whole box's figure below.")
    # One SysTick count is CORE_HZ_BUDGET's period: 5 instructions under `-icount shift=0`. A
    # calibration far from it makes every figure of the run suspect by the same factor.
    nominal = 1e9 / CORE_HZ_BUDGET
    check = ("" if abs(r["ipc"] - nominal) <= 0.1 * nominal else
             f" Beware: this run's calibration gave {r['ipc']:.2f} instructions a SysTick count where "
             f"the 200 MHz clock under `-icount shift=0` makes {nominal:g}; every figure of the run "
             f"scales with it.")
    out.append(f"- the whole box: **{busy / rx:.1f}** per byte (busy {busy:,.0f}/s, telemetry included): "
               f"{verdict(busy / rx, TARGET_BOX)}; the quiet run's load ({quiet_busy:,.0f}/s) is in it, "
               f"so it rises as fewer bytes arrive; without it, what the flood itself costs: "
               f"**{max(busy - quiet_busy, 0.0) / rx:.1f}** per byte.{check}")
    out.append(f"- the RX interrupt: **{irq / rx:.1f}** per byte as QEMU raises it ({rx / irqs if irqs else 0:.1f} "
               f"bytes per interrupt; QEMU's PL011 ignores the FIFO level); split with the per-byte loop of "
               f"{irq_loop} instructions (disassembly of `service`): {fixed:.0f} per interrupt plus {irq_loop} "
               f"per byte, so **{amortised:.1f}** per byte amortised at the real part's level of "
               f"{FIFO_LEVEL} bytes per interrupt: {verdict(amortised, TARGET_IRQ)}.")
    for other in ("aeolus-rx", "aydp", "aok"):
        if other == ("aeolus-rx", "aydp", "aok")[u]:
            continue
        v, spans = rate.get(other, (0, 0))
        out.append(f"- {other} (no byte received): ran {spans:,.0f} times/s for its own timer, "
                   f"{v / spans if spans else 0:,.0f} instructions a run; on the other "
                   f"{max(wakes - spans, 0):,.0f} wakes/s it is not run (its `has_work` test, in "
                   f"\"other\")")
    return out


def real_part(quiet, r, u, irq_loop):
    """What the flood would cost a real 50 MHz Cortex-M3 at the true line rate, from this run's
    per-byte and per-interrupt figures (the real PL011 interrupts once per FIFO_LEVEL bytes)."""
    secs = r["window_ms"] / 1000
    rate, q = net_rates(r), net_rates(quiet)
    rx = r["uart"][u][0] / secs
    line = BAUD[u] / 10
    irq, irqs = rate.get("rx-irq", (0, 0))
    fixed = max(irq - irq_loop * rx, 0.0) / irqs if irqs else 0.0
    link_cat = ("aeolus-rx", "aydp", "aok")[u]
    link = (rate.get(link_cat, (0, 0))[0] - q.get(link_cat, (0, 0))[0]) / rx
    other_wake = (rate.get("other", (0, 0))[0] - q.get("other", (0, 0))[0]) / max(
        rate.get("idle", (0, 0))[1] - q.get("idle", (0, 0))[1], 1)
    interrupts = line / FIFO_LEVEL
    flood = line * (link + irq_loop) + interrupts * (fixed + other_wake)
    quiet_busy = sum(v for k, (v, _) in q.items() if k != "idle")
    total = flood + quiet_busy
    return (f"**On a real part** (50 MHz Cortex-M3, UART{u} flooded at its true line rate, {line:,.0f} B/s, "
            f"an RX interrupt and a main-loop wake per {FIFO_LEVEL} bytes: {interrupts:,.0f}/s), from this run's "
            f"figures: {line:,.0f} x ({link:.1f} link + {irq_loop} interrupt loop) + {interrupts:,.0f} x "
            f"({fixed:.0f} interrupt entry + {other_wake:.0f} main-loop glue per wake) = {flood / 1e6:.2f} M "
            f"instructions/s for the flood, plus {quiet_busy / 1e6:.2f} M for the quiet load: "
            f"{100 * total / CORE_HZ_REFERENCE:.1f} % of 50 MHz.")


def telemetry_line(r, base=None):
    secs = r["window_ms"] / 1000
    parts = []
    for k in ("GYRO", "PRESSURE", "GPS"):
        n = r["tel"].get(k, 0) / secs
        share = f" ({100 * r['tel'][k] / base['tel'][k]:.1f} % of the quiet run)" if base and base["tel"].get(k) else ""
        parts.append(f"{k} {n:.1f}/s{share}")
    u = r["uart"]
    rx = ", ".join(f"UART{i} rx {u[i][0] / secs:,.0f} B/s (dropped {u[i][1]}, errors {u[i][2]})" for i in sorted(u) if u[i][0] or u[i][1])
    return "; ".join(parts) + f"; late-skipped slots {r.get('skipped', 0)}" + (f"; {rx}" if rx else "")


def realtime_flood(port, uart, seconds):
    """The normal build, no icount, same flood: AEOLUS telemetry from its 5 s log lines."""
    elf = build("board-qemu", seconds, os.path.join(root, "target", "budget-normal"))
    q = boot(elf, None, port, 60)
    flood = Flood(port, uart, 12)
    lines = []
    t0 = time.time()
    try:
        while time.time() - t0 < 14:
            line = q.stdout.readline()
            if not line:
                break
            lines.append(line)
            if "uptime 10" in line:
                # the AEOLUS line follows the UART lines
                for _ in range(4):
                    lines.append(q.stdout.readline())
                break
    finally:
        flood.close()
        stop(q)
    tel = [(int(m[1]), int(m[2])) for l in lines if (m := re.search(r"AEOLUS: telemetry (\d+) frames.*late skipped (\d+)", l))]
    rx = [int(m[1]) for l in lines if (m := re.search(rf"UART{uart}: rx (\d+)", l))]
    return tel, rx, flood.sent


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--seconds", type=int, default=10)
    ap.add_argument("--flood-uart", type=int, default=0, choices=[0, 1, 2])
    ap.add_argument("--no-flood", action="store_true")
    ap.add_argument("--no-realtime", action="store_true")
    ap.add_argument("--elf", help="a cpu-budget build to run instead of building one")
    ap.add_argument("--irq-loop", type=int, default=IRQ_LOOP,
                    help="instructions of the RX interrupt's per-byte loop (disassembly)")
    a = ap.parse_args()
    port = int(os.environ.get("BUDGET_PORT", "17800"))
    elf = a.elf or build("cpu-budget", a.seconds)
    quiet = [parse(run(elf, "shift=0,sleep=off", port, seconds=a.seconds)[0]) for _ in range(2)]
    same = quiet[0] == quiet[1]
    rows, busy, notes = table(quiet[0], "telemetry")
    print("## Firmware CPU budget\n")
    print(f"`python3 scripts/budget.py` (run by `scripts/bench.py`): the `cpu-budget` build of the QEMU board "
          f"(`cargo build -p firmware-example --release --target {TARGET} --features cpu-budget`) in "
          f"lm3s6965evb under `-icount shift=0`, {a.seconds} s of the box's clock after 1 s of warm-up. "
          f"Instructions are a lower bound of the cycles a real Cortex-M3 spends (loads, taken branches "
          f"and flash wait states add cycles); the share is of 50 MHz.\n")
    print(f"**Figure 1c telemetry, AYDP and AOK idle** (nothing received; `-icount shift=0,sleep=off`). "
          f"Two runs: {'identical account' if same else 'the two runs DIFFER'}. "
          f"Target (issue 29): at most {100 * TARGET_QUIET:g} % of 50 MHz "
          f"({TARGET_QUIET * CORE_HZ_REFERENCE:,.0f} instructions/s): "
          f"{'met' if busy <= TARGET_QUIET * CORE_HZ_REFERENCE else 'missed'} "
          f"({100 * busy / CORE_HZ_REFERENCE:.2f} %; issue 14's 5 %: "
          f"{'met' if busy <= 0.05 * CORE_HZ_REFERENCE else 'missed'}).\n")
    print("\n".join(rows))
    print(f"\n{notes} Telemetry: {telemetry_line(quiet[0])}.\n")
    print(METHOD)
    if not a.no_flood:
        u = a.flood_uart
        out, sent = run(elf, "shift=0", port + 10, flood_uart=u, seconds=a.seconds)
        fl = parse(out)
        rows, busy_f, notes = table(fl, "flood")
        print(f"**The same, while UART{u} receives random bytes at its line rate** ({BAUD[u]} Bd, "
              f"{BAUD[u] // 10} B/s paced by the script in host time; `-icount shift=0`, so the bytes' "
              f"arrival follows the host: not deterministic). {sent} bytes sent.\n")
        print("\n".join(rows))
        print(f"\n{notes} Telemetry: {telemetry_line(fl, quiet[0])}.\n")
        print("\n".join(per_byte(fl, u, a.irq_loop, quiet[0])) + "\n")
        print(real_part(quiet[0], fl, u, a.irq_loop) + "\n")
        if not a.no_realtime:
            tel, rx, sent = realtime_flood(port + 20, u, a.seconds)
            if len(tel) >= 2:
                (f5, s5), (f10, s10) = tel[0], tel[1]
                nominal = sum(quiet[0]["tel"].values()) / (quiet[0]["window_ms"] / 1000) * 5
                rxs = f"; UART{u} rx {rx[1] - rx[0]} B in those 5 s" if len(rx) >= 2 else ""
                print(f"**The normal build in real time** (`cargo qemu-build`, no icount, as `cargo qemu` runs it) "
                      f"under the same flood: from 5 s to 10 s of the box's clock, {f10 - f5} telemetry frames "
                      f"({100 * (f10 - f5) / nominal:.1f} % of the quiet run's rate), {s10 - s5} late-skipped "
                      f"slots{rxs}; {sent} bytes sent.\n")
            else:
                print("**The normal build in real time**: no 10 s log line within 14 s of host time.\n")


if __name__ == "__main__":
    main()
