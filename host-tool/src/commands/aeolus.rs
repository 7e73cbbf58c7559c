//! `protolink aeolus`: send a COMMAND or a SETTIME to an AEOLUS box, and wait for its answer.
//!
//! The box listens on UDP port 5002 in the field (`--to udp:127.0.0.1:5002` sends a datagram
//! there) or on its UART (`--to tcp:127.0.0.1:7000` for the QEMU firmware, `--to serial:...`).
//! Its answers are TOASTs in its telemetry: on the same link for a UART, on `--from` (its
//! telemetry port, `udp:5001`) for UDP. The outcome is one of three:
//!
//! - **confirmed**: a TOAST answered (`AEOLUS paused`, ...);
//! - **refused**: the TOAST says `unknown command: ...` (exit status 1);
//! - **unconfirmed**: no answer can come (UDP without `--from`; SETTIME, which the spec gives
//!   no answer), or none came within the timeout.

use std::net::{SocketAddr, UdpSocket};
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use aeolus_proto::message::{Message, SetTime, Text};
use aeolus_proto::{CrcMode, Decode};
use clap::{Args, Subcommand};

use crate::decoders::AEOLUS_CAPACITY;
use crate::endpoint::udp_out::bind_for;
use crate::endpoint::{Endpoint, Input, Link};
use crate::error::{Error, Result};
use crate::progress::Spinner;
use crate::render::{Out, escape_text};

/// Arguments of `protolink aeolus`.
#[derive(Debug, Clone, Args)]
pub(crate) struct AeolusArgs {
    /// The box: `udp:ADDR:PORT` sends a datagram to its command port (5002), `tcp:` or
    /// `serial:` writes to its UART.
    #[arg(long, value_name = "ENDPOINT")]
    pub(crate) to: Endpoint,
    /// Where its answers arrive, if not on the `--to` link: its telemetry port, e.g. `udp:5001`.
    #[arg(long, value_name = "ENDPOINT")]
    pub(crate) from: Option<Endpoint>,
    /// How long to wait for the answer: `2000` (ms), `2s` (1 ms to 1 h).
    #[arg(long, visible_alias = "timeout", value_name = "DURATION", default_value = "2000",
          value_parser = crate::args::timeout_ms)]
    pub(crate) timeout_ms: Duration,
    /// What to send.
    #[command(subcommand)]
    pub(crate) action: AeolusAction,
}

/// The AEOLUS actions.
#[derive(Debug, Clone, Subcommand)]
pub(crate) enum AeolusAction {
    /// Send a COMMAND text (the box knows `a pause`, `a resume`, `a reboot`).
    #[command(after_help = "Examples:
  protolink aeolus --to udp:127.0.0.1:5002 --from udp:5001 command \"a pause\"
  protolink aeolus --to tcp:127.0.0.1:7000 command \"a resume\"")]
    Command {
        /// The text, at most 255 bytes.
        text: String,
    },
    /// Set the box's clock (UTC): `now` (the default) or `YYYY-MM-DDTHH:MM:SS`.
    #[command(after_help = "Examples:
  protolink aeolus --to udp:127.0.0.1:5002 settime
  protolink aeolus --to tcp:127.0.0.1:7000 settime 2026-11-23T09:30:00")]
    Settime {
        /// `now`, or a UTC time as `YYYY-MM-DDTHH:MM:SS` (years 1900 to 2155).
        #[arg(default_value = "now", value_parser = parse_time)]
        when: SetTime,
    },
}

/// Parses `now` or `YYYY-MM-DDTHH:MM:SS` (UTC) into a SETTIME.
///
/// # Errors
/// A sentence when the text is neither form or a field is out of range.
pub(crate) fn parse_time(text: &str) -> std::result::Result<SetTime, String> {
    if text == "now" {
        let secs = SystemTime::now()
            .duration_since(UNIX_EPOCH)
            .map_err(|_| "the system clock is before 1970".to_string())?
            .as_secs();
        return from_unix(secs);
    }
    let bad = || format!("'{text}' is not now or a UTC time YYYY-MM-DDTHH:MM:SS");
    let (date, time) = text.split_once('T').ok_or_else(bad)?;
    let d: Vec<&str> = date.split('-').collect();
    let t: Vec<&str> = time.split(':').collect();
    let [y, mo, da] = d.as_slice() else {
        return Err(bad());
    };
    let [h, mi, s] = t.as_slice() else {
        return Err(bad());
    };
    let num = |x: &str, lo: u32, hi: u32| {
        x.parse::<u32>()
            .ok()
            .filter(|v| (lo..=hi).contains(v))
            .ok_or_else(|| format!("'{text}': '{x}' is out of range {lo}..={hi}"))
    };
    let year = num(y, 1900, 2155)?;
    Ok(SetTime {
        year_since_1900: (year - 1900) as u8,
        month0: (num(mo, 1, 12)? - 1) as u8,
        day: num(da, 1, 31)? as u8,
        hour: num(h, 0, 23)? as u8,
        minute: num(mi, 0, 59)? as u8,
        second: num(s, 0, 59)? as u8,
    })
}

/// Seconds since 1970 (UTC) as a SETTIME, by the days-from-civil calendar.
fn from_unix(secs: u64) -> std::result::Result<SetTime, String> {
    let days = secs / 86_400;
    let rem = secs % 86_400;
    let (year, month, day) = crate::civil::date_of(days as i64);
    let year_since_1900 = u8::try_from(year - 1900)
        .map_err(|_| format!("the year {year} does not fit SETTIME (1900 to 2155)"))?;
    Ok(SetTime {
        year_since_1900,
        month0: (month - 1) as u8,
        day: day as u8,
        hour: (rem / 3600) as u8,
        minute: (rem / 60 % 60) as u8,
        second: (rem % 60) as u8,
    })
}

