"""The API itself: names, attributes, misuse answered by a clear exception, the GIL released
while a buffer is decoded, and no Python object per input byte."""

import sys
import threading
import time
import tracemalloc

import pytest

import protolink
from protolink import aeolus, aok, aydp, gdl90
from conftest import TESTDATA

GYRO = aeolus.encode("GYRO", valid=True, timestamp_ms=7.0, x=0.5, y=-1.25, z=0.0078125)


def test_names():
    for mod in (aeolus, aydp, aok, gdl90):
        assert mod.Decoder.__name__ == "Decoder" and mod.Decoder.__module__ == mod.__name__
    assert callable(aeolus.encode) and callable(aydp.encode) and callable(aok.encode)
    assert callable(protolink.open) and callable(protolink.to_frames)
    assert aydp.Decoder().profile == "spec" and aydp.Decoder(profile="reference").profile == "reference"
    assert aok.Decoder().side == "device" and aok.Decoder(side="pc").side == "pc"


def test_message_attributes():
    d = aeolus.Decoder()
    (m,) = d.feed(b"\x00" * 3 + GYRO)
    assert (m.name, m.get_type(), m.id, m.offset, m.wire_len, m.proto) == ("GYRO", "GYRO", 62, 3, len(GYRO), "aeolus")
    assert (m.valid, m.timestamp_ms, m.x, m.y, m.z) == (True, 7.0, 0.5, -1.25, 0.0078125)
    assert m["y"] == -1.25 and "z" in m and "w" not in m
    assert m.meta == {"id": 62, "len": 38, "crc": "ok"}  # one byte escaped
    assert m.to_dict() == {"valid": True, "timestamp_ms": 7.0, "x": 0.5, "y": -1.25, "z": 0.0078125}
    copy = m.to_dict()
    copy["x"] = 99
    assert m.x == 0.5, "to_dict() gives a copy"
    assert (m.capture_time, m.flow, m.frame, m.is_error) == (None, None, None, False)
    assert {"name", "offset", "valid", "x"} <= set(dir(m))
    assert repr(m) == "GYRO(valid=True, timestamp_ms=7.0, x=0.5, y=-1.25, z=0.0078125)"
    with pytest.raises(AttributeError, match="GYRO has no field 'w'"):
        m.w
    with pytest.raises(KeyError):
        m["w"]


def test_error_event_attributes():
    bad = bytearray(GYRO)
    bad[5] ^= 0xFF
    (e,) = aeolus.Decoder().feed(bytes(bad))
    assert (e.name, e.get_type(), e.is_error, e.kind, e.offset, e.id, e.wire_len) == (
        "ERROR", "ERROR", True, "checksum_mismatch", 0, None, len(bad))
    assert e.error.startswith("CRC mismatch on message 62")
    assert e.to_dict() == {"kind": "checksum_mismatch", "error": e.error}
    assert repr(e).startswith('ERROR(kind="checksum_mismatch", offset=0')


def test_feed_takes_any_buffer():
    for data in (GYRO, bytearray(GYRO), memoryview(GYRO), memoryview(b"xx" + GYRO)[2:]):
        (m,) = aeolus.Decoder().feed(data)
        assert m.name == "GYRO"
    import array
    (m,) = aeolus.Decoder().feed(array.array("B", GYRO))
    assert m.x == 0.5


def test_datagram_boundaries():
    # A frame never spans two datagrams: the half frame at the end of one is given up.
    d = aeolus.Decoder()
    first = d.feed(GYRO[:10], datagram=True)
    second = d.feed(GYRO[10:], datagram=True)
    assert [e.kind for e in first] == ["truncated"] and second == []
    assert d.stats["truncated"] == 1
    d = aeolus.Decoder()
    assert d.feed(GYRO[:10]) == [] and d.feed(GYRO[10:])[0].name == "GYRO"


