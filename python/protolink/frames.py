"""Tables: a capture, file or list of messages as one table per message type, built in typed
columns by the native module (no Python object per message) and handed to pyarrow through the
Arrow C stream interface.

- :func:`to_arrow`: ``pyarrow.Table`` objects; :func:`to_frames`: pandas DataFrames of them;
- :func:`export`: Parquet or Arrow IPC files, as ``protolink export`` writes them.

pyarrow (and pandas for ``to_frames``) are optional extras (``pip install
"protolink[arrow]"``, ``"protolink[pandas]"``), imported only here."""

import os
from typing import TYPE_CHECKING, Any, Dict, Iterable, List, Sequence, Tuple, Union

from . import _native

if TYPE_CHECKING:  # pragma: no cover
    import pandas
    import pyarrow

Source = Union[str, "os.PathLike[str]", Iterable[Any]]


def _pyarrow() -> Any:
    try:
        import pyarrow
    except ImportError as e:
        raise ImportError(
            "protolink.to_arrow and to_frames need pyarrow, which is not installed: "
            'pip install pyarrow (or pip install "protolink[arrow]")'
        ) from e
    return pyarrow


def _tables(source: Source, proto: Union[str, None], options: Dict[str, Any]) -> Dict[str, Any]:
    """The native tables of ``source``, by message type."""
    errors = options.get("errors", True)
    if isinstance(source, (str, bytes, os.PathLike)):
        if isinstance(source, bytes):
            source = os.fsdecode(source)
        tables = _native.file_tables(source, proto, **options)
        if tables is not None:
            return tables
        # Not a file: an endpoint that ends (tcp:..., udp:... with a deadline), read as messages.
        reader_options = {k: v for k, v in options.items() if k != "row_group"}
        with _native.open(source, proto, **reader_options) as reader:
            return _native.message_tables(reader, errors=errors)
    if proto is not None or options.keys() - {"errors"}:
        raise TypeError("to_arrow and to_frames take proto= and options only with a path to open")
    return _native.message_tables(source, errors=errors)


def to_arrow(
    source: Source,
    proto: Union[str, None] = None,
    **options: Any,
) -> Dict[str, "pyarrow.Table"]:
    """One ``pyarrow.Table`` per message type, keyed by its name, ``get_type()`` (``"GYRO"``,
    ``"POSITION"``, ...); two protocols' types of one name (AYDP's and GDL90's ``HEARTBEAT``
    in one capture) are two tables, keyed ``"aydp.HEARTBEAT"`` and ``"gdl90.HEARTBEAT"``. Each
    table's schema names its protocol in its metadata (``b"proto"``).

    ``source`` is what :func:`protolink.open` opens (a capture, a raw file with ``proto=``, a
    live endpoint that ends), or messages already decoded (a ``Reader``, a list from
    ``Decoder.feed``). A file is read by the native module with the GIL released, a step at a
    time (Ctrl-C between two), its rows built into typed columns with no Python object per
    message. Options: ``profile=``, ``side=``, ``errors=`` (``False``: no ``ERROR`` table),
    ``strict=`` (a cut capture raises ``OSError`` instead of a
    :class:`protolink.TruncatedCaptureWarning`, a damaged one instead of a
    :class:`protolink.DamagedCaptureWarning`), ``row_group=`` (rows per record batch).

    Each row is one message: first its metadata, then its fields.

    - ``capture_time``: the capture record's time, seconds since the Unix epoch (null from a
      byte file);
    - ``time``: the row's time, a UTC timestamp of microseconds: the capture time, else an
      AYDP message's header time (``meta.time``); null when it has neither;
    - ``offset``: its first byte in the input (in its flow, for a capture);
    - ``flow``, ``frame``, ``proto``: the capture's flow, record number and protocol (only from
      a capture);
    - ``meta.KEY`` for each entry of ``Message.meta``, a nested one as ``meta.KEY.SUB``: AEOLUS
      ``meta.id``, ``meta.len``, ``meta.crc``; AYDP ``meta.type``, ``meta.expedited``,
      ``meta.len``, ``meta.time`` (the header time as a UTC timestamp), ``meta.time.profile``
      (``spec`` or ``reference``: the unit of ``meta.time.subsec``, ms or µs),
      ``meta.time.seconds``, ``meta.time.subsec``; AOK ``meta.len``; GDL90
      ``meta.id``, ``meta.len`` (``meta.len`` is ``wire_len``);
    - then the fields under the names of ``to_dict()``, a nested one as ``outer.inner``.

    Every message keeps the wire's types (Float32, UInt16, a fixed-size array as a column per
    element, a list of structs as a list column per field of its items: ``satellites.id``,
    ``satellites.snr``, ...). Some fields have the export's own name: AEOLUS ``timestamp_ms``
    is ``box_time``, a duration (µs) since the box started; GYRO, ACCEL and MAGNET ``x``,
    ``y``, ``z`` are ``x_radps``, ``x_mps2``, ``x_gauss``, ... Error events make the table
    ``"ERROR"`` (``kind``, ``error``). docs/columns.md lists every table's columns.
    """
    pa = _pyarrow()
    return {name: pa.table(t) for name, t in _tables(source, proto, options).items()}


