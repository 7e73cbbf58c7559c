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
    let mut flows: HashMap<FlowKey, Flow> = HashMap::new();
    let mut order: Vec<FlowKey> = Vec::new();
    let mut counters = CaptureCounters::default();
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
        counters.frames += 1;
        let (key, kind, bytes) = match rec.payload {
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
                let Some(proto) = proto.filter(|_| !bytes.is_empty()) else {
                    counters.skipped += 1;
                    continue;
                };
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
                (FlowKey::Ip(transport, src, dst), kind, bytes)
            }
            Payload::Stream {
                interface,
                kind,
                bytes,
            } if args.proto.is_none_or(|p| p == kind.proto) => {
                (FlowKey::Stream(interface), kind, bytes)
            }
            _ => {
                counters.skipped += 1;
                continue;
            }
        };
        if !flows.contains_key(&key) {
            if flows.len() >= MAX_FLOWS {
                counters.flows_dropped += 1;
                continue;
            }
            let name = match key {
                FlowKey::Ip(t, s, d) => {
                    let t = if t == Transport::Udp { "udp" } else { "tcp" };
                    format!("{t} {s} > {d}")
                }
                FlowKey::Stream(i) => format!("stream {i} linktype {}", kind.link_type()),
            };
            flows.insert(
                key,
                Flow {
                    name,
                    proto: kind.proto,
                    datagrams: matches!(key, FlowKey::Ip(Transport::Udp, ..)),
                    decoder: decoder_for(kind.proto, kind.profile, kind.side),
                    offset: 0,
                },
            );
            order.push(key);
        }
        let Some(flow) = flows.get_mut(&key) else {
            continue;
        };
        flow.decoder.feed(&bytes, flow.offset, &mut events);
        flow.offset += bytes.len() as u64;
        if flow.datagrams {
            flow.decoder.end_of_datagram(flow.offset, &mut events);
        }
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
    for key in &order {
        let Some(flow) = flows.get_mut(key) else {
            continue;
        };
        flow.decoder.finish(flow.offset, &mut events);
        for e in events.drain(..) {
            out.line(&line(&e, counters.frames, last_time, flow, args.json))?;
        }
        let s = summary(flow.offset, &flow.decoder.counters(), args.json);
        out.line(&if args.json {
            let mut v: Value = serde_json::from_str(&s).unwrap_or(Value::Null);
            if let Value::Object(m) = &mut v {
                m.insert("flow".into(), json!(flow.name));
                m.insert("proto".into(), json!(proto_name(flow.proto)));
            }
            v.to_string()
        } else {
            format!("{} ({}) {s}", flow.name, proto_name(flow.proto))
        })?;
    }
    if let Some(p) = &plot {
        eprintln!("{}", p.report());
    }
    let c = counters;
    out.line(&if args.json {
        json!({"kind": "capture", "frames": c.frames, "skipped": c.skipped, "flows": order.len(), "flows_dropped": c.flows_dropped}).to_string()
    } else {
        format!(
            "capture: frames={} skipped={} flows={} flows_dropped={}",
            c.frames,
            c.skipped,
            order.len(),
            c.flows_dropped
        )
    })?;
    out.flush()
}

fn line(e: &Event, frame: u64, time: f64, flow: &Flow, json_out: bool) -> String {
    if json_out {
        capture_json(e, frame, time, &flow.name, flow.proto).to_string()
    } else {
        format!("#{frame} {time:.6} {} {}", flow.name, e.to_text())
    }
}