MISUSE = [
    (lambda: aydp.Decoder(profile="draft"), ValueError, "profile is 'spec' or 'reference', not 'draft'"),
    (lambda: aok.Decoder(side="ground"), ValueError, "side is 'device' or 'pc', not 'ground'"),
    (lambda: aydp.Decoder(profile=3), TypeError, "profile is 'spec' or 'reference', not 3"),
    (lambda: aok.Decoder(side=1), TypeError, "side is 'device' or 'pc', not 1"),
    (lambda: protolink.open(TESTDATA / "qemu-uart0-aeolus.bin", proto=b"aeolus"), TypeError, "proto is 'aeolus' or"),
    (lambda: aeolus.Decoder().feed("7e52"), TypeError, "feed takes bytes, not str"),
    (lambda: aeolus.Decoder().feed(12), TypeError, "not int"),
    (lambda: aeolus.Decoder().feed([0x7E, 0x52]), TypeError, "not list"),
    (lambda: aeolus.Decoder().feed(None), TypeError, "not NoneType"),
    (lambda: aeolus.encode("GYRO2"), ValueError, "AEOLUS has no message 'GYRO2'"),
    (lambda: aeolus.encode("GYRO", valid=True, timestamp_ms=1.0, x=1.0, y=2.0), ValueError, "missing field `z`"),
    (lambda: aeolus.encode("GYRO", valid=True, timestamp_ms=1.0, x=1.0, y=2.0, z="3"), TypeError, "invalid type: string"),
    (lambda: aeolus.encode("GYRO", valid=True, timestamp_ms=1.0, x=1.0, y=2.0, z=3.0, w=4.0), ValueError,
     "GYRO has no field 'w': its fields are valid, timestamp_ms, x, y, z"),
    (lambda: aeolus.encode("GPS", valid=True, has_fix=True, satellites=300, timestamp_ms=0.0, latitude_deg=0.0,
                           longitude_deg=0.0, altitude_m=0.0, ground_speed_mps=0.0), ValueError, "300"),
    (lambda: aeolus.encode("TOAST", text="x" * 121), ValueError, "cannot encode TOAST"),
    (lambda: aeolus.encode("UNKNOWN", id=62, data=bytes(32)), ValueError, "it decodes as GYRO, not UNKNOWN"),
    (lambda: aeolus.encode("LOG", data="abc"), ValueError, "not a hex string"),
    (lambda: aeolus.encode("LOG", data=b"\x01" * 9000), ValueError, "cannot encode LOG"),
    (lambda: aeolus.encode("GYRO", valid=True, timestamp_ms=float("inf"), x=0.0, y=0.0, z=0.0), ValueError, "finite"),
    (lambda: aydp.encode("WIND_SPEED", value=3.5), ValueError, "it decodes as TBD"),
    (lambda: aydp.encode("POSITION", profile="reference", expedited=True, latitude=0.0, longitude=0.0, altitude=0.0),
     ValueError, "cannot encode POSITION"),
    (lambda: aydp.encode("SYSTEM_CONTROL", command="Reboot"), ValueError, "`command` is"),
    (lambda: aydp.encode("HEARTBEAT", time=(1, 2)), ValueError, "no header time"),
    (lambda: aok.encode("MOTOR_TEST", motor=13, value=1), ValueError, "motor number 13 outside 1..=12"),
    (lambda: aok.encode("EXTERNAL_CONTROL", roll=201, nick=0, yaw=0, pitch=0, expiry_ms=0), ValueError, "201"),
    (lambda: aok.encode("SET_WAYPOINT", slot="32", longitude=0, latitude=0), ValueError, "'32' is not a slot"),
    (lambda: aok.encode("READ_PARAMETER", number=256), ValueError, "256"),
    (lambda: protolink.open(TESTDATA / "qemu-uart0-aeolus.bin"), ValueError, "open needs proto="),
    (lambda: protolink.open(TESTDATA / "qemu-uart0-aeolus.bin", proto="mavlink"), ValueError, "proto is"),
    (lambda: protolink.open("/nonexistent/flight.pcapng", proto="aeolus"), FileNotFoundError, "cannot open"),
    (lambda: protolink.open(42), TypeError, "open takes a path or an endpoint"),
    (lambda: protolink.open("udp:99999", proto="aeolus"), ValueError, "invalid endpoint"),
    (lambda: protolink.open(TESTDATA / "qemu-uart0-aeolus.bin", proto="aeolus", colour=1), TypeError, "colour"),
]


@pytest.mark.parametrize("call,exc,text", MISUSE)
def test_misuse_raises_one_sentence(call, exc, text):
    with pytest.raises(exc) as info:
        call()
    message = str(info.value)
    assert text in message
    assert "\n" not in message and len(message) < 400


def test_bad_bytes_never_raise():
    d = aeolus.Decoder()
    events = d.feed(bytes(range(256)) * 50 + b"\x7e\x7d\x7e\x7d\x01\x7e")
    events += d.finish()
    assert all(e.is_error for e in events) and len(events) > 0


def test_feed_releases_the_gil():
    # Another thread notes the time as it runs. Holding the GIL, feed would stop it for the
    # whole decode of 100 MB; releasing it, the thread keeps running in the middle of it.
    # Flags only: every byte goes through the decoder's byte-at-a-time step and no event
    # comes out (zeros would not do: the decoder passes over garbage a word at a time, and
    # 100 MB of them took under 0.1 s).
    data = b"\x7e" * 100_000_000
    seen = []
    stop = threading.Event()

    def spin():
        while not stop.is_set():
            seen.append(time.perf_counter())
            for _ in range(200):
                pass

    old = sys.getswitchinterval()
    sys.setswitchinterval(0.001)
    t = threading.Thread(target=spin)
    t.start()
    try:
        time.sleep(0.05)
        d = aeolus.Decoder()
        started = time.perf_counter()
        d.feed(data)
        ended = time.perf_counter()
    finally:
        stop.set()
        t.join()
        sys.setswitchinterval(old)
    assert ended - started > 0.1, "the decode must take long enough to measure"
    inside = [x for x in seen if started + 0.03 < x < ended - 0.03]
    assert len(inside) > 10, f"the other thread ran {len(inside)} times in the {ended - started:.3f} s of feed"


def test_feed_holds_no_object_per_byte():
    # 20 MB fed: Python-side allocations stay far below one object (or pointer) per byte.
    data = bytes(20_000_000)
    d = aeolus.Decoder()
    tracemalloc.start()
    try:
        d.feed(data)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < 1_000_000, peak
    assert d.stats["bytes_discarded"] == 20_000_000
    # A memoryview is copied once (its owner may change it while the GIL is released): the
    # measure sees that copy, so it would see per-byte objects too.
    tracemalloc.start()
    try:
        d.feed(memoryview(data))
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert 20_000_000 <= peak < 21_000_000, peak


def test_stats_are_the_crate_counters():
    d = aok.Decoder()
    d.feed((TESTDATA / "qemu-uart2-aok.bin").read_bytes())
    assert d.stats == {"frames_ok": 234, "checksum_errors": 0, "unknown_bytes": 0, "invalid": 0,
                       "abandoned": 0, "bytes_discarded": 0}
    assert gdl90.Decoder().stats["frames_ok"] == 0
