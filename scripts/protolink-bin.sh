#!/usr/bin/env bash
# Prints the path of the `protolink` binary the checks run: $PROTOLINK when set (scripts/test.sh
# sets it to the binary its test build made, so protolink is compiled once per run), else this
# checkout's build with the `test` profile, made first (its dependencies are those of
# `cargo test`, so after a test build only protolink itself is compiled).
set -euo pipefail
cd "$(dirname "$0")/.."
if [ -n "${PROTOLINK:-}" ]; then
  [ -x "$PROTOLINK" ] || { echo "PROTOLINK=$PROTOLINK is not an executable file" >&2; exit 1; }
  echo "$PROTOLINK"
  exit 0
fi
cargo build -q --profile test -p protolink >&2
echo "$PWD/${CARGO_TARGET_DIR:-target}/debug/protolink"
