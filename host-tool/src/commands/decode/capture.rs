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

use serde_json::Value;
#[cfg(feature = "cli")]
use serde_json::json;

use super::tables::Select;
#[cfg(feature = "cli")]
use super::{DecodeArgs, summary};
use crate::capture::{CaptureReader, Payload, StreamKind, Transport, proto_for_port};
use crate::columns::{Origin, Tables};
#[cfg(feature = "cli")]
use crate::decoders::Event;
use crate::decoders::{Decoder, Kept};
use crate::error::Result;
use crate::proto::{ProfileArg, Proto};
#[cfg(feature = "cli")]
use crate::render::Out;
#[cfg(feature = "cli")]
use crate::stop::Deadline;

/// At most this many flows are decoded at once; payloads of further flows are dropped and
/// counted (`flows_dropped`), so a capture of a busy network cannot fill memory.
pub(crate) const MAX_FLOWS: usize = 64;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
enum FlowKey {
    Ip(Transport, SocketAddrV4, SocketAddrV4),
    Stream(u32),
}

struct Flow {
    name: String,
    proto: Proto,
    datagrams: bool,
    decoder: Decoder,
    offset: u64,
}

pub use crate::proto::proto_name;

/// One event of a capture as a JSON object: the live decoder's object with `frame`, `capture_time`
/// (seconds since the Unix epoch), `flow` and `proto` added after `offset`.
#[cfg(feature = "cli")]
pub(crate) fn capture_json(
    event: &Event,
    frame: u64,
    time: f64,
    flow: &str,
    proto: Proto,
) -> Value {
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
pub(crate) struct CaptureCounters {
    /// Records read.
    pub(crate) frames: u64,
    /// Records carrying none of our protocols (other ports, other link types, empty).
    pub(crate) skipped: u64,
    /// Payloads dropped because [`MAX_FLOWS`] flows were already open.
    pub(crate) flows_dropped: u64,
}

/// One thing a capture decode reports, in the order `decode` prints it.
#[derive(Debug, Clone, PartialEq)]
pub enum CaptureItem {
    /// A decoder's event, with the record it came in.
    Event {
        /// The record's number (for the events at the end of the capture: the last record's).
        frame: u64,
        /// The record's capture time, seconds since the Unix epoch.
        time: f64,
        /// The flow's name, e.g. `udp 127.0.0.1:40000 > 127.0.0.1:5001`.
        flow: String,
        /// The flow's protocol.
        proto: Proto,
        /// The item, typed; its offset is within the flow.
        item: Kept,
    },
    /// A flow is done (the capture ended): its bytes and its decoder's counters.
    FlowEnd {
        /// The flow's name.
        flow: String,
        /// The flow's protocol.
        proto: Proto,
        /// Bytes of the flow decoded.
        bytes: u64,
        /// Its decoder's counters, as `decode` prints them.
        counters: Value,
    },
}

/// A capture being decoded record by record: what `decode --from CAPTURE` prints, and what
/// the Python package (`python/`) iterates.
pub struct CaptureEvents {
    reader: CaptureReader,
    select: Select,
    flows: Flows,
    last_time: f64,
    /// No more records are read (the end of the file, or [`CaptureEvents::stop`]).
    stopped: bool,
    /// The flows' last events and summaries have been handed out.
    finished: bool,
}

impl std::fmt::Debug for CaptureEvents {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CaptureEvents")
            .field("reader", &self.reader)
            .field("flows", &self.flows.flows.len())
            .finish()
    }
}

impl CaptureEvents {
    /// Opens the capture at `path`; `select` chooses what is decoded, as `decode`'s
    /// `--proto`, `--profile` and `--side` do.
    ///
    /// # Errors
    /// Opening the file, or a file that is no capture.
    pub fn open(path: &Path, select: &Select) -> Result<Self> {
        Ok(CaptureEvents {
            reader: CaptureReader::open(path)?,
            select: *select,
            flows: Flows::default(),
            last_time: 0.0,
            stopped: false,
            finished: false,
        })
    }

    /// Where the next record starts: the bytes of the capture read so far.
    pub fn offset(&self) -> u64 {
        self.reader.offset()
    }

    /// Reads no further record: the next [`CaptureEvents::next_items`] ends the flows.
    pub fn stop(&mut self) {
        self.stopped = true;
    }

