#!/usr/bin/env bash
# The main job. Until the firmware lands, it decodes the AEOLUS known-answer
# vectors and prints every message.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cargo run -q -p aeolus-proto --example decode_vectors -- testdata/aeolus-frames.json
