"""``to_frames``: a capture, file or list of messages as pandas DataFrames, one per message
type. pandas is an optional extra (``pip install "protolink[pandas]"``), imported only here."""

import os
from typing import TYPE_CHECKING, Any, Dict, Iterable, List, Union

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


def to_frames(
    source: Union[str, "os.PathLike[str]", Iterable[Any]],
    proto: Union[str, None] = None,
    **options: Any,
) -> Dict[str, "pandas.DataFrame"]:
    """One DataFrame per message type, keyed by name (``"GYRO"``, ``"POSITION"``, ...).

    ``source`` is what :func:`protolink.open` opens (a capture, a raw file with ``proto=``, a
    live endpoint that ends), or messages already decoded (a ``Reader``, a list from
    ``Decoder.feed``). Each row is one message: ``time`` (its capture time, seconds since the
    Unix epoch, None from a plain byte file), ``offset``, ``flow`` (from a capture), then its
    fields (``to_dict()``). Error events go to the frame ``"ERROR"`` (columns ``kind`` and
    ``error``) unless ``errors=False``.

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
        table = tables.get(m.name)
        if table is None:
            table = tables[m.name] = _Columns()
        row: Dict[str, Any] = {"time": m.capture_time, "offset": m.offset}
        if m.flow is not None:
            row["flow"] = m.flow
        row.update(m.to_dict())
        table.add(row)
    return {name: pd.DataFrame(table.columns) for name, table in tables.items()}


class _Columns:
    """One message type's rows, kept as one list per column (in the order the columns first
    appear; None where a row lacks one): no dict per row held, and pandas builds the frame a
    column at a time, each conversion short, so Ctrl-C lands between two."""

    def __init__(self) -> None:
        self.columns: Dict[str, List[Any]] = {}
        self.rows = 0

    def add(self, row: Dict[str, Any]) -> None:
        for key in row:
            if key not in self.columns:
                self.columns[key] = [None] * self.rows
        for key, column in self.columns.items():
            column.append(row.get(key))
        self.rows += 1
