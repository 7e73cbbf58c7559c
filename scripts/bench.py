#!/usr/bin/env python3
"""Writes the whole of docs/BENCHMARKS.md, and each decoder's PERFORMANCE.md, from one run.

    python3 scripts/bench.py                      # every section; fuzzing 10 s per target
    FUZZ_SECONDS=300 python3 scripts/bench.py     # longer fuzzing
    python3 scripts/bench.py --only x86,cm3       # those sections; the others stay as published

Sections: x86 cm3 corruption footprint fuzz flood budget firmware c python noise. With --only, every
other section is copied unchanged from the page, and the header says which sections that run
regenerated. The page is written after every section, so a failure keeps what was measured. The PERFORMANCE.md files (aeolus-proto, aydp-proto, aok-proto; rustdoc includes
them) are written when the x86, cm3 and footprint figures are all at hand, from this run or the
page.

Needs what the sections' scripts need (`scripts/setup.sh qemu bench c python`): valgrind and
gungraun-runner 0.20, nightly (stack sizes, fuzzing), the thumbv7m/thumbv6m/thumbv7em targets,
qemu-system-arm, arm-none-eabi-gcc with picolibc, maturin and pymavlink. Builds go to
$CARGO_TARGET_DIR and $BENCH_TARGET_DIR (the x86 bench).
"""
import datetime, importlib.util, os, re, shutil, subprocess, sys, time

root = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
os.chdir(root)
PAGE = os.path.join(root, "docs", "BENCHMARKS.md")
bench_target = os.environ.get("BENCH_TARGET_DIR", "/tmp/protolink-bench-target")
cargo_target = os.environ.get("CARGO_TARGET_DIR", os.path.join(root, "target"))
FUZZ_SECONDS = int(os.environ.get("FUZZ_SECONDS", "10"))


def sh(cmd, cwd=root, env=None, check=True):
    e = dict(os.environ, **(env or {}))
    r = subprocess.run(cmd, cwd=cwd, env=e, shell=isinstance(cmd, str), capture_output=True, text=True)
    if check and r.returncode != 0:
        sys.stderr.write(r.stdout[-3000:] + r.stderr[-3000:])
        raise SystemExit(f"failed: {cmd}")
    return r.stdout


def cells(line):
    return [c.strip() for c in line.strip().strip("|").split("|")]


def table_rows(lines):
    """The body rows of the Markdown tables among `lines`, as lists of cells."""
    return [cells(l) for l in lines if l.startswith("|") and not re.match(r"^\|\s*-", l)
            and not re.match(r"^\|\s*(what|protocol|decoder|target|telemetry: category|flood: category|receive loop)\b", l)]


def verdict(value, target):
    if value <= target:
        return "met"
    pct = (value / target - 1) * 100
    return f"missed by {pct:.0f} %" if pct >= 9.95 else f"missed by {pct:.1f} %"


# ---------------------------------------------------------------- x86-64 (callgrind)

def instruction_counts():
    if not shutil.which("gungraun-runner"):
        sh("cargo install --locked gungraun-runner@0.20.0")
    env = {"CARGO_TARGET_DIR": bench_target}
    sizes = dict(l.split() for l in sh("cargo run -q --release --bin sizes", cwd="bench", env=env).splitlines())
    out = sh("cargo bench -q --bench codecs", cwd="bench", env=env)
    counts, name = {}, None
    for line in out.splitlines():
        m = re.match(r"^codecs::codecs::(\w+) ", line)
        if m:
            name = m.group(1)
        m = re.match(r"^\s+Instructions:\s+(\d+)", line)
        if m and name:
            counts[name] = int(m.group(1))
            name = None
    return {k: (v, int(sizes[k]), v / int(sizes[k])) for k, v in counts.items()}


# Bench key, the row's label (scripts/bench-check.py and scripts/cm3-bench.sh match rows by it),
# the note, the target (instructions per byte, set on Cortex-M3).
ROWS = [
    ("crc_section_4_3", "AEOLUS CRC alone (section 4.3, const table)", "", None),
    ("crc_crate_table", "peer: `crc` crate, CRC-16/XMODEM table", "same bytes", None),
    ("deframe", "AEOLUS deframe, `feed` one byte a call", "", 20),
    ("decode_aeolus", "AEOLUS full decode (deframe + typed parse), `feed` one byte a call", "", 20),
    ("deframe_slice", "AEOLUS deframe, `feed`", "", 10),
    ("decode_aeolus_slice", "AEOLUS full decode (deframe + typed parse), `feed`", "", 10),
    ("naive_aeolus", "peer: naive AEOLUS decoder (trusts the ID's length, allocates)", "", None),
    ("decode_mavlink", "peer: `mavlink` 0.21 v2 parser, ATTITUDE frames (40 B)", "", None),
    ("decode_aydp_push", "AYDP decode (Spec, typed parse), `feed` one byte a call", "", 15),
    ("decode_aydp", "AYDP decode (Spec, typed parse), `feed`", "", 5),
    ("decode_aok_pc_push", "AOK PC side (device's debug frames), `feed` one byte a call", "", 15),
    ("decode_aok_pc", "AOK PC side (device's debug frames), `feed`", "", 8),
    ("decode_aok_device_push", "AOK device side (PC's commands), `feed` one byte a call", "", 15),
    ("decode_aok_device", "AOK device side (PC's commands), `feed`", "", 8),
    ("encode_aeolus", "AEOLUS encode (typed message to escaped frame), per output byte", "", 10),
    ("encode_aydp", "AYDP encode (expedited), per output byte", "", 15),
    ("encode_aok", "AOK encode (debug frames), per output byte", "", 15),
]
LABEL = {k: l for k, l, _, _ in ROWS}

