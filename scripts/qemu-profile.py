#!/usr/bin/env python3
"""Executed instructions per function of a firmware ELF in QEMU (lm3s6965evb).

QEMU logs every translation block it translates (`-d in_asm`: its instructions) and every
block it executes (`-d exec,nochain`: its address); this script adds them up per function of
the ELF's symbol table. Under `-icount shift=0,sleep=off` the count is deterministic. It is the
profile behind the budget's categories: which functions the instructions of a category are.

  python3 scripts/qemu-profile.py ELF [--seconds S] [--top N] [--tick SYMBOL]
                                      [--blocks NAME | --callers NAME]

Limits: the count of code that makes several I/O accesses in one block (the UART handler's
FIFO loop) comes out too high: QEMU splits such a block at each access, and only the first
cut is recognised (the handler measured 369 k instructions a second here where the budget's
SysTick account, `scripts/budget.py`, gives 282 k). For such code the account is the figure.

--blocks NAME: per block of the functions whose name contains NAME (start address, its
instructions, how often it ran); --callers NAME: how often each function entered it (the block
run just before its first one).

The ELF runs for S seconds of host time (the log grows by about 1 GB a minute), then QEMU is
stopped. Counts are divided by the number of times the SysTick handler ran (one per millisecond
of the box's clock), so the figures are instructions per millisecond, and x 1000 per second.
Nothing is sent to the UARTs (the quiet scenario), unless --flood BYTES_PER_S: then UART0 is a
TCP socket on 127.0.0.1 into which random bytes are written at that rate in host time (as
`scripts/budget.py`'s flood; QEMU then runs with `-icount shift=0`, its clock following the host's
while the CPU sleeps, so the count is no longer deterministic). python3 stdlib, llvm-nm (the Rust toolchain's
or the system's) for the symbols.
"""
import argparse, bisect, glob, os, re, shutil, socket, subprocess, sys, tempfile, threading, time

root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def tool(name):
    found = glob.glob(os.path.expanduser(f"~/.rustup/toolchains/*/lib/rustlib/*/bin/{name}"))
    return found[0] if found else shutil.which(name) or sys.exit(f"qemu-profile: {name} is missing")


def symbols(elf):
    out = subprocess.run([tool("llvm-nm"), "-n", "-C", "--defined-only", elf], check=True,
                         capture_output=True, text=True).stdout
    syms = []
    for line in out.splitlines():
        parts = line.split(" ", 2)
        if len(parts) == 3 and parts[1] in "tTwW":
            syms.append((int(parts[0], 16) & ~1, parts[2]))
    syms.sort()
    return [a for a, _ in syms], [n for _, n in syms]