    /// Reads the next record and appends what it gives to `out` (nothing for a record of no
    /// flow); at the end of the capture appends every flow's last events and its
    /// [`CaptureItem::FlowEnd`]. Returns `false`, appending nothing, once all is said.
    ///
    /// # Errors
    /// A damaged or cut capture.
    pub fn next_items(&mut self, out: &mut Vec<CaptureItem>) -> Result<bool> {
        let mut events = Vec::new();
        match self.step()? {
            Step::Done => return Ok(false),
            Step::Nothing => {}
            Step::End { frames, time } => {
                for flow in &mut self.flows.flows {
                    flow.decoder.finish(|p| events.push(Kept::new(&p)));
                    out.extend(events.drain(..).map(|e| flow.item(e, frames, time)));
                    out.push(CaptureItem::FlowEnd {
                        flow: flow.name.clone(),
                        proto: flow.proto,
                        bytes: flow.offset,
                        counters: flow.decoder.counters(),
                    });
                }
            }
            Step::Bytes {
                flow,
                bytes,
                frame,
                time,
            } => {
                flow.feed(&bytes, &mut events);
                out.extend(events.drain(..).map(|e| flow.item(e, frame, time)));
            }
        }
        Ok(true)
    }

    /// Reads the next record and adds its events to `tables` as rows, each from its record
    /// (and from `source` when given); at the end of the capture adds every flow's last
    /// events. Returns `false`, adding nothing, once all is done. The rows are those of
    /// [`CaptureEvents::next_items`]' events, each message straight from its typed value.
    ///
    /// # Errors
    /// A damaged or cut capture.
    pub fn next_columns(&mut self, tables: &mut Tables, source: Option<&str>) -> Result<bool> {
        let origin = |flow: &Flow, frame: u64, time: f64| Origin {
            source: source.map(str::to_owned),
            capture_time: Some(time),
            flow: Some(flow.name.clone()),
            frame: Some(frame),
            proto: Some(flow.proto),
        };
        match self.step()? {
            Step::Done => return Ok(false),
            Step::Nothing => {}
            Step::End { frames, time } => {
                for flow in &mut self.flows.flows {
                    let o = origin(flow, frames, time);
                    flow.decoder.finish(|p| tables.add(&o, &p));
                }
            }
            Step::Bytes {
                flow,
                bytes,
                frame,
                time,
            } => {
                let o = origin(flow, frame, time);
                flow.decoder
                    .feed(&bytes, flow.offset, |p| tables.add(&o, &p));
                flow.offset += bytes.len() as u64;
                if flow.datagrams {
                    flow.decoder.end_of_datagram(|p| tables.add(&o, &p));
                }
            }
        }
        Ok(true)
    }

    /// Reads the next record and says what it holds for the flows; counts it, and its skip.
    fn step(&mut self) -> Result<Step<'_>> {
        if self.finished {
            return Ok(Step::Done);
        }
        let record = if self.stopped {
            None
        } else {
            self.reader.next_record()?
        };
        let Some(rec) = record else {
            self.finished = true;
            return Ok(Step::End {
                frames: self.flows.counters.frames,
                time: self.last_time,
            });
        };
        self.flows.counters.frames += 1;
        let (frame, time) = (rec.frame, rec.time.as_secs_f64());
        let Some((key, kind, bytes)) = classify(rec.payload, &self.select) else {
            self.flows.counters.skipped += 1;
            return Ok(Step::Nothing);
        };
        let Some(flow) = self.flows.open(key, kind) else {
            return Ok(Step::Nothing);
        };
        self.last_time = time;
        Ok(Step::Bytes {
            flow,
            bytes,
            frame,
            time,
        })
    }

    /// The capture's counters so far.
    #[cfg(feature = "cli")]
    pub(crate) fn counters(&self) -> CaptureCounters {
        self.flows.counters
    }

    /// The flows opened so far.
    #[cfg(feature = "cli")]
    pub(crate) fn flow_count(&self) -> usize {
        self.flows.flows.len()
    }

    /// Every flow opened so far, in the order they appeared: its name, protocol, bytes decoded
    /// and its decoder's counters.
    pub fn flows(&self) -> Vec<(String, Proto, u64, Value)> {
        self.flows
            .flows
            .iter()
            .map(|f| (f.name.clone(), f.proto, f.offset, f.decoder.counters()))
            .collect()
    }
}