# Why a missed target is missed: the instruction-level account of the Cortex-M3 harness
# (`llvm-objdump -d` of checks/cm3-bench's ELF, and QEMU's `-d in_asm,exec` per block).
REASON = {
    "deframe": "a byte through the inline store path is 12 instructions, the CRC at the flag 4.5 a byte, and each frame's flags the rest",
    "decode_aeolus": "the store path's 12 a byte, the CRC at the flag 4.5 a byte, and each frame (49 bytes on average) its flags, check and typed parse, 3.8 a byte",
    "deframe_slice": "the word loop is 7.75 a byte (ARMv7-M has no SIMD byte compare; the table CRC needs a load per byte) and each frame's flags about 160 instructions, 3.25 a byte",
    "decode_aeolus_slice": "the deframing's 11 a byte and the typed parse, about 67 instructions a frame; 10 would leave 110 a frame for both, which take 227",
    "decode_aydp_push": "18 of a frame's 22 bytes take the inline store path at 15 instructions, each of the other 4 a call returning its event through memory (65 to 110), and the typed parse 73 a frame",
    "decode_aydp": "the deframing alone is 4.35 a byte (95 instructions a 22-byte frame); the typed parse takes 73 a frame where 5 a byte leaves 14",
    "decode_aok_pc_push": "a 7-byte frame is about 138 instructions: five body bytes at 11 each, the first byte (the frame's length) 28, and the last (the check, the counters and the event, handed over in line) 55",
    "decode_aok_device_push": "frames of 5 bytes on average at about 112 instructions: body bytes at 11, the first byte (the command's length) 25 to 31, and the last (the check, the counters and the event, handed over in line) about 50",
    "encode_aeolus": "the word loop is 28 instructions per 4 bytes (the escape test 9, the table CRC 13) and each frame's header, CRC and flags the rest",
    "encode_aydp": "every encode checks the form against the profile first, about 8 instructions a message",
}


def x86_section(ic):
    """The x86-64 section (heading, method, table, ratio) from the counts."""
    out = [
        "## Instructions per byte (x86-64, callgrind), peers in the same run",
        "",
        "`cargo bench --bench codecs` in `bench/` under callgrind: executed instructions, exact. Inputs: 64 KiB",
        "of valid frames (AEOLUS: figure 1c's mix), per input byte (decoders) or output byte (encoders). The",
        "targets are Cortex-M3's (next section); CI (`scripts/bench-check.py`) fails on a rise over 3 % in either.",
        "",
        "| what | instructions | bytes | instr/byte | note |",
        "| --- | ---: | ---: | ---: | --- |",
    ]
    for key, label, note, target in ROWS:
        if key in ic:
            n, b, per = ic[key]
            if target:
                note = f"target {target}: {verdict(per, target)}"
            out.append(f"| {label} | {n} | {b} | {per:.2f} | {note} |")
    crc, full = ic["crc_section_4_3"][2], ic["decode_aeolus_slice"][2]
    out += ["", f"AEOLUS full decode (`feed`) / CRC alone = {full / crc:.2f} (target 2.2: {verdict(full / crc, 2.2)}).", ""]
    return out


# ---------------------------------------------------------------- Cortex-M3 (QEMU -icount)

def run_cm3(x86_doc=None, target_dir=bench_target + "-cm3"):
    env = {"CARGO_TARGET_DIR": target_dir} if target_dir else {}
    if x86_doc:
        env["X86_DOC"] = x86_doc
    return sh("bash scripts/cm3-bench.sh", env=env)


def cm3_section(out):
    """The Cortex-M3 section from scripts/cm3-bench.sh's output: its table, and every target's line."""
    lines = out.splitlines()
    tick = re.search(r"\*\*1 tick = ([\d.]+) instructions\*\*", out)
    same = re.search(r"(\d+) of (\d+) rows gave the\s+same tick count", out)
    stamp = re.search(r"Last run:\s+\S+, QEMU (\S+)", out)
    sec = [
        "## Cortex-M3 instruction counts (QEMU lm3s6965evb, `-icount shift=0`, SysTick)",
        "",
        "`scripts/cm3-bench.sh`: the x86 bench's kernels and inputs for thumbv7m (opt-level \"s\", LTO) in QEMU "
        + (stamp.group(1) if stamp else ""),
        f"under `-icount shift=0`, timed by SysTick (1 tick = {tick.group(1) if tick else '?'} instructions, calibrated); results checked",
        "against the x86 bench's; each build run twice" + (f" ({same.group(1)} of {same.group(2)} rows identical to the tick)" if same else "")
        + ".", "Instructions, not cycles (loads, taken branches and wait states add cycles).",
        "",
    ]
    # Each target's verdict, and the reason of a miss, in the row's note.
    per = {r[0]: int(r[1]) / int(r[2]) for r in table_rows(lines) if r[1].isdigit() and r[2].isdigit()}
    key_of = {label: key for key, label, _, _ in ROWS}
    target_of = {label: t for _, label, _, t in ROWS}
    for l in lines:
        if not l.startswith("|"):
            continue
        c = cells(l)
        label = c[0]
        if target_of.get(label) and label in per:
            v = verdict(per[label], target_of[label])
            note = f"target {target_of[label]}: {v}" + ("" if v == "met" else f": {REASON.get(key_of[label], 'not analysed')}")
            l = "| " + " | ".join(c[:-1] + [note]) + " |"
        sec.append(l)
    sec += [""] + [l for l in lines if l.startswith("Total input")] + [""]
    crc = per.get(LABEL["crc_section_4_3"])
    for key, how in (("decode_aeolus_slice", "`feed`"), ("decode_aeolus", "`feed` one byte a call")):
        if crc and LABEL[key] in per:
            r = per[LABEL[key]] / crc
            sec.append(f"- AEOLUS full decode ({how}) / CRC alone: {r:.2f} against 2.2, {verdict(r, 2.2)}"
                       + (": the reasons of that row above." if r > 2.2 else "."))
    sec.append("")
    return sec


# ---------------------------------------------------------------- corruption