def to_frames(
    source: Source,
    proto: Union[str, None] = None,
    **options: Any,
) -> Dict[str, "pandas.DataFrame"]:
    """One pandas DataFrame per message type: :func:`to_arrow`'s tables, converted by pyarrow
    (columns of numbers without a null keep their type; an integer column with nulls becomes
    float64 with NaN, as pandas has it). Each table's Arrow columns are released as it is
    converted: at any time the tables not converted yet and the frames made so far are held,
    about the size of the frames plus the largest table.

    Each frame's ``attrs`` keep what the Arrow schema said and pandas has no place for:
    ``attrs["proto"]`` (``"aeolus"``, ...; absent for a table that names none) and
    ``attrs["units"]``, ``{column: unit}`` for the columns with a unit (``{"x_radps": "rad/s", ...}``,
    as docs/columns.md lists them)."""
    try:
        import pandas  # noqa: F401
    except ImportError as e:
        raise ImportError(
            "protolink.to_frames needs pandas, which is not installed: "
            'pip install pandas (or pip install "protolink[pandas]")'
        ) from e
    tables = to_arrow(source, proto, **options)
    frames = {}
    for name in list(tables):
        table = tables.pop(name)
        attrs = _attrs(table.schema)
        frame = table.to_pandas(self_destruct=True, split_blocks=True)
        frame.attrs.update(attrs)
        frames[name] = frame
    return frames


def _attrs(schema: "pyarrow.Schema") -> Dict[str, Any]:
    """A table's protocol and its columns' units, from its Arrow schema's metadata."""
    attrs: Dict[str, Any] = {}
    proto = (schema.metadata or {}).get(b"proto")
    if proto is not None:
        attrs["proto"] = proto.decode()
    attrs["units"] = {f.name: f.metadata[b"unit"].decode()
                      for f in schema if f.metadata and b"unit" in f.metadata}
    return attrs


def _time_text(name: str, value: Any) -> Union[str, None]:
    """``since=`` or ``until=`` as the RFC 3339 text the native module reads."""
    import datetime

    if value is None or isinstance(value, str):
        return value
    if isinstance(value, datetime.datetime):
        if value.tzinfo is None:
            raise ValueError(f"{name}={value!r} has no time zone: give one (datetime.timezone.utc)")
        return value.isoformat()
    if isinstance(value, datetime.date):
        return value.isoformat()
    raise TypeError(f"{name}= is a text or a datetime, not {type(value).__name__}")


def export(
    sources: Union[str, "os.PathLike[str]", Sequence[Union[str, "os.PathLike[str]"]]],
    out: Union[str, "os.PathLike[str]"],
    format: str = "parquet",
    proto: Union[str, None] = None,
    **options: Any,
) -> List[Tuple[str, int, List[str]]]:
    """Writes captures and byte files (``proto=`` names their protocol) as tables under
    ``out``, one directory per protocol and message type in the Hive layout
    (``out/proto=aeolus/type=GYRO/part-00000.parquet``), each row naming its file in ``source``:
    ``format="parquet"`` (snappy) or ``"arrow"`` (Arrow IPC, LZ4), exactly as ``protolink
    export`` writes them, each row naming its file also by name (``file``) and by content
    (``capture_id``). Options: ``profile=``, ``side=``, ``row_group=``, and as ``protolink
    export`` chooses rows: ``types=`` (``["GYRO", "aydp.HEARTBEAT"]`` or ``"GYRO,PRESSURE"``),
    ``since=`` and ``until=`` (RFC 3339 texts, ``"2024-05-01T12:00:00Z"``, or a
    ``datetime.datetime`` with a time zone; a row without a time is left out), ``air=True``
    (also the table ``AIR``, the air data derived from each AEOLUS PRESSURE, as ``protolink
    export --air``). Returns
    ``[(type, rows, [part paths])]``. ``out`` is a new or empty directory (any other raises
    ``ValueError`` before anything is written, as does a bad type or time).

    ``format="duckdb"`` writes one DuckDB database file ``out`` instead (a new file; needs the
    ``duckdb`` package): a schema per protocol and a table per message type
    (``aeolus."GYRO"``, ``aydp."HEARTBEAT"``, ``gdl90."HEARTBEAT"``; the error events in
    ``PROTO."ERROR"``), each column's unit as its comment (``duckdb_columns()``'s ``comment``).
    The tables are exported as Parquet beside ``out`` first (``out + ".parts"``, removed
    after), then loaded; each entry returned names ``[out]`` as its one part. A capture's damaged
    blocks are skipped with a :class:`protolink.DamagedCaptureWarning`; a source that cannot be
    read is raised once the other sources are exported."""
    if isinstance(sources, (str, bytes, os.PathLike)):
        sources = [sources]
    if isinstance(options.get("types"), str):
        options["types"] = [t for t in options["types"].split(",") if t]
    for key in ("since", "until"):
        options[key] = _time_text(key, options.get(key))
    if format == "duckdb":
        return _export_duckdb([os.fspath(s) for s in sources], os.fspath(out), proto, options)
    return _native.export(
        [os.fspath(s) for s in sources], os.fspath(out), format, proto, **options
    )


