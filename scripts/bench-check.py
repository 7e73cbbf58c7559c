#!/usr/bin/env python3
"""Fails when a per-byte figure of the published Cortex-M3 table rises by more than 3 %.

    python3 scripts/bench-check.py              # runs scripts/cm3-bench.sh, compares
    python3 scripts/bench-check.py --from FILE  # compares the table in FILE (cm3-bench.sh's output)
    python3 scripts/bench-check.py --write      # runs it and puts its table into docs/BENCHMARKS.md

The Cortex-M3 counts are executed instructions under QEMU's `-icount shift=0`, exact and
repeatable for a given binary (cm3-bench.sh runs every build twice and fails if the two runs
differ), so a rise is a change of the code, never noise. Every row of the section "Cortex-M3
instruction counts" of docs/BENCHMARKS.md is compared by its label, as instructions divided by
bytes: a rise above 3 % fails (exit 1), a fall of more than 3 % is reported as a stale table
(regenerate it with --write, or `python3 scripts/bench.py`), a row missing from either side
fails. `--write` replaces that section by the new output, so the published table is the one the
next comparison holds the code to.
"""
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
DOC = ROOT / "docs" / "BENCHMARKS.md"
HEADING = "## Cortex-M3 instruction counts"
LIMIT = 0.03


def rows(text):
    """Label -> (instructions, bytes) for every table row with two integer columns after it."""
    out = {}
    for line in text.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) >= 4 and cells[1].isdigit() and cells[2].isdigit() and int(cells[2]) > 0:
            out[cells[0]] = (int(cells[1]), int(cells[2]))
    return out


def section(doc):
    """The Cortex-M3 section of the page: from its heading to the next heading of its level."""
    start = doc.find(HEADING)
    if start < 0:
        sys.exit(f"bench-check: no section '{HEADING}' in {DOC}")
    end = doc.find("\n## ", start + len(HEADING))
    return start, (len(doc) if end < 0 else end + 1)


def run_cm3():
    r = subprocess.run(["bash", "scripts/cm3-bench.sh"], cwd=ROOT, capture_output=True, text=True)
    if r.returncode != 0:
        sys.stderr.write(r.stderr)
        sys.exit("bench-check: scripts/cm3-bench.sh failed")
    # One heading level down, as scripts/bench.py puts it into the page.
    return "\n".join("#" + l if l.startswith("#") else l for l in r.stdout.splitlines()) + "\n"


def main(argv):
    if argv[:1] == ["--from"] and len(argv) == 2:
        new_text = Path(argv[1]).read_text()
    elif argv in ([], ["--write"]):
        new_text = run_cm3()
    else:
        sys.exit("usage: bench-check.py [--from FILE | --write]")
    doc = DOC.read_text()
    start, end = section(doc)
    if argv == ["--write"]:
        DOC.write_text(doc[:start] + new_text.rstrip("\n") + "\n\n" + doc[end:].lstrip("\n"))
        print(f"bench-check: {DOC.relative_to(ROOT)}'s Cortex-M3 table rewritten")
        return 0
    published, measured = rows(doc[start:end]), rows(new_text)
    if not published:
        sys.exit("bench-check: the published Cortex-M3 table has no rows")
    failed, stale = [], []
    print(f"{'published':>10} {'now':>10} {'change':>8}  per byte (Cortex-M3, -icount)")
    for label, (n0, b0) in published.items():
        if label not in measured:
            failed.append(f"'{label}' is published but was not measured")
            continue
        n1, b1 = measured[label]
        old, new = n0 / b0, n1 / b1
        change = new / old - 1
        print(f"{old:10.3f} {new:10.3f} {change:+8.2%}  {label}")
        if change > LIMIT:
            failed.append(f"'{label}' rose from {old:.3f} to {new:.3f} instructions per byte ({change:+.2%})")
        elif change < -LIMIT:
            stale.append(label)
    for label in measured.keys() - published.keys():
        failed.append(f"'{label}' was measured but is not published")
    if stale:
        print(f"bench-check: {len(stale)} figure(s) fell by more than 3 %: the published table is stale "
              "(python3 scripts/bench-check.py --write)")
    if failed:
        for f in failed:
            print(f"bench-check: {f}", file=sys.stderr)
        return 1
    print(f"bench-check: {len(published)} per-byte figures within +3 % of the published table")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
