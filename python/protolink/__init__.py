"""AEOLUS, AYDP, AOK and GDL90 in Python, on the very decoders the firmware runs.

The package is a thin face over the project's Rust crates (the ``protolink`` host tool's
decoders, capture reading and command line), so a flight decoded here is byte for byte what
``protolink decode`` and the box itself make of it::

    import protolink
    frames = protolink.to_frames("flight.pcapng")      # one pandas DataFrame per message type
    print(frames["GYRO"])
    tables = protolink.to_arrow("flight.pcapng")       # the same as pyarrow Tables
    protolink.export(["a.pcapng", "b.pcapng"], "tables")   # tables/proto=aeolus/type=GYRO/part-00000.parquet

    for msg in protolink.open("udp:5001", proto="aeolus"):   # like mavutil.mavlink_connection
        if msg.name == "ATTITUDE":
            print(msg.roll_rad, msg.pitch_rad)

    dec = protolink.aeolus.Decoder()
    for chunk in chunks:                                # the one loop: feed every piece,
        for msg in dec.feed(chunk):                     # messages and error events
            ...
    for msg in dec.finish():                            # then finish at the end of the stream
        ...
    for msg in dec.feed_iter(big_buffer):               # the same, lazily: bounded memory
        ...

Modules: :mod:`protolink.aeolus`, :mod:`protolink.aydp`, :mod:`protolink.aok`,
:mod:`protolink.gdl90` (each a ``Decoder`` and, but for GDL90, ``encode``).
"""

from . import aeolus, aok, aydp, gdl90
from ._native import ErrorEvent, FeedIter, Message, Reader, open
from ._warnings import DamagedCaptureWarning, TruncatedCaptureWarning
from .frames import export, to_arrow, to_frames

__version__ = "0.1.0"

__all__ = [
    "ErrorEvent",
    "FeedIter",
    "Message",
    "Reader",
    "TruncatedCaptureWarning",
    "DamagedCaptureWarning",
    "aeolus",
    "aok",
    "aydp",
    "export",
    "gdl90",
    "open",
    "to_arrow",
    "to_frames",
]
