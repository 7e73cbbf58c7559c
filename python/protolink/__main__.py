"""``python -m protolink decode FILE [--proto ...] [--json]``: what ``protolink decode --from
FILE`` prints, byte for byte (it is the host tool's own command line, built into the
package). A bare FILE is read as ``--from FILE``."""

import sys
from typing import List

from ._native import run_cli

USAGE = """usage: python -m protolink decode FILE|--from ENDPOINT [--proto P] [--profile P] [--side S] [--json]
  the same options as `protolink decode` (python -m protolink decode --help)"""

# The options of `protolink decode` that take a value.
_VALUED = {"--proto", "--profile", "--side", "--from", "--udp-json", "--seconds"}


def decode_args(args: List[str]) -> List[str]:
    """``decode``'s arguments with a bare FILE turned into ``--from FILE``."""
    out: List[str] = []
    bare: List[str] = []
    takes_value = False
    for a in args:
        if takes_value:
            out.append(a)
            takes_value = False
        elif a in _VALUED:
            out.append(a)
            takes_value = True
        elif a.startswith("-") and a != "-":
            out.append(a)
        else:
            bare.append(a)
    if len(bare) == 1 and "--from" not in out and not any(a.startswith("--from=") for a in out):
        out += ["--from", bare[0]]
    else:
        out += bare
    return out


def main(argv: List[str]) -> int:
    if not argv or argv[0] != "decode":
        print(USAGE, file=sys.stderr)
        return 2
    sys.stdout.flush()
    return run_cli(["decode"] + decode_args(argv[1:]))


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
