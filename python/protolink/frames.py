"""``to_frames``: a capture, file or list of messages as pandas DataFrames, one per message
type. pandas is an optional extra (``pip install "protolink[pandas]"``), imported only here."""

import os
from typing import TYPE_CHECKING, Any, Dict, Iterable, List, Set, Union

from ._native import open as _open

if TYPE_CHECKING:  # pragma: no cover
    import pandas


def _pandas() -> Any:
    try:
        import pandas
    except ImportError as e:
        raise ImportError(
            "protolink.to_frames needs pandas, which is not installed: "
            'pip install pandas (or pip install "protolink[pandas]")'
        ) from e
    return pandas


# The columns of every row before its fields, in this order: where and when the message came
# (`flow`, `frame` and `proto` only from a capture); then `Message.meta`, each entry KEY as the
# column `meta.KEY` (a nested one, AYDP's header time, as `meta.KEY.SUB`).
_METADATA_COLUMNS = ("capture_time", "offset", "flow", "frame", "proto")


def to_frames(
    source: Union[str, "os.PathLike[str]", Iterable[Any]],
    proto: Union[str, None] = None,
    **options: Any,
) -> Dict[str, "pandas.DataFrame"]:
    """One DataFrame per message type, keyed by its name, ``get_type()`` (``"GYRO"``,
    ``"POSITION"``, ...).

    ``source`` is what :func:`protolink.open` opens (a capture, a raw file with ``proto=``, a
    live endpoint that ends), or messages already decoded (a ``Reader``, a list from
    ``Decoder.feed``). Each row is one message: first its metadata, then its fields.

    - ``capture_time``: its capture time, seconds since the Unix epoch (``Message.capture_time``;
      None from a plain byte file);
    - ``offset``: its first byte in the input (``Message.offset``);
    - ``flow``, ``frame``, ``proto``: the capture's flow, record number and protocol (only from
      a capture);
    - ``meta.KEY`` for each entry of ``Message.meta``, a nested one as ``meta.KEY.SUB``:
      AEOLUS ``meta.id``, ``meta.len``, ``meta.crc``; AYDP ``meta.type``, ``meta.expedited``,
      ``meta.len`` and the normal header's time, ``meta.time.seconds`` and ``meta.time.subsec``;
      AOK ``meta.len``; GDL90 ``meta.id``, ``meta.len`` (``meta.len`` is ``wire_len``);
    - then the fields under their own names, exactly ``to_dict()``'s keys.

    No field of the four protocols is named like a metadata column (the tests check every
    message type); were one named ``capture_time``, ``offset``, ``flow``, ``frame``, ``proto`` or
    ``meta.``/``field.`` anything, its column would be ``field.`` and its name. Columns come
    in the order they first appear, the metadata's before the fields'; a row without a column
    holds None (NaN in a column of numbers). Error events go to the frame ``"ERROR"`` (its fields
    ``kind`` and ``error``) unless ``errors=False``.

    A capture cut inside a block (``protolink record`` killed mid-write) gives the frames of
    its whole records, then a :class:`protolink.TruncatedCaptureWarning` naming the byte
    offset where the cut block starts; ``strict=True`` raises ``OSError`` instead. Ctrl-C
    interrupts the reading within one step of the reader (``KeyboardInterrupt``).
    """
    pd = _pandas()
    if isinstance(source, (str, bytes, os.PathLike)):
        messages: Iterable[Any] = _open(source, proto, **options)
    else:
        if proto is not None or options:
            raise TypeError(
                "to_frames takes proto= and options only with a path or endpoint to open"
            )
        messages = source
    tables: Dict[str, _Columns] = {}
    for m in messages:
        name = m.get_type()
        table = tables.get(name)
        if table is None:
            table = tables[name] = _Columns()
        meta: Dict[str, Any] = {"capture_time": m.capture_time, "offset": m.offset}
        if m.flow is not None:
            meta["flow"] = m.flow
            meta["frame"] = m.frame
            meta["proto"] = m.proto
        if not m.is_error:
            for key, value in m.meta.items():
                if isinstance(value, dict):
                    for sub, v in value.items():
                        meta[f"meta.{key}.{sub}"] = v
                else:
                    meta[f"meta.{key}"] = value
        table.add(meta, m.to_dict())
    return {name: pd.DataFrame(table.columns()) for name, table in tables.items()}


def _field_column(name: str) -> str:
    """The column of the field ``name``: its name, unless that is a metadata column's."""
    if name in _METADATA_COLUMNS or name.startswith(("meta.", "field.")):
        return "field." + name
    return name


class _Columns:
    """One message type's rows, kept as one list per column (in the order the columns first
    appear, the metadata's before the fields'; None where a row lacks one): no dict per row
    held, and pandas builds the frame a column at a time, each conversion short, so Ctrl-C
    lands between two. A metadata string (``meta.crc``, ``flow``, ``proto``) is kept once per
    value, not once per row."""

    def __init__(self) -> None:
        self.meta: Dict[str, List[Any]] = {}
        self.fields: Dict[str, List[Any]] = {}
        self.strings: Dict[str, str] = {}
        self.plain: Set[str] = set()  # the fields seen whose column is their name
        self.rows = 0

    def add(self, meta: Dict[str, Any], fields: Dict[str, Any]) -> None:
        for key in meta:
            if key not in self.meta:
                self.meta[key] = [None] * self.rows
        for key, column in self.meta.items():
            value = meta.get(key)
            if isinstance(value, str):
                value = self.strings.setdefault(value, value)
            column.append(value)
        row = fields
        if not fields.keys() <= self.plain:  # a field not seen yet: is it named like metadata?
            row = {_field_column(k): v for k, v in fields.items()}
            self.plain.update(k for k in fields if _field_column(k) == k)
        for key in row:
            if key not in self.fields:
                self.fields[key] = [None] * self.rows
        for key, column in self.fields.items():
            column.append(row.get(key))
        self.rows += 1

    def columns(self) -> Dict[str, List[Any]]:
        return {**self.meta, **self.fields}