def _export_duckdb(sources: List[str], out: str, proto: Union[str, None],
                   options: Dict[str, Any]) -> List[Tuple[str, int, List[str]]]:
    """``export(format="duckdb")``: Parquet parts beside ``out``, loaded into one database. A
    source that cannot be read is raised after the others are loaded, as ``export`` does."""
    import glob
    import shutil

    try:
        import duckdb
    except ImportError as e:
        raise ImportError(
            'protolink.export(format="duckdb") needs duckdb, which is not installed: pip install duckdb'
        ) from e
    if os.path.lexists(out):
        raise ValueError(f"{out} exists already: a DuckDB export writes a new file")
    parts = out + ".parts"
    if os.path.lexists(parts):
        raise ValueError(f"{parts} exists already: a DuckDB export writes its parts there first")
    unread = None
    try:
        try:
            _native.export(sources, parts, "parquet", proto, **options)
        except ValueError:
            raise
        except Exception as e:  # a source that could not be read: the others are loaded first
            unread = e
        written = []
        con = duckdb.connect(out)
        try:
            for directory in sorted(glob.glob(os.path.join(glob.escape(parts), "proto=*", "type=*"))):
                written.append(_load(con, directory))
            con.execute("CHECKPOINT")
        finally:
            con.close()
    except BaseException:
        if os.path.exists(out):
            os.remove(out)
        raise
    finally:
        shutil.rmtree(parts, ignore_errors=True)
    if unread is not None:
        raise unread
    return [(name, rows, [out]) for name, rows in written]


def _quote(name: str) -> str:
    """An SQL identifier, quoted."""
    return '"' + name.replace('"', '""') + '"'


def _load(con: Any, directory: str) -> Tuple[str, int]:
    """One table's parts (``.../proto=P/type=T``) as the table ``P."T"``, each column's unit as
    its comment; its name and rows."""
    import json

    import pyarrow.parquet as pq

    proto = os.path.basename(os.path.dirname(directory)).split("=", 1)[1]
    name = os.path.basename(directory).split("=", 1)[1]
    files = sorted(os.path.join(directory, f) for f in os.listdir(directory) if f.endswith(".parquet"))
    table = f"{_quote(proto)}.{_quote(name)}"
    con.execute(f"CREATE SCHEMA IF NOT EXISTS {_quote(proto)}")
    con.execute(f"CREATE TABLE {table} AS SELECT * FROM read_parquet({_literal_list(files)}, union_by_name = true)")
    units: Dict[str, str] = {}
    for f in files:
        raw = (pq.read_metadata(f).metadata or {}).get(b"units")
        if raw:
            units.update(json.loads(raw))
    for column, unit in units.items():
        con.execute(f"COMMENT ON COLUMN {table}.{_quote(column)} IS {_literal(unit)}")
    (rows,) = con.execute(f"SELECT count(*) FROM {table}").fetchone()
    return name, rows


def _literal(text: str) -> str:
    """An SQL string literal."""
    return "'" + text.replace("'", "''") + "'"


def _literal_list(texts: List[str]) -> str:
    """An SQL list of string literals."""
    return "[" + ", ".join(_literal(t) for t in texts) + "]"
