"""A capture cut inside a block (what `protolink record` leaves when it is killed with
SIGKILL), issue 44: reading yields every whole record's messages, then warns
(`protolink.TruncatedCaptureWarning`) with the byte offset where the cut block starts;
`strict=True` raises `OSError` with that offset instead."""

import re
import struct
import subprocess
import warnings

import pytest

import protolink
from conftest import PROTOLINK, TESTDATA

SAMPLE = TESTDATA / "qemu-uart0-aeolus.bin"
EPB = 6  # pcapng's enhanced packet block


def blocks(data):
    """The blocks of a little-endian pcapng: (offset, type, length, payload or None)."""
    out, at = [], 0
    while at < len(data):
        kind, length = struct.unpack_from("<II", data, at)
        payload = None
        if kind == EPB:
            captured = struct.unpack_from("<I", data, at + 20)[0]
            payload = data[at + 28:at + 28 + captured]
        out.append((at, kind, length, payload))
        at += length
    return out


@pytest.fixture(scope="module")
def capture(tmp_path_factory):
    """A pcapng that `protolink record` wrote of 5 x the AEOLUS sample: 6 records of a byte
    stream (64 KiB each but the last), after a section header and an interface."""
    tmp = tmp_path_factory.mktemp("cut")
    raw = tmp / "stream.bin"
    raw.write_bytes(SAMPLE.read_bytes() * 5)
    path = tmp / "flight.pcapng"
    subprocess.run([PROTOLINK, "record", "--from", f"file:{raw}", "--proto", "aeolus", "--out", str(path)],
                   check=True, capture_output=True)
    return path


def summary(events):
    return [(e.name, e.offset, e.to_dict()) for e in events]


def expected(bs, cut):
    """What the whole records before `cut` hold, decoded as one stream and ended there."""
    stream = b"".join(p for at, kind, length, p in bs if kind == EPB and at + length <= cut)
    d = protolink.aeolus.Decoder()
    return summary(d.feed(stream) + d.finish())


def cut_points(bs):
    """Cuts inside the last block, the fifth (the third record) and the interface
    description (no record yet): just past its start, past its 8-byte header, in the middle,
    one byte short of its end."""
    out = []
    for at, kind, length, _ in (bs[-1], bs[4], bs[1]):
        out += [(at, at + n) for n in (1, 8, 12, length // 2, length - 1)]
    return out


def test_the_capture_has_the_blocks_the_test_cuts(capture):
    bs = blocks(capture.read_bytes())
    assert [kind for _, kind, _, _ in bs] == [0x0A0D0D0A, 1] + [EPB] * 6
    assert all(len(p) == 65536 for _, _, _, p in bs[2:-1])


def test_every_whole_record_then_a_warning_with_the_offset(capture, tmp_path):
    data = capture.read_bytes()
    bs = blocks(data)
    cut_file = tmp_path / "cut.pcapng"
    for start, cut in cut_points(bs):
        cut_file.write_bytes(data[:cut])
        whole = sum(1 for at, kind, length, _ in bs if kind == EPB and at + length <= cut)
        with pytest.warns(protolink.TruncatedCaptureWarning) as caught:
            with protolink.open(cut_file) as r:
                events = list(r)
                assert r.truncated_at == start
        (w,) = caught
        message = str(w.message)
        assert f"is cut inside the block at byte {start}, after frame {whole}:" in message, message
        assert "\n" not in message
        assert summary(events) == expected(bs, cut), (start, cut)
        assert max((m.frame for m in events), default=0) == whole
        # The first `start` bytes are a whole capture, as the warning says: no warning.
        cut_file.write_bytes(data[:start])
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            with protolink.open(cut_file) as r:
                assert summary(r) == summary(events) and r.truncated_at is None


def test_to_frames_of_a_cut_capture(capture, tmp_path):
    data = capture.read_bytes()
    bs = blocks(data)
    start = bs[4][0]
    cut = tmp_path / "cut.pcapng"
    cut.write_bytes(data[:start + 100])
    with pytest.warns(protolink.TruncatedCaptureWarning, match=f"at byte {start}, after frame 2:"):
        frames = protolink.to_frames(cut)
    rows = {}
    for name, _, _ in expected(bs, start + 100):
        rows[name] = rows.get(name, 0) + 1
    assert {k: len(v) for k, v in frames.items()} == rows
    assert rows["GYRO"] > 400  # two whole records: 1.7 samples of telemetry
    # The whole capture: no warning, more rows.
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert len(protolink.to_frames(capture)["GYRO"]) == 5 * 248


def test_strict_raises_oserror_with_the_offset(capture, tmp_path):
    data = capture.read_bytes()
    bs = blocks(data)
    start = bs[-1][0]
    cut = tmp_path / "cut.pcapng"
    cut.write_bytes(data[:start + 30])
    for read in (lambda: list(protolink.open(cut, strict=True)),
                 lambda: protolink.to_frames(cut, strict=True)):
        with warnings.catch_warnings():
            warnings.simplefilter("error")  # strict raises, never warns
            with pytest.raises(OSError) as info:
                read()
        message = str(info.value)
        assert message == (f"reading the capture {cut} failed at byte {start}, after frame 5: "
                           "the file ends inside the block that starts there")
    # Strict reads a whole capture as it always did.
    assert len(list(protolink.open(capture, strict=True))) == 5 * 1614


def test_warnings_as_errors_raise_after_every_whole_record(capture, tmp_path):
    data = capture.read_bytes()
    bs = blocks(data)
    cut = tmp_path / "cut.pcapng"
    cut.write_bytes(data[:bs[-1][0] + 30])
    got = []
    with warnings.catch_warnings():
        warnings.simplefilter("error", protolink.TruncatedCaptureWarning)
        with pytest.raises(protolink.TruncatedCaptureWarning):
            for m in protolink.open(cut):
                got.append(m)
    assert summary(got) == expected(bs, bs[-1][0])
    assert issubclass(protolink.TruncatedCaptureWarning, UserWarning)
    assert repr(protolink.TruncatedCaptureWarning("x")) == "TruncatedCaptureWarning('x')"
    assert protolink.TruncatedCaptureWarning.__module__ == "protolink"


def test_a_cut_classic_pcap(tmp_path):
    # Three AEOLUS datagrams to UDP 5001; cut inside the third record's header, then its data.
    frame = protolink.aeolus.encode("TOAST", text="hi")
    packet = (bytes(12) + b"\x08\x00"
              + struct.pack(">BBHHHBBH4s4s", 0x45, 0, 28 + len(frame), 0, 0, 64, 17, 0, bytes([127, 0, 0, 1]),
                            bytes([127, 0, 0, 1]))
              + struct.pack(">HHHH", 40000, 5001, 8 + len(frame), 0) + frame)
    data = struct.pack("<IHHiIII", 0xA1B2C3D4, 2, 4, 0, 0, 65535, 1)
    starts = []
    for i in range(3):
        starts.append(len(data))
        data += struct.pack("<IIII", 1_700_000_000 + i, 0, len(packet), len(packet)) + packet
    path = tmp_path / "cut.pcap"
    for cut in (starts[2] + 5, starts[2] + 20, len(data) - 1):
        path.write_bytes(data[:cut])
        with pytest.warns(protolink.TruncatedCaptureWarning, match=re.escape(f"at byte {starts[2]}, after frame 2:")):
            events = list(protolink.open(path))
        assert [(m.name, m.frame) for m in events] == [("TOAST", 1), ("TOAST", 2)]
