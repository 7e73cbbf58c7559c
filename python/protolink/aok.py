"""AOK (the copter's serial protocol, both directions): the stream ``Decoder`` and ``encode``.

``Decoder(side="device")`` reads what a device sends (debug values, parameter and waypoint
replies); ``Decoder(side="pc")`` reads what a PC sends (commands). Fields are the Rust crate's
(``aok-proto``), exactly the ``"fields"`` of ``protolink decode --json``: waypoint slots as
``"1"``..``"31"``, ``"poi"``, ``"ram-poi"``, ``"fbc"``; actions as ``"hold-and-climb:15"``.
"""

from typing import Any

from ._native import AokDecoder as Decoder
from ._native import aok_encode

__all__ = ["Decoder", "encode"]


def encode(name: str, /, **fields: Any) -> bytes:
    """One AOK frame from the name of a command (what a PC sends: ``READ_PARAMETER``,
    ``SET_PARAMETER``, ``SET_WAYPOINT``, ``MOTOR_TEST``, ``EXTERNAL_CONTROL``, ...) or of a
    message (what a device sends: ``DEBUG``, ``PARAMETER``, ``WAYPOINT``, ``ACK``) and its
    fields as ``Message.to_dict()`` gives them. Parameter replies are encoded headed (firmware
    0.31 and later).

    Raises ``ValueError`` or ``TypeError`` with one sentence for a name, field or value the
    protocol does not have (an out-of-range motor or stick included).
    """
    return aok_encode(name, **fields)
