"""`to_frames`: one pandas DataFrame per message type, with the right number of rows, the
metadata columns and the README's three-line example working as printed (test_frames_agree.py
checks every cell against the iterator)."""

import random
import re
import subprocess

import pandas as pd
import pytest

import protolink
from conftest import PROTOLINK, PYTHON, ROOT, TESTDATA

AEOLUS_ROWS = {"TOAST": 1, "GYRO": 248, "ACCEL": 248, "MAGNET": 248, "PRESSURE": 347, "ATTITUDE": 248,
               "COMPASS": 248, "GPS": 19, "TEMP": 3, "WIND": 2, "AEOLUSINFO": 2}


def recorded(tmp_path, name="flight.pcapng"):
    path = tmp_path / name
    subprocess.run([PROTOLINK, "record", "--from", f"file:{TESTDATA / 'qemu-uart0-aeolus.bin'}",
                    "--proto", "aeolus", "--out", str(path)], check=True, capture_output=True)
    return path


def test_rows_of_a_raw_file():
    frames = protolink.to_frames(TESTDATA / "qemu-uart0-aeolus.bin", proto="aeolus")
    assert {k: len(v) for k, v in frames.items()} == AEOLUS_ROWS
    gyro = frames["GYRO"]
    assert list(gyro.columns) == ["capture_time", "time", "offset", "meta.id", "meta.len", "meta.crc",
                                  "valid", "box_time", "x_radps", "y_radps", "z_radps"]
    assert gyro["offset"].iloc[0] == 15 and gyro["y_radps"].iloc[0] == pytest.approx(0.024415644)
    # The box's time since it started: a duration, the message's milliseconds to the µs.
    assert str(gyro["box_time"].dtype) == "timedelta64[us]"
    first = next(m for m in protolink.open(TESTDATA / "qemu-uart0-aeolus.bin", proto="aeolus") if m.name == "GYRO")
    assert gyro["box_time"].iloc[0] == pd.Timedelta(microseconds=round(first.timestamp_ms * 1000))
    assert gyro["capture_time"].isna().all() and gyro["time"].isna().all()  # a plain byte file has no clock
    assert set(gyro["meta.id"]) == {62} and set(gyro["meta.crc"]) == {"ok"}


def test_rows_of_a_capture(tmp_path):
    frames = protolink.to_frames(recorded(tmp_path))
    assert {k: len(v) for k, v in frames.items()} == AEOLUS_ROWS
    gyro = frames["GYRO"]
    assert list(gyro.columns[:9]) == ["capture_time", "time", "offset", "flow", "frame", "proto", "meta.id",
                                      "meta.len", "meta.crc"]
    assert gyro["capture_time"].notna().all() and (gyro["capture_time"] > 1e9).all()
    # `time`: the capture time as a UTC timestamp of microseconds.
    assert str(gyro["time"].dtype) == "datetime64[us, UTC]"
    assert ((gyro["time"].astype("int64") - gyro["capture_time"] * 1e6).abs() <= 1).all()
    assert set(gyro["flow"]) == {"stream 0 linktype 147"} and set(gyro["proto"]) == {"aeolus"}
    assert gyro["frame"].iloc[0] == 1


def test_frames_keep_their_protocol_and_units_in_attrs():
    frames = protolink.to_frames(TESTDATA / "qemu-uart0-aeolus.bin", proto="aeolus")
    gyro = frames["GYRO"]
    assert gyro.attrs["proto"] == "aeolus"
    assert gyro.attrs["units"] == {"capture_time": "s since 1970", "offset": "byte", "meta.len": "byte",
                                   "box_time": "µs since the box started",
                                   "x_radps": "rad/s", "y_radps": "rad/s", "z_radps": "rad/s"}
    assert frames["PRESSURE"].attrs["units"]["static_mbar"] == "mbar"
    assert "valid" not in gyro.attrs["units"]
    # A frame's attrs are its own: another table's units are not in them.
    assert frames["ACCEL"].attrs["units"]["x_mps2"] == "m/s²"
    assert frames["MAGNET"].attrs["units"]["x_gauss"] == "gauss"


def test_rows_of_messages_and_errors():
    d = protolink.aydp.Decoder()
    events = d.feed((TESTDATA / "qemu-uart1-aydp.bin").read_bytes() + b"\xff\x03\x2b\x00\x00\x00\x01")
    events += d.finish()
    frames = protolink.to_frames(events)
    assert {k: len(v) for k, v in frames.items()} == {"HEARTBEAT": 5, "POSITION": 5, "FIX_QUALITY": 5, "ERROR": 1}
    assert list(frames["ERROR"].columns) == ["capture_time", "time", "offset", "kind", "error"]
    assert frames["ERROR"]["kind"].iloc[0] == "truncated"
    assert list(frames["POSITION"]["altitude"]) == [1000.0] * 5
    # errors=False leaves them out (an option of open).
    frames = protolink.to_frames(TESTDATA / "qemu-uart2-aok.bin", proto="aok", side="pc", errors=False)
    assert "ERROR" not in frames


