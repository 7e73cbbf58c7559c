"""Every message and error event the package decodes equals what `protolink decode --json`
prints, field for field: the sample UART captures in testdata/, the shared vectors, hostile
streams, and pcapng / pcap captures (written by `protolink record` from files, from
`protolink sim` on UDP, and from `protolink gdl90`)."""

import random
import struct
import subprocess
import time

import pytest

import protolink
from conftest import (
    ARGS,
    PROTOLINK,
    TESTDATA,
    assert_all_same,
    decode_json,
    free_port,
    protolink as run_protolink,
    vectors,
)


def decoder(kind):
    if kind == "aeolus":
        return protolink.aeolus.Decoder()
    if kind.startswith("aydp"):
        return protolink.aydp.Decoder(profile=kind.split("-")[1])
    if kind.startswith("aok"):
        return protolink.aok.Decoder(side=kind.split("-")[1])
    return protolink.gdl90.Decoder()


def decode_py(kind, data, chunk=None):
    d = decoder(kind)
    events = []
    step = chunk or max(len(data), 1)
    for i in range(0, len(data), step):
        events += d.feed(data[i:i + step])
    events += d.finish()
    return events, d


def check_file(path, kind):
    js, rest = decode_json(path, *ARGS[kind])
    data = path.read_bytes()
    for chunk in (None, 1, 7, 4096):
        events, d = decode_py(kind, data, chunk)
        assert_all_same(events, js)
        assert d.stats == rest[-1]["counters"]
        assert d.bytes_fed == len(data) == rest[-1]["bytes"]
    # The same file through protolink.open (64 KiB reads).
    with protolink.open(path, kind.split("-")[0], profile=_profile(kind), side=_side(kind)) as r:
        assert_all_same(list(r), js)
        assert r.stats == rest[-1]["counters"]
    return js


def _profile(kind):
    return kind.split("-")[1] if kind.startswith("aydp") else None


def _side(kind):
    return kind.split("-")[1] if kind.startswith("aok") else "device"


TESTDATA_FILES = [
    ("qemu-uart0-aeolus.bin", "aeolus"),
    ("qemu-uart1-aydp.bin", "aydp-spec"),
    ("qemu-uart2-aok.bin", "aok-device"),
    # Another protocol's bytes: error events and resynchronisation, compared too.
    ("qemu-uart2-aok.bin", "aok-pc"),
    ("qemu-uart1-aydp.bin", "aydp-reference"),
    ("qemu-uart0-aeolus.bin", "gdl90"),
]


@pytest.mark.parametrize("name,kind", TESTDATA_FILES)
def test_testdata(name, kind):
    js = check_file(TESTDATA / name, kind)
    assert len(js) > 0


def test_testdata_literal_counts():
    # Literal figures of the sample captures (README: 1614 AEOLUS frames, 15 AYDP, 234 AOK).
    events, d = decode_py("aeolus", (TESTDATA / "qemu-uart0-aeolus.bin").read_bytes())
    names = [m.name for m in events]
    assert len(events) == 1614 and not any(m.is_error for m in events)
    assert names.count("GYRO") == 248 and names.count("PRESSURE") == 347 and names.count("GPS") == 19
    assert events[1].name == "GYRO" and events[1].offset == 15 and events[1].id == 62
    assert events[1].y == pytest.approx(0.024415644) and events[1].valid is True
    assert d.stats["frames_ok"] == 1614 and d.stats["frame_bytes"] == 75406
    events, _ = decode_py("aydp-spec", (TESTDATA / "qemu-uart1-aydp.bin").read_bytes())
    assert len(events) == 15 and events[1].name == "POSITION" and events[1].altitude == 1000.0
    events, _ = decode_py("aok-device", (TESTDATA / "qemu-uart2-aok.bin").read_bytes())
    assert len(events) == 234 and events[0].name == "DEBUG" and events[0].value == 2000


@pytest.mark.parametrize("kind", ["aeolus", "aydp-spec", "aydp-reference", "aok-pc", "aok-device"])
def test_shared_vectors(vector_files, kind):
    check_file(vector_files[kind], kind)


def test_aeolus_vectors_fields():
    # Independent of protolink decode: the vectors' own fields, as the spec's tables give them.
    for v in vectors("aeolus-frames.json"):
        if "frame" not in v or "fields" not in v:
            continue
        (m,) = protolink.aeolus.Decoder().feed(bytes.fromhex(v["frame"]))
        assert m.id == v["id"]
        for key, want in v["fields"].items():
            assert m[key] == pytest.approx(want), (v["name"], key)


