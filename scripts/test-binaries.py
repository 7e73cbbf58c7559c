#!/usr/bin/env python3
"""Lists the test executables of one cargo test build, for scripts/test.sh to run them itself.

    cargo test --workspace --all-features --no-run --message-format=json-render-diagnostics >BUILD.json
    python3 scripts/test-binaries.py BUILD.json [--only PACKAGE | --except PACKAGE]

Prints one line per test executable: the package's directory (cargo runs a test binary there),
the executable, and the label cargo's own `Running` line gives it (`tests/all/main.rs`,
`unittests src/lib.rs`), tab-separated, in the build's order. Running the executables of the
one build, instead of a second `cargo test -p ...`, keeps every crate's features as the
workspace build unified them: a `cargo test` over fewer packages resolves other features for
the shared dependencies and compiles them again.
"""
import json
import os
import sys


def main(argv):
    if not argv or len(argv) > 3 or (len(argv) == 3 and argv[1] not in ("--only", "--except")):
        sys.exit(__doc__)
    path = argv[0]
    mode, package = (argv[1], argv[2]) if len(argv) == 3 else (None, None)
    try:
        lines = open(path).read().splitlines()
    except OSError as e:
        sys.exit(f"test-binaries: cannot read {path}: {e.strerror}")
    found = 0
    for line in lines:
        if not line.startswith("{"):
            continue
        m = json.loads(line)
        if m.get("reason") != "compiler-artifact" or not m.get("profile", {}).get("test"):
            continue
        exe = m.get("executable")
        if not exe:
            continue
        target = m["target"]
        manifest_dir = os.path.dirname(m["manifest_path"])
        name = package_name(m["package_id"])
        if (mode == "--only" and name != package) or (mode == "--except" and name == package):
            continue
        src = os.path.relpath(target["src_path"], manifest_dir)
        label = f"unittests {src}" if target["kind"] != ["test"] else src
        print(f"{manifest_dir}\t{exe}\t{name}: {label}")
        found += 1
    if found == 0:
        sys.exit(f"test-binaries: no test executable in {path}")


def package_name(pid):
    """The package's name from cargo's package id: `path+file:///dir#name@version`, or
    `path+file:///dir/name#version` when the directory bears the package's name."""
    base, frag = pid.rsplit("#", 1)
    return frag.split("@", 1)[0] if "@" in frag else base.rstrip("/").rsplit("/", 1)[-1]


if __name__ == "__main__":
    main(sys.argv[1:])