def corruption_section():
    out = sh("cargo run -q --release -p protolink-tests --example corruption").splitlines()
    rows = table_rows(out)
    channels, protocols = [], {}
    for p, ch, sent, dc, wc, dn, wn in (r[:7] for r in rows if len(r) >= 7):
        if ch not in channels:
            channels.append(ch)
        pct = lambda s: s.split("(")[1].rstrip(")") if "(" in s else s
        protocols.setdefault(p, {})[ch] = f"{pct(dc)} ({wc}) / {pct(dn)} ({wn})"
    short = [re.sub(r"^\((\w)\) ", r"(\1) ", c).replace("garbage 0..=64 B between frames", "garbage 0..=64 B")
             .replace("bit flips, ", "").replace("byte drops, rate", "drops") for c in channels]
    sec = [
        "## Corruption (100,000 frames per protocol and channel)",
        "",
        "`cargo run --release -p protolink-tests --example corruption`: the same damaged bytes through the",
        "crate's decoder and through a naive one that trusts the claimed length. Each cell: intact frames",
        "delivered (wrongly accepted frames), the crate / the naive decoder.",
        "",
        "| protocol | " + " | ".join(short) + " |",
        "| --- |" + " ---: |" * len(short),
    ]
    for p, byc in protocols.items():
        sec.append(f"| {p} | " + " | ".join(byc.get(c, "") for c in channels) + " |")
    sec += ["",
            "AOK's many wrongly accepted frames in garbage: its two-byte commands (`63 xx`, `67 NUM`, `47 NUM`,",
            "`78 NUM`) carry no checksum, so random bytes that spell one are a valid command.", ""]
    return sec


# ---------------------------------------------------------------- footprint

FOOT_ROWS = ["aeolus-decode", "aeolus-encode", "aydp-decode", "aydp-encode", "aok-decode", "aok-encode",
             "aeolus-read", "aydp-read", "aok-read"]


def footprint_figures(text):
    """{(triple, row): (flash, stack, ram)} from scripts/footprint.py's output."""
    figs, triple = {}, "thumbv7m-none-eabi"
    for line in text.splitlines():
        m = re.match(r"^### (\S+)", line)
        if m:
            triple = m.group(1)
        c = cells(line) if line.startswith("|") else []
        if c and c[0] in FOOT_ROWS:
            figs[(triple, c[0])] = tuple(int(x) for x in c[1:4])
    return figs


def footprint_section():
    env = {"FOOTPRINT_TARGET_DIR": os.path.join(cargo_target, "footprint")}
    figs = footprint_figures(sh("python3 scripts/footprint.py", env=env))
    sec = [
        "## Footprint on Cortex-M3 and Cortex-M0 (checks/footprint)",
        "",
        "`python3 scripts/footprint.py`: a binary that only decodes (encodes, reads through `embedded-io`) one",
        "protocol, minus the empty binary: flash (text + data), static RAM (data + bss), worst stack of the entry",
        "point (`-Z emit-stack-sizes` over the disassembly's call graph). Bytes.",
        "",
        "| protocol, direction | thumbv7m flash | stack | static RAM | thumbv6m flash | stack | static RAM |",
        "| --- | ---: | ---: | ---: | ---: | ---: | ---: |",
    ]
    for r in FOOT_ROWS:
        a, b = figs.get(("thumbv7m-none-eabi", r)), figs.get(("thumbv6m-none-eabi", r))
        if a and b:
            sec.append(f"| {r} | {a[0]} | {a[1]} | {a[2]} | {b[0]} | {b[1]} | {b[2]} |")
    sec += ["", "Targets, decoder with typed parse (the `*-decode` rows, both targets):"]
    dec = [(t, r) for (t, r) in figs if r.endswith("-decode")]
    worst_flash = max(figs[k][0] for k in dec)
    worst_stack = max(figs[k][1] for k in figs)
    sec.append(f"- at most 4 KiB of flash: largest {worst_flash} B, {verdict(worst_flash, 4096)}"
               + ("." if worst_flash <= 4096 else ": see the rows over it."))
    sec.append(f"- at most 512 B of stack beyond its buffer: deepest of all rows {worst_stack} B, {verdict(worst_stack, 512)}.")
    reads = [figs[k][0] for k in figs if k[1].endswith("-read")]
    if reads and max(reads) > 4096:
        sec.append(f"- (no target) the `*-read` rows, {min(reads)} to {max(reads)} B, add the reader, its buffer and the slice path.")
    sec.append("")
    return sec, figs


# ---------------------------------------------------------------- fuzzing

def fuzz_section():
    env = dict(os.environ, FUZZ_JOBS=os.environ.get("FUZZ_JOBS", str(os.cpu_count() or 1)))
    r = subprocess.run(["bash", "scripts/fuzz.sh", str(FUZZ_SECONDS)], cwd=root, env=env,
                       capture_output=True, text=True)
    runs = [l.split() for l in r.stdout.splitlines() if re.match(r"^\w+\s+\d+\s+\d+$", l)]
    if not runs:
        sys.stderr.write(r.stdout[-3000:] + r.stderr[-3000:])
        raise SystemExit("failed: scripts/fuzz.sh printed no table")
    sec = [
        "## Fuzzing",
        "",
        f"`scripts/fuzz.sh {FUZZ_SECONDS}`: every cargo-fuzz target for {FUZZ_SECONDS} s (libFuzzer, seeded from the",
        "known-answer vectors); CI runs the same for 20 s each (`scripts/test.sh`). Executions per target:",
        "",
        "| protocol | executions by target | crashes |",
        "| --- | --- | ---: |",
    ]
    by = {}
    for t, n, c in runs:
        by.setdefault(t.split("_")[0], []).append((t.split("_", 1)[1], int(n), int(c)))
    for p, ts in by.items():
        sec.append(f"| {p} | " + ", ".join(f"{t} {n:,}" for t, n, _ in ts) + f" | {sum(c for *_, c in ts)} |")
    crashes = sum(int(c) for *_, c in runs)
    sec += ["", f"Target, no crash: {'met' if crashes == 0 else f'missed, {crashes} target(s) crashed'}.", ""]
    return sec


# ---------------------------------------------------------------- line noise, 24 hours

NOISE_LINE = re.compile(r"(AOK|AYDP) (.+?), ([0-9.]+) h, ([0-9]+) bytes, .*?([0-9.]+) s: (.*)$")


