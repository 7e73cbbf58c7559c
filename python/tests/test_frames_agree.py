"""`to_frames` gives what the iterator gives: for each protocol and each message type, every
field and every metadata value of every message (`offset`, `capture_time`, the capture's
`flow`, `frame` and `proto`, and each entry of `Message.meta`, AYDP's header `time` among
them) in the columns python/README.md names, on the sample streams of testdata/ as byte files
and as pcapng captures, on GDL90 frames of every type, and on streams of every message type
drawn by hypothesis. The frames of a file (built by the native columns) equal the frames of its
messages (the iterator's objects, turned into columns), column types included."""

import json
import math
import pathlib
import subprocess
import tempfile

import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import protolink
from conftest import GDL90_FRAMES, PROTOLINK, TESTDATA
from strategies import KINDS, every_type

# The options of `open` (and so of `to_frames`) for each stream kind.
OPTIONS = {
    "aeolus": {"proto": "aeolus"},
    "aydp-spec": {"proto": "aydp", "profile": "spec"},
    "aydp-reference": {"proto": "aydp", "profile": "reference"},
    "aok-pc": {"proto": "aok", "side": "pc"},
    "aok-device": {"proto": "aok", "side": "device"},
    "gdl90": {"proto": "gdl90"},
}
# `protolink record`'s options for a byte stream of each kind.
RECORD = {
    "aeolus": ["--proto", "aeolus"],
    "aydp-spec": ["--proto", "aydp", "--profile", "spec"],
    "aydp-reference": ["--proto", "aydp", "--profile", "reference"],
    "aok-pc": ["--proto", "aok"],
    "aok-device": ["--proto", "aok"],
    "gdl90": ["--proto", "gdl90"],
}
SAMPLES = [
    ("qemu-uart0-aeolus.bin", "aeolus"),
    ("qemu-uart1-aydp.bin", "aydp-spec"),
    ("qemu-uart2-aok.bin", "aok-device"),
    # Another side's or profile's view of the same bytes: error events among the messages.
    ("qemu-uart2-aok.bin", "aok-pc"),
    ("qemu-uart1-aydp.bin", "aydp-reference"),
]


def decoder(kind):
    options = {k: v for k, v in OPTIONS[kind].items() if k != "proto"}
    return getattr(protolink, OPTIONS[kind]["proto"]).Decoder(**options)


class Micros:
    """A timestamp column's value: microseconds since the Unix epoch (None: null)."""

    def __init__(self, value):
        self.value = value


def header_micros(m, profile):
    """An AYDP message's header time in microseconds (None without one): its sub-seconds are
    milliseconds in the `spec` profile, microseconds in `reference`."""
    time = None if m.is_error else m.meta.get("time")
    if not isinstance(time, dict):
        return None
    return time["seconds"] * 1_000_000 + time["subsec"] * (1_000 if profile == "spec" else 1)


def expected_row(m, columns=(), profile="spec"):
    """The row `to_frames` gives message or error event `m`, as python/README.md words the
    rule: `capture_time`, `time` (the capture time, else an AYDP header time in `profile`'s
    unit), `offset`; from a capture `flow`, `frame` and `proto`; each entry of `meta` as
    `meta.KEY` (a nested one as `meta.KEY.SUB`; the AYDP header time also as `meta.time`, a
    timestamp, and `meta.time.profile`); then the fields under their own names. (metadata
    columns, field columns)."""
    header = header_micros(m, profile)
    time = round(m.capture_time * 1e6) if m.capture_time is not None else header
    meta = {"capture_time": m.capture_time, "time": Micros(time), "offset": m.offset}
    if m.flow is not None:
        meta.update(flow=m.flow, frame=m.frame, proto=m.proto)
    if not m.is_error:
        for key, value in m.meta.items():
            if isinstance(value, dict):
                if key == "time":
                    meta.update({"meta.time": Micros(header), "meta.time.profile": profile})
                meta.update({f"meta.{key}.{sub}": v for sub, v in value.items()})
            else:
                meta[f"meta.{key}"] = value
    fields = columns_of(flat(m.to_dict()), columns, None if m.is_error else m.name)
    assert not meta.keys() & fields.keys(), (m, fields)  # no field is named like metadata
    return meta, fields