/// Decodes the capture at `path`, printing one line per event and a summary per flow.
///
/// # Errors
/// Opening or reading the capture, or writing the output.
#[cfg(feature = "cli")]
pub(crate) fn run(path: &Path, args: &DecodeArgs, deadline: Deadline) -> Result<()> {
    let mut capture = CaptureEvents::open(path, &args.select())?;
    let mut out = Out::new();
    let mut items = Vec::new();
    let mut plot = args
        .udp_json
        .map(super::plot::PlotSender::new)
        .transpose()?;
    loop {
        // The deadline ends the records: the flows' last events and summaries still follow.
        if deadline.reached() {
            capture.stop();
        }
        if !capture.next_items(&mut items)? {
            break;
        }
        for item in items.drain(..) {
            match item {
                CaptureItem::Event {
                    frame,
                    time,
                    flow,
                    proto,
                    item,
                } => {
                    let event = item.with(|p| p.to_event());
                    if let Some(p) = plot.as_mut() {
                        p.send(proto, std::slice::from_ref(&event), time);
                    }
                    out.line(&line(&event, frame, time, &flow, proto, args.json))?;
                }
                CaptureItem::FlowEnd {
                    flow,
                    proto,
                    bytes,
                    counters,
                } => out.line(&flow_summary(&flow, proto, bytes, &counters, args.json))?,
            }
        }
        out.flush()?;
    }
    if let Some(p) = &plot {
        eprintln!("{}", p.report());
    }
    out.line(&capture_summary(
        capture.counters(),
        capture.flow_count(),
        args.json,
    ))?;
    out.flush()
}

/// What one record of a capture holds for its flows ([`CaptureEvents::step`]).
enum Step<'a> {
    /// All was said before: the end was handled already.
    Done,
    /// The capture ended, or reading was stopped: every flow is to be finished, its last
    /// events as of the capture's record count and last record time.
    End { frames: u64, time: f64 },
    /// A record of no flow: skipped, or beyond the flow limit.
    Nothing,
    /// A flow's bytes, from the record of this frame number at this capture time.
    Bytes {
        flow: &'a mut Flow,
        bytes: Vec<u8>,
        frame: u64,
        time: f64,
    },
}

/// The flow a record's payload belongs to, what it carries and its bytes; `None` for a
/// record that carries none of our protocols (or not the one `--proto` asks for).
fn classify(payload: Payload, args: &Select) -> Option<(FlowKey, StreamKind, Vec<u8>)> {
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
    /// An event of this flow as a [`CaptureItem`], with its record's number and time.
    fn item(&self, item: Kept, frame: u64, time: f64) -> CaptureItem {
        CaptureItem::Event {
            frame,
            time,
            flow: self.name.clone(),
            proto: self.proto,
            item,
        }
    }

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
            decoder: Decoder::new(kind.proto, kind.profile, kind.side),
            offset: 0,
        }
    }

    /// Decodes the next payload of the flow (a whole datagram on UDP).
    fn feed(&mut self, bytes: &[u8], items: &mut Vec<Kept>) {
        self.decoder
            .feed(bytes, self.offset, |p| items.push(Kept::new(&p)));
        self.offset += bytes.len() as u64;
        if self.datagrams {
            self.decoder.end_of_datagram(|p| items.push(Kept::new(&p)));
        }
    }
}

/// A flow's summary line: the live decoder's, with the flow and its protocol.
#[cfg(feature = "cli")]
fn flow_summary(flow: &str, proto: Proto, bytes: u64, counters: &Value, json_out: bool) -> String {
    let s = summary(bytes, counters, json_out);
    if json_out {
        let mut v: Value = serde_json::from_str(&s).unwrap_or(Value::Null);
        if let Value::Object(m) = &mut v {
            m.insert("flow".into(), json!(flow));
            m.insert("proto".into(), json!(proto_name(proto)));
        }
        v.to_string()
    } else {
        format!("{flow} ({}) {s}", proto_name(proto))
    }
}

/// The capture's summary line: records read and skipped, flows decoded and dropped.
#[cfg(feature = "cli")]
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

#[cfg(feature = "cli")]
fn line(e: &Event, frame: u64, time: f64, flow: &str, proto: Proto, json_out: bool) -> String {
    if json_out {
        capture_json(e, frame, time, flow, proto).to_string()
    } else {
        format!("#{frame} {time:.6} {flow} {}", e.to_text())
    }
}