def test_to_frames_misuse():
    with pytest.raises(TypeError, match="to_arrow and to_frames take proto= and options only with a path"):
        protolink.to_frames([], proto="aeolus")


def test_without_pandas():
    code = ("import sys; sys.modules['pandas'] = None\n"
            "import protolink\n"
            "try:\n    protolink.to_frames([])\nexcept ImportError as e:\n    print(e)\n")
    out = subprocess.run([PYTHON, "-c", code], capture_output=True, check=True, cwd=ROOT.parent).stdout.decode()
    assert out.startswith("protolink.to_frames needs pandas, which is not installed: pip install pandas")
    # Everything else works without pandas.
    code = "import sys; sys.modules['pandas'] = None\nimport protolink\nprint(len(protolink.aeolus.Decoder().feed(b'')))"
    assert subprocess.run([PYTHON, "-c", code], capture_output=True, check=True, cwd=ROOT.parent).stdout == b"0\n"


def test_readme_example(tmp_path):
    # The three lines of python/README.md, as printed, on a capture recorded by protolink.
    readme = (ROOT / "python" / "README.md").read_text()
    block = re.search(r"```python\n(import protolink\n.*?)```", readme, re.S).group(1)
    assert len(block.strip().splitlines()) == 3
    recorded(tmp_path)
    out = subprocess.run([PYTHON, "-c", block], capture_output=True, check=True, cwd=tmp_path).stdout.decode()
    assert "[248 rows x 14 columns]" in out and out.split()[:2] == ["capture_time", "time"]


def test_columns_of_a_file_and_of_its_messages(tmp_path):
    # The frames of a file (built natively, no object per message) equal the frames of the
    # messages `open` gives for it (the same columns, dtypes and values), on every sample, a
    # capture, and streams of messages and garbage (TOAST with and without `hex`, so that rows
    # lack columns) read by every decoder.
    rnd = random.Random(44)
    pieces = [protolink.aeolus.encode("TOAST", text="hi"), protolink.aeolus.encode("TOAST", hex="ff00"),
              protolink.aeolus.encode("LOG", data=b"\xff\xfe")]
    junk = tmp_path / "junk.bin"
    junk.write_bytes(b"".join(rnd.choice(pieces) + rnd.randbytes(rnd.randrange(8)) for _ in range(2000)))
    cases = [(TESTDATA / "qemu-uart0-aeolus.bin", {"proto": "aeolus"}),
             (TESTDATA / "qemu-uart1-aydp.bin", {"proto": "aydp"}),
             (TESTDATA / "qemu-uart2-aok.bin", {"proto": "aok", "side": "pc"}),
             (TESTDATA / "qemu-uart2-aok.bin", {"proto": "aok", "side": "device"}),
             (recorded(tmp_path), {})]
    cases += [(junk, {"proto": p}) for p in ("aeolus", "aydp", "aok", "gdl90")]
    for path, options in cases:
        of_messages = protolink.to_frames(list(protolink.open(path, **options)))
        of_file = protolink.to_frames(path, **options)
        assert of_file.keys() == of_messages.keys()
        for name in of_file:
            pd.testing.assert_frame_equal(of_file[name], of_messages[name], check_dtype=True)
    toast = protolink.to_frames(junk, proto="aeolus")["TOAST"]
    assert set(toast.columns) >= {"text", "hex"} and toast["hex"].isna().any() and toast["hex"].notna().any()


def test_typed_columns():
    # An AEOLUS message of a fixed layout keeps the wire's types; rendered fields are int64,
    # float64, bool and strings.
    gyro = protolink.to_arrow(TESTDATA / "qemu-uart0-aeolus.bin", proto="aeolus")["GYRO"]
    assert [(f.name, str(f.type)) for f in gyro.schema] == [
        ("capture_time", "double"), ("time", "timestamp[us, tz=UTC]"), ("offset", "int64"), ("meta.id", "int64"), ("meta.len", "int64"),
        ("meta.crc", "string"), ("valid", "bool"), ("box_time", "duration[us]"), ("x_radps", "float"),
        ("y_radps", "float"), ("z_radps", "float")]
    info = protolink.to_arrow(TESTDATA / "qemu-uart0-aeolus.bin", proto="aeolus")["AEOLUSINFO"]
    # A fixed-size array is a column per element.
    assert [info.column(f"mac.{i}").to_pylist()[0] for i in range(6)] == [2, 174, 1, 5, 0, 1]
    assert str(info.schema.field("mac.0").type) == "uint8" and "mac.6" not in info.column_names
    position = protolink.to_arrow(TESTDATA / "qemu-uart1-aydp.bin", proto="aydp")["POSITION"]
    assert [str(position.schema.field(c).type) for c in ("latitude", "meta.time.seconds", "meta.expedited")] == [
        "double", "int64", "bool"]
