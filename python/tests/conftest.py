"""Shared helpers: where the sample data are, and `protolink decode --json` as the reference
every decoded message is compared with.

The `protolink` binary is $PROTOLINK when set (scripts/test.sh builds it and sets it), else
target/release/protolink or target/debug/protolink of this checkout, built if missing.
"""

import json
import os
import pathlib
import socket
import subprocess
import sys

import pytest
from hypothesis import settings
from hypothesis.database import DirectoryBasedExampleDatabase

ROOT = pathlib.Path(__file__).resolve().parents[2]

# Hypothesis keeps its examples under target/, not in the working tree.
settings.register_profile(
    "protolink", database=DirectoryBasedExampleDatabase(str(ROOT / "target" / "hypothesis")))
settings.load_profile("protolink")
TESTDATA = ROOT / "testdata"
VECTORS = ROOT.parent / "shared" / "vectors"


def _protolink() -> str:
    env = os.environ.get("PROTOLINK")
    if env:
        return env
    for profile in ("release", "debug"):
        path = ROOT / "target" / profile / "protolink"
        if path.exists():
            return str(path)
    subprocess.run(["cargo", "build", "-q", "-p", "protolink"], cwd=ROOT, check=True)
    return str(ROOT / "target" / "debug" / "protolink")


PROTOLINK = _protolink()

# The options `protolink decode` takes for each stream kind the tests use.
ARGS = {
    "aeolus": ["--proto", "aeolus"],
    "aydp-spec": ["--proto", "aydp", "--profile", "spec"],
    "aydp-reference": ["--proto", "aydp", "--profile", "reference"],
    "aok-pc": ["--proto", "aok", "--side", "pc"],
    "aok-device": ["--proto", "aok", "--side", "device"],
    "gdl90": ["--proto", "gdl90"],
}


def protolink(*args: str, **kw) -> subprocess.CompletedProcess:
    """Runs the protolink binary; its output as bytes."""
    return subprocess.run([PROTOLINK, *args], capture_output=True, check=True, **kw)


def decode_json(path, *args: str):
    """`protolink decode --from PATH --json ARGS`: (events, summaries), each a JSON object."""
    out = protolink("decode", "--from", str(path), "--json", *args).stdout
    lines = [json.loads(line) for line in out.decode().splitlines()]
    events = [x for x in lines if x["kind"] in ("message", "error")]
    rest = [x for x in lines if x["kind"] not in ("message", "error")]
    return events, rest


CAPTURE_KEYS = {"frame", "capture_time", "flow", "proto"}


def assert_same(py_event, js: dict) -> None:
    """One Python event equals one `decode --json` line, field for field."""
    assert py_event.offset == js["offset"], (py_event, js)
    if js["kind"] == "error":
        assert py_event.is_error, (py_event, js)
        assert py_event.name == "ERROR"
        assert py_event.error == js["error"]
        assert py_event.kind and py_event.kind == py_event.kind.lower()
    else:
        assert not py_event.is_error, (py_event, js)
        assert py_event.get_type() == js["name"]
        assert py_event.to_dict() == js["fields"], (py_event, js)
        meta = {k: v for k, v in js.items()
                if k not in {"offset", "kind", "name", "fields"} | CAPTURE_KEYS}
        assert py_event.meta == meta
        assert py_event.wire_len == js["len"]
    if "capture_time" in js:
        assert py_event.capture_time == js["capture_time"]
        assert py_event.flow == js["flow"]
        assert py_event.frame == js["frame"]
        assert py_event.proto == js["proto"]
    else:
        assert py_event.flow is None and py_event.frame is None


def assert_all_same(py_events, js_events) -> None:
    assert len(py_events) == len(js_events)
    for p, j in zip(py_events, js_events):
        assert_same(p, j)


def free_port(kind=socket.SOCK_DGRAM) -> int:
    with socket.socket(socket.AF_INET, kind) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def vectors(name: str) -> list:
    return json.loads((VECTORS / name).read_text())["vectors"]


