//! `protolink aydp`: read and write an AYDP device's system values, store its configuration and
//! drive its outputs.
//!
//! AYDP has no acknowledgement, so every command that changes something is checked by reading
//! the value back (request data, answered by a system value update), unless `--no-verify`.
//! Requests go out as expedited messages in the `Spec` profile, like the document's examples, and as normal
//! messages (22-byte header) in the `Reference` profile, which has no expedited form. Other traffic from the
//! device (heartbeats, positions) is skipped while waiting.

use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use aydp_proto::{
    Decode, Decoder, DirectOutputBuilder, Encoder, Message, OutputEntry, Payload, Profile,
    SystemControl, SystemValueUpdate, Timestamp, UpdateMode,
};
use clap::{Args, Subcommand};
use serde_json::Value;

use crate::decoders::AYDP_CAPACITY;
use crate::endpoint::{Endpoint, Input, Link};
use crate::error::{Error, Result};
use crate::progress::Spinner;
use crate::proto::ProfileArg;
use crate::render::{Out, hex};
use crate::value_type::ValueType;

/// Address of "enable direct control" (DECISIONS.md Y9).
pub(crate) const DIRECT_CONTROL: u16 = 0x0000;

/// Arguments of `protolink aydp`.
#[derive(Debug, Clone, Args)]
pub(crate) struct AydpArgs {
    /// The device (serial:PATH@BAUD, tcp:HOST:PORT, udp:PORT, -).
    #[arg(long, value_name = "ENDPOINT")]
    pub(crate) to: Endpoint,
    /// AYDP profile of the device.
    #[arg(long, value_enum, default_value_t = ProfileArg::Spec)]
    pub(crate) profile: ProfileArg,
    /// How long to wait for each reply: `2000` (ms), `2s`, `500ms` (1 ms to 1 h).
    #[arg(long, visible_alias = "timeout", value_name = "DURATION", default_value = "2000",
          value_parser = crate::args::timeout_ms)]
    pub(crate) timeout_ms: Duration,
    /// Do not read values back after changing them.
    #[arg(long)]
    pub(crate) no_verify: bool,
    /// What to do.
    #[command(subcommand)]
    pub(crate) action: AydpAction,
}

/// The AYDP actions.
#[derive(Debug, Clone, Subcommand)]
pub(crate) enum AydpAction {
    /// Read a system value (request data).
    #[command(
        after_help = "Example:\n  protolink aydp --to tcp:127.0.0.1:7001 get 0x0001 --as char[40]"
    )]
    Get {
        /// Address (decimal or 0x hex).
        #[arg(value_parser = parse_address)]
        address: u16,
        /// The value's type: u8, u16, u32, i32, f32, f64, `char[N]`, or an array such as `f32[3]`.
        /// Without it the bytes are printed in hex.
        #[arg(long = "as", value_name = "TYPE")]
        value_type: Option<ValueType>,
    },
    /// Write a system value: single (`ADDR VALUE`), whole array (`ADDR V1,V2,V3` with an array
    /// type) or one element (`ADDR[INDEX] VALUE`).
    #[command(after_help = "Examples:\n  \
        protolink aydp --to tcp:127.0.0.1:7001 set 0x0110 64.5 --as f32\n  \
        protolink aydp --to tcp:127.0.0.1:7001 set 0x0100 7,5,92,829,1000,1000 --as u32[6]\n  \
        protolink aydp --to tcp:127.0.0.1:7001 set 0x0100[1] 6 --as u32[6]")]
    Set {
        /// Address, with `[INDEX]` for the element form.
        #[arg(value_name = "ADDR[INDEX]", value_parser = parse_target)]
        target: Target,
        /// The value (comma-separated for a whole array).
        #[arg(allow_hyphen_values = true)]
        value: String,
        /// The value's type.
        #[arg(long = "as", value_name = "TYPE")]
        value_type: ValueType,
    },
    /// Store the configuration in the device's non-volatile memory (unconfirmed: AYDP has no
    /// acknowledgement; --verify reads the box's store counters).
    #[command(after_help = "Examples:\n  \
        protolink aydp --to tcp:127.0.0.1:7001 store\n  \
        protolink aydp --to tcp:127.0.0.1:7001 store --verify")]
    Store {
        /// Confirm the outcome by reading the box's store counters before and after (this
        /// project's sensor box: `u32[5]` at --counters: written, unchanged, failed, refused in
        /// flight, refused by the rate limit).
        #[arg(long)]
        verify: bool,
        /// Where the store counters are, for --verify.
        #[arg(long, value_name = "ADDR", default_value = "0x0310", value_parser = parse_address)]
        counters: u16,
    },
    /// Set outputs directly (direct output control).
    #[command(
        after_help = "Example:\n  protolink aydp --to tcp:127.0.0.1:7001 output 1:2=10.0 1:3=-5 --enable --verify"
    )]
    Output {
        /// Outputs as DEVICE:CHANNEL=VALUE.
        #[arg(required = true, value_name = "DEV:CH=VALUE", value_parser = parse_output)]
        outputs: Vec<OutputEntry>,
        /// Enable direct control (address 0x0000 = 1) first.
        #[arg(long)]
        enable: bool,
        /// Confirm the outcome by reading the box's link counters before and after (this
        /// project's sensor box: `u32[10]` at --counters, element 8 applied, 9 refused).
        #[arg(long)]
        verify: bool,
        /// Where the link counters are, for --verify.
        #[arg(long, value_name = "ADDR", default_value = "0x0300", value_parser = parse_address)]
        counters: u16,
    },
}

