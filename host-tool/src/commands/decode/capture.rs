//! `decode --from CAPTURE`: the AEOLUS, AYDP, AOK and GDL90 payloads of a pcapng or pcap file,
//! found by port or link type, decoded per flow as if they came live, each event tagged with
//! its frame number and the capture's timestamp.
//!
//! A flow is one direction of one UDP or TCP conversation, or one stream interface. UDP
//! datagram boundaries are kept (a frame never spans two datagrams); TCP payloads and stream
//! chunks are one byte stream per flow. `offset` is the byte offset within the flow.

use std::collections::HashMap;
use std::net::SocketAddrV4;
use std::path::Path;

use serde_json::{Value, json};

use super::{DecodeArgs, summary};
use crate::capture::{CaptureReader, Payload, StreamKind, Transport, proto_for_port};
use crate::decoders::{Event, StreamDecoder, decoder_for};
use crate::error::Result;
use crate::proto::{ProfileArg, Proto};
use crate::render::Out;
use crate::stop::Deadline;

/// At most this many flows are decoded at once; payloads of further flows are dropped and
/// counted (`flows_dropped`), so a capture of a busy network cannot fill memory.
pub const MAX_FLOWS: usize = 64;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
enum FlowKey {
    Ip(Transport, SocketAddrV4, SocketAddrV4),
    Stream(u32),
}

struct Flow {
    name: String,
    proto: Proto,
    datagrams: bool,
    decoder: Box<dyn StreamDecoder>,
    offset: u64,
}

fn proto_name(p: Proto) -> &'static str {
    match p {
        Proto::Aeolus => "aeolus",
        Proto::Aydp => "aydp",
        Proto::Aok => "aok",
        Proto::Gdl90 => "gdl90",
    }
}

/// One event of a capture as a JSON object: the live decoder's object with `frame`, `capture_time`
/// (seconds since the Unix epoch), `flow` and `proto` added after `offset`.
pub fn capture_json(event: &Event, frame: u64, time: f64, flow: &str, proto: Proto) -> Value {
    let mut v = event.to_json();
    if let Value::Object(m) = &mut v {
        let rest = std::mem::take(m);
        m.insert("frame".into(), json!(frame));
        m.insert("capture_time".into(), json!(time));
        m.insert("flow".into(), json!(flow));
        m.insert("proto".into(), json!(proto_name(proto)));
        m.extend(rest);
    }
    v
}

/// Counters of a capture decode, beside each flow's decoder counters.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct CaptureCounters {
    /// Records read.
    pub frames: u64,
    /// Records carrying none of our protocols (other ports, other link types, empty).
    pub skipped: u64,
    /// Payloads dropped because [`MAX_FLOWS`] flows were already open.
    pub flows_dropped: u64,
}

/// Decodes the capture at `path`, printing one line per event and a summary per flow.
///
/// # Errors
/// Opening or reading the capture, or writing the output.
pub fn run(path: &Path, args: &DecodeArgs, deadline: Deadline) -> Result<()> {
    let mut reader = CaptureReader::open(path)?;
    let mut out = Out::new();
    let mut flows = Flows::default();
    let mut events = Vec::new();
    let mut last_time = 0.0;
    let mut plot = args
        .udp_json
        .map(super::plot::PlotSender::new)
        .transpose()?;
    while !deadline.reached() {
        let Some(rec) = reader.next_record()? else {
            break;
        };
        flows.counters.frames += 1;
        let Some((key, kind, bytes)) = classify(rec.payload, args) else {
            flows.counters.skipped += 1;
            continue;
        };
        let Some(flow) = flows.open(key, kind) else {
            continue;
        };
        flow.feed(&bytes, &mut events);
        let time = rec.time.as_secs_f64();
        last_time = time;
        if let Some(p) = plot.as_mut() {
            p.send(&events, time);
        }
        for e in events.drain(..) {
            out.line(&line(&e, rec.frame, time, flow, args.json))?;
        }
        out.flush()?;
    }
    let frames = flows.counters.frames;
    for flow in &mut flows.flows {
        flow.decoder.finish(flow.offset, &mut events);
        for e in events.drain(..) {
            out.line(&line(&e, frames, last_time, flow, args.json))?;
        }
        out.line(&flow_summary(flow, args.json))?;
    }
    if let Some(p) = &plot {
        eprintln!("{}", p.report());
    }
    out.line(&capture_summary(
        flows.counters,
        flows.flows.len(),
        args.json,
    ))?;
    out.flush()
}

