#!/usr/bin/env python3
"""Counts each library crate's public surface and fails when a protocol crate passes its limit.

    python3 scripts/surface.py            # the table; exit 1 if a limited crate is over
    python3 scripts/surface.py --markdown # the same as a Markdown table

The count is the one issue 45 set: lines under the crate's `src/` that declare a `pub` fn,
struct, enum, const, mod, type or trait (`pub(crate)` and re-exports are not counted; a
`pub` item inside a private module is, since its line still reads as public to a reader of
the file). It is a measure of how much a newcomer reads, kept small on purpose: a protocol
crate holds at most LIMIT such lines.
"""

import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
LIMIT = 200
# The crates a firmware engineer links: held to LIMIT.
LIMITED = ["frame-io", "aeolus-proto", "aydp-proto", "aok-proto", "gdl90-proto"]
# The others, counted and shown.
SHOWN = ["sensor-box", "host-tool", "c-api", "python"]
DECLARATION = re.compile(
    r'^\s*pub (const |async |unsafe |extern "C" )*(fn|struct|enum|const|mod|type|trait) '
)


def count(crate):
    return sum(
        1
        for path in sorted((ROOT / crate / "src").rglob("*.rs"))
        for line in path.read_text(encoding="utf-8").splitlines()
        if DECLARATION.match(line)
    )


def main():
    markdown = "--markdown" in sys.argv[1:]
    over = []
    rows = []
    for crate in LIMITED + SHOWN:
        n = count(crate)
        limit = LIMIT if crate in LIMITED else None
        if limit is not None and n > limit:
            over.append(crate)
        rows.append((crate, n, limit))
    if markdown:
        print("| crate | public items | limit |")
        print("| --- | ---: | ---: |")
        for crate, n, limit in rows:
            print(f"| {crate} | {n} | {limit if limit else '-'} |")
    else:
        for crate, n, limit in rows:
            verdict = "" if limit is None else ("over" if n > limit else "ok")
            print(f"{crate:14} {n:4}  {verdict}")
    if over:
        print(f"over the limit of {LIMIT} public items: {', '.join(over)}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
