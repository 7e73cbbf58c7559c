"""`protolink export` and `protolink.export`: several captures at once into Parquet and Arrow IPC
tables, read back by the engines an analyst runs (DuckDB, Polars, pyarrow) and compared with
`protolink decode --json` of each capture: per message type, the rows of each source (their
count, their metadata and every field's value)."""

import datetime
import json
import re
import subprocess

import duckdb
import numpy as np
import polars as pl
import pyarrow as pa
import pyarrow.parquet as pq
import pytest

import protolink
from conftest import GDL90_FRAMES, PROTOLINK, TESTDATA, decode_json, gdl90_frame
from test_frames_agree import Json, Millis, columns_of, flat
from test_same_as_decode import ethernet_udp, write_pcap

# (capture name, the byte file it records, `protolink record`'s options, the decode options)
CAPTURES = [
    ("flight1.pcapng", "qemu-uart0-aeolus.bin", ["--proto", "aeolus"], 0),
    ("aydp.pcapng", "qemu-uart1-aydp.bin", ["--proto", "aydp", "--profile", "spec"], 0),
    ("aok.pcapng", "qemu-uart2-aok.bin", ["--proto", "aok"], 0),
    # A second, shorter AEOLUS flight: its first 30,001 bytes (the last frame cut).
    ("flight2.pcapng", "qemu-uart0-aeolus.bin", ["--proto", "aeolus"], 30_001),
]


@pytest.fixture(scope="module")
def fleet(tmp_path_factory):
    """Four captures recorded by `protolink record`, and the paths as export names them."""
    tmp = tmp_path_factory.mktemp("fleet")
    paths = []
    for name, sample, options, cut in CAPTURES:
        data = (TESTDATA / sample).read_bytes()
        raw = tmp / (name + ".bin")
        raw.write_bytes(data[:cut] if cut else data)
        out = tmp / name
        subprocess.run([PROTOLINK, "record", "--from", f"file:{raw}", *options, "--out", str(out)],
                       check=True, capture_output=True)
        paths.append(out)
    return paths


def expected(paths):
    """`decode --json` of each capture: {type: [(source, event)]}, in the order read."""
    by_type = {}
    for path in paths:
        events, _ = decode_json(path)
        for e in events:
            name = e["name"] if e["kind"] == "message" else "ERROR"
            by_type.setdefault(name, []).append((str(path), e))
    return by_type


def expected_row(source, e, columns):
    """The row a `decode --json` event makes: metadata, then fields as columns."""
    row = {"source": source, "capture_time": e["capture_time"], "offset": e["offset"], "flow": e["flow"],
           "frame": e["frame"], "proto": e["proto"]}
    if e["kind"] == "error":
        row["error"] = e["error"]
        return row
    for key, value in e.items():
        if key in ("offset", "kind", "name", "fields") or key in row:
            continue
        if isinstance(value, dict):
            row.update({f"meta.{key}.{sub}": v for sub, v in value.items()})
        else:
            row[f"meta.{key}"] = value
    row.update(columns_of(flat(e["fields"]), columns, e["name"]))
    return row


def equal(got, want, kind):
    """A value read back equals `decode --json`'s: a FLOAT column holds the f32 the printed
    decimal stands for; a list of other lists' type (JSON) is kept as its JSON text; a list
    column holds the items; `box_time` is a duration of microseconds (a BIGINT of them in
    DuckDB and Spark, which read Parquet's durations as integers)."""
    if isinstance(want, Json):
        return json.loads(got) == want.value
    if isinstance(want, Millis):
        if want.micros() is None:
            return got is None
        if isinstance(got, datetime.timedelta):
            got = got // datetime.timedelta(microseconds=1)
        return got == want.micros()
    if isinstance(want, list):
        item = "FLOAT" if kind in ("FLOAT[]", "array<float>") else kind
        return isinstance(got, list) and len(got) == len(want) and all(
            equal(g, w, item) for g, w in zip(got, want))
    if kind == "FLOAT" and want is not None:
        return got == float(np.float32(want))
    if isinstance(want, float) or isinstance(got, float):
        return got == want
    return type(got) is type(want) and got == want


def part(out, name, ext="parquet"):
    """The first part of the table `name` of an export (of whichever protocol has it)."""
    found = list(out.glob(f"proto=*/type={name}/part-00000.{ext}"))
    assert len(found) == 1, (name, found)
    return found[0]


def check_duckdb(out, want):
    """Every table of `out`, read by DuckDB over the Hive layout, holds the rows of `want`."""
    con = duckdb.connect()
    for name, rows in want.items():
        glob = f"{out}/proto=*/type={name}/*.parquet"
        counts = dict(con.sql(f"SELECT source, count(*) FROM read_parquet('{glob}', union_by_name = true) "
                              "GROUP BY source").fetchall())
        per_source = {}
        for source, _ in rows:
            per_source[source] = per_source.get(source, 0) + 1
        assert counts == per_source, name
        rel = con.sql(f"SELECT * FROM read_parquet('{glob}', union_by_name = true)")
        kinds = dict(zip(rel.columns, (str(t) for t in rel.types)))
        got = rel.fetchall()
        assert len(got) == len(rows)
        for cells, (source, e) in zip(got, rows):
            row = dict(zip(rel.columns, cells))
            want_row = expected_row(source, e, kinds)
            for column, value in want_row.items():
                assert column in row, (name, column)
                assert equal(row[column], value, kinds[column]), (name, column, row[column], value)
            if e["kind"] == "error":
                assert row["kind"] and row["kind"] == row["kind"].lower()


