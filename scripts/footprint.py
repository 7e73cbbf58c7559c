#!/usr/bin/env python3
"""Flash and stack figures of the protocol crates on thumbv7m and thumbv6m (checks/footprint).

`python3 scripts/footprint.py [TARGET...]`: thumbv7m-none-eabi then thumbv6m-none-eabi by default
(nightly needs both targets: the script adds the ones it lacks with `rustup target add
--toolchain nightly`).

Flash: each protocol's decode-only (then encode-only) binary minus the empty baseline, from
llvm-size (text + data); static RAM likewise (data + bss: the decoder or reader, static there). Stack: nightly's -Z emit-stack-sizes gives every function's frame; the
call graph comes from the disassembly (bl/blx/b.w to a symbol); the worst stack of an entry point
is its frame plus the deepest chain of frames it can call. Prints a Markdown table.
"""
import glob, os, re, subprocess, sys

root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
crate = os.path.join(root, "checks", "footprint")
target = os.environ.get("FOOTPRINT_TARGET_DIR", "/tmp/footprint-target")
tools = glob.glob(os.path.expanduser("~/.rustup/toolchains/1.95.0-*/lib/rustlib/*/bin"))[0]
size_tool, readobj, objdump = (os.path.join(tools, t) for t in ("llvm-size", "llvm-readobj", "llvm-objdump"))
targets = sys.argv[1:] or ["thumbv7m-none-eabi", "thumbv6m-none-eabi"]
features = ["", "aeolus-decode", "aeolus-encode", "aydp-decode", "aydp-encode", "aok-decode", "aok-encode",
            "aeolus-read", "aydp-read", "aok-read"]


def add_nightly_targets(triples):
    """Adds to nightly the targets it lacks (the stack figures are built with it)."""
    listed = subprocess.run(["rustup", "+nightly", "target", "list", "--installed"], capture_output=True,
                            text=True, check=True).stdout.split()
    missing = [t for t in triples if t not in listed]
    if missing:
        subprocess.run(["rustup", "target", "add", "--toolchain", "nightly"] + missing, check=True)


def build(triple, feature, nightly):
    tdir = os.path.join(target, ("n-" if nightly else "s-") + (feature or "baseline"))
    cmd = ["cargo"] + (["+nightly"] if nightly else []) + ["build", "-q", "--release", "--target-dir", tdir,
                                                            "--target", triple]
    if feature:
        cmd += ["--features", feature]
    env = dict(os.environ)
    if nightly:
        env["RUSTFLAGS"] = "-Z emit-stack-sizes -C link-arg=--entry=entry -C link-arg=--gc-sections"
    subprocess.run(cmd, cwd=crate, check=True, env=env)
    return os.path.join(tdir, triple, "release", "footprint")


def sizes(elf):
    """(flash, static RAM): text + data, data + bss."""
    out = subprocess.run([size_tool, elf], capture_output=True, text=True, check=True).stdout.split("\n")[1].split()
    return int(out[0]) + int(out[1]), int(out[1]) + int(out[2])


def stack_sizes(elf):
    out = subprocess.run([readobj, "--stack-sizes", elf], capture_output=True, text=True).stdout
    sizes, name = {}, None
    for line in out.splitlines():
        m = re.search(r"Functions: \[(.*)\]", line)
        if m:
            name = m.group(1).split(",")[0].strip()
        m = re.search(r"Size: (0x[0-9A-Fa-f]+|\d+)", line)
        if m and name:
            sizes[name] = int(m.group(1), 0)
            name = None
    return sizes


def call_graph(elf):
    out = subprocess.run([objdump, "-d", "--no-show-raw-insn", elf], capture_output=True, text=True).stdout
    graph, cur = {}, None
    for line in out.splitlines():
        m = re.match(r"^[0-9a-f]+ <(.+)>:$", line)
        if m:
            cur = m.group(1)
            graph.setdefault(cur, set())
            continue
        m = re.search(r"\s(bl|blx|b\.w|b)\s+0x[0-9a-f]+ <([^+>]+)>", line)
        if m and cur and m.group(2) != cur:
            graph[cur].add(m.group(2))
    return graph


def worst(fn, sizes, graph, seen=()):
    if fn in seen:
        return float("inf")  # recursion: unbounded
    below = [worst(c, sizes, graph, seen + (fn,)) for c in graph.get(fn, ())]
    return sizes.get(fn, 0) + max(below, default=0)


def table(triple):
    base, base_ram = sizes(build(triple, "", False))
    print("| protocol, direction | flash (B, minus baseline) | worst stack of the entry point (B) | static RAM (B, minus baseline) |")
    print("| --- | ---: | ---: | ---: |")
    for f in features[1:]:
        size, ram = sizes(build(triple, f, False))
        size, ram = size - base, ram - base_ram
        elf = build(triple, f, True)
        fn = "fp_" + f.replace("-", "_")
        st = worst(fn, stack_sizes(elf), call_graph(elf))
        print(f"| {f} | {size} | {st} | {ram} |")
    print(f"\nbaseline (empty binary): {base} B of flash, {base_ram} B of static RAM")


add_nightly_targets(targets)
for i, triple in enumerate(targets):
    if i:
        # The first target's table stands under the caller's heading; the others get their own.
        core = {"thumbv6m-none-eabi": "Cortex-M0/M0+", "thumbv7m-none-eabi": "Cortex-M3",
                "thumbv7em-none-eabihf": "Cortex-M4F"}.get(triple, triple)
        print(f"\n### {triple} ({core})\n")
    table(triple)
