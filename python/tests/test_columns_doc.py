"""docs/columns.md lists the columns of every table `protolink export` and `to_arrow` make: for
each protocol and message type, each column's name, Arrow type and unit, as the tables of a
stream of every message type of AEOLUS, AYDP and AOK (hypothesis's simplest) and of a GDL90
frame of every type have them. The schema is part of the contract: a change to it fails this test until the
document says it (`PROTOLINK_WRITE_DOCS=1` rewrites the document's tables).

Each column's unit is the one its Arrow field carries (metadata key `unit`, written by the host
tool's `columns::unit`), so the files say what the document says."""

import os

from hypothesis import HealthCheck, find, settings

import protolink
from conftest import GDL90_FRAMES, ROOT
from strategies import every_type

DOC = ROOT / "docs" / "columns.md"
BEGIN, END = "<!-- columns: begin (python/tests/test_columns_doc.py) -->", "<!-- columns: end -->"

METADATA = {"source", "capture_time", "time", "offset", "flow", "frame", "proto"}


def stream(kind, tmp_path):
    """A file of one message of every type `kind`'s decoder reads: hypothesis's simplest such
    stream, the same on every run."""
    path = tmp_path / f"{kind}.bin"
    # Derandomized and without the example database: the same stream on every run.
    fixed = settings(database=None, derandomize=True, suppress_health_check=list(HealthCheck))
    path.write_bytes(b"".join(f for _, f in find(every_type(kind), lambda _: True, settings=fixed)))
    return path


def schemas(tmp_path):
    """{protocol: {type: {column: (type, unit)}}}, the columns of every kind's tables merged."""
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
                unit = (field.metadata or {}).get(b"unit", b"").decode()
                columns.setdefault(field.name, (str(field.type), unit))
    return out


def render(found):
    lines = []
    for proto, types in found.items():
        lines += [f"### {proto.upper()}", ""]
        for name in sorted(types):
            fields = [(c, t, u) for c, (t, u) in types[name].items() if c not in METADATA]
            lines += [f"**{name}**", "", "| column | type | unit |", "| --- | --- | --- |"]
            lines += [f"| `{c}` | {t} | {u} |" for c, t, u in fields]
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