def test_cli_export_read_by_duckdb_and_polars(fleet, tmp_path):
    out = tmp_path / "tables"
    run = subprocess.run([PROTOLINK, "export", "--out", str(out), *map(str, fleet)],
                         capture_output=True, check=True, text=True)
    want = expected(fleet)
    assert set(p.name for p in out.glob("proto=*/type=*")) == {f"type={name}" for name in want}
    check_duckdb(out, want)
    total = sum(len(rows) for rows in want.values())
    assert run.stdout.splitlines()[-1] == (
        f"export: 4 sources, {sum(p.stat().st_size for p in fleet)} bytes, {total} rows in {len(want)} tables")
    # Polars reads every table as it is: the same rows as DuckDB, per source.
    for name, rows in want.items():
        frame = pl.read_parquet(f"{out}/proto=*/type={name}/*.parquet")
        assert frame.height == len(rows)
        assert frame["source"].to_list() == [s for s, _ in rows]
        assert frame["offset"].to_list() == [e["offset"] for _, e in rows]
        assert frame["frame"].to_list() == [e["frame"] for _, e in rows]
    gyro = pl.read_parquet(f"{out}/proto=aeolus/type=GYRO/*.parquet")
    assert gyro.schema["x_radps"] == pl.Float32 and gyro.schema["box_time"] == pl.Duration("us")
    assert gyro.group_by("source").len().sort("source")["len"].to_list() == [
        sum(1 for s, _ in want["GYRO"] if s == str(p)) for p in sorted(fleet) if "flight" in p.name]


def test_arrow_ipc_and_python_export(fleet, tmp_path):
    # The Arrow IPC files hold what the Parquet files hold; protolink.export writes what the
    # command line writes.
    cli = tmp_path / "cli"
    subprocess.run([PROTOLINK, "export", "--out", str(cli), *map(str, fleet)], capture_output=True, check=True)
    ipc = tmp_path / "ipc"
    written = protolink.export(fleet, ipc, format="arrow")
    want = expected(fleet)
    assert [(name, rows) for name, rows, _ in written] == [(n, len(r)) for n, r in want.items()]
    py = tmp_path / "py"
    protolink.export([str(p) for p in fleet], py)
    for name in want:
        parquet = pq.read_table(part(cli, name))
        assert pq.read_table(part(py, name)).equals(parquet)
        with pa.memory_map(str(part(ipc, name, "arrow"))) as f:
            arrow = pa.ipc.open_file(f).read_all()
        assert arrow.equals(parquet), name
        assert pl.read_ipc(part(ipc, name, "arrow")).height == len(want[name])
    # to_arrow of one capture: that capture's rows of the export, without the columns that
    # name its file.
    one = protolink.to_arrow(fleet[1])
    exported = pq.read_table(cli / "proto=aydp" / "type=POSITION" / "part-00000.parquet")
    mine = exported.filter(pa.compute.equal(exported["source"], str(fleet[1])))
    assert exported.column_names[:3] == ["source", "file", "capture_id"]
    # The export's files leave out `proto`, which their path holds.
    assert one["POSITION"].drop_columns(["proto"]).equals(mine.drop_columns(["source", "file", "capture_id"]))