def noise_section():
    """The long scenarios of sensor-box's noise tests for 24 simulated hours (the tests run 15
    minutes), in the test profile (the box's crates at opt-level 3): every scenario's bytes, time
    and tally."""
    out = sh("cargo test -q -p sensor-box --test all noise:: -- --nocapture --test-threads=1",
             env={"NOISE_MINUTES": "1440"})
    # A line may start with the dots of `-q`: searched for, not matched at its start.
    rows = [m.groups() for m in map(NOISE_LINE.search, out.splitlines()) if m]
    if len(rows) < 6:
        sys.stderr.write(out[-3000:])
        raise SystemExit("failed: the noise tests printed fewer than 6 scenarios")
    sec = [
        TITLE["noise"],
        "",
        "`NOISE_MINUTES=1440 cargo test -p sensor-box --test all noise:: -- --nocapture`: random",
        "bytes through the real AOK and AYDP links for a simulated day per scenario (the models and what",
        "counts as a state change: `docs/RELIABILITY.md`, \"Line noise commands nothing\"). `cargo test` runs",
        "the same scenarios for 15 minutes. Every scenario passed (no state change in flight, no motor run).",
        "",
        "| link | scenario | simulated | bytes | CPU time | tally |",
        "| --- | --- | ---: | ---: | ---: | --- |",
    ]
    for link, name, hours, nbytes, secs, tally in rows:
        sec.append(f"| {link} | {name} | {float(hours):.0f} h | {int(nbytes):,} | {float(secs):.0f} s | `{tally}` |")
    sec.append("")
    return sec


# ---------------------------------------------------------------- the host tool under flood

def flood_section():
    binary = os.path.join(cargo_target, "release", "protolink")
    sh("cargo build -q --release -p protolink")
    out = sh(["python3", "scripts/flood.py", "--seconds", "10", "--bin", binary])
    sec = [
        "## protolink under a loopback flood",
        "",
        "`python3 scripts/flood.py --seconds 10`: peak RSS of each command (VmHWM and wait4), the share of",
        "telemetry `bridge` forwards while its in-port is flooded, and whether `sim` obeys a command sent",
        "right after the flood. Targets: under 50 MB, at least 99 % (the `met?` column).",
        "",
    ]
    sec += [l for l in out.splitlines() if l.startswith("|")]
    return sec + [""]


# ---------------------------------------------------------------- firmware CPU budget

def budget_section():
    out = sh("python3 scripts/budget.py").splitlines()
    text = "\n".join(out)
    quiet, flood, in_flood = {}, {}, False
    for line in out:
        if line.startswith("| flood: category"):
            in_flood = True
        c = cells(line) if line.startswith("|") else []
        if len(c) == 5 and not c[0].startswith("---") and "category" not in c[0]:
            (flood if in_flood else quiet)[c[0]] = c
    sec = [
        "## Firmware CPU budget",
        "",
        "`python3 scripts/budget.py`: the `cpu-budget` build in lm3s6965evb under `-icount shift=0`, 10 s of the",
        "box's clock, each SysTick count charged to the category `sensor_box::budget::span` marks; instructions a",
        "second as a share of 50 MHz. Quiet: figure 1c telemetry, AYDP and AOK idle (deterministic, run twice).",
        "Flood: the same while UART0 receives random bytes paced at 921 600 Bd in host time (not deterministic).",
        "",
        "| category | what | quiet, instr/s | share | UART0 flood, instr/s | share |",
        "| --- | --- | ---: | ---: | ---: | ---: |",
    ]
    for cat, q in quiet.items():
        f = flood.get(cat, ["", "", "", ""])
        sec.append(f"| {cat} | {q[1]} | {q[2]} | {q[3]} | {f[2]} | {f[3]} |")
    sec.append("")
    m = re.search(r"Two runs: (identical account|the two runs DIFFER)", text)
    busy = quiet.get("**busy**", ["", "", "", "?"])[3].strip("*").replace(" %", "")
    try:
        b = float(busy)
        sec.append(f"- Quiet load at most 4 % of 50 MHz: {busy} %, {verdict(b, 4.0)}"
                   + (f" ({m.group(1)} in the two runs)." if m else "."))
    except ValueError:
        sec.append("- Quiet load: not parsed from scripts/budget.py's output.")
    rx = re.search(r"UART0 rx ([\d,]+) B/s", text)
    if rx:
        sec.append(f"- Under the flood QEMU delivered {rx.group(1)} B/s to UART0 in the box's clock, per received byte:")
    for line in out:
        if line.startswith("- ") and "(no byte received)" not in line:
            line = line.replace("**", "")
            fixed = re.search(r"(\d+) per interrupt plus", line)
            if "the RX interrupt" in line and "missed" in line and fixed:
                line += (" Why: the PL011 byte loop's floor is 9 instructions, and at 8 bytes an interrupt 10 a"
                         f" byte leaves 8 for the handler's entry, status reads and ring bookkeeping, {fixed.group(1)} here.")
            if "the whole box" in line and "missed" in line and rx:
                run = re.search(r"\(([\d.]+) bytes per interrupt", text)
                line += (f" Why: QEMU delivered {rx.group(1)} B/s of the box's clock in this run"
                         + (f", {run.group(1)} bytes an interrupt" if run else "")
                         + " (QEMU hands over the host-paced flood in runs whose length depends on the host; a real"
                         " UART's FIFO gives 8), so each interrupt's and wake's fixed cost is shared by fewer bytes.")
            sec.append(line)
    for line in out:
        if line.startswith("**On a real part**") or line.startswith("**The normal build in real time**"):
            sec += ["", line.replace("**", "")]
    sec.append("")
    return sec


