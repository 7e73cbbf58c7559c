#!/usr/bin/env python3
"""Prints the features of scripts/test.sh's host test build: every feature of every workspace
member, except those that turn on `defmt`.

    cargo build --profile test --workspace --features "$(python3 scripts/test-features.py)" ...

One comma-separated list of `package/feature`. Left out: each member's `defmt` feature and every
feature that turns one on, directly or through other features (firmware-example's boards). The
reason is the Python extension, which that build makes too: with `defmt` on, every defmt format
string becomes an exported symbol of the extension named by its JSON text, which the linker's
version script cannot hold (rust-lld and GNU ld both stop at the first one). On the host a
`defmt` derive does nothing a test could observe; clippy (`--all-features`, host) type-checks
it and the thumb check and firmware builds compile it where it runs.

`--left-out` prints the features left out instead, one per line.
"""
import json
import subprocess
import sys


def main(argv):
    if argv not in ([], ["--left-out"]):
        sys.exit(__doc__)
    try:
        out = subprocess.run(
            ["cargo", "metadata", "--no-deps", "--format-version", "1"],
            check=True, capture_output=True, text=True,
        ).stdout
    except (OSError, subprocess.CalledProcessError) as e:
        sys.exit(f"test-features: cargo metadata failed: {e}")
    packages = json.loads(out)["packages"]
    members = {p["name"]: p["features"] for p in packages}
    keep, left_out = [], []
    for name, features in members.items():
        for feature in sorted(features):
            if feature == "default":
                continue
            if turns_on_defmt(members, name, feature, set()):
                left_out.append(f"{name}/{feature}")
            else:
                keep.append(f"{name}/{feature}")
    print("\n".join(left_out) if argv else ",".join(keep))


def turns_on_defmt(members, package, feature, seen):
    """Whether `package/feature` turns on a `defmt` feature or dependency of a member, through
    the member features it enables (`f`, `member/f`, `member?/f`)."""
    if (package, feature) in seen:
        return False
    seen.add((package, feature))
    if feature == "defmt":
        return True
    for item in members.get(package, {}).get(feature, []):
        if item.startswith("dep:"):
            if item[4:].startswith("defmt"):
                return True
            continue
        target, _, sub = item.partition("/")
        if sub:
            target = target.rstrip("?")
            if target.startswith("defmt") or sub == "defmt":
                return True
            if target in members and turns_on_defmt(members, target, sub, seen):
                return True
        elif turns_on_defmt(members, package, item, seen):
            return True
    return False


if __name__ == "__main__":
    main(sys.argv[1:])