/// An address, and an element index for the element form.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Target {
    /// The address.
    pub(crate) address: u16,
    /// The element, for `ADDR[INDEX]`.
    pub(crate) index: Option<u32>,
}

/// Parses an address: decimal or `0x` hex, 0..=0xFFFF.
///
/// # Errors
/// A sentence when the text is not an address.
pub(crate) fn parse_address(text: &str) -> std::result::Result<u16, String> {
    let parsed = match text.strip_prefix("0x").or_else(|| text.strip_prefix("0X")) {
        Some(hex) => u16::from_str_radix(hex, 16),
        None => text.parse::<u16>(),
    };
    parsed.map_err(|_| format!("'{text}' is not an address (0..=65535, or 0x0000..=0xFFFF)"))
}

/// Parses `ADDR` or `ADDR[INDEX]`.
///
/// # Errors
/// A sentence when the text is neither form.
pub(crate) fn parse_target(text: &str) -> std::result::Result<Target, String> {
    match text.strip_suffix(']').and_then(|t| t.split_once('[')) {
        Some((addr, index)) => Ok(Target {
            address: parse_address(addr)?,
            index: Some(
                index
                    .parse::<u32>()
                    .map_err(|_| format!("'{index}' is not an element index"))?,
            ),
        }),
        None => Ok(Target {
            address: parse_address(text)?,
            index: None,
        }),
    }
}

/// Parses `DEVICE:CHANNEL=VALUE`.
///
/// # Errors
/// A sentence when the text is not that form.
pub(crate) fn parse_output(text: &str) -> std::result::Result<OutputEntry, String> {
    let bad = || format!("'{text}' is not DEVICE:CHANNEL=VALUE (e.g. 1:2=10.0)");
    let (dc, value) = text.split_once('=').ok_or_else(bad)?;
    let (device, channel) = dc.split_once(':').ok_or_else(bad)?;
    Ok(OutputEntry {
        device: device.trim().parse().map_err(|_| bad())?,
        channel: channel.trim().parse().map_err(|_| bad())?,
        value: crate::args::finite(value.trim())
            .map_err(|_| format!("'{text}': the value must be a finite number"))?,
    })
}

/// One request as it goes on the wire. The `Spec` profile sends it expedited, like the
/// document's examples; the `Reference` profile has no expedited form (the AYDP reference
/// software reads every frame with the 22-byte header), so there it is a normal message
/// stamped with `now` (seconds and microseconds since 1970).
///
/// # Errors
/// The payload does not encode.
pub(crate) fn request<P: Payload + ?Sized>(
    encoder: &Encoder,
    payload: &P,
    now: SystemTime,
) -> Result<Vec<u8>> {
    let expedited = encoder.profile() == Profile::Spec;
    let mut buf = vec![0u8; encoder.frame_len(payload, expedited)];
    let since = now.duration_since(UNIX_EPOCH).unwrap_or_default();
    let stamp = (!expedited).then(|| Timestamp {
        seconds: i64::try_from(since.as_secs()).unwrap_or(i64::MAX),
        subsec: i64::from(since.subsec_micros()),
    });
    let n = encoder
        .encode(payload, stamp, &mut buf)
        .map_err(|source| Error::Aydp {
            what: "encoding the request".into(),
            source,
        })?;
    buf.truncate(n);
    Ok(buf)
}

