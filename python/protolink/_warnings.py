"""The package's warning categories (re-exported by ``protolink``)."""

__all__ = ["TruncatedCaptureWarning"]


class TruncatedCaptureWarning(UserWarning):
    """A capture file ends inside a block: what ``protolink record`` leaves when it is killed
    mid-write. Every whole record was read; the message names the byte offset where the cut
    block starts (``Reader.truncated_at``). ``strict=True`` raises ``OSError`` instead."""


TruncatedCaptureWarning.__module__ = "protolink"