def budget_embassy_section():
    """The async firmware's CPU budget: its `cpu-budget` build (firmware-embassy's QEMU board,
    the same account and report lines as the blocking board's) through scripts/budget.py --elf."""
    fw = os.path.join(root, "firmware-embassy")
    tdir = os.path.join(cargo_target, "embassy")
    env = dict(os.environ, CARGO_TARGET_DIR=tdir, BUDGET_SECONDS="10")
    subprocess.run(["cargo", "build", "-q", "--release", "--target", "thumbv7m-none-eabi", "--no-default-features",
                    "--features", "cpu-budget"], cwd=fw, env=env, check=True)
    built = os.path.join(tdir, "thumbv7m-none-eabi", "release", "sensor-box-embassy")
    elf = built + "-cpu-budget"
    shutil.copyfile(built, elf)
    # The normal ELF back in its place (cargo has it cached: a copy, no compile).
    subprocess.run(["cargo", "qemu-build", "-q"], cwd=fw, env=dict(os.environ, CARGO_TARGET_DIR=tdir), check=True)
    out = sh(["python3", "scripts/budget.py", "--elf", elf, "--no-realtime"]).splitlines()
    tables, current = [], None
    for line in out:
        if line.startswith("| telemetry: category") or line.startswith("| flood: category"):
            current = {}
            tables.append(current)
        elif current is not None and line.startswith("|"):
            c = cells(line)
            if len(c) == 5 and not c[0].startswith("---"):
                current[c[0]] = c
        else:
            current = None
    quiet, flood = (tables + [{}, {}])[:2]
    text = "\n".join(out)
    sent = re.search(r"\) (\d+) bytes sent", text)
    rx = re.search(r"UART0 rx ([\d,]+) B/s", text)
    sec = [
        "## Firmware CPU budget: the async firmware",
        "",
        "The same measurement of `firmware-embassy`'s QEMU board (its `cpu-budget` build: `cargo build --release",
        "--target thumbv7m-none-eabi --no-default-features --features cpu-budget` in `firmware-embassy/`, run by",
        "`scripts/budget.py --elf`): the same account on SysTick and the same report. Its categories differ in what",
        "they hold: `other` is the executor's polls and the async glue (the `FrameReader`s' decoding, the pumps, the",
        "tick), `rx-irq` / `tx-irq` the two halves of its PL011 interrupt, `systick` the embassy time driver; `idle`",
        "is measured from the executor's trace hooks (`executor_idle` to the next `poll_start`).",
        "",
        "| category | quiet, instr/s | share | UART0 flood, instr/s | share |",
        "| --- | ---: | ---: | ---: | ---: |",
    ]
    for cat, q in quiet.items():
        f = flood.get(cat, ["", "", "", ""])
        sec.append(f"| {cat} | {q[2]} | {q[3]} | {f[2]} | {f[3]} |")
    sec.append("")
    m = re.search(r"Two runs: (identical account|the two runs DIFFER)", text)
    if m:
        sec.append(f"- Quiet: {m.group(1)} in the two runs.")
    if rx:
        sec.append(f"- Under the flood QEMU delivered {rx.group(1)} B/s to UART0 in the box's clock"
                   + (f" ({sent.group(1)} bytes sent)." if sent else "."))
    for line in out:
        if line.startswith("- ") and ("the whole box" in line or "the AEOLUS link" in line):
            sec.append(line.replace("**", ""))
    return sec + [""]


# ---------------------------------------------------------------- firmware sizes

def llvm_size(elf):
    sections = {}
    for line in sh(["llvm-size", "-A", elf]).splitlines():
        p = line.split()
        if len(p) >= 2 and p[1].isdigit():
            sections[p[0]] = int(p[1])
    return sections


def double_float(elf):
    """The bytes of double-precision software floating point in `elf`: compiler_builtins'
    arithmetic (`__adddf3`, `__muldf3`, `__divdf3`, `__subdf3`), the EABI conversions and
    comparisons (`__aeabi_d*`, `__aeabi_*2d`) and libm's `fmax`/`fmin`."""
    total = 0
    for line in sh(["llvm-nm", "-C", "-S", "--radix=d", elf]).splitlines():
        p = line.split(None, 3)
        if len(p) == 4 and p[1].isdigit() and re.fullmatch(
                r"(.*::)?(__(add|sub|mul|div)df3|__aeabi_d\w+|__aeabi_\w+2d|fmax|fmin)", p[3]):
            total += int(p[1])
    return total


def boot_stack(elf):
    """The stack high-water the firmware logs at boot (`booted: ...`), from a QEMU boot."""
    spec = importlib.util.spec_from_file_location("budget", os.path.join(root, "scripts", "budget.py"))
    budget = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(budget)
    q = budget.boot(elf, None, int(os.environ.get("BUDGET_PORT", "17800")) + 40, 20)
    try:
        t0 = time.time()
        while time.time() - t0 < 20:
            line = q.stdout.readline()
            if not line:
                break
            m = re.search(r"booted: App (\d+) bytes, stack high-water (\d+) bytes", line)
            if m:
                return int(m.group(1)), int(m.group(2))
    finally:
        budget.stop(q)
    return None


def embassy_elf():
    """The async firmware's QEMU board (firmware-embassy, its own workspace), built into
    target/embassy as scripts/test.sh and the QEMU tests build it; its ELF."""
    env = dict(os.environ, CARGO_TARGET_DIR=os.path.join(cargo_target, "embassy"))
    subprocess.run(["cargo", "qemu-build", "-q"], cwd=os.path.join(root, "firmware-embassy"), env=env, check=True)
    return os.path.join(cargo_target, "embassy", "thumbv7m-none-eabi", "release", "sensor-box-embassy")