/// A system value as the device reported it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Reading {
    /// The address.
    pub(crate) address: u16,
    /// The update mode of the reply.
    pub(crate) mode: UpdateMode,
    /// The value bytes.
    pub(crate) data: Vec<u8>,
}

/// An AYDP conversation with one device.
#[derive(Debug)]
pub(crate) struct Session {
    link: Link,
    encoder: Encoder,
    decoder: Box<Decoder<AYDP_CAPACITY>>,
    timeout: Duration,
    /// Messages received that were not the awaited reply (heartbeats, positions...).
    pub(crate) skipped: u32,
}

impl Session {
    /// Opens `endpoint` for `profile`, waiting `timeout` for each reply.
    ///
    /// # Errors
    /// Opening the endpoint.
    pub(crate) fn open(
        endpoint: &Endpoint,
        profile: ProfileArg,
        timeout: Duration,
    ) -> Result<Self> {
        Ok(Session {
            link: endpoint.open()?,
            encoder: Encoder::new(profile.into()),
            decoder: Box::new(Decoder::new(profile.into())),
            timeout,
            skipped: 0,
        })
    }

    /// Sends one expedited message.
    ///
    /// # Errors
    /// Encoding or writing.
    pub(crate) fn send<P: Payload + ?Sized>(&mut self, payload: &P) -> Result<()> {
        let frame = request(&self.encoder, payload, SystemTime::now())?;
        self.link.write_all(&frame)
    }

    /// Requests the value at `address` and waits for the system value update that answers it.
    ///
    /// # Errors
    /// [`Error::Timeout`] when no answer comes, or a read error.
    pub(crate) fn read(&mut self, address: u16) -> Result<Reading> {
        self.send(&SystemControl::RequestData { address })?;
        let what = format!("request data for address {address:#06x}");
        let _spinner = Spinner::start(&format!("waiting for the answer to {what}"));
        let started = Instant::now();
        let mut buf = vec![0u8; 65_536];
        loop {
            let left = self.timeout.saturating_sub(started.elapsed());
            if left.is_zero() {
                return Err(Error::Timeout {
                    what: format!(
                        "{what} from {} (is the address in its registry?)",
                        self.link.name()
                    ),
                    ms: self.timeout.as_millis() as u64,
                });
            }
            match self
                .link
                .read(&mut buf, left.min(Duration::from_millis(50)))?
            {
                Input::Data(n) => {
                    if let Some(r) = self.scan(&buf[..n], address) {
                        return Ok(r);
                    }
                }
                Input::Idle => {}
                Input::End => {
                    return Err(Error::Device(format!(
                        "{} closed the connection while waiting for the answer to {what}",
                        self.link.name()
                    )));
                }
            }
        }
    }

    /// Reads the direct-output counters (applied, refused) from the link counters at
    /// `address` (u32 elements 8 and 9, little-endian).
    ///
    /// # Errors
    /// No answer, or an answer too short to hold them.
    pub(crate) fn output_counters(&mut self, address: u16) -> Result<(u32, u32)> {
        let r = self.read(address)?;
        let word = |i: usize| {
            r.data
                .get(i * 4..i * 4 + 4)
                .and_then(|b| b.try_into().ok())
                .map(u32::from_le_bytes)
        };
        match (word(8), word(9)) {
            (Some(applied), Some(refused)) => Ok((applied, refused)),
            _ => Err(Error::Device(format!(
                "the counters at {address:#06x} are {} bytes, too short for --verify (40 needed)",
                r.data.len()
            ))),
        }
    }

    /// Reads the box's store counters (written, unchanged, failed, refused in flight,
    /// refused by the rate limit) at `address` (`u32[5]`, little-endian).
    ///
    /// # Errors
    /// No answer, or an answer too short to hold them.
    pub(crate) fn store_counters(&mut self, address: u16) -> Result<[u32; 5]> {
        let r = self.read(address)?;
        let mut out = [0u32; 5];
        for (i, slot) in out.iter_mut().enumerate() {
            *slot = r
                .data
                .get(i * 4..i * 4 + 4)
                .and_then(|b| b.try_into().ok())
                .map(u32::from_le_bytes)
                .ok_or_else(|| {
                    Error::Device(format!(
                        "the store counters at {address:#06x} are {} bytes, too short for \
                         --verify (20 needed)",
                        r.data.len()
                    ))
                })?;
        }
        Ok(out)
    }

