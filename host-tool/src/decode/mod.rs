//! `protolink decode`: one line per message (text or JSON), errors in the stream with their byte
//! offset, and the decoder's counters at the end.
//!
//! The offset of a message is the 0-based index of its first byte in the input: the opening
//! flag of an AEOLUS frame, the 0xFF start of an AYDP message, the first byte of an AOK frame,
//! also for messages a rescan found among bytes already held. `len` is its length on the wire,
//! so its bytes are `offset..offset + len`. An AEOLUS or AYDP error is reported at the first
//! byte of the failed frame or candidate; an AOK error at the byte that revealed it.

use std::time::Duration;

use aydp_proto::Profile;
use clap::{Args, ValueEnum};
use serde_json::{Map, Value, json};

mod aeolus;
mod aok;
mod aydp;
pub mod capture;
mod gdl90;
pub mod plot;

pub use aeolus::{AEOLUS_CAPACITY, AeolusDecoder, aeolus_fields, text_fields};
pub use aok::{
    AokDecoder, action_name, aok_command_fields, aok_message_fields, slot_name, waypoint_fields,
};
pub use aydp::{AYDP_CAPACITY, AydpDecoder, aydp_fields};
pub use gdl90::{GDL90_CAPACITY, Gdl90Decoder, gdl90_fields};

use crate::endpoint::{Endpoint, Input, Link};
use crate::error::Result;
use crate::render::{self, Out};
use crate::stop::Deadline;

/// Which protocol a stream carries.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Proto {
    /// AEOLUS sensor-box telemetry (7E-framed, CRC-16).
    Aeolus,
    /// AYDP, the yacht protocol (FF start, XOR checksum).
    Aydp,
    /// AOK, the copter's serial protocol.
    Aok,
    /// GDL90 and the ForeFlight extensions, as EFB apps receive them (7E-framed, CRC-16).
    Gdl90,
}

/// Which AYDP convention applies (DECISIONS.md Y1, Y2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, ValueEnum)]
pub enum ProfileArg {
    /// The 2016 document: the length counts the whole message, sub-seconds are ms.
    #[default]
    Spec,
    /// The released AYDP software: the length counts data only, sub-seconds are µs.
    Reference,
}

impl From<ProfileArg> for Profile {
    fn from(p: ProfileArg) -> Self {
        match p {
            ProfileArg::Spec => Profile::Spec,
            ProfileArg::Reference => Profile::Reference,
        }
    }
}

/// Who sent the AOK bytes being decoded.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, ValueEnum)]
pub enum Side {
    /// The ground PC sent them: commands, read as the device reads them.
    Pc,
    /// The device sent them: debug values, acks and replies, read as the PC reads them.
    #[default]
    Device,
}

/// Arguments of `protolink decode`.
#[derive(Debug, Clone, Args)]
pub struct DecodeArgs {
    /// The protocol of the stream (a capture: found by port or link type; --proto picks one).
    #[arg(long, value_enum)]
    pub proto: Option<Proto>,
    /// AYDP profile (default: spec; in a capture, AYDP on TCP/UDP 6321 is read as reference, as the reference software sends it and the dissector reads it).
    #[arg(long, value_enum)]
    pub profile: Option<ProfileArg>,
    /// AOK: who sent the bytes (pc: commands; device: debug values, acks, replies).
    #[arg(long, value_enum, default_value_t = Side::Device)]
    pub side: Side,
    /// Where the bytes come from (serial:PATH@BAUD, tcp:HOST:PORT, udp:PORT, file:PATH, -); a pcapng or pcap file is read as a capture.
    #[arg(long, value_name = "ENDPOINT")]
    pub from: Endpoint,
    /// One JSON object per line instead of text.
    #[arg(long)]
    pub json: bool,
    /// Also send one flat JSON object per message (timestamp, numeric fields) to this UDP address, as PlotJuggler's UDP server reads them.
    #[arg(long, value_name = "ADDR:PORT", value_parser = crate::endpoint::parse_local_addr)]
    pub udp_json: Option<std::net::SocketAddr>,
    /// Stop after this long: `10` (seconds), `500ms`, `2min` (default: at the end of the input, or on Ctrl-C).
    #[arg(long, value_name = "DURATION", value_parser = crate::args::run_time)]
    pub seconds: Option<std::time::Duration>,
}

/// One thing a decoder reports.
#[derive(Debug, Clone, PartialEq)]
pub struct Event {
    /// Input offset at which it was reported.
    pub offset: u64,
    /// What it is.
    pub body: Body,
}

/// A message or an error.
#[derive(Debug, Clone, PartialEq)]
pub enum Body {
    /// A decoded message.
    Message {
        /// Its name, e.g. `GYRO`.
        name: String,
        /// Facts about the frame (id, length, CRC state, header time...).
        meta: Map<String, Value>,
        /// The message's fields.
        fields: Value,
    },
    /// An error in the stream.
    Error {
        /// One sentence.
        error: String,
    },
}

impl Event {
    fn message(
        offset: u64,
        name: impl Into<String>,
        meta: Map<String, Value>,
        fields: Value,
    ) -> Self {
        Event {
            offset,
            body: Body::Message {
                name: name.into(),
                meta,
                fields,
            },
        }
    }

    fn error(offset: u64, error: impl Into<String>) -> Self {
        Event {
            offset,
            body: Body::Error {
                error: error.into(),
            },
        }
    }

