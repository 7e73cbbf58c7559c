"""`Decoder.feed_iter`: the events `feed` returns, decoded lazily a bounded step at a time
(issue 44), so that a big input is decoded in bounded memory."""

import os
import subprocess

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import protolink
from conftest import PYTHON, ROOT, TESTDATA

DECODERS = {
    "aeolus": protolink.aeolus.Decoder,
    "aydp-spec": lambda: protolink.aydp.Decoder(profile="spec"),
    "aydp-reference": lambda: protolink.aydp.Decoder(profile="reference"),
    "aok-pc": lambda: protolink.aok.Decoder(side="pc"),
    "aok-device": lambda: protolink.aok.Decoder(side="device"),
    "gdl90": protolink.gdl90.Decoder,
}


def summary(events):
    return [(e.name, e.offset, e.to_dict()) for e in events]


@pytest.mark.parametrize("kind", sorted(DECODERS))
def test_feed_iter_equals_feed(vector_files, kind):
    # Every sample and the kind's shared vectors (the others' bytes are noise to it), in
    # several 64 KiB pieces.
    data = b"".join(p.read_bytes() for p in sorted(TESTDATA.glob("*.bin")))
    vectors = vector_files[kind].read_bytes() if kind in vector_files else b""
    data = (data + vectors) * 40
    for datagram in (False, True):
        a, b = DECODERS[kind](), DECODERS[kind]()
        lazy = list(b.feed_iter(data, datagram=datagram))
        assert summary(lazy) == summary(a.feed(data, datagram=datagram))
        assert a.stats == b.stats and a.bytes_fed == b.bytes_fed == len(data)
        assert summary(a.finish()) == summary(b.finish())


@settings(max_examples=60, deadline=None)
@given(st.lists(st.binary(max_size=200_000), max_size=4), st.booleans())
def test_feed_iter_equals_feed_on_any_bytes(chunks, datagram):
    # Random bytes with AEOLUS frames between: any split into calls gives the same events.
    frame = protolink.aeolus.encode("GYRO", valid=True, timestamp_ms=1.0, x=0.5, y=0.25, z=0.125)
    a, b = protolink.aeolus.Decoder(), protolink.aeolus.Decoder()
    events_a, events_b = [], []
    for chunk in chunks:
        data = frame + chunk + frame
        events_a += a.feed(data, datagram=datagram)
        events_b += list(b.feed_iter(bytearray(data), datagram=datagram))
    assert summary(events_a + a.finish()) == summary(events_b + b.finish())


def test_feed_iter_of_every_buffer_and_of_nothing():
    frame = protolink.aeolus.encode("TOAST", text="hi")
    for buf in (frame, bytearray(frame), memoryview(frame)):
        (m,) = protolink.aeolus.Decoder().feed_iter(buf)
        assert m.name == "TOAST" and m.text == "hi"
    d = protolink.aeolus.Decoder()
    it = d.feed_iter(b"")
    assert iter(it) is it and list(it) == [] and it.bytes_left == 0
    # An empty datagram still ends one: the half frame before it is given up.
    d.feed(frame[:3])
    (e,) = d.feed_iter(b"", datagram=True)
    assert e.kind == "truncated"
    assert repr(protolink.aeolus.Decoder().feed_iter(frame)) == f"protolink.FeedIter(bytes_left={len(frame)}, ready=0)"


def test_feed_iter_misuse():
    d = protolink.aeolus.Decoder()
    with pytest.raises(TypeError, match="feed_iter takes bytes, not str"):
        d.feed_iter("text")
    with pytest.raises(TypeError, match="feed_iter takes bytes, bytearray, memoryview or another buffer"):
        d.feed_iter(5)
    # The decoder fed elsewhere in the middle of the iteration: refused, not interleaved.
    data = (TESTDATA / "qemu-uart0-aeolus.bin").read_bytes() * 20
    it = d.feed_iter(data)
    next(it)
    d.feed(b"\x7e")
    with pytest.raises(RuntimeError, match="the decoder was fed elsewhere while feed_iter was feeding it"):
        list(it)


# A child decodes about 60 MB of AEOLUS (1.2 M messages) with `feed` (a list of them all) or
# `feed_iter` (counting them as they come), and prints its peak RSS (VmHWM, the high-water
# mark of its own memory: ru_maxrss would start at this process's RSS, inherited at fork)
# before and after.
PEAK = f"""
import sys
import protolink
def peak():
    for line in open("/proc/self/status"):
        if line.startswith("VmHWM:"):
            return int(line.split()[1]) * 1024
data = open({str(TESTDATA / "qemu-uart0-aeolus.bin")!r}, "rb").read() * 760
before = peak()
d = protolink.aeolus.Decoder()
if sys.argv[1] == "feed":
    n = len(d.feed(data))
else:
    n = sum(1 for _ in d.feed_iter(data))
print(n, before, peak())
"""


def peak_growth(how):
    out = subprocess.run([PYTHON, "-c", PEAK, how], capture_output=True, text=True, check=True,
                         cwd=ROOT.parent).stdout.split()
    return int(out[0]), int(out[2]) - int(out[1])


@pytest.mark.skipif(not os.path.exists("/proc/self/status"), reason="VmHWM is Linux's")
def test_feed_iter_decodes_a_big_input_in_bounded_memory():
    n_iter, lazy = peak_growth("feed_iter")
    n_feed, whole = peak_growth("feed")
    print(f"peak RSS growth over 60 MB: feed_iter {lazy / 2**20:.0f} MiB, feed {whole / 2**20:.0f} MiB"
          f" ({n_feed} messages)")
    assert n_iter == n_feed > 1_000_000
    # One step's events at a time: a few MiB at most (0 measured). The list of every message
    # is over 200 MiB (about 180 bytes a message), well past the bound.
    bound = 64 * 2**20
    assert lazy < bound
    assert whole > 2 * bound