/// The flow a record's payload belongs to, what it carries and its bytes; `None` for a
/// record that carries none of our protocols (or not the one `--proto` asks for).
fn classify(payload: Payload, args: &DecodeArgs) -> Option<(FlowKey, StreamKind, Vec<u8>)> {
    match payload {
        Payload::Ip {
            transport,
            src,
            dst,
            bytes,
        } => {
            let by_port = proto_for_port(dst.port()).or_else(|| proto_for_port(src.port()));
            let proto = match (args.proto, by_port) {
                (Some(p), None) => Some(p),
                (Some(p), Some(q)) if p == q => Some(p),
                (None, q) => q,
                _ => None,
            };
            let proto = proto.filter(|_| !bytes.is_empty())?;
            // The AYDP reference software's port carries its profile; --profile overrides.
            let port_profile = if by_port == Some(Proto::Aydp) {
                ProfileArg::Reference
            } else {
                ProfileArg::Spec
            };
            let kind = StreamKind {
                proto,
                profile: args.profile.unwrap_or(port_profile),
                side: args.side,
            };
            Some((FlowKey::Ip(transport, src, dst), kind, bytes))
        }
        Payload::Stream {
            interface,
            kind,
            bytes,
        } if args.proto.is_none_or(|p| p == kind.proto) => {
            Some((FlowKey::Stream(interface), kind, bytes))
        }
        _ => None,
    }
}

/// The flows of a capture in the order they appeared, at most [`MAX_FLOWS`], and the
/// capture's counters.
#[derive(Default)]
struct Flows {
    index: HashMap<FlowKey, usize>,
    flows: Vec<Flow>,
    counters: CaptureCounters,
}

impl Flows {
    /// The flow `key`, opened with a decoder for `kind` when it is new; `None` (counted as
    /// dropped) when it is new and [`MAX_FLOWS`] are open.
    fn open(&mut self, key: FlowKey, kind: StreamKind) -> Option<&mut Flow> {
        if let Some(&i) = self.index.get(&key) {
            return self.flows.get_mut(i);
        }
        if self.flows.len() >= MAX_FLOWS {
            self.counters.flows_dropped += 1;
            return None;
        }
        self.index.insert(key, self.flows.len());
        self.flows.push(Flow::new(key, kind));
        self.flows.last_mut()
    }
}

impl Flow {
    fn new(key: FlowKey, kind: StreamKind) -> Self {
        let name = match key {
            FlowKey::Ip(t, s, d) => {
                let t = if t == Transport::Udp { "udp" } else { "tcp" };
                format!("{t} {s} > {d}")
            }
            FlowKey::Stream(i) => format!("stream {i} linktype {}", kind.link_type()),
        };
        Flow {
            name,
            proto: kind.proto,
            datagrams: matches!(key, FlowKey::Ip(Transport::Udp, ..)),
            decoder: decoder_for(kind.proto, kind.profile, kind.side),
            offset: 0,
        }
    }

    /// Decodes the next payload of the flow (a whole datagram on UDP).
    fn feed(&mut self, bytes: &[u8], events: &mut Vec<Event>) {
        self.decoder.feed(bytes, self.offset, events);
        self.offset += bytes.len() as u64;
        if self.datagrams {
            self.decoder.end_of_datagram(self.offset, events);
        }
    }
}

/// A flow's summary line: the live decoder's, with the flow and its protocol.
fn flow_summary(flow: &Flow, json_out: bool) -> String {
    let s = summary(flow.offset, &flow.decoder.counters(), json_out);
    if json_out {
        let mut v: Value = serde_json::from_str(&s).unwrap_or(Value::Null);
        if let Value::Object(m) = &mut v {
            m.insert("flow".into(), json!(flow.name));
            m.insert("proto".into(), json!(proto_name(flow.proto)));
        }
        v.to_string()
    } else {
        format!("{} ({}) {s}", flow.name, proto_name(flow.proto))
    }
}

/// The capture's summary line: records read and skipped, flows decoded and dropped.
fn capture_summary(c: CaptureCounters, flows: usize, json_out: bool) -> String {
    if json_out {
        json!({"kind": "capture", "frames": c.frames, "skipped": c.skipped, "flows": flows, "flows_dropped": c.flows_dropped}).to_string()
    } else {
        format!(
            "capture: frames={} skipped={} flows={} flows_dropped={}",
            c.frames, c.skipped, flows, c.flows_dropped
        )
    }
}

fn line(e: &Event, frame: u64, time: f64, flow: &Flow, json_out: bool) -> String {
    if json_out {
        capture_json(e, frame, time, &flow.name, flow.proto).to_string()
    } else {
        format!("#{frame} {time:.6} {} {}", flow.name, e.to_text())
    }
}
