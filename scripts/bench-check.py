#!/usr/bin/env python3
"""Fails when a per-byte figure of a published instruction-count table rises by more than 3 %.

    python3 scripts/bench-check.py                          # measures both tables, compares
    python3 scripts/bench-check.py --only x86|cm3           # one of them
    python3 scripts/bench-check.py --only x86|cm3 --from F  # compares F (the measuring script's output)
    python3 scripts/bench-check.py [--only x86|cm3] --write # measures and puts the tables into the page

The two tables of docs/BENCHMARKS.md it guards:
- "Instructions per byte (x86-64, callgrind)": the `codecs` bench of bench/ under callgrind
  (gungraun), measured with scripts/bench.py's own functions (needs valgrind and
  gungraun-runner 0.20, which it installs if missing: `scripts/setup.sh bench`).
- "Cortex-M3 instruction counts": scripts/cm3-bench.sh, QEMU's `-icount shift=0`.
Both sections are produced by scripts/bench.py's own functions (`x86_section`, `cm3_section`), so
`--write` leaves the page as `python3 scripts/bench.py --only x86,cm3` would (except the decoders'
PERFORMANCE.md files, which only bench.py writes).

Both are counts of executed instructions, exact and repeatable for a given binary, so a rise is
a change of the code, never noise. Every row is compared by its label, as instructions divided
by bytes: a rise above 3 % fails (exit 1), a fall of more than 3 % is reported as a stale table
(regenerate it with --write, or `python3 scripts/bench.py`), a row missing from either side
fails. `--write` replaces the section by the new output, so the published table is the one the
next comparison holds the code to; it writes the x86 table first, because the Cortex-M3 table
shows the x86 figures beside its own.
"""
import importlib.util
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
DOC = ROOT / "docs" / "BENCHMARKS.md"
LIMIT = 0.03


def rows(text):
    """Label -> (instructions, bytes) for every table row with two integer columns after it."""
    out = {}
    for line in text.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) >= 4 and cells[1].isdigit() and cells[2].isdigit() and int(cells[2]) > 0:
            out[cells[0]] = (int(cells[1]), int(cells[2]))
    return out


def section(doc, heading):
    """The section of the page that starts with `heading`: up to the next heading of its level."""
    start = doc.find(heading)
    if start < 0:
        sys.exit(f"bench-check: no section '{heading}' in {DOC}")
    end = doc.find("\n## ", start + len(heading))
    return start, (len(doc) if end < 0 else end + 1)


def bench():
    """scripts/bench.py as a module: the page's sections are written by its functions."""
    spec = importlib.util.spec_from_file_location("bench", ROOT / "scripts" / "bench.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def run_x86():
    b = bench()
    return "\n".join(b.x86_section(b.instruction_counts())) + "\n"


def run_cm3():
    # The section as scripts/bench.py writes it (its table beside the page's x86 figures);
    # built where CARGO_TARGET_DIR says, as the script's default.
    b = bench()
    return "\n".join(b.cm3_section(b.run_cm3(target_dir=None))) + "\n"


# Name, heading of its section in the page, how it is measured, what its figures are.
TABLES = {
    "x86": ("## Instructions per byte (x86-64, callgrind)", run_x86, "x86-64, callgrind"),
    "cm3": ("## Cortex-M3 instruction counts", run_cm3, "Cortex-M3, -icount"),
}


def compare(name, new_text):
    """Prints the comparison of one table; returns the failures."""
    heading, _, what = TABLES[name]
    doc = DOC.read_text()
    start, end = section(doc, heading)
    published, measured = rows(doc[start:end]), rows(new_text)
    if not published:
        return [f"the published {what} table has no rows"]
    failed, stale = [], []
    print(f"{'published':>10} {'now':>10} {'change':>8}  per byte ({what})")
    for label, (n0, b0) in published.items():
        if label not in measured:
            failed.append(f"'{label}' ({what}) is published but was not measured")
            continue
        n1, b1 = measured[label]
        old, new = n0 / b0, n1 / b1
        change = new / old - 1
        print(f"{old:10.3f} {new:10.3f} {change:+8.2%}  {label}")
        if change > LIMIT:
            failed.append(f"'{label}' ({what}) rose from {old:.3f} to {new:.3f} instructions per byte ({change:+.2%})")
        elif change < -LIMIT:
            stale.append(label)
    for label in measured.keys() - published.keys():
        failed.append(f"'{label}' ({what}) was measured but is not published")
    if stale:
        print(f"bench-check: {len(stale)} {what} figure(s) fell by more than 3 %: the published table is "
              "stale (python3 scripts/bench-check.py --write)")
    if not failed:
        print(f"bench-check: {len(published)} {what} per-byte figures within +3 % of the published table")
    return failed


def write(name, new_text):
    heading = TABLES[name][0]
    doc = DOC.read_text()
    start, end = section(doc, heading)
    DOC.write_text(doc[:start] + new_text.rstrip("\n") + "\n\n" + doc[end:].lstrip("\n"))
    print(f"bench-check: {DOC.relative_to(ROOT)}'s {TABLES[name][2]} table rewritten")


def main(argv):
    names, source, mode = list(TABLES), None, "check"
    args = list(argv)
    while args:
        a = args.pop(0)
        if a == "--only" and args and args[0] in TABLES:
            names = [args.pop(0)]
        elif a == "--from" and args:
            source = Path(args.pop(0))
        elif a == "--write":
            mode = "write"
        else:
            sys.exit("usage: bench-check.py [--only x86|cm3] [--from FILE | --write]")
    if source is not None and (len(names) != 1 or mode == "write"):
        sys.exit("bench-check: --from compares one table: give --only x86 or --only cm3, and no --write")
    failed = []
    for name in names:
        new_text = source.read_text() if source else TABLES[name][1]()
        if mode == "write":
            write(name, new_text)
        else:
            failed += compare(name, new_text)
    for f in failed:
        print(f"bench-check: {f}", file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
