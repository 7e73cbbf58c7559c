#!/usr/bin/env python3
"""Fails when a word the code no longer uses stands in the repository's text.

The AEOLUS `Deframer<N>` became `Decoder<N>` and `Decoder::push_slice` became `Decoder::feed`
(issue 27); `feed_until`, `flush_next`, `idle_next`, AOK's `DeviceDecoder` and `PcDecoder`
and the C library's `pl_*_parse_byte`, `pl_*_poll` and `pl_aok_*_idle` went with the one
decoder contract (issue 45); AEOLUS's `Frame::check` became `Frame::new_checked`, the name
every crate gives its checked constructor (issue 55), and the free `encode_*` functions of AOK
and GDL90 and AYDP's `encode_normal` / `encode_expedited` / `iter_normal` / `iter_expedited`
went with the one encode vocabulary (issue 55); a stale word in a comment or document sends a newcomer looking for a type or a
method that does not exist. The history of the names stays where history belongs: the
CHANGELOGs, and the table of removed names in docs/architecture.md ("Names removed before
the first release"), and this script's own list. Every other file git tracks is read.

    python3 scripts/check-words.py

Prints each stale word as `path:line: word` and exits 1 when there is one.
"""

import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
STALE = re.compile(
    r"\b(deframers?|push_slice|feed_until|flush_next|idle_next|DeviceDecoder|PcDecoder"
    r"|pl_\w+_parse_byte|pl_\w+_poll|pl_aok_\w+_idle|Frame::check"
    r"|encode_(?:command|debug|ack|parameter|bulk|waypoint|heartbeat|ownship|traffic"
    r"|geo_altitude|foreflight_id|ahrs|stratux_ahrs|normal|expedited)|iter_normal|iter_expedited"
    r"|StreamDecoder|EventSink|decoder_for|AeolusItem|feed_items|finish_items"
    r"|end_of_datagram_items|add_aeolus|add_event|aydp_fields)\b",
    re.IGNORECASE,
)
HISTORY_SECTION = ("docs/architecture.md", "## Names removed before the first release")


def tracked():
    out = subprocess.run(
        ["git", "ls-files", "-z"], cwd=ROOT, check=True, capture_output=True
    ).stdout
    return [p for p in out.decode().split("\0") if p]


def main():
    found = 0
    for rel in tracked():
        if Path(rel).name == "CHANGELOG.md" or rel == "scripts/check-words.py":
            continue
        try:
            text = (ROOT / rel).read_text(encoding="utf-8")
        except (UnicodeDecodeError, FileNotFoundError, IsADirectoryError):
            continue
        in_history = False
        for n, line in enumerate(text.splitlines(), 1):
            if rel == HISTORY_SECTION[0] and line.startswith("## "):
                in_history = line.strip() == HISTORY_SECTION[1]
            if in_history:
                continue
            for m in STALE.finditer(line):
                print(f"{rel}:{n}: {m.group(0)}")
                found += 1
    print(f"check-words: {found} stale words")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
