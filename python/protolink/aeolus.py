"""AEOLUS sensor-box telemetry (0x7E framing, CRC-16): the stream ``Decoder`` and ``encode``.

Field names and units are the Rust crate's (``aeolus-proto``): ``timestamp_ms`` in ms,
angles in radians (``roll_rad``), rates in rad/s, accelerations in m/s², ``altitude_m``,
``latitude_deg``; exactly the ``"fields"`` of ``protolink decode --json``.
"""

from typing import Any

from ._native import AeolusDecoder as Decoder
from ._native import aeolus_encode

__all__ = ["Decoder", "encode"]


def encode(name: str, /, crc: bool = True, **fields: Any) -> bytes:
    """One AEOLUS frame (flags, escapes and CRC included) from a message name and its fields.

    The fields are those ``Message.to_dict()`` gives, so ``encode(m.name, **m.to_dict())``
    gives the frame back (``UNKNOWN`` also takes ``id=``). Raw data (``data``, ``hex``) may be
    bytes or a hex string; texts (``TOAST``, ``COMMAND``) take ``text=``. ``crc=False`` sends
    ``00 00`` ("no CRC", which the spec allows; ``Message.meta["crc"]`` is then ``"none"``).

    >>> encode("TOAST", text="hi").hex()
    '7e5268690073ec7e'

    Raises ``ValueError`` (an unknown name or field, a value out of range) or ``TypeError``
    (a value of the wrong type), each with one sentence.
    """
    return aeolus_encode(name, crc=crc, **fields)