def test_byte_files_and_row_groups(tmp_path):
    # Byte files (their protocol named), small row groups: every batch a row group, the same
    # rows as decode --json, the metadata columns of a capture present (null).
    out = tmp_path / "t"
    sample = TESTDATA / "qemu-uart0-aeolus.bin"
    subprocess.run([PROTOLINK, "export", "--out", str(out), "--proto", "aeolus", "--row-group", "100",
                    str(sample), str(sample)], capture_output=True, check=True)
    f = pq.ParquetFile(out / "proto=aeolus" / "type=PRESSURE" / "part-00000.parquet")
    events, _ = decode_json(sample, "--proto", "aeolus")
    n = sum(1 for e in events if e.get("name") == "PRESSURE")
    assert f.metadata.num_rows == 2 * n and f.metadata.num_row_groups == -(-2 * n // 100)
    table = f.read()
    assert table["flow"].null_count == 2 * n and str(table.schema.field("frame").type) == "int64"
    assert table["offset"].to_pylist() == 2 * [e["offset"] for e in events if e.get("name") == "PRESSURE"]
    assert f.metadata.row_group(0).column(0).compression == "SNAPPY"
    # Each column with a unit carries it in its field's metadata, as docs/columns.md lists it.
    units = {field.name: (field.metadata or {}).get(b"unit") for field in table.schema}
    assert (units["airspeed_mps"], units["static_mbar"], units["offset"], units["frame"]) == (
        b"m/s", b"mbar", b"byte", None)
    # And in the file's key-value metadata, which DuckDB shows.
    in_file = json.loads(f.metadata.metadata[b"units"])
    assert in_file == {name.decode() if isinstance(name, bytes) else name: unit.decode()
                       for name, unit in units.items() if unit is not None}
    glob = f"{out}/proto=aeolus/type=PRESSURE/*.parquet"
    kv = dict(duckdb.sql(f"SELECT decode(key), decode(value) FROM parquet_kv_metadata('{glob}')").fetchall())
    assert json.loads(kv["units"])["airspeed_mps"] == "m/s"


@pytest.mark.parametrize("args,sentence", [
    ([], "the following required arguments were not provided"),
    (["/nonexistent.pcapng"], "/nonexistent.pcapng is no file to export"),
    (["--row-group", "0", "X"], "'0' is not a row count from 1 to 1048576"),
    (["--format", "csv", "X"], "invalid value 'csv' for '--format <FORMAT>'"),
])
def test_cli_refusals(tmp_path, args, sentence):
    run = subprocess.run([PROTOLINK, "export", "--out", str(tmp_path / "o"), *args], capture_output=True, text=True)
    assert run.returncode != 0 and sentence in run.stderr


def test_no_protocol_and_no_overwrite(fleet, tmp_path):
    raw = tmp_path / "raw.bin"
    raw.write_bytes((TESTDATA / "qemu-uart0-aeolus.bin").read_bytes())
    run = subprocess.run([PROTOLINK, "export", "--out", str(tmp_path / "o"), str(raw)], capture_output=True, text=True)
    assert run.returncode == 2
    assert f"error: {raw} is no pcapng or pcap capture: say which protocol its bytes are (--proto)" in run.stderr
    out = tmp_path / "again"
    subprocess.run([PROTOLINK, "export", "--out", str(out), str(fleet[0])], capture_output=True, check=True)
    before = sorted((p, p.read_bytes()) for p in out.rglob("*") if p.is_file())
    run = subprocess.run([PROTOLINK, "export", "--out", str(out), str(fleet[0])], capture_output=True, text=True)
    assert run.returncode == 2
    assert run.stderr == f"error: {out} is not empty: an export goes to a new or empty directory\n"
    with pytest.raises(ValueError, match="is not empty"):
        protolink.export(fleet[0], out)
    assert sorted((p, p.read_bytes()) for p in out.rglob("*") if p.is_file()) == before


def damaged_capture(tmp, name="damaged.pcapng"):
    """A capture of 13 copies of the AEOLUS sample (about 1 MB, blocks of 64 KiB, as `protolink
    record` writes a file), with 200 bytes of 0xFF written over the block boundary nearest byte
    700,000; and the same capture undamaged."""
    raw = tmp / (name + ".bin")
    raw.write_bytes((TESTDATA / "qemu-uart0-aeolus.bin").read_bytes() * 13)
    good = tmp / ("good-" + name)
    subprocess.run([PROTOLINK, "record", "--from", f"file:{raw}", "--proto", "aeolus", "--out", str(good)],
                   check=True, capture_output=True)
    data = bytearray(good.read_bytes())
    at, boundaries = 0, []
    while at < len(data):
        boundaries.append(at)
        at += int.from_bytes(data[at + 4:at + 8], "little")
    end = min(boundaries, key=lambda b: abs(b - 700_000))
    data[end - 100:end + 100] = b"\xff" * 200
    bad = tmp / name
    bad.write_bytes(bytes(data))
    return bad, good


def rows_per_source(out):
    """Rows of every message table of an export (not the derived AIR), per source, read by
    DuckDB."""
    con = duckdb.connect()
    counts = {}
    for table in out.glob("proto=*/type=*"):
        if table.name == "type=AIR":
            continue
        glob = f"{table}/*.parquet"
        for source, n in con.sql(f"SELECT source, count(*) FROM read_parquet('{glob}', union_by_name = true) "
                                 "GROUP BY source").fetchall():
            counts[source] = counts.get(source, 0) + n
    return counts


def test_a_damaged_capture_among_four_is_exported_around_its_damage(fleet, tmp_path):
    bad, good = damaged_capture(tmp_path)
    sources = [fleet[0], fleet[1], bad, fleet[3]]
    out = tmp_path / "tables"
    run = subprocess.run([PROTOLINK, "export", "--out", str(out), *map(str, sources)], capture_output=True, text=True)
    # Every source is exported; the exit status and one sentence say that one lost something.
    assert run.returncode == 1, run.stderr
    assert run.stderr == "error: 1 of 4 sources was not exported whole: the lines above say what it lost\n"
    lines = {line.split(": ")[0]: line for line in run.stdout.splitlines()}
    assert "bytes lost in 1 damaged region, the first at byte" in lines[str(bad)]
    assert run.stdout.splitlines()[-1].startswith("export: 4 sources, ")
    got = rows_per_source(out)
    want = {str(p): len(decode_json(p)[0]) for p in sources if p != bad}
    assert {s: n for s, n in got.items() if s != str(bad)} == want
    # The damaged capture: its rows before and after the damage, two blocks' worth fewer (the
    # 200 bytes end one 64 KiB block and start the next) of its 16.
    whole = len(decode_json(good)[0])
    assert whole * 0.8 < got[str(bad)] < whole * 0.95
    # The Python face: the same tables, and a warning naming the damage.
    with pytest.warns(protolink.DamagedCaptureWarning, match="holds 1 damaged region of"):
        protolink.export(sources, tmp_path / "py")
    assert rows_per_source(tmp_path / "py") == got
    with pytest.warns(protolink.DamagedCaptureWarning):
        tables = protolink.to_arrow(bad)
    assert sum(len(t) for t in tables.values()) == got[str(bad)]
    with pytest.raises(OSError, match="damaged region"):
        protolink.to_arrow(bad, strict=True)


@pytest.fixture(scope="module")
def two_exports(fleet, tmp_path_factory):
    """Two exports of different captures under one directory, as a fleet keeps them: day1 holds
    the first flight, the AYDP capture and a GDL90 capture (both with a HEARTBEAT), day2 the
    second flight and the AOK capture. Returns (the directory, {export: its sources})."""
    tmp = tmp_path_factory.mktemp("exports")
    raw = tmp / "gdl90.bin"
    raw.write_bytes(b"".join(GDL90_FRAMES.values()) * 3)
    gdl90 = tmp / "gdl90.pcapng"
    subprocess.run([PROTOLINK, "record", "--from", f"file:{raw}", "--proto", "gdl90", "--out", str(gdl90)],
                   check=True, capture_output=True)
    exports = {"day1": [fleet[0], fleet[1], gdl90], "day2": [fleet[3], fleet[2]]}
    root = tmp / "exports"
    for name, sources in exports.items():
        subprocess.run([PROTOLINK, "export", "--out", str(root / name), *map(str, sources)],
                       check=True, capture_output=True)
    return root, exports


def count(sources, name, proto):
    """Messages of type `name` of `proto` in `sources`, as `decode --json` gives them."""
    return sum(1 for p in sources for e in decode_json(p)[0]
               if e.get("name") == name and e["proto"] == proto)


def test_the_hive_layout_keeps_protocols_apart_and_one_glob_reads_two_exports(two_exports):
    root, exports = two_exports
    day1 = root / "day1"
    # AYDP's and GDL90's HEARTBEAT: two tables, each in its protocol's directory, and no file
    # holds a `proto` column (the path does).
    assert (day1 / "proto=aydp" / "type=HEARTBEAT").is_dir() and (day1 / "proto=gdl90" / "type=HEARTBEAT").is_dir()
    assert all("proto" not in pq.read_schema(f).names for f in root.rglob("*.parquet"))
    everything = [p for sources in exports.values() for p in sources]
    con = duckdb.connect()
    heartbeats = dict(con.sql(f"SELECT proto, count(*) FROM read_parquet('{root}/*/proto=*/type=HEARTBEAT/*.parquet', "
                              "hive_partitioning = true, union_by_name = true) GROUP BY proto").fetchall())
    assert heartbeats == {"aydp": count(everything, "HEARTBEAT", "aydp"),
                          "gdl90": count(everything, "HEARTBEAT", "gdl90")}
    # One table of one protocol over both exports: one schema, no option but the layout's.
    glob = f"{root}/*/proto=aeolus/type=GYRO/*.parquet"
    gyro = count(everything, "GYRO", "aeolus")
    got = con.sql(f"SELECT proto, type, count(*), count(DISTINCT source) FROM read_parquet('{glob}', "
                  "hive_partitioning = true) GROUP BY ALL").fetchall()
    assert got == [("aeolus", "GYRO", gyro, 2)]
    frame = pl.scan_parquet(glob, hive_partitioning=True).collect()
    assert frame.height == gyro
    assert set(frame["proto"]) == {"aeolus"} and set(frame["type"]) == {"GYRO"}
    assert frame.schema["x_radps"] == pl.Float32 and frame.schema["box_time"] == pl.Duration("us")


def test_a_capture_has_one_id_wherever_it_is_and_whatever_its_name(fleet, tmp_path):
    # The same capture under another name in another directory, given by a relative path: the
    # same capture_id; its own file name and source as given. Another capture: another id.
    copy_dir = tmp_path / "copies"
    copy_dir.mkdir()
    copy = copy_dir / "renamed.pcapng"
    copy.write_bytes(fleet[0].read_bytes())
    out = tmp_path / "tables"
    subprocess.run([PROTOLINK, "export", "--out", str(out), str(fleet[0]), "renamed.pcapng", str(fleet[3])],
                   capture_output=True, check=True, cwd=copy_dir)
    ids = duckdb.sql(f"SELECT DISTINCT source, file, capture_id FROM read_parquet('{out}/proto=aeolus/type=GYRO/*.parquet') "
                     "ORDER BY source").fetchall()
    by_source = {source: (file, capture_id) for source, file, capture_id in ids}
    assert set(by_source) == {str(fleet[0]), "renamed.pcapng", str(fleet[3])}
    assert by_source["renamed.pcapng"] == ("renamed.pcapng", by_source[str(fleet[0])][1])
    assert by_source[str(fleet[0])][0] == fleet[0].name
    assert by_source[str(fleet[3])][1] != by_source[str(fleet[0])][1]
    assert all(len(i) == 16 and int(i, 16) >= 0 for _, i in by_source.values())
    # Every table of the export names them on every row.
    for f in out.rglob("*.parquet"):
        t = pq.read_table(f, columns=["file", "capture_id"])
        assert t["file"].null_count == 0 and t["capture_id"].null_count == 0, f


def test_types_since_and_until(fleet, tmp_path):
    # The AEOLUS flight's GYRO and the AYDP capture's POSITION: their tables only, whole.
    want = expected(fleet[:2])
    written = protolink.export(fleet[:2], tmp_path / "types", types="gyro,aydp.POSITION")
    assert [(name, rows) for name, rows, _ in written] == [("GYRO", len(want["GYRO"])),
                                                         ("POSITION", len(want["POSITION"]))]
    run = subprocess.run([PROTOLINK, "export", "--out", str(tmp_path / "cli"), "--types", "GYRO,aydp.POSITION",
                          *map(str, fleet[:2])], capture_output=True, check=True, text=True)
    assert pq.read_table(tmp_path / "cli/proto=aeolus/type=GYRO/part-00000.parquet").equals(
        pq.read_table(tmp_path / "types/proto=aeolus/type=GYRO/part-00000.parquet"))
    assert "rows left out by --types, --since or --until" in run.stdout.splitlines()[-1]
    # A capture of AEOLUS datagrams 10 ms apart: --since and --until cut it by the records'
    # times; a datetime with a time zone is the same time as its RFC 3339 text.
    data = (TESTDATA / "qemu-uart0-aeolus.bin").read_bytes()
    frames = [data[m.offset:m.offset + m.wire_len] for m in protolink.aeolus.Decoder().feed(data)]
    start = 1_700_000_000
    packets = [(start + i / 100, ethernet_udp(40000, 5001, b"".join(frames[i * 10:i * 10 + 10])))
               for i in range(len(frames) // 10)]
    cap = tmp_path / "timed.pcap"
    write_pcap(cap, packets)
    since = datetime.datetime.fromtimestamp(start + 0.5, datetime.timezone.utc)
    got = {}
    for tag, options in [("all", {}), ("since", {"since": since}), ("until", {"until": since.isoformat()}),
                         ("both", {"since": "2023-11-14T22:13:20.250Z", "until": since})]:
        written = protolink.export(cap, tmp_path / tag, types=["GYRO"], **options)
        got[tag] = pq.read_table(written[0][2][0])["capture_time"].to_pylist()
    assert len(got["all"]) > 100
    assert got["since"] == [t for t in got["all"] if t >= start + 0.5]
    assert got["until"] == [t for t in got["all"] if t < start + 0.5]
    assert got["both"] == [t for t in got["all"] if start + 0.25 <= t < start + 0.5]
    assert got["since"] and got["until"] and got["both"]
    # Refused in one sentence, before anything is written.
    for options, sentence in [({"types": "GYROS"}, "'GYROS' is no message type of aeolus, aydp, aok or gdl90"),
                              ({"since": "May 1st"}, "'May 1st' is not a time: give one as 2024-05-01T12:00:00Z"),
                              ({"since": "2024-05-02", "until": "2024-05-01"}, "--since (2024-05-02T00:00:00Z) is not before"),
                              ({"until": datetime.datetime(2024, 5, 1)}, "has no time zone")]:
        with pytest.raises(ValueError, match=re.escape(sentence)):
            protolink.export(fleet[0], tmp_path / "refused", **options)
        assert not (tmp_path / "refused").exists()


def test_one_duckdb_file(fleet, tmp_path):
    # One database: a schema per protocol, a table per type, the same rows as the Parquet
    # export, each column's unit as its comment.
    db = tmp_path / "fleet.duckdb"
    written = protolink.export(fleet, db, format="duckdb")
    want = expected(fleet)
    assert sorted((name, rows) for name, rows, _ in written) == sorted((n, len(r)) for n, r in want.items())
    assert all(parts == [str(db)] for _, _, parts in written)
    assert not (tmp_path / "fleet.duckdb.parts").exists()
    con = duckdb.connect(str(db), read_only=True)
    tables = dict(((schema, name), rows) for schema, name, rows in con.sql(
        "SELECT schema_name, table_name, estimated_size FROM duckdb_tables()").fetchall())
    assert ("aeolus", "GYRO") in tables and ("aydp", "HEARTBEAT") in tables and ("aok", "DEBUG") in tables
    [(n,)] = con.sql('SELECT count(*) FROM aeolus."GYRO"').fetchall()
    assert n == len(want["GYRO"])
    cli = tmp_path / "parquet"
    subprocess.run([PROTOLINK, "export", "--out", str(cli), *map(str, fleet)], check=True, capture_output=True)
    parquet = duckdb.sql(f"SELECT * FROM read_parquet('{cli}/proto=aydp/type=POSITION/*.parquet') ORDER BY source, \"offset\"")
    assert con.sql('SELECT * FROM aydp."POSITION" ORDER BY source, "offset"').fetchall() == parquet.fetchall()
    comments = dict(con.sql("SELECT column_name, comment FROM duckdb_columns() "
                            "WHERE schema_name = 'aeolus' AND table_name = 'PRESSURE'").fetchall())
    assert (comments["airspeed_mps"], comments["meta.len"], comments["valid"]) == ("m/s", "byte", None)
    con.close()
    # A new file only; options as export's, refused before anything is written.
    with pytest.raises(ValueError, match="exists already: a DuckDB export writes a new file"):
        protolink.export(fleet, db, format="duckdb")
    with pytest.raises(ValueError, match="is no message type"):
        protolink.export(fleet, tmp_path / "bad.duckdb", format="duckdb", types="NOPE")
    assert not (tmp_path / "bad.duckdb").exists() and not (tmp_path / "bad.duckdb.parts").exists()
    only = protolink.export(fleet, tmp_path / "gyro.duckdb", format="duckdb", types="GYRO")
    assert [(name, rows) for name, rows, _ in only] == [("GYRO", len(want["GYRO"]))]


def test_the_air_table_derives_air_data_from_each_pressure(fleet, tmp_path):
    # A row per PRESSURE, at its place and time; the air-data module's formulas (ISA sea-level
    # density for IAS, the ideal gas for TAS with the flow's latest TEMP, ISA pressure
    # altitude); a vertical speed once half a second of box time is seen.
    out = tmp_path / "tables"
    subprocess.run([PROTOLINK, "export", "--air", "--out", str(out), str(fleet[0])], check=True, capture_output=True)
    con = duckdb.connect()
    air = con.sql(f"SELECT * FROM read_parquet('{out}/proto=aeolus/type=AIR/*.parquet') ORDER BY \"offset\"")
    pressure = con.sql(f"SELECT * FROM read_parquet('{out}/proto=aeolus/type=PRESSURE/*.parquet') ORDER BY \"offset\"")
    a = [dict(zip(air.columns, r)) for r in air.fetchall()]
    p = [dict(zip(pressure.columns, r)) for r in pressure.fetchall()]
    assert len(a) == len(p) > 100
    temps = con.sql(f"SELECT \"offset\", celsius FROM read_parquet('{out}/proto=aeolus/type=TEMP/*.parquet')").fetchall()
    for row, msg in zip(a, p):
        assert (row["offset"], row["time"], row["box_time"]) == (msg["offset"], msg["time"], msg["box_time"])
        assert row["static_hpa"] == pytest.approx(msg["static_mbar"])
        q = max(msg["pitot_mbar"] * 100.0, 0.0)
        assert row["ias_mps"] == pytest.approx((2 * q / 1.225) ** 0.5)
        assert row["pressure_altitude_m"] == pytest.approx(44330.77 * (1 - (msg["static_mbar"] / 1013.25) ** 0.190263))
        before = [c for off, c in temps if off < row["offset"]]
        if before:
            rho = msg["static_mbar"] * 100.0 / (287.05 * (before[-1] + 273.15))
            assert row["celsius"] == pytest.approx(before[-1]) and row["tas_mps"] == pytest.approx((2 * q / rho) ** 0.5)
        else:
            assert row["celsius"] is None and row["tas_mps"] is None
    assert a[0]["vertical_speed_mps"] is None and a[-1]["vertical_speed_mps"] is not None
    assert any(r["tas_mps"] is not None for r in a)
    # Units where the engines show them.
    kv = dict(con.sql(f"SELECT decode(key), decode(value) FROM parquet_kv_metadata('{out}/proto=aeolus/type=AIR/*.parquet')").fetchall())
    units = json.loads(kv["units"])
    assert (units["ias_mps"], units["static_hpa"], units["dynamic_pa"], units["pressure_altitude_m"],
            units["vertical_speed_mps"], units["celsius"]) == ("m/s", "hPa", "Pa", "m", "m/s", "°C")
    # --types AIR: the air data alone, from the PRESSURE and TEMP rows it leaves out; air=True
    # in Python as --air; without either, no AIR.
    only = protolink.export(fleet[0], tmp_path / "air", types="AIR")
    assert [(name, rows) for name, rows, _ in only] == [("AIR", len(a))]
    assert pq.read_table(only[0][2][0]).equals(pq.read_table(out / "proto=aeolus/type=AIR/part-00000.parquet"))
    py = protolink.export(fleet[0], tmp_path / "py", air=True)
    assert ("AIR", len(a)) in [(name, rows) for name, rows, _ in py]
    assert "AIR" not in [name for name, _, _ in protolink.export(fleet[0], tmp_path / "plain")]


# GDL90 with every optional field absent: an OWNSHIP without position, altitude, track, speed
# or vertical rate, a ForeFlight AHRS without any value, a geometric altitude without VFOM.
BARE_GDL90 = [
    GDL90_FRAMES["HEARTBEAT"],
    gdl90_frame(bytes([10, 0x00, 0xA1, 0xB2, 0xC3, 0, 0, 0, 0, 0, 0, 0xFF, 0xF0, 0x00, 0xFF, 0xF8, 0x00, 0x00,
                       0x01]) + b"N12345  " + b"\x00"),
    gdl90_frame(bytes([0x65, 0x01, 0x7F, 0xFF, 0x7F, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF])),
    GDL90_FRAMES["GEO_ALTITUDE"],
]


# AYDP lists, full and empty: a FIX_DETAIL of two satellites and a DIRECT_OUTPUT of one entry,
# and the same types with none.
SATELLITES = [{"id": 7, "azimuth": 180.0, "elevation": 45.0, "snr": 38.0},
              {"id": 9, "azimuth": 90.0, "elevation": 10.0, "snr": 20.5}]
ENTRIES = [{"device": 1, "channel": 2, "value": 10.0}]


def aydp_lists(satellites, entries):
    """An AYDP byte stream of a FIX_DETAIL and a DIRECT_OUTPUT with these lists."""
    return (protolink.aydp.encode("FIX_DETAIL", time=(1_700_000_000, 5), satellites=satellites)
            + protolink.aydp.encode("DIRECT_OUTPUT", time=(1_700_000_001, 5), entries=entries))


@pytest.fixture(scope="module")
def optional_exports(fleet, tmp_path_factory):
    """Two exports of different captures under one directory (with AIR): `full` holds a GDL90
    capture with its optional fields present, an AYDP capture whose lists have items and the
    first flight, `bare` one with every optional field absent, an AYDP capture of empty lists
    and the second flight. Returns (the directory, {export: its sources})."""
    tmp = tmp_path_factory.mktemp("optional")
    captures = {}
    for name, frames in (("full", list(GDL90_FRAMES.values())), ("bare", BARE_GDL90)):
        raw = tmp / f"{name}.bin"
        raw.write_bytes(b"".join(frames) * 2)
        captures[name] = tmp / f"{name}-gdl90.pcapng"
        subprocess.run([PROTOLINK, "record", "--from", f"file:{raw}", "--proto", "gdl90", "--out",
                        str(captures[name])], check=True, capture_output=True)
    for name, stream in (("full", aydp_lists(SATELLITES, ENTRIES)), ("bare", aydp_lists([], []))):
        raw = tmp / f"{name}-aydp.bin"
        raw.write_bytes(stream)
        captures[f"{name}-aydp"] = tmp / f"{name}-aydp.pcapng"
        subprocess.run([PROTOLINK, "record", "--from", f"file:{raw}", "--proto", "aydp", "--profile", "spec",
                        "--out", str(captures[f"{name}-aydp"])], check=True, capture_output=True)
    exports = {"full": [captures["full"], captures["full-aydp"], fleet[0]],
               "bare": [captures["bare"], captures["bare-aydp"], fleet[3]]}
    root = tmp / "exports"
    for name, sources in exports.items():
        subprocess.run([PROTOLINK, "export", "--air", "--out", str(root / name), *map(str, sources)],
                       check=True, capture_output=True)
    return root, exports


def test_a_capture_without_optional_fields_has_the_schema_of_one_with_them(optional_exports):
    root, exports = optional_exports
    bare_events = decode_json(exports["bare"][0])[0]
    ownship = [e for e in bare_events if e.get("name") == "OWNSHIP"][0]["fields"]
    assert ownship["position"] is None and ownship["track"] is None and ownship["ground_speed_kt"] is None
    ahrs = [e for e in bare_events if e.get("name") == "FOREFLIGHT_AHRS"][0]["fields"]
    assert all(v is None for v in ahrs.values())
    # Every table the two exports share: one schema, field for field, units included.
    tables = {p.relative_to(root / "full") for p in (root / "full").glob("proto=*/type=*")}
    shared = sorted(t for t in tables if (root / "bare" / t).is_dir())
    assert {"proto=gdl90/type=OWNSHIP", "proto=gdl90/type=FOREFLIGHT_AHRS", "proto=aeolus/type=GYRO",
            "proto=aeolus/type=AIR", "proto=aydp/type=FIX_DETAIL", "proto=aydp/type=DIRECT_OUTPUT"} <= {
                str(t) for t in shared}
    for t in shared:
        full = pq.read_schema(root / "full" / t / "part-00000.parquet")
        bare = pq.read_schema(root / "bare" / t / "part-00000.parquet")
        assert bare.equals(full, check_metadata=True), t
        assert all(str(f.type) != "null" for f in bare), t
        assert not list((root / "bare" / t).glob("part-00001.*")), t
    # DuckDB and Polars read each table of both exports through one glob, no schema option.
    for name in ("OWNSHIP", "FOREFLIGHT_AHRS"):
        glob = f"{root}/*/proto=gdl90/type={name}/*.parquet"
        want = count(exports["full"] + exports["bare"], name, "gdl90")
        rows = duckdb.sql(f"SELECT count(*), count(DISTINCT capture_id) FROM read_parquet('{glob}')").fetchall()
        assert rows == [(want, 2)], name
        frame = pl.scan_parquet(glob, hive_partitioning=True).collect()
        assert frame.height == want and set(frame["proto"]) == {"gdl90"}
    nulls = duckdb.sql(f"SELECT file, count(\"position.lat_deg\") FROM read_parquet('{root}/*/proto=gdl90/type=OWNSHIP/*.parquet') "
                       "GROUP BY file ORDER BY file").fetchall()
    assert nulls == [("bare-gdl90.pcapng", 0), ("full-gdl90.pcapng", 2)]


def test_aydp_lists_are_lists_of_their_items_type_empty_or_full(optional_exports):
    # A list of structs is a list column per field of its items, of the items' wire types, in
    # the schema of every export: full lists and empty ones.
    root, _ = optional_exports
    fix = pq.read_schema(next((root / "bare").glob("proto=aydp/type=FIX_DETAIL/*.parquet")))
    assert [(f.name, str(f.type)) for f in fix if f.name.startswith("satellites")] == [
        ("satellites.id", "list<item: uint8>"), ("satellites.azimuth", "list<item: float>"),
        ("satellites.elevation", "list<item: float>"), ("satellites.snr", "list<item: float>")]
    assert "satellites" not in fix.names
    glob = f"{root}/*/proto=aydp/type=FIX_DETAIL/*.parquet"
    con = duckdb.connect()
    rel = con.sql(f"SELECT file, \"satellites.id\", \"satellites.snr\" FROM read_parquet('{glob}') ORDER BY file")
    assert [str(t) for t in rel.types] == ["VARCHAR", "UTINYINT[]", "FLOAT[]"]
    assert rel.fetchall() == [("bare-aydp.pcapng", [], []), ("full-aydp.pcapng", [7, 9], [38.0, 20.5])]
    # One row per satellite: the parallel lists unnest together.
    rows = con.sql(f"SELECT unnest(\"satellites.id\") AS id, unnest(\"satellites.elevation\") AS e "
                   f"FROM read_parquet('{glob}') ORDER BY id").fetchall()
    assert rows == [(7, 45.0), (9, 10.0)]
    frame = pl.scan_parquet(f"{root}/*/proto=aydp/type=DIRECT_OUTPUT/*.parquet", hive_partitioning=True).collect()
    assert (frame.schema["entries.device"], frame.schema["entries.value"]) == (pl.List(pl.UInt8), pl.List(pl.Float32))
    assert sorted(frame["entries.value"].to_list()) == [[], [10.0]]
    assert frame.explode(["entries.device", "entries.channel", "entries.value"]).drop_nulls("entries.device").select(
        "entries.device", "entries.channel", "entries.value").rows() == [(1, 2, 10.0)]


def test_box_time_is_a_duration(optional_exports):
    # AEOLUS's time since the box started: a duration of microseconds in pyarrow and Polars, a
    # BIGINT of microseconds in DuckDB (Parquet has no duration; its unit says so); the motion
    # columns name their units.
    root, _ = optional_exports
    gyro = pq.read_schema(next((root / "full").glob("proto=aeolus/type=GYRO/*.parquet")))
    assert str(gyro.field("box_time").type) == "duration[us]"
    assert gyro.field("box_time").metadata[b"unit"] == "µs since the box started".encode()
    assert [n for n in gyro.names if n[0] in "xyz"] == ["x_radps", "y_radps", "z_radps"]
    assert "timestamp_ms" not in gyro.names and "x" not in gyro.names
    glob = f"{root}/*/proto=aeolus/type=GYRO/*.parquet"
    frame = pl.scan_parquet(glob, hive_partitioning=True).collect()
    assert frame.schema["box_time"] == pl.Duration("us")
    rel = duckdb.sql(f"SELECT box_time FROM read_parquet('{glob}')")
    assert [str(t) for t in rel.types] == ["BIGINT"]
    assert sorted(frame["box_time"].dt.total_microseconds().to_list()) == sorted(r[0] for r in rel.fetchall())
    for name, suffix in (("ACCEL", "mps2"), ("MAGNET", "gauss")):
        schema = pq.read_schema(next((root / "full").glob(f"proto=aeolus/type={name}/*.parquet")))
        assert [n for n in schema.names if n[0] in "xyz"] == [f"{a}_{suffix}" for a in "xyz"]
        assert str(schema.field("box_time").type) == "duration[us]"
    air = pq.read_schema(next((root / "full").glob("proto=aeolus/type=AIR/*.parquet")))
    assert str(air.field("box_time").type) == "duration[us]"
