//! The decoders behind the Python classes, without Python: one of the host tool's four stream
//! decoders and the count of bytes fed, run with the GIL released. What they report waits as
//! `Pending` (the typed item, its bytes kept) until it becomes a Python object.

use protolink::decoders::{Decoder, Kept, Placed};
use protolink::proto::{ProfileArg, Proto, Side};
use serde_json::Value;

/// Something a decoder reported, before it becomes a Python object: the typed item, its bytes
/// kept.
pub(crate) type Pending = Kept;

/// A decoder and the bytes it has been fed, so that every event carries its input offset.
#[derive(Debug)]
pub(crate) struct Stream {
    core: Decoder,
    proto: Proto,
    offset: u64,
}

impl Stream {
    /// A decoder for `proto`, as `protolink decode --proto ... --profile ... --side ...` builds
    /// it (the profile only counts for AYDP, the side only for AOK).
    pub(crate) fn new(proto: Proto, profile: ProfileArg, side: Side) -> Self {
        Stream {
            core: Decoder::new(proto, profile, side),
            proto,
            offset: 0,
        }
    }

    /// The protocol decoded.
    pub(crate) fn proto(&self) -> Proto {
        self.proto
    }

    /// Bytes fed so far.
    pub(crate) fn bytes_fed(&self) -> u64 {
        self.offset
    }

    /// Decodes `bytes`; `datagram` says they are one whole UDP datagram (a frame never spans
    /// two, so a frame still open at its end is given up).
    pub(crate) fn feed(&mut self, bytes: &[u8], datagram: bool, out: &mut Vec<Pending>) {
        let start = self.offset;
        self.offset += bytes.len() as u64;
        self.core.feed(bytes, start, |p| out.push(pending(p)));
        if datagram {
            self.core.end_of_datagram(|p| out.push(pending(p)));
        }
    }

    /// The end of the input: what is still held is given up (AOK: rescanned, as after a quiet
    /// line) and reported.
    pub(crate) fn finish(&mut self, out: &mut Vec<Pending>) {
        self.core.finish(|p| out.push(pending(p)));
    }

    /// The counters, as `protolink decode` prints them in its summary: the crate's `Stats`
    /// plus the host tool's `malformed` and `truncated`.
    pub(crate) fn counters(&self) -> Value {
        self.core.counters()
    }
}

/// An item as it waits.
fn pending(p: Placed<'_>) -> Pending {
    Kept::new(&p)
}
