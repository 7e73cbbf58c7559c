"""Attribute and item access never mean different things: whenever a message has a field `x`,
`m.x` is `m["x"]`, for every attribute of `Message` and every message type of the four
protocols (a field wins over the attribute of its name). The fields named like an attribute
are exactly those listed here, so that a new one is a decision, not an accident; and no field
is named like a metadata column of `to_frames`."""

import warnings

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import protolink
from conftest import GDL90_FRAMES, TESTDATA
from strategies import KINDS, every_type

# (protocol, message type) -> the fields named like an attribute of Message.
SHADOWED = {
    # The length of the raw data; the frame's length on the wire is `wire_len`.
    ("aeolus", "CALIBINFO"): {"len"},
    ("aeolus", "DEBUGINFO"): {"len"},
    ("aeolus", "LOG"): {"len"},
    ("aeolus", "UNKNOWN"): {"len"},
    # The device's name; the message's is get_type().
    ("gdl90", "FOREFLIGHT_ID"): {"name"},
    # The message ID, the same number as the `id` of every message.
    ("gdl90", "UNKNOWN"): {"id"},
}
ATTRIBUTES = sorted(a for a in dir(protolink.Message) if not a.startswith("_"))
# The columns to_frames adds beside the fields (and the `meta.` ones, which no field can be).
FRAME_COLUMNS = {"capture_time", "time", "offset", "flow", "frame", "proto"}


def check(m):
    assert not m.is_error, m
    fields = m.to_dict()
    shadowed = {a for a in ATTRIBUTES if a in fields}
    assert shadowed == SHADOWED.get((m.proto, m.get_type()), set()), (m.proto, m.get_type(), shadowed)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # reading a field never warns, `len` included
        for a in shadowed:
            assert getattr(m, a) == m[a] == fields[a], (m, a)
    for a in ATTRIBUTES:
        if a not in fields:
            with pytest.raises(KeyError):
                m[a]
    assert not FRAME_COLUMNS & fields.keys() and not any("." in k for k in fields), fields


def decoder(kind):
    if kind == "aeolus":
        return protolink.aeolus.Decoder()
    if kind.startswith("aydp"):
        return protolink.aydp.Decoder(profile=kind.split("-")[1])
    return protolink.aok.Decoder(side=kind.split("-")[1])


@pytest.mark.parametrize("kind", KINDS)
@settings(max_examples=40, deadline=None)
@given(data=st.data())
def test_every_type(kind, data):
    frames = data.draw(every_type(kind))
    d = decoder(kind)
    events = d.feed(b"".join(f for _, f in frames)) + d.finish()
    assert [m.get_type() for m in events] == [name for name, _ in frames]
    for m in events:
        check(m)
    assert all(m.wire_len == m.meta["len"] > 0 for m in events)


def test_every_gdl90_type():
    events = protolink.gdl90.Decoder().feed(b"".join(GDL90_FRAMES.values()))
    assert [m.get_type() for m in events] == list(GDL90_FRAMES)
    for m in events:
        check(m)
    assert all(m.wire_len == m.meta["len"] > 0 for m in events)
    ident = events[list(GDL90_FRAMES).index("FOREFLIGHT_ID")]
    assert (ident.name, ident["name"], ident.get_type()) == ("Box", "Box", "FOREFLIGHT_ID")
    unknown = events[-1]
    assert (unknown.id, unknown["id"], unknown.meta["id"]) == (7, 7, 7)


def test_samples():
    for name, kind in [("qemu-uart0-aeolus.bin", "aeolus"), ("qemu-uart1-aydp.bin", "aydp-spec"),
                       ("qemu-uart2-aok.bin", "aok-device")]:
        events = decoder(kind).feed((TESTDATA / name).read_bytes())
        for m in events:
            check(m)
        assert all(m.wire_len == m.meta["len"] > 0 for m in events)


def test_len_and_wire_len():
    # AEOLUS LOG: `len` is its field, the data's length, as m["len"]; the frame's length on
    # the wire is `wire_len` (flags, ID, escapes and CRC included).
    frame = protolink.aeolus.encode("LOG", data=b"\x7e\x01\x02")
    (log,) = protolink.aeolus.Decoder().feed(frame)
    assert (log.len, log["len"], log.wire_len, len(frame)) == (3, 3, 9, 9)
    # Where no field is named `len`, `m.len` is the deprecated name of `wire_len`.
    gyro_frame = protolink.aeolus.encode("GYRO", valid=True, timestamp_ms=1.0, x=0.0, y=0.0, z=0.0)
    (gyro,) = protolink.aeolus.Decoder().feed(gyro_frame)
    with pytest.warns(DeprecationWarning, match=r"Message\.len is deprecated: use wire_len"):
        assert gyro.len == gyro.wire_len == len(gyro_frame)
    # An error event's wire_len is the length of the bytes it condemns: here the whole frame
    # with its bad CRC, flag to flag (the deprecated len gives the same, with a warning).
    bad = bytearray(gyro_frame)
    bad[5] ^= 0xFF
    (err,) = protolink.aeolus.Decoder().feed(bytes(bad))
    assert err.is_error and (err.offset, err.wire_len) == (0, len(bad))
    with pytest.warns(DeprecationWarning):
        assert err.len == len(bad)
    assert "wire_len" in dir(gyro) and "len" not in dir(gyro) and "len" in dir(log)