    fn scan(&mut self, bytes: &[u8], address: u16) -> Option<Reading> {
        let mut found = None;
        let mut skipped = 0u32;
        self.decoder.feed(bytes, |ev| {
            let Ok(frame) = ev else { return };
            match frame.message() {
                Ok(Message::SystemValueUpdate(u)) if u.address == address && found.is_none() => {
                    found = Some(Reading {
                        address,
                        mode: u.mode,
                        data: u.data.to_vec(),
                    });
                }
                _ => skipped += 1,
            }
        });
        self.skipped = self.skipped.wrapping_add(skipped);
        found
    }
}

fn describe(reading: &Reading, value_type: Option<ValueType>) -> Result<(String, Value)> {
    match value_type {
        Some(t) => {
            let v = t.decode(&reading.data).map_err(|e| {
                Error::Device(format!(
                    "the answer for {:#06x} does not fit: {e}",
                    reading.address
                ))
            })?;
            Ok((format!("{:#06x} {t} = {}", reading.address, show(&v)), v))
        }
        None => {
            let mode = match reading.mode {
                UpdateMode::Single => "single".to_string(),
                UpdateMode::Array { count } => format!("array of {count}"),
                UpdateMode::Element { index } => format!("element {index}"),
            };
            let text = format!(
                "{:#06x} = {} ({} bytes, {mode})",
                reading.address,
                hex(&reading.data),
                reading.data.len()
            );
            Ok((text, Value::String(hex(&reading.data))))
        }
    }
}

fn show(v: &Value) -> String {
    match v {
        Value::String(s) => format!("{s:?}"),
        Value::Array(items) => format!(
            "[{}]",
            items.iter().map(show).collect::<Vec<_>>().join(", ")
        ),
        other => other.to_string(),
    }
}

fn usage(e: String) -> Error {
    Error::Usage(e)
}

/// Runs `protolink aydp`.
///
/// # Errors
/// Opening the endpoint, a bad value, a timeout, or a value the device did not take.
pub(crate) fn run(args: &AydpArgs) -> Result<()> {
    let mut s = Session::open(&args.to, args.profile, args.timeout_ms)?;
    let check = !args.no_verify;
    let lines = match &args.action {
        AydpAction::Get {
            address,
            value_type,
        } => vec![describe(&s.read(*address)?, *value_type)?.0],
        AydpAction::Set {
            target,
            value,
            value_type,
        } => vec![set(&mut s, target, value, *value_type, check)?],
        AydpAction::Store { verify, counters } => {
            vec![store(&mut s, check, verify.then_some(*counters))?]
        }
        AydpAction::Output {
            outputs,
            enable,
            verify,
            counters,
        } => {
            let outcome = output(&mut s, outputs, *enable, check, verify.then_some(*counters))?;
            outputs
                .iter()
                .map(|e| format!("output {}:{} = {}: {outcome}", e.device, e.channel, e.value))
                .collect()
        }
    };
    let mut out = Out::beside(&args.to);
    for line in &lines {
        out.line(line)?;
    }
    out.flush()
}

/// `set`: one value, one element or a whole array; read back unless `check` is off.
fn set(
    s: &mut Session,
    target: &Target,
    value: &str,
    value_type: ValueType,
    check: bool,
) -> Result<String> {
    let (mode, data) = match target.index {
        Some(index) => (
            UpdateMode::Element { index },
            value_type.element().encode(value).map_err(usage)?,
        ),
        None => {
            let data = value_type.encode(value).map_err(usage)?;
            let mode = match value_type {
                ValueType::Array(_, n) => UpdateMode::Array { count: n as u32 },
                _ => UpdateMode::Single,
            };
            (mode, data)
        }
    };
    s.send(&SystemValueUpdate {
        address: target.address,
        mode,
        data: &data,
    })?;
    if !check {
        return Ok(format!(
            "{:#06x} set: unconfirmed (--no-verify: not read back)",
            target.address
        ));
    }
    let reading = s.read(target.address)?;
    verify(&reading, target, value_type, &data)?;
    let line = describe(&reading, Some(value_type))?.0;
    Ok(format!("{line}: confirmed (read back)"))
}