def hostile(seed, n, alphabet):
    rnd = random.Random(seed)
    return bytes(rnd.choice(alphabet) if rnd.random() < 0.6 else rnd.randrange(256) for _ in range(n))


@pytest.mark.parametrize("kind,alphabet", [
    ("aeolus", [0x7E, 0x7D, 0x5D, 0x5E, 0x00, 0x3E, 0x52]),
    ("gdl90", [0x7E, 0x7D, 0x5D, 0x5E, 0x00, 0x0A, 0x65]),
    ("aydp-spec", [0xFF, 0x00, 0x03, 0x08, 0x09, 0x80, 0x89, 0x2B]),
    ("aydp-reference", [0xFF, 0x00, 0x01, 0x11, 0x04, 0x07]),
    ("aok-pc", [0x67, 0x73, 0x77, 0x53, 0x33, 0x00, 0x0C]),
    ("aok-device", [0x1C, 0xFF, 0x57, 0x4F, 0x45, 0x49, 0x00]),
])
def test_hostile_streams(tmp_path, kind, alphabet):
    path = tmp_path / "hostile.bin"
    path.write_bytes(hostile(31, 60_000, alphabet))
    js = check_file(path, kind)
    assert any(e["kind"] == "error" for e in js)


def record(tmp_path, source, proto_args, name):
    out = tmp_path / name
    run_protolink("record", "--from", f"file:{source}", *proto_args, "--out", str(out))
    return out


def check_capture(path, *args, **options):
    js, rest = decode_json(path, *args)
    with protolink.open(path, **options) as r:
        events = list(r)
        stats = r.stats
    assert_all_same(events, js)
    flows = {x["flow"]: x for x in rest if x["kind"] == "summary"}
    assert set(stats) == set(flows)
    for flow, s in stats.items():
        assert s["counters"] == flows[flow]["counters"]
        assert s["bytes"] == flows[flow]["bytes"] and s["proto"] == flows[flow]["proto"]
    return events


@pytest.mark.parametrize("name,proto_args", [
    ("qemu-uart0-aeolus.bin", ["--proto", "aeolus"]),
    ("qemu-uart1-aydp.bin", ["--proto", "aydp", "--profile", "spec"]),
    ("qemu-uart2-aok.bin", ["--proto", "aok", "--side", "device"]),
])
def test_recorded_stream_capture(tmp_path, name, proto_args):
    cap = record(tmp_path, TESTDATA / name, proto_args, "stream.pcapng")
    events = check_capture(cap)
    assert len(events) > 10 and all(m.frame == 1 for m in events[:5])
    assert all(m.flow == events[0].flow for m in events)
    assert events[0].flow.startswith("stream 0 linktype 1")


