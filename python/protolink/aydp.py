"""AYDP (0xFF start, XOR checksum, both the 2016 document's and the released software's
profile): the stream ``Decoder`` and ``encode``.

Fields are the Rust crate's (``aydp-proto``), exactly the ``"fields"`` of ``protolink decode
--json``; the header (``type``, ``expedited``, ``len``, ``time``) is in ``Message.meta``
(``to_frames``: the columns ``meta.type``, ..., ``meta.time.seconds``, ``meta.time.subsec``).
"""

from typing import Any, Mapping, Optional, Tuple, Union

from ._native import AydpDecoder as Decoder
from ._native import aydp_encode

__all__ = ["Decoder", "encode"]


def encode(
    name: str,
    /,
    profile: str = "spec",
    expedited: Optional[bool] = None,
    time: Union[Mapping[str, int], Tuple[int, int], None] = None,
    **fields: Any,
) -> bytes:
    """One AYDP message (header and checksum included) from a message name and its fields.

    The fields are those ``Message.to_dict()`` gives; ``profile`` is ``"spec"`` or
    ``"reference"``; ``expedited`` picks the 6-byte header (by default only ``HEARTBEAT`` is
    expedited; the reference profile has none); ``time`` is the normal header's time,
    ``{"seconds": s, "subsec": n}`` as ``Message.meta["time"]`` gives it, or ``(s, n)``
    (zero when left out). Requests and commands to a device: ``SYSTEM_CONTROL``
    (``command="RequestData", address=...`` or ``command="StoreConfiguration"``),
    ``SYSTEM_VALUE_UPDATE`` (``address``, ``mode``, ``data``), ``DIRECT_OUTPUT`` (``entries``).

    Raises ``ValueError`` or ``TypeError`` with one sentence for a name, field or value the
    protocol does not have.
    """
    return aydp_encode(name, profile=profile, expedited=expedited, time=time, **fields)