def flat(fields, prefix=""):
    """The fields as columns: a nested object's fields as `outer.inner` (a list as it is: see
    `columns_of`)."""
    out = {}
    for key, value in fields.items():
        name = prefix + key
        if isinstance(value, dict):
            out.update(flat(value, name + "."))
        else:
            out[name] = value
    return out


# The export's own names for some fields, one entry per message type, as the host tool's
# columns/names.rs has them: AEOLUS `timestamp_ms` is `box_time` (a duration of microseconds),
# GYRO, ACCEL and MAGNET `x`, `y`, `z` name their units.
BOX_TIME_TYPES = {"PRESSURE", "GYRO", "ACCEL", "MAGNET", "TEMP", "GPS", "ATTITUDE", "COMPASS", "WIND"}
MOTION_UNITS = {"GYRO": "radps", "ACCEL": "mps2", "MAGNET": "gauss"}


def export_names(name):
    """{field: column} of message type `name`'s fields that the tables name their own way."""
    names = {"timestamp_ms": "box_time"} if name in BOX_TIME_TYPES else {}
    if name in MOTION_UNITS:
        names.update({axis: f"{axis}_{MOTION_UNITS[name]}" for axis in "xyz"})
    return names


class Millis:
    """A box time in milliseconds, which the table keeps as a duration of microseconds."""

    def __init__(self, value):
        self.value = value

    def micros(self):
        """The microseconds the table holds: the milliseconds rounded half away from zero, as
        Rust's `f64::round` (None for no value, or one out of a duration's range)."""
        if self.value is None or not math.isfinite(self.value * 1000.0):
            return None
        us = int(math.copysign(math.floor(abs(self.value) * 1000.0 + 0.5), self.value))
        return us if -2**63 <= us < 2**63 else None


def columns_of(fields, columns, name=None):
    """`flat` fields of message type `name` as the table's columns: an AEOLUS fixed-size array
    (its column `name.0` exists) a column per element, a list of objects (AYDP `satellites`,
    `entries`) a list per field of its items (every such column of the table, an empty list
    for a message without items), another list its JSON text (compared parsed); a field the
    tables name their own way under that name (`box_time` a `Millis`)."""
    renamed = export_names(name)
    out = {}
    for key, value in fields.items():
        lists = sorted(c for c in columns if c.startswith(key + ".") and not c[len(key) + 1:].isdigit())
        if isinstance(value, list) and f"{key}.0" in columns:
            out.update({f"{key}.{i}": v for i, v in enumerate(value)})
        elif isinstance(value, list) and lists:
            out.update({c: [item[c[len(key) + 1:]] for item in value] for c in lists})
        elif isinstance(value, list):
            out[key] = Json(value)
        elif key == "timestamp_ms" and "timestamp_ms" in renamed:
            out["box_time"] = Millis(value)
        else:
            out[renamed.get(key, key)] = value
    return out


class Json:
    """A value the table keeps as its JSON text."""

    def __init__(self, value):
        self.value = value


def as_f32(v):
    """A JSON value with every real as the f32 it stands for."""
    if isinstance(v, float):
        return float(np.float32(v))
    if isinstance(v, list):
        return [as_f32(x) for x in v]
    if isinstance(v, dict):
        return {k: as_f32(x) for k, x in v.items()}
    return v