def firmware_section():
    boards = [("lm3s6965evb (`cargo qemu-build`)", "qemu-build", "thumbv7m-none-eabi"),
              ("STM32F411 (`cargo stm32-build`)", "stm32-build", "thumbv7em-none-eabihf"),
              ("async firmware on lm3s6965evb (`firmware-embassy`, `cargo qemu-build`)", None, "thumbv7m-none-eabi")]
    figs = []
    for name, alias, triple in boards:
        if alias:
            sh(["cargo", alias, "-q"])
            elf = os.path.join(cargo_target, triple, "release", "sensor-box")
        else:
            elf = embassy_elf()
        s = llvm_size(elf)
        flash = [s.get(k, 0) for k in (".vector_table", ".text", ".rodata", ".data")]
        ram = [s.get(k, 0) for k in (".data", ".bss", ".uninit")]
        stack = boot_stack(elf) if alias != "stm32-build" else None
        figs.append((name, flash, ram, stack, double_float(elf)))
    sec = [
        "## Firmware sizes",
        "",
        "Each board's release build, `llvm-size -A target/<target>/release/sensor-box` (the async firmware:",
        "`target/embassy/thumbv7m-none-eabi/release/sensor-box-embassy`); the stack high-water is the firmware's",
        "own (painted stack, its `booted:` log line in one QEMU boot). The blocking firmware builds its crates and",
        "`aok-proto` at opt-level \"z\", `aeolus-proto` and `aydp-proto` at \"s\" (root `Cargo.toml`); the async",
        "firmware builds everything at \"s\" with LTO (`firmware-embassy/Cargo.toml`). Flash counts .data's initial",
        "values too (copied from flash at boot).",
        "",
        "| what | " + " | ".join(f[0] for f in figs) + " |",
        "| --- |" + " ---: |" * len(figs),
        "| flash: vector table + .text + .rodata + .data (B) | " + " | ".join(
            f"{' + '.join(str(x) for x in f[1])} = {sum(f[1])}" for f in figs) + " |",
        "| static RAM: .data + .bss + .uninit (B) | " + " | ".join(
            f"{' + '.join(str(x) for x in f[2])} = {sum(f[2])}" for f in figs) + " |",
        "| `App` / stack high-water at boot (B) | " + " | ".join(
            f"{f[3][0]} / {f[3][1]}" if f[3] else "not measured here (RTT log)" for f in figs) + " |",
        "",
    ]
    name, flash, ram, stack, double = figs[0]
    sec.append(f"- lm3s6965evb flash at most 64 KiB (65 536 B): {sum(flash)} B, {verdict(sum(flash), 65536)}"
               + (f", {65536 - sum(flash)} B spare. Of it, {double} B is double-precision software floating"
                  " point (the flight simulation's `f64`; the Cortex-M3 has no FPU), and about 14 KiB the"
                  " settings map (`sequential-storage` and its adapter; `docs/RELIABILITY.md`)."
                  if sum(flash) <= 65536 else
                  f". Why: {double} B of it is double-precision software floating point (compiler_builtins'"
                  " `__adddf3`, `__muldf3`, `__divdf3`, the EABI conversions and comparisons, `fmax`;"
                  " `llvm-nm -S`), which the flight simulation's `f64` positions and angles (`flight_sim`)"
                  " and a few `f64` scalings in `sensor-box` bring in, and about 14 KiB the settings map."))
    if stack:
        total = sum(ram) + stack[1]
        sec.append(f"- lm3s6965evb RAM at most 16 KiB: static {sum(ram)} B and stack {stack[1]} B = {total} B, "
                   f"{verdict(total, 16384)}.")
    sec.append("- STM32F411: no target (512 KiB of flash, 128 KiB of RAM); it carries the HAL and hard-float code.")
    _, aflash, aram, astack, _ = figs[2]
    sec.append(f"- The async firmware on the same chip costs {sum(aflash) - sum(flash)} B more flash and"
               f" {sum(aram) - sum(ram)} B more static RAM than the blocking one"
               + (f" (stack high-water at boot {astack[1]} B against {stack[1]} B)" if astack and stack else "")
               + ". Where: the executor's task futures are static (.bss), so what the blocking board keeps on its"
               " main stack (the links' state while they run, the readers' buffers) is counted as static RAM here,"
               " and the async firmware runs the protocol crates' async `FrameReader`s and the settings map's"
               " async store path (`persist::store_in_async`) beside the blocking boot path, plus"
               " `embassy-executor`, `embassy-time` and its timer queue; it has no flash target of its own"
               " (the lm3s6965's 256 KiB).")
    return sec + [""]


# ---------------------------------------------------------------- the C library

def c_section():
    out = sh("bash scripts/c-bench.sh").splitlines()
    tables = [l for l in out if l.startswith("|")]
    gcc = next((l for l in out if l.startswith("Flash and static RAM on Cortex-M3")), "")
    cal = re.search(r"calibrated: 1 tick = ([\d.]+) instructions", "\n".join(out))
    sec = [
        "## The C library (c-api)",
        "",
        "`scripts/c-bench.sh`: `c-api/bench/footprint.c` and `cm3.c`, arm-none-eabi-gcc `-Os -mcpu=cortex-m3`,",
        "picolibc; flash and RAM minus the receive loop alone. Instructions per byte as in the Cortex-M3 section"
        + (f" (1 tick = {cal.group(1)})" if cal else "") + ",",
        "the C calls beside the crates' own loops (the archive's `bench` feature) on the same capture, same run.",
        "",
    ]
    first = True
    for l in tables:
        if re.match(r"^\| protocol", l) and not first:
            sec.append("")
        if re.match(r"^\| (receive loop|protocol)", l):
            first = False
        sec.append(l)
    sec += ["", "Target, the C `feed` call within 10 % of the Rust `feed` loop:", ""]
    missed = False
    for r in table_rows(tables):
        if len(r) == 10:
            ratio = float(r[9])
            missed |= ratio > 1.10
            sec.append(f"- {r[0]}: {ratio:.2f} times, {verdict(ratio, 1.10)}.")
    if missed:
        sec += ["", "Why missed: the C `feed` takes the pull form (`decode`) an event at a time, to give each"
                " message its offset and wire length, and fills the item and calls back for each; AOK's"
                " `decode` costs several times its `feed`, and its frames are short."]
    sec += ["", "`parse` a byte at a time (no target) pays a call per byte: prologue, pointer checks, the"
            " state check, the byte count of each message's place.", ""]
    return sec


# ---------------------------------------------------------------- Python

