"""The package's warning categories (re-exported by ``protolink``)."""

__all__ = ["DamagedCaptureWarning", "TruncatedCaptureWarning"]


class TruncatedCaptureWarning(UserWarning):
    """A capture file ends inside a block: what ``protolink record`` leaves when it is killed
    mid-write. Every whole record was read; the message names the byte offset where the cut
    block starts (``Reader.truncated_at``). ``strict=True`` raises ``OSError`` instead."""


class DamagedCaptureWarning(UserWarning):
    """A capture file holds blocks or records that cannot be read (bytes overwritten, a length
    that points nowhere). They were skipped and every whole record around them was read; the
    message names the bytes lost and where the first damage starts. ``strict=True`` raises
    ``OSError`` instead."""


TruncatedCaptureWarning.__module__ = "protolink"
DamagedCaptureWarning.__module__ = "protolink"