/// `store`: AYDP has no acknowledgement. With the box's store counters at `counters`, their
/// change says what became of it; else, unless `check` is off, a request answered after the
/// store shows that the device is alive and has read the store before it.
fn store(s: &mut Session, check: bool, counters: Option<u16>) -> Result<String> {
    let before = counters.map(|c| s.store_counters(c)).transpose()?;
    s.send(&SystemControl::StoreConfiguration)?;
    if let (Some(before), Some(address)) = (before, counters) {
        // The box writes its flash after the poll that received the store, so a request
        // answered in that same poll could still see the counters from before: a first
        // request, answered, shows the store received; the counters read after it are the
        // ones after the write.
        s.read(DIRECT_CONTROL)?;
        return stored(&before, &s.store_counters(address)?);
    }
    if !check {
        return Ok("store configuration: unconfirmed (AYDP has no acknowledgement)".into());
    }
    s.read(DIRECT_CONTROL)?;
    Ok(
        "store configuration: unconfirmed (AYDP has no acknowledgement; the device \
         answered a request sent after it, so it received the store; --verify reads the box's \
         store counters)"
            .into(),
    )
}

/// What became of a store, from the box's store counters before and after it (written,
/// unchanged, failed, refused in flight, refused by the rate limit): confirmed when the
/// written or the unchanged one moved, refused or failed (an error) when another did,
/// unconfirmed (an error too: the box did not count it) when none did.
///
/// # Errors
/// [`Error::Refused`] when the box refused the store or its flash write failed, or counted
/// nothing.
pub(crate) fn stored(before: &[u32; 5], after: &[u32; 5]) -> Result<String> {
    let moved = |i: usize| after[i] != before[i];
    if moved(3) {
        return Err(Error::Refused(
            "the box refused to store its configuration: it is flying".into(),
        ));
    }
    if moved(4) {
        return Err(Error::Refused(
            "the box refused to store its configuration: too soon after the last stores \
             (its rate limit)"
                .into(),
        ));
    }
    if moved(2) {
        return Err(Error::Refused(
            "the box could not store its configuration: its flash write failed".into(),
        ));
    }
    if moved(0) {
        return Ok(format!(
            "store configuration: confirmed (written; the box's written counter went from {} to {})",
            before[0], after[0]
        ));
    }
    if moved(1) {
        return Ok(
            "store configuration: confirmed (unchanged: the flash already held this \
             configuration, nothing written)"
                .into(),
        );
    }
    Err(Error::Refused(
        "the box's store counters did not change: the store was not received or not acted on"
            .into(),
    ))
}

/// `output`: direct control on (with `enable`) and checked (unless `check` is off), the
/// outputs sent, and, with the box's counters at `counters`, whether it applied them.
/// Returns the outcome every output's line ends with.
fn output(
    s: &mut Session,
    outputs: &[OutputEntry],
    enable: bool,
    check: bool,
    counters: Option<u16>,
) -> Result<String> {
    if enable {
        s.send(&SystemValueUpdate {
            address: DIRECT_CONTROL,
            mode: UpdateMode::Single,
            data: &[1],
        })?;
    }
    if check {
        check_direct_control(s, enable)?;
    }
    let before = counters.map(|c| s.output_counters(c)).transpose()?;
    let mut buf = vec![0u8; 2 + outputs.len() * OutputEntry::LEN];
    let mut builder = DirectOutputBuilder::new(&mut buf);
    for e in outputs {
        builder.push(*e).map_err(|source| Error::Aydp {
            what: "building the output message".into(),
            source,
        })?;
    }
    let message = builder.finish();
    s.send(&message)?;
    match (before, counters) {
        (Some(before), Some(address)) => applied(before, s.output_counters(address)?),
        _ => Ok(
            "unconfirmed (AYDP has no acknowledgement; --verify reads the box's \
                 counters)"
                .to_string(),
        ),
    }
}

/// Direct control (0x0000) must read 1 before outputs are sent.
fn check_direct_control(s: &mut Session, enabled: bool) -> Result<()> {
    let r = s.read(DIRECT_CONTROL)?;
    if r.data == [1] {
        return Ok(());
    }
    Err(Error::Refused(if enabled {
        format!(
            "the device refused to enable direct control: 0x0000 reads {}",
            hex(&r.data)
        )
    } else {
        format!(
            "the device refuses direct outputs: direct control is off (0x0000 = \
             {}); pass --enable to turn it on",
            hex(&r.data)
        )
    }))
}

