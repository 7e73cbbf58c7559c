//! `protolink decode`: one line per message (text or JSON), errors in the stream with their byte
//! offset, and the decoder's counters at the end.
//!
//! The offset of a message is the 0-based index of its first byte in the input: the opening
//! flag of an AEOLUS frame, the 0xFF start of an AYDP message, the first byte of an AOK frame,
//! also for messages a rescan found among bytes already held. `len` is its length on the wire,
//! so its bytes are `offset..offset + len`. An error is reported at the first byte of what it
//! condemns (an AEOLUS or GDL90 frame's opening flag, an AYDP candidate's 0xFF, an AOK frame's
//! first byte), its `len` those bytes' length on the wire.

#[cfg(feature = "cli")]
use std::time::Duration;

#[cfg(feature = "cli")]
use clap::Args;
#[cfg(feature = "cli")]
use serde_json::{Value, json};

pub mod capture;
#[cfg(all(feature = "cli", feature = "parquet"))]
pub(crate) mod export;
#[cfg(feature = "cli")]
pub mod plot;
pub mod tables;

#[cfg(feature = "cli")]
use crate::decoders::{Decoder, Event};
#[cfg(feature = "cli")]
use crate::endpoint::{Endpoint, Input, Link};
#[cfg(feature = "cli")]
use crate::error::Result;
#[cfg(feature = "cli")]
use crate::proto::{ProfileArg, Proto, Side};
#[cfg(feature = "cli")]
use crate::render::{self, Out};
#[cfg(feature = "cli")]
use crate::stop::Deadline;
#[cfg(feature = "cli")]
use tables::Select;

/// Arguments of `protolink decode`.
#[cfg(feature = "cli")]
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

#[cfg(feature = "cli")]
impl DecodeArgs {
    /// What decodes the input: `--proto`, `--profile` and `--side`.
    ///
    /// ```
    /// use protolink::commands::decode::DecodeArgs;
    /// use protolink::endpoint::Endpoint;
    /// use protolink::proto::{Proto, Side};
    /// let args = DecodeArgs {
    ///     proto: Some(Proto::Aok),
    ///     profile: None,
    ///     side: Side::Pc,
    ///     from: Endpoint::File("pc.bin".into()),
    ///     json: false,
    ///     udp_json: None,
    ///     seconds: None,
    /// };
    /// let select = args.select();
    /// assert_eq!((select.proto, select.side), (Some(Proto::Aok), Side::Pc));
    /// ```
    pub fn select(&self) -> Select {
        Select {
            proto: self.proto,
            profile: self.profile,
            side: self.side,
        }
    }
}

/// The summary line printed at the end.
#[cfg(feature = "cli")]
pub(crate) fn summary(bytes: u64, counters: &Value, json_out: bool) -> String {
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
#[cfg(feature = "cli")]
pub(crate) fn run(args: &DecodeArgs) -> Result<()> {
    // Ctrl-C ends the input: the counters are still printed.
    crate::stop::install_ctrl_c();
    let deadline = Deadline::after(args.seconds);
    if let Endpoint::File(path) = &args.from
        && crate::capture::file_is_capture(path)
    {
        return capture::run(path, args, deadline);
    }
    let Some(proto) = args.proto else {
        return Err(crate::error::Error::Usage(format!(
            "--proto is needed for {}: only a pcapng or pcap capture names its protocols",
            args.from
        )));
    };
    let mut link = args.from.open()?;
    let mut decoder = Decoder::new(proto, args.profile.unwrap_or_default(), args.side);
    let mut out = Out::new();
    let mut plot = args.udp_json.map(plot::PlotSender::new).transpose()?;
    let offset = pump(&mut link, &mut decoder, deadline, |events| {
        if let Some(p) = plot.as_mut() {
            p.send(proto, events, plot::now());
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
#[cfg(feature = "cli")]
pub(crate) fn pump(
    link: &mut Link,
    decoder: &mut Decoder,
    deadline: Deadline,
    mut emit: impl FnMut(&[Event]) -> Result<()>,
) -> Result<u64> {
    let mut buf = vec![0u8; 65_536];
    let mut offset = 0u64;
    let mut events = Vec::new();
    while !deadline.reached() {
        match link.read(&mut buf, deadline.left(Duration::from_millis(100)))? {
            Input::Data(n) => {
                decoder.feed(&buf[..n], offset, |p| events.push(p.to_event()));
                offset += n as u64;
                if link.is_datagram() {
                    decoder.end_of_datagram(|p| events.push(p.to_event()));
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
    decoder.finish(|p| events.push(p.to_event()));
    emit(&events)?;
    Ok(offset)
}
