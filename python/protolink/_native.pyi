"""Type stubs of the native module (Rust, pyo3): the classes and functions that
``protolink``, ``protolink.aeolus``, ``protolink.aydp``, ``protolink.aok`` and
``protolink.gdl90`` re-export."""

import os
from typing import Any, Dict, Iterable, Iterator, List, Mapping, Optional, Sequence, Tuple, Union

Event = Union["Message", "ErrorEvent"]
Buffer = Union[bytes, bytearray, memoryview, Any]

class Message:
    """A decoded message: one attribute per field in the protocol crate's units. A field wins
    over the attribute of its name: ``m.x`` is ``m["x"]`` whenever the message has a field
    ``x`` (GDL90 FOREFLIGHT_ID's ``name``, GDL90 UNKNOWN's ``id``, the ``len`` of the AEOLUS
    raw messages)."""

    @property
    def name(self) -> str:
        """The message's name; the field ``name`` where there is one (``get_type()`` is
        always the message's name)."""
    @property
    def id(self) -> Optional[int]:
        """The message's identifier on the wire; the field ``id`` where there is one (GDL90
        UNKNOWN: the same number)."""
    @property
    def offset(self) -> int: ...
    @property
    def wire_len(self) -> Optional[int]:
        """The message's length on the wire, in bytes: ``meta["len"]``."""
    @property
    def len(self) -> Any:
        """The field ``len`` where there is one (AEOLUS CALIBINFO, DEBUGINFO, LOG, UNKNOWN:
        the data's length); elsewhere the deprecated name of ``wire_len``
        (``DeprecationWarning``)."""
    @property
    def proto(self) -> str: ...
    @property
    def meta(self) -> Dict[str, Any]: ...
    @property
    def capture_time(self) -> Optional[float]: ...
    @property
    def flow(self) -> Optional[str]: ...
    @property
    def frame(self) -> Optional[int]: ...
    @property
    def is_error(self) -> bool: ...
    def get_type(self) -> str: ...
    def to_dict(self) -> Dict[str, Any]: ...
    def __getattr__(self, field: str) -> Any: ...
    def __getitem__(self, field: str) -> Any: ...
    def __contains__(self, field: str) -> bool: ...

class ErrorEvent:
    """Bad bytes in a stream: ``kind``, ``error`` (one sentence), ``offset`` and ``wire_len``
    (the bytes it condemns)."""

    @property
    def name(self) -> str: ...
    @property
    def kind(self) -> str: ...
    @property
    def error(self) -> str: ...
    @property
    def offset(self) -> int: ...
    @property
    def id(self) -> None: ...
    @property
    def wire_len(self) -> int: ...
    @property
    def len(self) -> int:
        """The deprecated name of ``wire_len`` (``DeprecationWarning``)."""
    @property
    def proto(self) -> str: ...
    @property
    def capture_time(self) -> Optional[float]: ...
    @property
    def flow(self) -> Optional[str]: ...
    @property
    def frame(self) -> Optional[int]: ...
    @property
    def is_error(self) -> bool: ...
    def get_type(self) -> str: ...
    def to_dict(self) -> Dict[str, str]: ...

class Reader:
    """Messages and error events from a file, capture or live link."""

    def __iter__(self) -> "Reader": ...
    def __next__(self) -> Event: ...
    def recv_match(
        self, type: Union[str, Sequence[str], None] = None, timeout: Optional[float] = None
    ) -> Optional[Message]: ...
    @property
    def stats(self) -> Dict[str, Any]: ...
    @property
    def truncated_at(self) -> Optional[int]:
        """Where a cut capture's cut block starts (its first ``truncated_at`` bytes are a
        whole capture); None otherwise."""
    @property
    def source(self) -> str: ...
    def close(self) -> None: ...
    def __enter__(self) -> "Reader": ...
    def __exit__(self, *args: Any) -> bool: ...

class FeedIter(Iterator[Event]):
    """What ``Decoder.feed_iter(data)`` returns: the events of ``data``, decoded one bounded
    step (64 KiB pieces, until 20 ms or 4 096 events) at a time as they are read."""

    def __iter__(self) -> "FeedIter": ...
    def __next__(self) -> Event: ...
    @property
    def bytes_left(self) -> int:
        """Bytes of ``data`` not yet fed to the decoder."""

class Decoder:
    """What every protocol's ``Decoder`` is: ``feed`` every piece of the input, ``finish`` at
    its end."""

    def feed(self, data: Buffer, /, datagram: bool = False) -> List[Event]:
        """Every event of ``data`` as one list (use ``feed_iter`` for a big input). Ctrl-C
        lands between two steps; the decoder is then fed up to a 64 KiB boundary
        (``bytes_fed``) and keeps those bytes' events for the next call."""
    def feed_iter(self, data: Buffer, /, datagram: bool = False) -> FeedIter:
        """The events ``feed`` would return, lazily: memory bounded whatever ``len(data)``."""
    def finish(self) -> List[Event]:
        """The end of the input: what the decoder still holds, reported (``truncated``)."""
    @property
    def stats(self) -> Dict[str, int]: ...
    @property
    def bytes_fed(self) -> int: ...

class AeolusDecoder(Decoder):
    """``protolink.aeolus.Decoder``."""

    def __init__(self) -> None: ...

class AydpDecoder(Decoder):
    """``protolink.aydp.Decoder``."""

    def __init__(self, profile: str = "spec") -> None: ...
    @property
    def profile(self) -> str: ...

class AokDecoder(Decoder):
    """``protolink.aok.Decoder``."""

    def __init__(self, side: str = "device") -> None: ...
    @property
    def side(self) -> str: ...

class Gdl90Decoder(Decoder):
    """``protolink.gdl90.Decoder``."""

    def __init__(self) -> None: ...

def aeolus_encode(name: str, /, crc: bool = True, **fields: Any) -> bytes: ...
def aydp_encode(
    name: str,
    /,
    profile: str = "spec",
    expedited: Optional[bool] = None,
    time: Union[Mapping[str, int], Tuple[int, int], None] = None,
    **fields: Any,
) -> bytes: ...
def aok_encode(name: str, /, **fields: Any) -> bytes: ...
def open(
    source: Union[str, "os.PathLike[str]"],
    proto: Optional[str] = None,
    *,
    profile: Optional[str] = None,
    side: str = "device",
    errors: bool = True,
    strict: bool = False,
) -> Reader: ...
def run_cli(args: List[str]) -> int: ...

class ArrowTable:
    """One message type's rows as Arrow record batches (the Arrow PyCapsule interface)."""

    def __arrow_c_stream__(self, requested_schema: Optional[object] = None) -> object: ...
    def __len__(self) -> int: ...
    @property
    def column_names(self) -> List[str]: ...

def file_tables(
    source: Union[str, "os.PathLike[str]"],
    proto: Optional[str] = None,
    *,
    profile: Optional[str] = None,
    side: str = "device",
    errors: bool = True,
    strict: bool = False,
    row_group: int = 65536,
) -> Optional[Dict[str, ArrowTable]]: ...
def message_tables(messages: Iterable[Any], *, errors: bool = True) -> Dict[str, ArrowTable]: ...
def export(
    sources: List[str],
    out: str,
    format: str = "parquet",
    proto: Optional[str] = None,
    *,
    profile: Optional[str] = None,
    side: str = "device",
    row_group: int = 65536,
    types: List[str] = ...,
    since: Optional[str] = None,
    until: Optional[str] = None,
    air: bool = False,
) -> List[Tuple[str, int, List[str]]]: ...
