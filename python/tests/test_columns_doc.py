"""docs/columns.md lists the columns of every table `protolink export` and `to_arrow` make: for
each protocol and message type, each column's name, Arrow type and unit, as the tables of a
stream of every message type of AEOLUS, AYDP and AOK (hypothesis's simplest) and of a GDL90
frame of every type have them. The schema is part of the contract: a change to it fails this test until the
document says it (`PROTOLINK_WRITE_DOCS=1` rewrites the document's tables).

Units are the protocol crates' (SI as the box sends: m, m/s, mbar, rad, deg, ms), named by the
fields' suffixes where the crates give them one, and listed here for the rest."""

import os
import re

from hypothesis import HealthCheck, find, settings

import protolink
from conftest import GDL90_FRAMES, ROOT
from strategies import every_type

DOC = ROOT / "docs" / "columns.md"
BEGIN, END = "<!-- columns: begin (python/tests/test_columns_doc.py) -->", "<!-- columns: end -->"

# Units by a column's last name part's suffix, then by (message type, column) for the rest.
SUFFIX = [("_ms", "ms"), ("_mps", "m/s"), ("_mbar", "mbar"), ("_deg", "deg"), ("_rad", "rad"),
          ("_m", "m"), ("celsius", "°C"), ("_percent", "%"), ("_ft", "ft"), ("_kt", "kt"), ("_fpm", "ft/min"),
          ("_dps", "deg/s"), ("g_load", "g")]
UNITS = {
    ("GYRO", "x"): "rad/s", ("GYRO", "y"): "rad/s", ("GYRO", "z"): "rad/s",
    ("ACCEL", "x"): "m/s²", ("ACCEL", "y"): "m/s²", ("ACCEL", "z"): "m/s²",
    ("MAGNET", "x"): "gauss", ("MAGNET", "y"): "gauss", ("MAGNET", "z"): "gauss",
    ("POSITION", "latitude"): "deg", ("POSITION", "longitude"): "deg", ("POSITION", "altitude"): "m",
    ("OWNSHIP", "track.TrueTrack"): "deg", ("TRAFFIC", "track.TrueTrack"): "deg",
    ("capture_time", None): "s since 1970", ("offset", None): "byte", ("meta.len", None): "byte",
    ("meta.time.seconds", None): "s", ("meta.time.subsec", None): "ms (spec) or µs (reference)",
}
METADATA = {"source", "capture_time", "offset", "flow", "frame", "proto"}


def unit(name, column):
    if (column, None) in UNITS:
        return UNITS[(column, None)]
    if (name, column) in UNITS:
        return UNITS[(name, column)]
    last = column.split(".")[0] if re.fullmatch(r".*\.\d+", column) else column.split(".")[-1]
    for suffix, u in SUFFIX:
        if last.endswith(suffix):
            return u
    return ""


def stream(kind, tmp_path):
    """A file of one message of every type `kind`'s decoder reads: hypothesis's simplest such
    stream, the same on every run."""
    path = tmp_path / f"{kind}.bin"
    # Derandomized and without the example database: the same stream on every run.
    fixed = settings(database=None, derandomize=True, suppress_health_check=list(HealthCheck))
    path.write_bytes(b"".join(f for _, f in find(every_type(kind), lambda _: True, settings=fixed)))
    return path


def schemas(tmp_path):
    """{protocol: {type: [(column, type)]}}, the columns of every kind's tables merged."""
    gdl90 = tmp_path / "gdl90.bin"
    gdl90.write_bytes(b"".join(GDL90_FRAMES.values()))
    sources = [("aeolus", stream("aeolus", tmp_path), {"proto": "aeolus"}),
               ("aydp", stream("aydp-spec", tmp_path), {"proto": "aydp", "profile": "spec"}),
               ("aydp", stream("aydp-reference", tmp_path), {"proto": "aydp", "profile": "reference"}),
               ("aok", stream("aok-pc", tmp_path), {"proto": "aok", "side": "pc"}),
               ("aok", stream("aok-device", tmp_path), {"proto": "aok", "side": "device"}),
               ("gdl90", gdl90, {"proto": "gdl90"})]
    out = {}
    for proto, path, options in sources:
        for name, table in protolink.to_arrow(path, errors=False, **options).items():
            columns = out.setdefault(proto, {}).setdefault(name, {})
            for field in table.schema:
                columns.setdefault(field.name, str(field.type))
    return out


def render(found):
    lines = []
    for proto, types in found.items():
        lines += [f"### {proto.upper()}", ""]
        for name in sorted(types):
            fields = [(c, t) for c, t in types[name].items() if c not in METADATA]
            lines += [f"**{name}**", "", "| column | type | unit |", "| --- | --- | --- |"]
            lines += [f"| `{c}` | {t} | {unit(name, c)} |" for c, t in fields]
            lines.append("")
    return "\n".join(lines).rstrip() + "\n"


def test_the_document_lists_every_table(tmp_path):
    found = schemas(tmp_path)
    assert set(found) == {"aeolus", "aydp", "aok", "gdl90"}
    body = render(found)
    text = DOC.read_text()
    start, end = text.index(BEGIN) + len(BEGIN) + 1, text.index(END)
    if os.environ.get("PROTOLINK_WRITE_DOCS") == "1":
        DOC.write_text(text[:start] + body + text[end:])
        text = DOC.read_text()
        start, end = text.index(BEGIN) + len(BEGIN) + 1, text.index(END)
    assert text[start:end] == body, "docs/columns.md differs from the tables: PROTOLINK_WRITE_DOCS=1 rewrites it"