def python_section():
    venv = os.path.join(cargo_target, "py-venv")
    if not os.path.exists(os.path.join(venv, "bin", "python")):
        sh(["python3", "-m", "venv", "--system-site-packages", venv])
    env = {"PATH": os.path.join(venv, "bin") + os.pathsep + os.path.expanduser("~/.local/bin") + os.pathsep
           + os.environ["PATH"]}
    # The package of this checkout, built the way its README says (as scripts/test-python.sh --wheel does).
    sh(["python", "-m", "pip", "install", "-q", "--no-build-isolation", "--force-reinstall", "--no-deps",
        "./python"], env=env)
    out = sh(["python", "python/bench/bench.py"], env=env).splitlines()
    head = [l for l in out if re.match(r"^(machine|AEOLUS|MAVLink):", l)]
    sec = [
        "## Python",
        "",
        "`python3 python/bench/bench.py` (this checkout's package, installed as `scripts/test-python.sh --wheel` does):",
        "messages a second of `Decoder.feed` beside pymavlink's `parse_buffer` (pure Python, and with its Rust",
        "CRC `fastcrc`), 64 KiB pieces; protolink the best of three runs, pymavlink one run.",
        "; ".join(re.sub(r"\s+", " ", l) for l in head) + ".",
        "",
    ]
    tables, block = [], []
    for l in out + [""]:
        if l.startswith("|"):
            block.append(l)
        elif block:
            tables.append(block)
            block = []
    rows = tables[0] if tables else []
    sec += rows
    feed = next((cells(l) for l in rows if "Decoder: feed |" in l), None)
    sec.append("")
    if feed:
        x = float(feed[3].rstrip("x"))
        sec.append(f"Target, `Decoder.feed` at least 20 times pymavlink's pure-Python rate: {x:.1f} times, {verdict(20, x)}.")
    sec += ["Reading every field is slower: fields become Python objects when first read (`to_dict()`: all).", ""]
    columns = tables[1] if len(tables) > 1 else []
    if columns:
        sec += [
            "The columns, in the same run: `protolink.to_frames` of the AEOLUS stream as a file (one DataFrame per",
            "type, every field a column; best of three, each run in a process of its own, peak RSS above the",
            "process's after its imports) beside pymavlink's pure-Python `parse_buffer` reading every field of",
            "every message (`getattr` of each of its `_fieldnames`); then `protolink export` of ten copies of the",
            "file, 1 GB, to Parquet (target/release/protolink; best of three).",
            "",
        ] + columns + [""]
        frames = next((cells(l) for l in columns if l.startswith("| protolink.to_frames")), None)
        export = next((cells(l) for l in columns if l.startswith("| protolink export")), None)
        if frames:
            seconds, ratio = float(frames[1]), float(frames[4].rstrip("x"))
            sec.append(f"Target, 100 MB to DataFrames in at most 2 s: {seconds:.2f} s, {verdict(seconds, 2.0)}.")
            sec.append(f"Target, at least 20 times pymavlink's pure-Python parse with every field read: {ratio:.1f} times, "
                       f"{verdict(20, ratio)}.")
        if export:
            rate = float(export[3])
            sec.append(f"Target, export to Parquet at least 50 MB/s: {rate:.1f} MB/s, {verdict(50, rate)}.")
        sec += ["Memory: `to_frames` holds each type's Arrow table until it converts it into its frame, so its peak is",
                "about the frames plus the largest table; `export` holds a row group (65,536 rows) per type and the",
                "256 KiB read buffer, whatever the sources' size.", ""]
    return sec


# ---------------------------------------------------------------- each decoder's PERFORMANCE.md

def per_byte(section_lines, label, col):
    for r in table_rows(section_lines):
        if r and r[0] == label:
            return r[col]
    return "-"


def performance_files(page_lines, date):
    """A short table per decoder crate, from the page's x86, Cortex-M3 and footprint sections."""
    x86 = section_of(page_lines, "## Instructions per byte (x86-64")
    cm3 = section_of(page_lines, "## Cortex-M3 instruction counts")
    foot = {}
    for r in table_rows(section_of(page_lines, "## Footprint")):
        if len(r) == 7 and r[1].isdigit():
            foot[("thumbv7m-none-eabi", r[0])] = tuple(int(x) for x in r[1:4])
            foot[("thumbv6m-none-eabi", r[0])] = tuple(int(x) for x in r[4:7])
    crates = {
        "aeolus-proto": ("`Decoder<MAX_FIXED_FRAME>`", [
            ("decode (deframe + typed parse), whole slices", "decode_aeolus_slice"),
            ("decode (deframe + typed parse), one byte a call", "decode_aeolus"),
            ("encode, per output byte", "encode_aeolus")], "aeolus-decode"),
        "aydp-proto": ("`Decoder<128>` (Spec profile)", [
            ("decode (typed parse), whole slices", "decode_aydp"),
            ("decode (typed parse), one byte a call", "decode_aydp_push"),
            ("encode (expedited), per output byte", "encode_aydp")], "aydp-decode"),
        "aok-proto": ("The device side's `CommandDecoder`", [
            ("device side (PC's commands), whole slices", "decode_aok_device"),
            ("device side (PC's commands), one byte a call", "decode_aok_device_push"),
            ("PC side (device's debug frames), whole slices", "decode_aok_pc"),
            ("PC side (device's debug frames), one byte a call", "decode_aok_pc_push"),
            ("encode (debug frames), per output byte", "encode_aok")], "aok-decode"),
    }
    for crate, (decoder, rows, foot_row) in crates.items():
        a, b = foot.get(("thumbv7m-none-eabi", foot_row)), foot.get(("thumbv6m-none-eabi", foot_row))
        text = [
            "# Performance",
            "",
            f"Measured by `python3 scripts/bench.py` in the protolink repository ({date}), where",
            "`docs/BENCHMARKS.md` gives the method, the peers and the targets. Executed instructions per",
            "byte of valid frames: callgrind on x86-64, QEMU `-icount` on Cortex-M3 (release, opt-level \"s\").",
            "",
            "| instructions per byte | x86-64 | Cortex-M3 |",
            "| --- | ---: | ---: |",
        ]
        for what, key in rows:
            text.append(f"| {what} | {per_byte(x86, LABEL[key], 3)} | {per_byte(cm3, LABEL[key], 3)} |")
        text += ["", f"{decoder} in a binary that only decodes (typed parse of one message), minus the",
                 "empty binary; the worst stack of the decoding call, its deepest call chain included:", "",
                 "| bytes | thumbv7m (Cortex-M3) | thumbv6m (Cortex-M0) |", "| --- | ---: | ---: |"]
        if a and b:
            text += [f"| flash | {a[0]} | {b[0]} |", f"| worst stack | {a[1]} | {b[1]} |",
                     f"| static RAM of the decoder | {a[2]} | {b[2]} |"]
        path = os.path.join(root, crate, "PERFORMANCE.md")
        open(path, "w").write("\n".join(text) + "\n")
        print(f"wrote {os.path.relpath(path, root)}")


