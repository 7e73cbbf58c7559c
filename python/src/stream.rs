//! The decoders behind the Python classes, without Python: one of the host tool's four stream
//! decoders and the count of bytes fed, run with the GIL released. What they report waits as
//! `Pending` until it becomes a Python object.

use protolink::decoders::{
    AeolusDecoder, AeolusItem, AokDecoder, AydpDecoder, Event, Gdl90Decoder, StreamDecoder,
};
use protolink::proto::{ProfileArg, Proto, Side};
use serde_json::Value;

/// An AEOLUS frame whose data parses as its message, kept as received: its fields are
/// rendered (by the host tool's `aeolus_fields`) only when Python reads them.
#[derive(Debug, Clone)]
pub(crate) struct AeolusFrame {
    /// Offset of its opening flag in the input.
    pub(crate) offset: u64,
    /// The message ID.
    pub(crate) id: u8,
    /// Whether it carried a CRC (`00 00` means none).
    pub(crate) has_crc: bool,
    /// Its length on the wire, both flags included.
    pub(crate) len: u64,
    /// The unescaped data, ID and CRC removed.
    pub(crate) data: Box<[u8]>,
}

/// Something a decoder reported, before it becomes a Python object.
#[derive(Debug, Clone)]
pub(crate) enum Pending {
    /// An AEOLUS message, kept raw.
    Aeolus(AeolusFrame),
    /// A message or an error as `protolink decode` renders it.
    Event(Event),
}

/// One of the host tool's decoders.
#[derive(Debug)]
enum Core {
    Aeolus(AeolusDecoder),
    Aydp(AydpDecoder),
    Aok(AokDecoder),
    Gdl90(Gdl90Decoder),
}

impl Core {
    /// The decoder as the host tool's `StreamDecoder` (AEOLUS's events rendered, not kept raw).
    fn as_dyn(&mut self) -> &mut dyn StreamDecoder {
        match self {
            Core::Aeolus(d) => d,
            Core::Aydp(d) => d,
            Core::Aok(d) => d,
            Core::Gdl90(d) => d,
        }
    }
}

/// A decoder and the bytes it has been fed, so that every event carries its input offset.
#[derive(Debug)]
pub(crate) struct Stream {
    core: Core,
    proto: Proto,
    offset: u64,
}

impl Stream {
    /// A decoder for `proto`, as `protolink decode --proto ... --profile ... --side ...` builds
    /// it (the profile only counts for AYDP, the side only for AOK).
    pub(crate) fn new(proto: Proto, profile: ProfileArg, side: Side) -> Self {
        let core = match proto {
            Proto::Aeolus => Core::Aeolus(AeolusDecoder::new()),
            Proto::Aydp => Core::Aydp(AydpDecoder::new(profile.into())),
            Proto::Aok => Core::Aok(AokDecoder::new(side)),
            Proto::Gdl90 => Core::Gdl90(Gdl90Decoder::default()),
        };
        Stream {
            core,
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
        match &mut self.core {
            Core::Aeolus(d) => {
                d.feed_items(bytes, start, |at, item| out.push(pending(at, item)));
                if datagram {
                    d.end_of_datagram_items(|at, item| out.push(pending(at, item)));
                }
            }
            other => stream_feed(other.as_dyn(), bytes, start, datagram, out),
        }
    }

    /// The end of the input: what is still held is given up (AOK: rescanned, as after a quiet
    /// line) and reported.
    pub(crate) fn finish(&mut self, out: &mut Vec<Pending>) {
        let end = self.offset;
        match &mut self.core {
            Core::Aeolus(d) => d.finish_items(|at, item| out.push(pending(at, item))),
            other => stream_finish(other.as_dyn(), end, out),
        }
    }

    /// The counters, as `protolink decode` prints them in its summary: the crate's `Stats`
    /// plus the host tool's `malformed` and `truncated`.
    pub(crate) fn counters(&self) -> Value {
        match &self.core {
            Core::Aeolus(d) => d.counters(),
            Core::Aydp(d) => d.counters(),
            Core::Aok(d) => d.counters(),
            Core::Gdl90(d) => d.counters(),
        }
    }
}

fn pending(offset: u64, item: AeolusItem<'_>) -> Pending {
    match item {
        AeolusItem::Message { frame, len, .. } => Pending::Aeolus(AeolusFrame {
            offset,
            id: frame.id(),
            has_crc: frame.has_crc(),
            len,
            data: frame.data().into(),
        }),
        other => Pending::Event(other.to_event(offset)),
    }
}

fn stream_feed(
    d: &mut dyn StreamDecoder,
    bytes: &[u8],
    start: u64,
    datagram: bool,
    out: &mut Vec<Pending>,
) {
    let mut events = Vec::new();
    d.feed(bytes, start, &mut events);
    if datagram {
        d.end_of_datagram(start + bytes.len() as u64, &mut events);
    }
    out.extend(events.into_iter().map(Pending::Event));
}

fn stream_finish(d: &mut dyn StreamDecoder, end: u64, out: &mut Vec<Pending>) {
    let mut events = Vec::new();
    d.finish(end, &mut events);
    out.extend(events.into_iter().map(Pending::Event));
}