/// Where a command goes: a datagram to the box's port, or the box's UART.
enum Target {
    Datagram { socket: UdpSocket, to: SocketAddr },
    Uart(Link),
}

/// Runs `protolink aeolus`.
///
/// # Errors
/// Opening an endpoint, sending, or a refusal by the box.
pub(crate) fn run(args: &AeolusArgs) -> Result<()> {
    let (message_name, message) = match &args.action {
        AeolusAction::Command { text } => {
            let t = Text::new(text).map_err(|_| {
                Error::Usage(format!(
                    "the command text is {} bytes, and COMMAND holds at most 255",
                    text.len()
                ))
            })?;
            (
                format!("COMMAND \"{}\"", escape_text(text.as_bytes())),
                Message::Command(t),
            )
        }
        AeolusAction::Settime { when } => (
            format!(
                "SETTIME {:04}-{:02}-{:02}T{:02}:{:02}:{:02}",
                1900 + u32::from(when.year_since_1900),
                when.month0 + 1,
                when.day,
                when.hour,
                when.minute,
                when.second
            ),
            Message::SetTime(*when),
        ),
    };
    let mut frame = vec![0u8; aeolus_proto::max_encoded_len(512)];
    let n = message
        .encode(&mut frame, CrcMode::Compute)
        .map_err(|e| Error::Usage(format!("{message_name} cannot be encoded: {e}")))?;
    frame.truncate(n);

    // Listen before sending, so an answer is never missed.
    let mut answers = match &args.from {
        Some(from) => Some(from.open()?),
        None => None,
    };
    let mut target = match &args.to {
        Endpoint::Udp(to) => Target::Datagram {
            socket: bind_for(*to, false)?,
            to: *to,
        },
        other => Target::Uart(other.open()?),
    };
    match &mut target {
        Target::Datagram { socket, to } => {
            socket.send_to(&frame, *to).map_err(|source| Error::Io {
                what: format!("sending {message_name} to {to}"),
                source,
            })?;
        }
        Target::Uart(link) => link.write_all(&frame)?,
    }
    let link = match (&mut answers, &mut target) {
        (Some(link), _) | (None, Target::Uart(link)) => Some(link),
        (None, Target::Datagram { .. }) => None,
    };
    let mut out = Out::beside(&args.to);
    let outcome = match (link, &args.action) {
        (_, AeolusAction::Settime { .. }) => {
            "unconfirmed (AEOLUS defines no answer to SETTIME)".to_string()
        }
        (None, _) => "unconfirmed (no --from to hear the box's answer on)".to_string(),
        (Some(link), AeolusAction::Command { .. }) => {
            match wait_for_toast(link, args.timeout_ms, &message_name)? {
                Some(toast) if toast.starts_with("unknown command") => {
                    return Err(Error::Refused(format!(
                        "the box refused {message_name}: TOAST \"{toast}\""
                    )));
                }
                Some(toast) => format!("confirmed (TOAST \"{toast}\")"),
                None => format!(
                    "unconfirmed (no TOAST within {})",
                    crate::args::show(args.timeout_ms)
                ),
            }
        }
    };
    out.line(&format!("{message_name}: {outcome}"))?;
    out.flush()
}

/// Reads `link` for up to `timeout` and returns the first TOAST's text (escaped).
fn wait_for_toast(link: &mut Link, timeout: Duration, what: &str) -> Result<Option<String>> {
    let _spinner = Spinner::start(&format!("waiting for the answer to {what}"));
    let started = Instant::now();
    let mut decoder = Box::new(aeolus_proto::Decoder::<AEOLUS_CAPACITY>::new());
    let mut buf = vec![0u8; 65_536];
    while let Some(left) = timeout.checked_sub(started.elapsed()) {
        match link.read(&mut buf, left.min(Duration::from_millis(50)))? {
            Input::Data(n) => {
                let mut toast = None;
                decoder.feed(buf.get(..n).unwrap_or(&[]), |ev| {
                    if let Ok(frame) = ev
                        && let Ok(Message::Toast(t)) = frame.message()
                    {
                        toast.get_or_insert_with(|| escape_text(t.as_bytes()));
                    }
                });
                if toast.is_some() {
                    return Ok(toast);
                }
                if link.is_datagram() {
                    decoder.reset();
                }
            }
            Input::Idle => {}
            Input::End => break,
        }
    }
    Ok(None)
}

/// The examples of this module's items, as tests (the items are crate-private, so rustdoc
/// does not run them).
#[cfg(test)]
#[allow(unused_imports, clippy::unnecessary_wraps)]
mod examples {
    use super::*;

    #[test]
    fn parse_time_example() -> Result<(), Box<dyn std::error::Error>> {
        let t = parse_time("2026-11-23T09:30:05").unwrap();
        assert_eq!(
            (
                t.year_since_1900,
                t.month0,
                t.day,
                t.hour,
                t.minute,
                t.second
            ),
            (126, 10, 23, 9, 30, 5)
        );
        assert!(parse_time("2026-13-01T00:00:00").is_err());
        assert!(parse_time("now").is_ok());
        Ok(())
    }
}
