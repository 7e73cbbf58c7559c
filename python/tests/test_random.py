"""Random bytes never raise: every decoder takes any input, in any chunks, and reports bad
bytes as error events and counters. The counters add up to the bytes fed, and every error
counted is an event (errors travel as events, never only as counters)."""

import struct

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import protolink

# Bytes that matter to each protocol, mixed into the random ones so that frames, escapes and
# false starts actually happen.
SPECIAL = {
    "aeolus": [0x7E, 0x7D, 0x5D, 0x5E, 0x00, 0x3E, 0x52],
    "gdl90": [0x7E, 0x7D, 0x5D, 0x5E, 0x00, 0x0A, 0x65],
    "aydp-spec": [0xFF, 0x00, 0x03, 0x07, 0x08, 0x09, 0x80, 0x89],
    "aydp-reference": [0xFF, 0x00, 0x01, 0x04, 0x11],
    "aok-pc": [0x67, 0x73, 0x77, 0x53, 0x33, 0x00, 0x0C, 0x02],
    "aok-device": [0x1C, 0xFF, 0x00, 0x0C, 0x57],
}


def decoder(kind):
    if kind == "aeolus":
        return protolink.aeolus.Decoder()
    if kind == "gdl90":
        return protolink.gdl90.Decoder()
    if kind.startswith("aydp"):
        return protolink.aydp.Decoder(profile=kind.split("-")[1])
    return protolink.aok.Decoder(side=kind.split("-")[1])


def stream(kind):
    byte = st.one_of(st.integers(0, 255), st.sampled_from(SPECIAL[kind]))
    return st.lists(byte, max_size=3000).map(bytes)


def signature(events):
    return [(e.name, e.offset, e.to_dict()) for e in events]


def aydp_frame_len(data, event, profile):
    """The wire length of the frame a malformed-message event names, from its header: the
    length field counts the whole message (spec) or its data only (reference: + 23)."""
    (length,) = struct.unpack_from("<I", data, event.offset + 2)
    return length if profile == "spec" else length + 23


@pytest.mark.parametrize("kind", sorted(SPECIAL))
@settings(max_examples=150, deadline=None)
@given(data=st.data())
def test_random_bytes(kind, data):
    raw = data.draw(stream(kind))
    cuts = sorted(data.draw(st.lists(st.integers(0, len(raw)), max_size=8)))
    whole = decoder(kind)
    events = whole.feed(raw) + whole.finish()
    pieces = decoder(kind)
    chunked = []
    for a, b in zip([0] + cuts, cuts + [len(raw)]):
        chunked += pieces.feed(memoryview(raw)[a:b] if a % 2 else raw[a:b])
    chunked += pieces.finish()
    # Chunks change nothing.
    assert signature(chunked) == signature(events)
    assert pieces.stats == whole.stats

    s = whole.stats
    messages = [e for e in events if not e.is_error]
    errors = [e for e in events if e.is_error]
    assert all(e.kind and e.error for e in errors)
    assert all(isinstance(m.name, str) and m.wire_len > 0 for m in messages)
    assert whole.bytes_fed == len(raw)
    if kind in ("aeolus", "gdl90"):
        # Every byte is noise, frame or flag.
        assert s["bytes_discarded"] + s["frame_bytes"] + s["flags"] == len(raw)
    if kind == "aeolus":
        assert len(messages) == s["frames_ok"] + s["frames_no_crc"] - s["malformed"]
        assert len(errors) == (s["checksum_errors"] + s["missing_crc"] + s["overflows"] + s["too_short"]
                               + s["bad_escapes"] + s["malformed"] + s["truncated"])
    elif kind == "gdl90":
        assert len(messages) == s["frames_ok"]
        assert len(errors) == (s["invalid"] + s["checksum_errors"] + s["overflows"] + s["too_short"]
                               + s["bad_escapes"] + s["truncated"])
    elif kind.startswith("aydp"):
        profile = kind.split("-")[1]
        malformed = [e for e in errors if e.error.startswith("type ")]
        assert len(malformed) == s["malformed"]
        assert len(messages) + s["malformed"] == s["frames_ok"]
        assert len(errors) == s["checksum_errors"] + s["length_errors"] + s["malformed"] + s["truncated"]
        frames = sum(m.wire_len for m in messages) + sum(aydp_frame_len(raw, e, profile) for e in malformed)
        assert s["bytes_discarded"] + frames == len(raw)
    else:
        # Every byte is part of a message or discarded.
        assert s["bytes_discarded"] + sum(m.wire_len for m in messages) == len(raw)
        assert len(errors) == s["checksum_errors"] + s["invalid"] + s["abandoned"]


def test_counters_literal():
    # A good frame, noise, a bad CRC and a frame cut off by the end: each counted once.
    good = protolink.aeolus.encode("TOAST", text="hi")
    bad = bytearray(good)
    bad[3] ^= 1
    d = protolink.aeolus.Decoder()
    events = d.feed(b"\x01\x02" + good + bytes(bad) + good[:5]) + d.finish()
    assert [e.name for e in events] == ["TOAST", "ERROR", "ERROR"]
    assert [e.kind for e in events[1:]] == ["checksum_mismatch", "truncated"]
    assert [e.offset for e in events] == [2, 10, 18]
    # Discarded: the 2 noise bytes, the 6 between the bad frame's flags, the 4 after the flag
    # of the cut frame.
    assert d.stats["bytes_discarded"] == 2 + 6 + 4 and d.stats["checksum_errors"] == 1
    assert d.stats["truncated"] == 1 and d.stats["frames_ok"] == 1