def run_for(args, seconds):
    return subprocess.Popen([PROTOLINK, *args, "--seconds", str(seconds)],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def test_recorded_udp_capture_of_sim(tmp_path):
    port, port_in = free_port(), free_port()
    cap = tmp_path / "sim.pcapng"
    rec = run_for(["record", "--from", f"udp:{port}", "--out", str(cap)], 3)
    time.sleep(0.4)
    run_protolink("sim", "--udp-out", f"127.0.0.1:{port}", "--udp-in", str(port_in),
                  "--pack", "3", "--seconds", "1.5")
    assert rec.wait(timeout=20) == 0
    events = check_capture(cap, "--proto", "aeolus", proto="aeolus")
    names = [m.name for m in events]
    assert names.count("GYRO") > 50 and names[0] == "TOAST"
    assert all(m.flow.startswith("udp 127.0.0.1:") and m.flow.endswith(f"> 127.0.0.1:{port}") for m in events)
    assert all(m.capture_time > 1e9 for m in events)
    # Without proto= the port names nothing: every record is skipped, as in decode.
    assert list(protolink.open(cap)) == []


def test_recorded_gdl90_capture(tmp_path):
    aeolus_port, gdl90_port, port_in = free_port(), free_port(), free_port()
    cap = tmp_path / "gdl90.pcapng"
    rec = run_for(["record", "--from", f"udp:{gdl90_port}", "--out", str(cap)], 4.5)
    bridge = run_for(["gdl90", "--from", f"udp:{aeolus_port}", "--to", f"127.0.0.1:{gdl90_port}"], 4)
    time.sleep(0.4)
    run_protolink("sim", "--udp-out", f"127.0.0.1:{aeolus_port}", "--udp-in", str(port_in), "--seconds", "3")
    assert bridge.wait(timeout=20) == 0 and rec.wait(timeout=20) == 0
    events = check_capture(cap, "--proto", "gdl90", proto="gdl90")
    names = {m.get_type() for m in events}  # FOREFLIGHT_ID's `name` is the device's
    assert {"HEARTBEAT", "OWNSHIP", "FOREFLIGHT_AHRS"} <= names, names


def ethernet_udp(src_port, dst_port, payload):
    """One Ethernet/IPv4/UDP packet from 127.0.0.1 to 127.0.0.1."""
    udp = struct.pack(">HHHH", src_port, dst_port, 8 + len(payload), 0) + payload
    ip = struct.pack(">BBHHHBBH4s4s", 0x45, 0, 20 + len(udp), 0, 0, 64, 17, 0,
                     bytes([127, 0, 0, 1]), bytes([127, 0, 0, 1]))
    return bytes(12) + b"\x08\x00" + ip + udp


def write_pcap(path, packets):
    """A classic pcap (microseconds, Ethernet) of (time, packet) pairs."""
    out = struct.pack("<IHHiIII", 0xA1B2C3D4, 2, 4, 0, 0, 65535, 1)
    for t, p in packets:
        out += struct.pack("<IIII", int(t), int(round((t % 1) * 1e6)), len(p), len(p)) + p
    path.write_bytes(out)


def test_classic_pcap_by_port(tmp_path):
    # AEOLUS frames to UDP 5001 (three per datagram), a GDL90 heartbeat to 4000, DNS to 53:
    # the ports name the protocols, as in decode.
    frames = [m for m in protolink.aeolus.Decoder().feed((TESTDATA / "qemu-uart0-aeolus.bin").read_bytes())][:60]
    wire = [protolink.aeolus.encode(m.name, **m.to_dict()) for m in frames]
    packets = []
    t = 1_700_000_000.25
    for i in range(0, len(wire), 3):
        packets.append((t, ethernet_udp(40000, 5001, b"".join(wire[i:i + 3]))))
        t += 0.01
    heartbeat = bytes.fromhex("7e" "00810000000000" "0000" "7e")  # CRC 00 00: an error in GDL90
    packets.append((t, ethernet_udp(40001, 4000, heartbeat)))
    packets.append((t + 0.5, ethernet_udp(40002, 53, b"\x12\x34")))
    cap = tmp_path / "ports.pcap"
    write_pcap(cap, packets)
    events = check_capture(cap)
    assert [m.name for m in events[:60]] == [m.name for m in frames]
    assert events[0].capture_time == pytest.approx(1_700_000_000.25)
    assert events[0].flow == "udp 127.0.0.1:40000 > 127.0.0.1:5001" and events[0].proto == "aeolus"
    assert events[-1].proto == "gdl90" and events[-1].is_error and events[-1].kind == "checksum_mismatch"
    # proto= keeps one protocol, as decode --proto does.
    only = list(protolink.open(cap, proto="gdl90"))
    assert len(only) == 1 and only[0].kind == "checksum_mismatch"


# The AEOLUS messages of a fixed layout: ID and data length (aeolus-proto's layout table).
FIXED = {51: 32, 61: 32, 62: 32, 63: 40, 64: 32, 65: 32, 66: 32, 71: 52, 72: 80, 73: 32, 12: 32}


def escaped(body):
    return body.replace(b"\x7d", b"\x7d\x5d").replace(b"\x7e", b"\x7d\x5e")


def test_any_field_bits(tmp_path):
    # Fixed-layout frames with arbitrary data bytes, float bit patterns that no encoder makes
    # included (NaN, infinities, subnormals, -0.0): the package renders their fields itself
    # (to_python.rs), and must give what decode --json gives. Sent without CRC (00 00).
    rnd = random.Random(7)
    specials = [struct.pack("<f", v) for v in (float("nan"), float("inf"), -float("inf"), -0.0, 1e-45, 3.4e38)]
    specials += [struct.pack("<d", v)[:4] for v in (float("nan"), 5e-324)]
    stream = b""
    for _ in range(3000):
        id_, n = rnd.choice(list(FIXED.items()))
        data = bytearray(rnd.randbytes(n))
        for _ in range(rnd.randrange(4)):
            at = rnd.randrange(0, n - 3)
            data[at:at + 4] = rnd.choice(specials)
        stream += b"\x7e" + escaped(bytes([id_]) + bytes(data) + b"\x00\x00") + b"\x7e"
    path = tmp_path / "fields.bin"
    path.write_bytes(stream)
    js = check_file(path, "aeolus")
    assert len(js) == 3000 and not any(e["kind"] == "error" for e in js)
    assert any(v is None for e in js for v in e["fields"].values())  # a NaN read as None