def flood(port, rate, stop):
    """Writes random bytes at `rate` a second into the TCP socket of QEMU's UART0 until `stop`."""
    deadline = time.monotonic() + 10
    while not stop.is_set():
        try:
            conn = socket.create_connection(("127.0.0.1", port), timeout=1)
            break
        except OSError:
            if time.monotonic() > deadline:
                return
            time.sleep(0.05)
    else:
        return
    chunk, start, sent = 1024, time.monotonic(), 0
    with conn:
        while not stop.is_set():
            due = start + sent / rate
            if due > time.monotonic():
                time.sleep(due - time.monotonic())
            try:
                conn.sendall(os.urandom(chunk))
            except OSError:
                return
            sent += chunk


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("elf")
    ap.add_argument("--seconds", type=float, default=20)
    ap.add_argument("--top", type=int, default=40)
    ap.add_argument("--tick", default="SysTick", help="the 1 ms handler's symbol")
    ap.add_argument("--callers", metavar="NAME",
                    help="who enters the function whose name contains NAME: the block run before its first block, per caller")
    ap.add_argument("--flood", type=int, default=0, metavar="BYTES_PER_S",
                    help="random bytes a second (host time) into UART0, 0 for none")
    ap.add_argument("--blocks", metavar="NAME", help="per block (address: instructions) of the functions whose name contains NAME")
    a = ap.parse_args()
    if not os.path.isfile(a.elf):
        sys.exit(f"qemu-profile: no file {a.elf}")
    if not 0 < a.seconds <= 600:
        sys.exit("qemu-profile: --seconds must be in (0, 600]")
    if not 1 <= a.top <= 10_000:
        sys.exit("qemu-profile: --top must be in 1..=10000")
    if not 0 <= a.flood <= 1_000_000:
        sys.exit("qemu-profile: --flood must be in 0..=1000000 bytes a second")
    if not shutil.which("qemu-system-arm"):
        sys.exit("qemu-profile: qemu-system-arm is missing: run 'scripts/setup.sh qemu'")
    addrs, names = symbols(a.elf)
    with tempfile.TemporaryDirectory() as tmp:
        log = os.path.join(tmp, "qemu.log")
        args = ["qemu-system-arm", "-machine", "lm3s6965evb", "-cpu", "cortex-m3",
                "-semihosting-config", "enable=on,target=native", "-display", "none",
                "-monitor", "none", "-serial", "null", "-serial", "null", "-serial", "null",
                "-icount", "shift=0,sleep=off", "-d", "in_asm,exec,nochain", "-D", log,
                "-kernel", a.elf]
        stop = threading.Event()
        if a.flood:
            with socket.socket() as s:
                s.bind(("127.0.0.1", 0))
                port = s.getsockname()[1]
            args[args.index("-serial") + 1] = f"tcp:127.0.0.1:{port},server=on,wait=off"
            args[args.index("shift=0,sleep=off")] = "shift=0"
        q = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        if a.flood:
            threading.Thread(target=flood, args=(port, a.flood, stop), daemon=True).start()
        time.sleep(a.seconds)
        stop.set()
        q.terminate()
        q.wait()
        # Per block start: the addresses of its instructions (the longest translation; a block
        # that QEMU cut short for an I/O access under icount carries its length in cflags).
        blocks = {}
        runs = {}
        callers = {}
        last_pc = None
        block = None
        prev = None
        with open(log, errors="replace") as f:
            for line in f:
                if line.startswith("Trace "):
                    block = None
                    m = re.search(r"\[[0-9a-f]+/([0-9a-f]+)/[0-9a-f]+/([0-9a-f]+)\]", line)
                    if not m:
                        continue
                    pc, count = int(m[1], 16), int(m[2], 16) & 0x1FF
                    # An I/O access inside a block ends it under icount: QEMU stops the block
                    # before the access and runs the access as a block of its own (count set),
                    # so the block before it ran only up to that address.
                    if count and prev is not None:
                        ppc, pcount = prev
                        addrs_prev = blocks.get(ppc, [])
                        if not pcount and pc in addrs_prev[1:]:
                            runs[prev] = runs.get(prev, 0) - 1
                            cut = (ppc, addrs_prev.index(pc))
                            runs[cut] = runs.get(cut, 0) + 1
                    key = (pc, count)
                    runs[key] = runs.get(key, 0) + 1
                    if a.callers and last_pc is not None:
                        i = bisect.bisect_right(addrs, pc) - 1
                        if i >= 0 and addrs[i] == pc and a.callers in names[i]:
                            j = bisect.bisect_right(addrs, last_pc) - 1
                            caller = names[j] if j >= 0 else f"0x{last_pc:x}"
                            callers[caller] = callers.get(caller, 0) + 1
                    last_pc = pc
                    prev = key
                elif line.startswith("IN:"):
                    block = []
                elif block is not None and line.startswith("0x"):
                    block.append(int(line.split(":", 1)[0], 16))
                    if len(block) > len(blocks.get(block[0], [])):
                        blocks[block[0]] = list(block)
    size = {pc: len(a) for pc, a in blocks.items()}
    per_fn = {}
    for (pc, count), n in runs.items():
        insns = count or size.get(pc, 0)
        i = bisect.bisect_right(addrs, pc) - 1
        name = names[i] if i >= 0 else f"0x{pc:x}"
        per_fn[name] = per_fn.get(name, 0) + n * insns
    ticks = sum(n for (pc, _), n in runs.items()
                if (i := bisect.bisect_right(addrs, pc) - 1) >= 0 and names[i] == a.tick
                and pc == addrs[i])
    total = sum(per_fn.values())
    print(f"{total:,} instructions; {a.tick} ran {ticks:,} times")
    if a.callers:
        for caller, n in sorted(callers.items(), key=lambda x: -x[1])[:a.top]:
            print(f"{n / max(ticks, 1) * 1000:,.0f} calls/s from {caller[:110]}")
        return
    if a.blocks:
        rows = []
        for (pc, count), n in runs.items():
            i = bisect.bisect_right(addrs, pc) - 1
            if i >= 0 and a.blocks in names[i]:
                rows.append((n * (count or size.get(pc, 0)), pc, n, count or size.get(pc, 0)))
        for cost, pc, n, insns in sorted(rows, reverse=True)[:a.top]:
            print(f"0x{pc:08x}: {insns} instructions x {n:,} = {cost / max(ticks, 1) * 1000:,.0f}/s")
        return
    scale = 1000 / ticks if ticks else 1
    unit = "per second of the box's clock" if ticks else "in the run"
    print(f"| function | instructions {unit} | share |")
    print("| --- | ---: | ---: |")
    for name, n in sorted(per_fn.items(), key=lambda x: -x[1])[:a.top]:
        print(f"| `{name[:110]}` | {n * scale:,.0f} | {100 * n / total:.1f} % |")


if __name__ == "__main__":
    main()