def same(got, want, single=False):
    """A frame's cell equals the message's value (pandas reads None as NaN in a number column,
    and gives an int column with a None as floats). In a Float32 column (`single`, an AEOLUS
    field of the wire's f32) the value is the f32 the message's decimal stands for."""
    if isinstance(want, Micros):
        # A timestamp to the microsecond (the capture time, a double of seconds, rounds to
        # within one).
        if want.value is None:
            return got is pd.NaT or got is None
        return abs(got.value // 1_000 - want.value) <= 1
    if isinstance(want, Millis):
        # A duration of microseconds (pandas: a Timedelta, NaT for none).
        if want.micros() is None:
            return got is pd.NaT or got is None
        return got // pd.Timedelta(microseconds=1) == want.micros()
    if hasattr(got, "tolist"):
        got = got.tolist()
    if isinstance(want, Json):
        # A list's JSON text writes each real at its own width (an f32 as its shortest decimal).
        return isinstance(got, str) and as_f32(json.loads(got)) == as_f32(want.value)
    if isinstance(want, list):
        return (isinstance(got, list) and len(got) == len(want)
                and all(same(g, w, single) for g, w in zip(got, want)))
    if want is None:
        return got is None or got is pd.NaT or (isinstance(got, float) and math.isnan(got))
    if isinstance(want, float) and math.isnan(want):
        return isinstance(got, float) and math.isnan(got)
    if single and isinstance(want, float):
        return got == float(np.float32(want))
    return type(got) is type(want) and got == want if isinstance(want, (bool, str)) else got == want


def assert_agree(frames, events, profile="spec"):
    """`frames` (from to_frames) holds `events` (from the iterator): one frame per type, one
    row per message in order, metadata columns first (in the order they first appear), then
    fields (a column of the type that no message here fills is all null); every cell the
    message's value."""
    by_type = {}
    for e in events:
        by_type.setdefault(e.get_type(), []).append(e)
    assert sorted(frames) == sorted(by_type)
    for name, messages in by_type.items():
        frame = frames[name]
        rows = [expected_row(m, set(frame.columns), profile) for m in messages]
        meta_columns, field_columns = {}, {}
        for meta, fields in rows:
            meta_columns.update(dict.fromkeys(meta))
            field_columns.update(dict.fromkeys(fields))
        # A table's columns are its message type's, whatever these messages hold: those no
        # message here has (an optional field absent from all) are all null.
        # Their order is the type's: metadata first, in the order the messages give them.
        filled = [c for c in frame.columns if c in meta_columns or c in field_columns]
        assert filled[:len(meta_columns)] == [*meta_columns], name
        assert sorted(filled[len(meta_columns):]) == sorted(field_columns), name
        for column in set(frame.columns) - set(filled):
            assert frame[column].isna().all(), (name, column)
        assert len(frame) == len(messages), name
        for column in frame.columns:
            cells = frame[column].tolist()
            single = frame[column].dtype == np.float32 or (
                len(cells) and hasattr(cells[0], "dtype") and cells[0].dtype == np.float32)
            for i, (meta, fields) in enumerate(rows):
                want = meta.get(column, fields.get(column))
                assert same(cells[i], want, single), (name, column, i, cells[i], want)


def record(path, kind, out):
    subprocess.run([PROTOLINK, "record", "--from", f"file:{path}", *RECORD[kind], "--out", str(out)],
                   check=True, capture_output=True)
    return out


def check_byte_file(path, kind):
    """to_frames of a byte file agrees with `open` and with `Decoder.feed`; so does to_frames
    of the file recorded as a pcapng capture with `open` of that capture."""
    profile = OPTIONS[kind].get("profile", "spec")
    frames = protolink.to_frames(path, **OPTIONS[kind])
    events = list(protolink.open(path, **OPTIONS[kind]))
    assert_agree(frames, events, profile)
    assert_same_frames(frames, protolink.to_frames(events))
    d = decoder(kind)
    assert_agree(frames, d.feed(path.read_bytes()) + d.finish(), profile)
    cap = record(path, kind, path.with_suffix(".pcapng"))
    captured = protolink.to_frames(cap, **OPTIONS[kind])
    events = list(protolink.open(cap, **OPTIONS[kind]))
    assert events and all(e.capture_time is not None and e.flow is not None for e in events)
    assert_agree(captured, events, profile)
    assert_same_frames(captured, protolink.to_frames(events))
    return frames, captured


def assert_same_frames(got, want):
    """The same frames, columns, dtypes and values."""
    assert got.keys() == want.keys()
    for name in got:
        pd.testing.assert_frame_equal(got[name], want[name], check_dtype=True)


@pytest.mark.parametrize("name,kind", SAMPLES)
def test_samples_agree(tmp_path, name, kind):
    path = tmp_path / name
    path.write_bytes((TESTDATA / name).read_bytes())
    check_byte_file(path, kind)


def test_aydp_header_time_of_a_byte_file(tmp_path):
    # A plain byte file has no capture time, but AYDP's header has its own: the columns
    # meta.time.seconds and meta.time.subsec (the normal header's; the expedited HEARTBEAT has
    # none), what Message.meta["time"] holds.
    frames = protolink.to_frames(TESTDATA / "qemu-uart1-aydp.bin", proto="aydp")
    position = frames["POSITION"]
    messages = [m for m in protolink.open(TESTDATA / "qemu-uart1-aydp.bin", proto="aydp") if m.name == "POSITION"]
    assert list(position["meta.time.seconds"]) == [m.meta["time"]["seconds"] for m in messages] == [0, 1, 2, 3, 4]
    assert list(position["meta.time.subsec"]) == [m.meta["time"]["subsec"] for m in messages]
    assert position["capture_time"].isna().all()
    assert list(position.columns[:9]) == ["capture_time", "time", "offset", "meta.type", "meta.expedited",
                                          "meta.len", "meta.time", "meta.time.profile", "meta.time.seconds"]
    # No capture time: `time` is the header's, its sub-seconds in the unit of the profile named
    # beside it (the document's: milliseconds).
    assert list(position["meta.time.profile"]) == ["spec"] * 5
    header = [s * 1_000_000 + sub * 1_000 for s, sub in zip(position["meta.time.seconds"], position["meta.time.subsec"])]
    assert list(position["time"].astype("int64")) == list(position["meta.time"].astype("int64")) == header
    # The expedited HEARTBEAT has no header time: its columns are there (one schema per
    # message type), null.
    assert frames["HEARTBEAT"]["meta.time.seconds"].isna().all()


def test_gdl90_frames_agree(tmp_path):
    # testdata/ holds no GDL90: a stream of every GDL90 type, twice, with a frame cut short.
    path = tmp_path / "gdl90.bin"
    path.write_bytes(b"".join(GDL90_FRAMES.values()) * 2 + GDL90_FRAMES["OWNSHIP"][:9])
    frames, captured = check_byte_file(path, "gdl90")
    assert set(frames) == set(GDL90_FRAMES) | {"ERROR"}
    assert frames["FOREFLIGHT_ID"]["name"].tolist() == ["Box", "Box"]
    assert frames["UNKNOWN"][["meta.id", "id", "meta.len"]].values.tolist() == [[7, 7, 8]] * 2


def test_only_messages_make_rows():
    # Messages already decoded become rows; any other object is refused in one sentence (the
    # rule for a field named like a metadata column, `field.NAME`, is tested in host-tool).
    with pytest.raises(TypeError, match="to_frames and to_arrow take messages .Message, ErrorEvent., not dict"):
        protolink.to_frames([{"offset": 1}])


@pytest.mark.parametrize("kind", KINDS)
@settings(max_examples=15, deadline=None)
@given(data=st.data())
def test_every_type_agrees(kind, data):
    # One message of every type the kind's decoder reads, in a drawn order, drawn fields.
    frames = data.draw(every_type(kind))
    stream = b"".join(f for _, f in frames) * data.draw(st.integers(1, 3))
    with tempfile.TemporaryDirectory() as tmp:
        path = pathlib.Path(tmp) / "every-type.bin"
        path.write_bytes(stream)
        got, _ = check_byte_file(path, kind)
    assert set(got) == {name for name, _ in frames}