/// The box's (applied, refused) counters before and after the outputs: confirmed when only
/// the applied one moved.
fn applied(before: (u32, u32), after: (u32, u32)) -> Result<String> {
    if after.1 != before.1 {
        return Err(Error::Refused(format!(
            "the device refused the outputs (its direct-refused counter went \
             from {} to {}): an unknown device or channel, or direct control off",
            before.1, after.1
        )));
    }
    if after.0 == before.0 {
        return Err(Error::Refused(format!(
            "the device refused the outputs: its direct-applied counter stayed \
             at {}",
            after.0
        )));
    }
    Ok(format!(
        "confirmed (the direct-applied counter went from {} to {})",
        before.0, after.0
    ))
}

fn verify(reading: &Reading, target: &Target, value_type: ValueType, sent: &[u8]) -> Result<()> {
    let got: &[u8] = match (target.index, value_type) {
        (Some(i), _) => {
            let size = value_type.element().size();
            let start = i as usize * size;
            reading.data.get(start..start + size).unwrap_or(&[])
        }
        (None, ValueType::Chars(_)) => {
            let end = reading
                .data
                .iter()
                .position(|&b| b == 0)
                .unwrap_or(reading.data.len());
            &reading.data[..end]
        }
        (None, _) => &reading.data,
    };
    if got == sent {
        Ok(())
    } else {
        let now = describe(reading, Some(value_type))
            .map(|d| d.0)
            .unwrap_or_else(|_| hex(&reading.data));
        Err(Error::Refused(format!(
            "the device did not take the value (read back: {now}); the address may be read-only, \
             or the value out of range or of another type"
        )))
    }
}

/// The examples of this module's items, as tests (the items are crate-private, so rustdoc
/// does not run them).
#[cfg(test)]
#[allow(unused_imports, clippy::unnecessary_wraps)]
mod examples {
    use super::*;

    #[test]
    fn parse_address_example() -> Result<(), Box<dyn std::error::Error>> {
        assert_eq!(parse_address("0x0100"), Ok(256));
        assert_eq!(parse_address("8"), Ok(8));
        assert!(parse_address("0x10000").is_err());
        Ok(())
    }

    #[test]
    fn parse_target_example() -> Result<(), Box<dyn std::error::Error>> {
        assert_eq!(
            parse_target("0x0101[2]"),
            Ok(Target {
                address: 0x101,
                index: Some(2)
            })
        );
        assert_eq!(
            parse_target("5"),
            Ok(Target {
                address: 5,
                index: None
            })
        );
        Ok(())
    }

    #[test]
    fn parse_output_example() -> Result<(), Box<dyn std::error::Error>> {
        use aydp_proto::OutputEntry;
        assert_eq!(
            parse_output("1:2=10.0"),
            Ok(OutputEntry {
                device: 1,
                channel: 2,
                value: 10.0
            })
        );
        assert!(parse_output("1=10").is_err());
        assert!(parse_output("1:2=nan").is_err());
        Ok(())
    }

    #[test]
    fn request_example() -> Result<(), Box<dyn std::error::Error>> {
        use aydp_proto::{Encoder, Profile, SystemControl};
        use std::time::{Duration, UNIX_EPOCH};
        let now = UNIX_EPOCH + Duration::from_micros(1_700_000_000_250_000);
        let store = SystemControl::StoreConfiguration;
        let spec = request(&Encoder::new(Profile::Spec), &store, now)?;
        assert_eq!(spec, [0xFF, 0x89, 0x08, 0, 0, 0, 0x02, 0x7C]);
        let reference = request(&Encoder::new(Profile::Reference), &store, now)?;
        assert_eq!(reference.len(), 22 + 1 + 1);
        assert_eq!(&reference[..6], &[0xFF, 0x09, 1, 0, 0, 0]); // type 9, 1 data byte
        assert_eq!(
            i64::from_le_bytes(reference[6..14].try_into()?),
            1_700_000_000
        );
        assert_eq!(i64::from_le_bytes(reference[14..22].try_into()?), 250_000);
        Ok(())
    }

    #[test]
    fn stored_example() -> Result<(), Box<dyn std::error::Error>> {
        assert!(
            stored(&[3, 0, 0, 0, 0], &[4, 0, 0, 0, 0])
                .unwrap()
                .contains("confirmed")
        );
        assert!(stored(&[3, 0, 0, 0, 0], &[3, 0, 0, 1, 0]).is_err()); // refused: flying
        Ok(())
    }
}
