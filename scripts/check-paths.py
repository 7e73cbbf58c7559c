#!/usr/bin/env python3
"""Every relative path that a Markdown file or a Rust doc comment names must exist.

Looks at the Markdown files of the repository and at the `//!` and `///` comments of its
Rust sources, takes each path-like word written in backticks or as a Markdown link target
(a word with a slash and a file extension, such as `docs/RELIABILITY.md` or
`tests/tests/all/soak.rs`), and checks that it names a file or folder: relative to the file
that names it, to the crate it is in, to the repository root, or (for `../shared/...`) to
the folder beside the repository. Generated paths (`target/...`), home and absolute paths,
URLs and patterns (`*`, `{...}`, `NAME`) are not checked.

Exit status 0 when every named path exists; 1, with one line per missing path
(`file:line: path`), when one does not.

    python3 scripts/check-paths.py
"""
import os
import re
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EXTENSIONS = (
    "md rs sh py toml lua json txt bin x html js css yml yaml c h pcap pcapng lock pyi cfg"
).split()
WORD = r"[A-Za-z0-9_.@+-]+"
PATH = re.compile(
    r"(?:\.\./|\./)*" + WORD + r"(?:/" + WORD + r")+\.(?:" + "|".join(EXTENSIONS) + r")\b"
)
QUOTED = re.compile(r"`([^`\n]+)`|\]\(([^)\s#]+)")


def tracked_files():
    out = subprocess.run(
        ["git", "ls-files"], cwd=ROOT, capture_output=True, text=True, check=True
    ).stdout
    return [f for f in out.splitlines() if os.path.isfile(os.path.join(ROOT, f))]


def crate_dir(path):
    d = os.path.dirname(path)
    while d and not os.path.isfile(os.path.join(ROOT, d, "Cargo.toml")):
        d = os.path.dirname(d)
    return d


def skipped(p):
    return (
        p.startswith(("target/", "http", "/", "~", "$"))
        or "://" in p
        or any(c in p for c in "*{}<>")
        or re.match(r"[A-Z_]+/", p) is not None
        or re.search(r"\bNAME\b|\bN\b|XXX|\.\.\.", p) is not None
    )


def crate_dirs():
    out = []
    for dirpath, dirnames, filenames in os.walk(ROOT):
        dirnames[:] = [d for d in dirnames if not d.startswith(".") and d != "target"]
        if "Cargo.toml" in filenames:
            rel = os.path.relpath(dirpath, ROOT)
            out += [rel, os.path.join(rel, "src")]
    return out


CRATES = crate_dirs()


def exists(candidate, origin):
    """Relative to the naming file's folder or its parent, to its crate, to the repository
    root, or to any crate or its `src/` ("each crate's `tests/io.rs`")."""
    here = os.path.dirname(origin)
    bases = [here, os.path.dirname(here), crate_dir(origin), ""] + CRATES
    for base in bases:
        full = os.path.normpath(os.path.join(ROOT, base, candidate))
        if os.path.exists(full):
            return True
    return False


def texts(path):
    """(line number, text) pairs to scan: every line of Markdown, doc comments of Rust."""
    with open(os.path.join(ROOT, path), encoding="utf-8", errors="replace") as f:
        for n, line in enumerate(f, 1):
            if path.endswith(".md"):
                yield n, line
            else:
                stripped = line.lstrip()
                if stripped.startswith(("//!", "///")):
                    yield n, stripped


def main():
    missing = []
    checked = 0
    for path in tracked_files():
        if not path.endswith((".md", ".rs")):
            continue
        for n, line in texts(path):
            for m in QUOTED.finditer(line):
                inner = m.group(1) or m.group(2)
                for found in PATH.finditer(inner):
                    p = found.group(0).rstrip(".")
                    before = inner[: found.start()]
                    # Part of a pattern (`*/tests/io.rs`) or of an environment path.
                    if before.endswith(("*", "/", "$")) or re.search(r"[A-Z_]+/$", before):
                        continue
                    if skipped(p):
                        continue
                    checked += 1
                    if not exists(p, path):
                        missing.append(f"{path}:{n}: {p}")
    for m in missing:
        print(m)
    print(f"check-paths: {checked} paths named in Markdown and doc comments, {len(missing)} missing")
    return 1 if missing else 0


if __name__ == "__main__":
    sys.exit(main())
