"""GDL90 and the ForeFlight and Stratux extensions, as EFB apps receive them on UDP port 4000:
the stream ``Decoder``. Fields are the Rust crate's (``gdl90-proto``), exactly the
``"fields"`` of ``protolink decode --json``.
"""

from ._native import Gdl90Decoder as Decoder

__all__ = ["Decoder"]