    /// The event as one JSON object.
    ///
    /// ```
    /// # use protolink::decode::{Body, Event};
    /// let e = Event { offset: 7, body: Body::Error { error: "checksum mismatch".into() } };
    /// assert_eq!(e.to_json().to_string(), r#"{"offset":7,"kind":"error","error":"checksum mismatch"}"#);
    /// ```
    pub fn to_json(&self) -> Value {
        let mut m = Map::new();
        m.insert("offset".into(), json!(self.offset));
        match &self.body {
            Body::Message { name, meta, fields } => {
                m.insert("kind".into(), json!("message"));
                m.insert("name".into(), json!(name));
                m.extend(meta.clone());
                m.insert("fields".into(), fields.clone());
            }
            Body::Error { error } => {
                m.insert("kind".into(), json!("error"));
                m.insert("error".into(), json!(error));
            }
        }
        Value::Object(m)
    }

    /// The event as one readable line.
    ///
    /// ```
    /// # use protolink::decode::{Body, Event};
    /// let e = Event { offset: 7, body: Body::Error { error: "checksum mismatch".into() } };
    /// assert_eq!(e.to_text(), "@7 error: checksum mismatch");
    /// ```
    pub fn to_text(&self) -> String {
        match &self.body {
            Body::Message { name, meta, fields } => {
                let meta = render::text(&Value::Object(meta.clone()));
                let fields = render::text(fields);
                let mut line = format!("@{} {name}", self.offset);
                for part in [meta, fields] {
                    if !part.is_empty() {
                        line.push(' ');
                        line.push_str(&part);
                    }
                }
                line
            }
            Body::Error { error } => format!("@{} error: {error}", self.offset),
        }
    }
}

/// A stream decoder for one protocol, reporting [`Event`]s.
pub trait StreamDecoder {
    /// Feeds bytes that start at input offset `offset`.
    fn feed(&mut self, bytes: &[u8], offset: u64, out: &mut Vec<Event>);
    /// A datagram ended at `offset` (the next byte starts a new one).
    fn end_of_datagram(&mut self, _offset: u64, _out: &mut Vec<Event>) {}
    /// The input ended at `offset` (its length).
    fn finish(&mut self, _offset: u64, _out: &mut Vec<Event>) {}
    /// The counters, as a JSON object.
    fn counters(&self) -> Value;
}

/// Builds the decoder the arguments ask for.
pub fn decoder_for(proto: Proto, profile: ProfileArg, side: Side) -> Box<dyn StreamDecoder> {
    match proto {
        Proto::Aeolus => Box::new(AeolusDecoder::new()),
        Proto::Aydp => Box::new(AydpDecoder::new(profile.into())),
        Proto::Aok => Box::new(AokDecoder::new(side)),
        Proto::Gdl90 => Box::new(Gdl90Decoder::default()),
    }
}

/// The summary line printed at the end.
pub fn summary(bytes: u64, counters: &Value, json_out: bool) -> String {
    if json_out {
        json!({ "kind": "summary", "bytes": bytes, "counters": counters }).to_string()
    } else {
        format!("summary: bytes={bytes} {}", render::text(counters))
    }
}

/// Runs `protolink decode`.
///
/// # Errors
/// Opening or reading the endpoint, or writing the output.
pub fn run(args: &DecodeArgs) -> Result<()> {
    // Ctrl-C ends the input: the counters are still printed.
    crate::stop::install_ctrl_c();
    let deadline = Deadline::after(args.seconds);
    if let Endpoint::File(path) = &args.from
        && crate::capture::file_is_capture(path)
    {
        return capture::run(path, args, deadline);
    }
    let Some(proto) = args.proto else {
        return Err(crate::Error::Usage(format!(
            "--proto is needed for {}: only a pcapng or pcap capture names its protocols",
            args.from
        )));
    };
    let mut link = args.from.open()?;
    let mut decoder = decoder_for(proto, args.profile.unwrap_or_default(), args.side);
    let mut out = Out::new();
    let mut plot = args.udp_json.map(plot::PlotSender::new).transpose()?;
    let offset = pump(&mut link, decoder.as_mut(), deadline, |events| {
        if let Some(p) = plot.as_mut() {
            p.send(events, plot::now());
        }
        for e in events {
            let line = if args.json {
                e.to_json().to_string()
            } else {
                e.to_text()
            };
            out.line(&line)?;
        }
        out.flush()
    })?;
    out.line(&summary(offset, &decoder.counters(), args.json))?;
    if let Some(p) = &plot {
        eprintln!("{}", p.report());
    }
    out.flush()
}

/// Reads `link` until it ends or `deadline` passes, feeding `decoder` and handing every batch of
/// events to `emit`. Returns the number of bytes read.
///
/// # Errors
/// Reading the endpoint, or whatever `emit` returns.
pub fn pump(
    link: &mut Link,
    decoder: &mut dyn StreamDecoder,
    deadline: Deadline,
    mut emit: impl FnMut(&[Event]) -> Result<()>,
) -> Result<u64> {
    let mut buf = vec![0u8; 65_536];
    let mut offset = 0u64;
    let mut events = Vec::new();
    while !deadline.reached() {
        match link.read(&mut buf, deadline.left(Duration::from_millis(100)))? {
            Input::Data(n) => {
                decoder.feed(&buf[..n], offset, &mut events);
                offset += n as u64;
                if link.is_datagram() {
                    decoder.end_of_datagram(offset, &mut events);
                }
            }
            Input::Idle => continue,
            Input::End => break,
        }
        if !events.is_empty() {
            emit(&events)?;
            events.clear();
        }
    }
    decoder.finish(offset, &mut events);
    emit(&events)?;
    Ok(offset)
}
