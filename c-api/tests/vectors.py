#!/usr/bin/env python3
"""Writes the shared vectors as byte streams, one file per protocol (and AYDP profile, AOK
direction), for c-api/tests/host.sh: vectors.py VECTOR_DIR OUT_DIR."""
import json
import pathlib
import sys

src, out = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2])
out.mkdir(parents=True, exist_ok=True)


def vectors(name):
    return json.loads((src / name).read_text())["vectors"]


aeolus = vectors("aeolus-frames.json")
(out / "aeolus.bin").write_bytes(b"".join(bytes.fromhex(v["frame"]) for v in aeolus if "frame" in v))
aydp = vectors("aydp-messages.json")
for profile in ("spec", "reference"):
    data = b"".join(bytes.fromhex(v["bytes"]) for v in aydp if v.get("profile") == profile)
    (out / f"aydp-{profile}.bin").write_bytes(data)
aok = vectors("aok-frames.json")
for direction, side in (("to-device", "aok-pc"), ("from-device", "aok-device")):
    data = b"".join(bytes.fromhex(v["bytes"]) for v in aok if v.get("direction") == direction)
    (out / f"{side}.bin").write_bytes(data)