# ---------------------------------------------------------------- the page

ORDER = ["x86", "cm3", "corruption", "footprint", "fuzz", "flood", "budget", "budget_embassy", "firmware", "c",
         "python", "noise"]
HEADING = {
    "x86": "## Instructions per byte (x86-64", "cm3": "## Cortex-M3 instruction counts",
    "corruption": "## Corruption", "footprint": "## Footprint", "fuzz": "## Fuzzing",
    "flood": "## protolink under a loopback flood", "budget": "## Firmware CPU budget",
    "budget_embassy": "## Firmware CPU budget: the async firmware",
    "firmware": "## Firmware sizes", "c": "## The C library", "python": "## Python",
    "noise": "## Line noise",
}


def section_of(lines, heading):
    """The lines of the page's section that starts with `heading`, up to the next `## `."""
    out, inside = [], False
    # A longer heading that starts with this one is another section's.
    longer = [h for h in HEADING.values() if h != heading and h.startswith(heading)]
    for l in lines:
        if l.startswith("## "):
            inside = l.startswith(heading) and not any(l.startswith(h) for h in longer)
        if inside:
            out.append(l)
    return out


TITLE = {
    "x86": "## Instructions per byte (x86-64, callgrind), peers in the same run",
    "cm3": "## Cortex-M3 instruction counts (QEMU lm3s6965evb, `-icount shift=0`, SysTick)",
    "corruption": "## Corruption (100,000 frames per protocol and channel)",
    "footprint": "## Footprint on Cortex-M3 and Cortex-M0 (checks/footprint)",
    "fuzz": "## Fuzzing", "flood": "## protolink under a loopback flood",
    "budget": "## Firmware CPU budget", "budget_embassy": "## Firmware CPU budget: the async firmware",
    "firmware": "## Firmware sizes", "c": "## The C library (c-api)", "python": "## Python",
    "noise": "## Line noise, 24 simulated hours",
}


def write_page(sections, old, only, done, now, cpu, rustc):
    """Writes the page: this run's sections, the others as the page had them (or a line saying
    they were not measured)."""
    head = [
        "# Benchmarks",
        "",
        "Every figure on this page comes from one command, which also writes each decoder's `PERFORMANCE.md`:",
        "",
        "```sh",
        "python3 scripts/bench.py         # FUZZ_SECONDS=10 (s per fuzz target) by default",
        "```",
        "",
    ]
    if set(done) == set(ORDER):
        head.append(f"Run {now} on {cpu}, rustc {rustc}.")
    else:
        prev = next((l for l in old if l.startswith("Run ")), "")
        if prev:
            head.append(prev)
        head.append(f"Regenerated on {now} ({cpu}, rustc {rustc}, `--only {','.join(only)}`): "
                    f"{', '.join(done) or 'nothing yet'}; the other sections are from the run above.")
    head += ["The history of these figures is in the crates' CHANGELOGs (\"Performance history\") and in git.", ""]
    page = head
    for name in ORDER:
        body = sections.get(name) or section_of(old, HEADING[name]) or [
            TITLE[name], "", f"Not measured yet: `python3 scripts/bench.py --only {name}`."]
        while body and body[-1] == "":
            body = body[:-1]
        page += body + [""]
    open(PAGE, "w").write("\n".join(page).rstrip("\n") + "\n")
    return page


def main(argv):
    only = ORDER
    if argv[:1] == ["--only"] and len(argv) == 2:
        only = argv[1].split(",")
        bad = [s for s in only if s not in ORDER]
        if bad:
            sys.exit(f"bench.py: unknown section(s) {bad}; sections: {','.join(ORDER)}")
    elif argv:
        sys.exit(__doc__)
    old = open(PAGE).read().splitlines() if os.path.exists(PAGE) else []
    now = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d")
    cpu = sh("grep -m1 'model name' /proc/cpuinfo", check=False).split(":")[-1].strip()
    rustc = sh("rustc --version").split()[1]
    sections, done = {}, []
    t0 = time.time()
    for name in ORDER:
        if name not in only:
            continue
        print(f"bench.py: {name} ...", file=sys.stderr, flush=True)
        if name == "x86":
            sections["x86"] = x86_section(instruction_counts())
        elif name == "cm3":
            # The Cortex-M3 table shows the x86 figure beside each of its own: from this run's
            # x86 section when there is one, else from the page.
            x86 = sections.get("x86") or section_of(old, HEADING["x86"])
            tmp = os.path.join(cargo_target, "bench-x86-section.md")
            os.makedirs(cargo_target, exist_ok=True)
            open(tmp, "w").write("\n".join(x86) + "\n## Cortex-M3\n")
            sections["cm3"] = cm3_section(run_cm3(tmp))
        elif name == "footprint":
            sections["footprint"] = footprint_section()[0]
        else:
            sections[name] = globals()[f"{name}_section"]()
        done.append(name)
        # Written after every section, so a later failure keeps what was measured.
        page = write_page(sections, old, only, done, now, cpu, rustc)
        print(f"bench.py: {name} done ({time.time() - t0:.0f} s)", file=sys.stderr, flush=True)
    print(f"wrote {os.path.relpath(PAGE, root)} ({len(page)} lines)")
    if all(section_of(page, HEADING[n])[2:] and "Not measured yet" not in "\n".join(section_of(page, HEADING[n]))
           for n in ("x86", "cm3", "footprint")):
        performance_files(page, now)


if __name__ == "__main__":
    main(sys.argv[1:])
