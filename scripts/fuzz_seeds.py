#!/usr/bin/env python3
"""Writes fuzz seed corpora from the known-answer vectors in testdata/.

Usage: fuzz_seeds.py CORPUS_DIR. Each target gets the inputs it reads: whole wire streams for
the stream decoders, ID + unescaped data for the AEOLUS typed parses.
"""
import json, os, sys

root = os.path.join(os.path.dirname(__file__), "..", "testdata")
out = sys.argv[1]


def put(target, name, data):
    d = os.path.join(out, target)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, "seed-" + name), "wb") as f:
        f.write(data)


def unescape(body):
    res, it = bytearray(), iter(body)
    for b in it:
        res.append(next(it, 0) ^ 0x20 if b == 0x7D else b)
    return bytes(res)


aeolus = json.load(open(os.path.join(root, "aeolus-frames.json")))["vectors"]
for v in aeolus:
    wire = bytes.fromhex(v.get("frame") or v["bytes"])
    for t in ("aeolus_deframe", "aeolus_datagram"):
        put(t, v["name"], wire)
    for frame in wire.split(b"\x7e"):
        if len(frame) >= 3:
            raw = unescape(frame)
            for t in ("aeolus_parse", "aeolus_roundtrip"):
                put(t, v["name"] + "-" + str(raw[0]), raw[:-2])

# AYDP and AOK: every target of the protocol gets the whole wire bytes of every vector.
targets = os.listdir(os.path.join(os.path.dirname(__file__), "..", "fuzz", "fuzz_targets"))
for proto, fname in (("aydp", "aydp-messages.json"), ("aok", "aok-frames.json")):
    vectors = json.load(open(os.path.join(root, fname)))["vectors"]
    for t in sorted(x[:-3] for x in targets if x.startswith(proto + "_")):
        for v in vectors:
            put(t, v["name"], bytes.fromhex(v["bytes"]))

# GDL90: the ICD's heartbeat example and a ForeFlight AHRS frame, as a stream (gdl90_decode
# reads a chunk-size byte first) and as ID + data (gdl90_roundtrip).
gdl90 = {
    "icd-heartbeat": bytes.fromhex("7e008141dbd008 02b38b7e".replace(" ", "")),
}
for name, wire in gdl90.items():
    put("gdl90_decode", name, b"\x05" + wire + wire)
    for frame in wire.split(b"\x7e"):
        if len(frame) >= 3:
            raw = unescape(frame)
            put("gdl90_roundtrip", name, raw[:-2])
put("gdl90_roundtrip", "ahrs", bytes([0x65, 0x01, 0x01, 0x2C, 0xFF, 0xE7, 0x03, 0x84, 0x00, 0x6E, 0xFF, 0xFF]))
put("gdl90_roundtrip", "geo-altitude", bytes([0x0B, 0x00, 0xC8, 0x00, 0x0A]))