def vector_streams(tmp: pathlib.Path) -> dict:
    """The shared vectors as byte streams, one file per protocol kind (as
    c-api/tests/vectors.py writes them): {kind: path}."""
    streams = {
        "aeolus": b"".join(bytes.fromhex(v["frame"]) for v in vectors("aeolus-frames.json") if "frame" in v),
    }
    aydp = vectors("aydp-messages.json")
    for profile in ("spec", "reference"):
        streams[f"aydp-{profile}"] = b"".join(
            bytes.fromhex(v["bytes"]) for v in aydp if v.get("profile") == profile)
    aok = vectors("aok-frames.json")
    for direction, kind in (("to-device", "aok-pc"), ("from-device", "aok-device")):
        streams[kind] = b"".join(bytes.fromhex(v["bytes"]) for v in aok if v.get("direction") == direction)
    paths = {}
    for kind, data in streams.items():
        path = tmp / f"vectors-{kind}.bin"
        path.write_bytes(data)
        paths[kind] = path
    return paths


@pytest.fixture(scope="session")
def vector_files(tmp_path_factory):
    return vector_streams(tmp_path_factory.mktemp("vectors"))


PYTHON = sys.executable


def _crc_table():
    table = []
    for i in range(256):
        crc = i << 8
        for _ in range(8):
            crc = ((crc << 1) ^ (0x1021 if crc & 0x8000 else 0)) & 0xFFFF
        table.append(crc)
    return table


_CRC_TABLE = _crc_table()


def gdl90_frame(body: bytes) -> bytes:
    """One GDL90 frame of `body` (the message ID, then its data): the CRC of the ICD (the
    AEOLUS one, sent LSB first), the escapes and both flags. The package has no GDL90 encoder."""
    crc = 0
    for b in body:
        crc = _CRC_TABLE[crc >> 8] ^ ((crc << 8) & 0xFFFF) ^ b
    raw = body + bytes([crc & 0xFF, crc >> 8])
    return b"\x7e" + raw.replace(b"\x7d", b"\x7d\x5d").replace(b"\x7e", b"\x7d\x5e") + b"\x7e"


# One frame of every GDL90 message type the package decodes (gdl90-proto's lengths: the
# heartbeat 6 data bytes, a report 27, the geometric altitude 4, ForeFlight ID 38 and AHRS 11
# with their sub-ID, the Stratux AHRS 23 with its `45 01 01` header), and one of an ID it
# keeps raw (UNKNOWN, whose fields are `id` and `data`).
GDL90_FRAMES = {
    "HEARTBEAT": gdl90_frame(bytes([0, 0x81, 0x01, 0x10, 0x0E, 0x00, 0x00])),
    "OWNSHIP": gdl90_frame(bytes([10, 0x00, 0xA1, 0xB2, 0xC3, 0x1F, 0xEF, 0x6E, 0xB5, 0x1C, 0x91, 0x0D, 0xA9,
                                  0x88, 0x20, 0x01, 0x00, 0x08, 0x01, 0x4E, 0x31, 0x32, 0x33, 0x34, 0x35,
                                  0x20, 0x20, 0x00])),
    "GEO_ALTITUDE": gdl90_frame(bytes([11, 0x01, 0x2C, 0x7F, 0xFF])),
    "TRAFFIC": gdl90_frame(bytes([20, 0x00, 0xAB, 0x45, 0x49, 0x1F, 0xEF, 0x15, 0xA8, 0x89, 0x78, 0x0F, 0x09,
                                  0xA9, 0x07, 0xB0, 0x01, 0x20, 0x01, 0x4E, 0x31, 0x32, 0x33, 0x34, 0x35,
                                  0x20, 0x20, 0x00])),
    "FOREFLIGHT_ID": gdl90_frame(bytes([0x65, 0x00, 0x01]) + (1234).to_bytes(8, "big") + b"Box\0\0\0\0\0"
                                 + b"Sensor box\0\0\0\0\0\0" + bytes([0, 0, 0, 1])),
    "FOREFLIGHT_AHRS": gdl90_frame(bytes([0x65, 0x01, 0xFF, 0x83, 0x00, 0x1E, 0x8A, 0x99, 0x00, 0x62, 0xFF, 0xFF])),
    "STRATUX_AHRS": gdl90_frame(bytes([0x4C, 0x45, 0x01, 0x01, 0x00, 0x0A, 0xFF, 0xF6, 0x03, 0x84, 0x00, 0x05,
                                       0x00, 0x0C, 0x00, 0x0A, 0x00, 0x64, 0x00, 0x00, 0x1B, 0x58, 0x00, 0x00])),
    "UNKNOWN": gdl90_frame(bytes([7, 1, 2, 3])),
}
