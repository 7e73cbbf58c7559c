//! `protolink aok`: drive an AOK flight controller through the `aok-proto` client.
//!
//! The client switches debug output off and drains the line before every request that has a
//! reply, and switches it back on afterwards, so debug frames that arrive late never pass for a
//! reply (DECISIONS.md K6).

#[cfg(feature = "cli")]
use std::time::{Duration, Instant};

use aok_proto::{Action, ActionWord, FirmwareVersion, WaypointNumber, WaypointSlot};
#[cfg(feature = "cli")]
use aok_proto::{
    Client, Command, Config, ExternalControl, Motor, MotorTest, Outcome, Stick, Waypoint,
};
#[cfg(feature = "cli")]
use clap::{Args, Subcommand};

use crate::decoders::action_name;
#[cfg(feature = "cli")]
use crate::decoders::slot_name;
#[cfg(feature = "cli")]
use crate::endpoint::Endpoint;
#[cfg(feature = "cli")]
use crate::error::{Error, Result};
#[cfg(feature = "cli")]
use crate::nb_serial::NbSerial;
#[cfg(feature = "cli")]
use crate::progress::Spinner;
#[cfg(feature = "cli")]
use crate::render::Out;

/// Arguments of `protolink aok`.
#[cfg(feature = "cli")]
#[derive(Debug, Clone, Args)]
pub(crate) struct AokArgs {
    /// The device (serial:PATH@38400, tcp:HOST:PORT, udp:PORT, -).
    #[arg(long, value_name = "ENDPOINT")]
    pub(crate) to: Endpoint,
    /// The device's firmware version: <= 0.30 answers parameter reads without a header, bulk
    /// read needs >= 0.35.
    #[arg(long, value_name = "MAJOR.MINOR", default_value = "0.35", value_parser = parse_firmware)]
    pub(crate) firmware: FirmwareVersion,
    /// How long to wait for a reply: `2000` (ms), `2s`, `500ms` (1 ms to 1 h).
    #[arg(long, visible_alias = "timeout", value_name = "DURATION", default_value = "2000",
          value_parser = crate::args::timeout_ms)]
    pub(crate) timeout_ms: Duration,
    /// How long the line must stay quiet after debug-off before a request goes out: `50` (ms),
    /// `0.1s` (0 ms to 1 h).
    #[arg(long, value_name = "DURATION", default_value = "50", value_parser = crate::args::period_ms)]
    pub(crate) quiet_ms: Duration,
    /// The device is not sending debug values (skip the debug-off/on around requests).
    #[arg(long)]
    pub(crate) debug_is_off: bool,
    /// What to do.
    #[command(subcommand)]
    pub(crate) action: AokAction,
}

/// The AOK actions.
#[cfg(feature = "cli")]
#[derive(Debug, Clone, Subcommand)]
pub(crate) enum AokAction {
    /// Switch the debug value stream on or off.
    #[command(after_help = "Example:\n  protolink aok --to tcp:127.0.0.1:7002 debug off")]
    Debug {
        /// on or off.
        #[arg(value_parser = ["on", "off"])]
        state: String,
    },
    /// Read a parameter.
    #[command(after_help = "Example:\n  protolink aok --to tcp:127.0.0.1:7002 get 12")]
    Get {
        /// Parameter number.
        number: u8,
    },
    /// Set a parameter (in RAM) and wait for the ack.
    #[command(after_help = "Example:\n  protolink aok --to tcp:127.0.0.1:7002 set 12 1500")]
    Set {
        /// Parameter number.
        number: u8,
        /// The value.
        #[arg(allow_hyphen_values = true)]
        value: i32,
    },
    /// Read 16 parameters N..N+15 at once (firmware >= 0.35).
    #[command(after_help = "Example:\n  protolink aok --to tcp:127.0.0.1:7002 bulk 0")]
    Bulk {
        /// The first parameter number.
        first: u8,
    },
    /// Read or write a waypoint, the POIs or the FBC target.
    #[command(subcommand)]
    Waypoint(WaypointAction),
    /// Motor test: one value, sent twice 20 ms apart (the box runs a motor from its second
    /// frame), which lapses after 500 ms unless repeated (see --hold-ms).
    #[command(
        after_help = "Example:\n  protolink aok --to tcp:127.0.0.1:7002 motor 3 40 --hold-ms 2000"
    )]
    Motor {
        /// Motor 1..=12.
        #[arg(value_parser = parse_motor)]
        motor: Motor,
        /// Test value 0..=255.
        value: u8,
        /// Repeat the value every 200 ms for this long: `2000` (ms), `2s` (0 ms to 1 h).
        #[arg(long, value_name = "DURATION", value_parser = crate::args::period_ms)]
        hold_ms: Option<Duration>,
        /// Check the outcome in the debug values: flight status (86) and this project's
        /// motor-test mask (14).
        #[arg(long)]
        verify: bool,
    },
    /// External control: roll, nick, yaw (-200..=200) and the unused pitch field.
    #[command(
        name = "extern",
        after_help = "Example:\n  protolink aok --to tcp:127.0.0.1:7002 extern 32 -32 0 0 --expiry 500"
    )]
    Extern {
        /// Roll stick.
        #[arg(allow_hyphen_values = true, value_parser = parse_stick)]
        roll: Stick,
        /// Nick stick.
        #[arg(allow_hyphen_values = true, value_parser = parse_stick)]
        nick: Stick,
        /// Yaw stick.
        #[arg(allow_hyphen_values = true, value_parser = parse_stick)]
        yaw: Stick,
        /// Pitch (throttle) field, ignored by the device.
        #[arg(allow_hyphen_values = true)]
        pitch: i16,
        /// How long the values hold without a new frame, in ms.
        #[arg(long, value_name = "MS")]
        expiry: u16,
    },
    /// Save the parameters to flash set N.
    #[command(
        name = "save-set",
        after_help = "Example:\n  protolink aok --to tcp:127.0.0.1:7002 save-set 1"
    )]
    SaveSet {
        /// Set number.
        set: u8,
    },
    /// Load parameter set N from flash.
    #[command(
        name = "load-set",
        after_help = "Example:\n  protolink aok --to tcp:127.0.0.1:7002 load-set 1"
    )]
    LoadSet {
        /// Set number.
        set: u8,
    },
    /// Reset the device.
    #[command(after_help = "Example:\n  protolink aok --to tcp:127.0.0.1:7002 reset")]
    Reset,
}

/// The waypoint actions.
#[cfg(feature = "cli")]
#[derive(Debug, Clone, Subcommand)]
pub(crate) enum WaypointAction {
    /// Read a slot: 1..=31, poi (mission POI), ram-poi or fbc.
    #[command(after_help = "Example:\n  protolink aok --to tcp:127.0.0.1:7002 waypoint get 1")]
    Get {
        /// The slot.
        #[arg(value_parser = parse_slot)]
        slot: WaypointSlot,
    },
    /// Write a slot. Coordinates are raw i32 (the spec states no unit, so they are sent as given).
    #[command(
        after_help = "Example:\n  protolink aok --to tcp:127.0.0.1:7002 waypoint set 1 237512345 480012345 \
        --action1 hold-and-climb:15 --action2 set-fly-speed:250"
    )]
    Set {
        /// The slot.
        #[arg(value_parser = parse_slot)]
        slot: WaypointSlot,
        /// Longitude, raw.
        #[arg(allow_hyphen_values = true)]
        longitude: i32,
        /// Latitude, raw.
        #[arg(allow_hyphen_values = true)]
        latitude: i32,
        /// First action as ACTION:VALUE (none, pause, hold-and-climb, hold-and-sink,
        /// fly-and-climb, fly-and-sink, set-fly-speed).
        #[arg(long, value_name = "ACTION:VALUE", default_value = "none:0", value_parser = parse_action)]
        action1: ActionWord,
        /// Second action as ACTION:VALUE.
        #[arg(long, value_name = "ACTION:VALUE", default_value = "none:0", value_parser = parse_action)]
        action2: ActionWord,
    },
}

/// Parses `MAJOR.MINOR` (`0.35`).
///
/// ```
/// use aok_proto::FirmwareVersion;
/// assert_eq!(protolink::commands::aok::parse_firmware("0.30"), Ok(FirmwareVersion::new(0, 30)));
/// assert!(protolink::commands::aok::parse_firmware("35").is_err());
/// ```
///
/// # Errors
/// A sentence when the text is not a version.
pub fn parse_firmware(text: &str) -> std::result::Result<FirmwareVersion, String> {
    let bad = || format!("'{text}' is not a firmware version such as 0.35");
    let (major, minor) = text.split_once('.').ok_or_else(bad)?;
    Ok(FirmwareVersion::new(
        major.parse().map_err(|_| bad())?,
        minor.parse().map_err(|_| bad())?,
    ))
}

/// Parses a waypoint slot: `1`..`31`, `poi`, `ram-poi` or `fbc`.
///
/// ```
/// use aok_proto::WaypointSlot;
/// assert_eq!(protolink::commands::aok::parse_slot("fbc"), Ok(WaypointSlot::FbcTarget));
/// assert_eq!(protolink::commands::aok::parse_slot("1").map(|s| s.wire()), Ok(0));
/// assert!(protolink::commands::aok::parse_slot("32").is_err());
/// ```
///
/// # Errors
/// A sentence when the text names no slot.
pub fn parse_slot(text: &str) -> std::result::Result<WaypointSlot, String> {
    match text {
        "poi" => Ok(WaypointSlot::MissionPoi),
        "ram-poi" => Ok(WaypointSlot::RamPoi),
        "fbc" => Ok(WaypointSlot::FbcTarget),
        n => n
            .parse::<u8>()
            .ok()
            .and_then(|n| WaypointNumber::new(n).ok())
            .map(WaypointSlot::Waypoint)
            .ok_or_else(|| format!("'{text}' is not a slot: expected 1..=31, poi, ram-poi or fbc")),
    }
}

/// Parses `ACTION:VALUE` into an action word.
///
/// ```
/// use aok_proto::{Action, ActionWord};
/// assert_eq!(protolink::commands::aok::parse_action("pause:5"), Ok(ActionWord::new(Action::Pause, 5)));
/// assert!(protolink::commands::aok::parse_action("loop:1").is_err());
/// ```
///
/// # Errors
/// A sentence when the text names no action or the value is not an i16.
pub fn parse_action(text: &str) -> std::result::Result<ActionWord, String> {
    let (name, value) = text.split_once(':').unwrap_or((text, "0"));
    let action = Action::ALL
        .into_iter()
        .find(|a| action_name(ActionWord::new(*a, 0)).split(':').next() == Some(name))
        .ok_or_else(|| {
            format!(
                "'{name}' is not an action: expected none, pause, hold-and-climb, hold-and-sink, \
                 fly-and-climb, fly-and-sink or set-fly-speed"
            )
        })?;
    let value: i16 = value
        .parse()
        .map_err(|_| format!("'{value}' is not an action value (-32768..=32767)"))?;
    Ok(ActionWord::new(action, value))
}

/// Parses a motor number 1..=12.
///
/// # Errors
/// A sentence when out of range.
#[cfg(feature = "cli")]
pub(crate) fn parse_motor(text: &str) -> std::result::Result<Motor, String> {
    text.parse::<u8>()
        .ok()
        .and_then(|n| Motor::new(n).ok())
        .ok_or_else(|| format!("'{text}' is not a motor number (1..=12)"))
}

/// Parses a stick value -200..=200.
///
/// # Errors
/// A sentence when out of range.
#[cfg(feature = "cli")]
pub(crate) fn parse_stick(text: &str) -> std::result::Result<Stick, String> {
    text.parse::<i16>()
        .ok()
        .and_then(|v| Stick::new(v).ok())
        .ok_or_else(|| format!("'{text}' is not a stick value (-200..=200)"))
}

/// An AOK conversation over one endpoint.
#[cfg(feature = "cli")]
#[derive(Debug)]
pub(crate) struct Session {
    client: Client<NbSerial>,
    started: Instant,
    timeout_ms: u32,
}

#[cfg(feature = "cli")]
impl Session {
    /// Opens the endpoint and sets the client up from the arguments.
    ///
    /// # Errors
    /// Opening the endpoint.
    pub(crate) fn open(args: &AokArgs) -> Result<Self> {
        let link = args.to.open()?;
        let mut config = Config::new(args.firmware);
        config.timeout_ms = millis(args.timeout_ms);
        config.quiet_ms = millis(args.quiet_ms);
        config.debug_on = !args.debug_is_off;
        Ok(Session {
            client: Client::new(NbSerial::new(link), config),
            started: Instant::now(),
            timeout_ms: millis(args.timeout_ms),
        })
    }

    /// Runs one command to its end.
    ///
    /// # Errors
    /// A timeout, a refusal, or an I/O error, as one sentence naming `what`.
    pub(crate) fn run(&mut self, command: Command, what: &str) -> Result<Outcome> {
        let started = self.started;
        let _spinner = (command.expected_reply() != aok_proto::Expect::Nothing)
            .then(|| Spinner::start(&format!("waiting for the answer to {what}")));
        let result = self
            .client
            .run(command, || started.elapsed().as_millis() as u32);
        let serial = self.client.serial_mut();
        if let Some(e) = serial.take_error() {
            return Err(e);
        }
        match result {
            Ok(o) => Ok(o),
            Err(aok_proto::ClientError::Timeout) if serial.ended() => Err(Error::Device(format!(
                "{} closed the connection before answering {what}",
                serial.name()
            ))),
            Err(aok_proto::ClientError::Timeout) => Err(Error::Timeout {
                what: format!("{what} from {}", serial.name()),
                ms: u64::from(self.timeout_ms),
            }),
            Err(aok_proto::ClientError::Rejected) => {
                Err(Error::Refused(format!("the device rejected {what} ('E')")))
            }
            Err(aok_proto::ClientError::RefusedInFlight) => Err(Error::Refused(format!(
                "the device refused {what} in flight ('I')"
            ))),
            Err(source) => Err(Error::Aok {
                what: what.to_string(),
                source,
            }),
        }
    }
}

/// A duration as the client's `u32` milliseconds (the parsers keep it within an hour).
#[cfg(feature = "cli")]
fn millis(d: Duration) -> u32 {
    u32::try_from(d.as_millis()).unwrap_or(u32::MAX)
}

#[cfg(feature = "cli")]
fn waypoint_line(w: &Waypoint) -> String {
    format!(
        "waypoint {}: longitude={} latitude={} action1={} action2={}",
        slot_name(w.slot),
        w.longitude,
        w.latitude,
        action_name(w.action1),
        action_name(w.action2)
    )
}

/// How a command that changes the box ended, when it did not fail.
#[cfg(feature = "cli")]
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum Answer {
    /// The box said yes (an ack, or a read-back that matches).
    Confirmed(String),
    /// The protocol gives no answer to this command; the sentence says what is known.
    Unconfirmed(String),
}

#[cfg(feature = "cli")]
impl Answer {
    /// The outcome as the end of an output line.
    pub(crate) fn show(&self) -> String {
        match self {
            Answer::Confirmed(why) => format!("confirmed ({why})"),
            Answer::Unconfirmed(why) => format!("unconfirmed ({why})"),
        }
    }
}

#[cfg(feature = "cli")]
impl Session {
    /// Sends a command the spec gives no ack and waits for one all the same: this project's
    /// box (and some firmware) answers 'O', 'E' or 'I'. No answer within the timeout is
    /// [`Answer::Unconfirmed`]; 'E' and 'I' are [`Error::Refused`].
    ///
    /// # Errors
    /// A refusal, or an I/O error.
    pub(crate) fn run_acked(&mut self, command: Command, what: &str) -> Result<Answer> {
        let started = self.started;
        self.client
            .start_expecting(command, aok_proto::Expect::Ack)
            .map_err(|source| Error::Aok {
                what: what.to_string(),
                source,
            })?;
        let result = {
            let _spinner = Spinner::start(&format!("waiting for the answer to {what}"));
            self.client.wait(|| started.elapsed().as_millis() as u32)
        };
        let serial = self.client.serial_mut();
        if let Some(e) = serial.take_error() {
            return Err(e);
        }
        match result {
            Ok(_) => Ok(Answer::Confirmed("acked 'O'".into())),
            Err(aok_proto::ClientError::Timeout) => Ok(Answer::Unconfirmed(format!(
                "no ack within {} ms; AOK defines no answer to {what}",
                self.timeout_ms
            ))),
            Err(aok_proto::ClientError::Rejected) => {
                Err(Error::Refused(format!("the device rejected {what} ('E')")))
            }
            Err(aok_proto::ClientError::RefusedInFlight) => Err(Error::Refused(format!(
                "the device refused {what} in flight ('I')"
            ))),
            Err(source) => Err(Error::Aok {
                what: what.to_string(),
                source,
            }),
        }
    }

    /// Watches the debug values for up to the timeout after a motor test: flight status (86,
    /// bit 0 = flying) refuses it, the motor-test mask (14, bit `motor - 1`) confirms it.
    ///
    /// # Errors
    /// The box is flying, or an I/O error.
    pub(crate) fn verify_motor(&mut self, motor: Motor, value: u8) -> Result<Answer> {
        let started = Instant::now();
        let limit = Duration::from_millis(u64::from(self.timeout_ms));
        let now = self.started;
        let mut seen = false;
        while started.elapsed() < limit {
            let _ = self.client.poll(now.elapsed().as_millis() as u32);
            while let Some(d) = self.client.next_debug() {
                seen = true;
                match d.number {
                    86 if d.value & 1 != 0 => {
                        return Err(Error::Refused(format!(
                            "the box is flying (debug value 86 = {}), so it ignores motor tests",
                            d.value
                        )));
                    }
                    14 if value > 0 && d.value & (1 << (motor.get() - 1)) != 0 => {
                        return Ok(Answer::Confirmed(format!(
                            "debug value 14 shows motor {} under test",
                            motor.get()
                        )));
                    }
                    _ => {}
                }
            }
            if let Some(e) = self.client.serial_mut().take_error() {
                return Err(e);
            }
            std::thread::sleep(Duration::from_millis(1));
        }
        Ok(Answer::Unconfirmed(if seen {
            "the debug values did not show the motor under test".into()
        } else {
            "no debug values arrived to check it against".into()
        }))
    }
}

/// Runs `protolink aok`.
///
/// Commands that read print what the device answered; commands that change it end in
/// `confirmed (...)` or `unconfirmed (...)`, and a refusal is an error (exit status 1).
///
/// # Errors
/// Opening the endpoint, a timeout, or a refusal.
#[cfg(feature = "cli")]
pub(crate) fn run(args: &AokArgs) -> Result<()> {
    let mut s = Session::open(args)?;
    let lines = match &args.action {
        AokAction::Debug { state } => vec![debug(&mut s, state)?],
        AokAction::Get { number } => vec![get(&mut s, *number)?],
        AokAction::Set { number, value } => vec![set(&mut s, *number, *value)?],
        AokAction::Bulk { first } => bulk(&mut s, args.firmware, *first)?,
        AokAction::Waypoint(WaypointAction::Get { slot }) => vec![waypoint_get(&mut s, *slot)?],
        AokAction::Waypoint(WaypointAction::Set {
            slot,
            longitude,
            latitude,
            action1,
            action2,
        }) => vec![waypoint_set(
            &mut s,
            Waypoint {
                slot: *slot,
                longitude: *longitude,
                latitude: *latitude,
                action1: *action1,
                action2: *action2,
            },
        )?],
        AokAction::Motor {
            motor,
            value,
            hold_ms,
            verify,
        } => vec![motor_test(&mut s, *motor, *value, *hold_ms, *verify)?],
        AokAction::Extern {
            roll,
            nick,
            yaw,
            pitch,
            expiry,
        } => vec![external_control(
            &mut s,
            ExternalControl {
                roll: *roll,
                nick: *nick,
                yaw: *yaw,
                pitch: *pitch,
                expiry_ms: *expiry,
            },
        )?],
        AokAction::SaveSet { set } => {
            let answer = s.run_acked(Command::SaveSet(*set), &format!("save-set {set}"))?;
            vec![format!("save parameters to set {set}: {}", answer.show())]
        }
        AokAction::LoadSet { set } => {
            let answer = s.run_acked(Command::LoadSet(*set), &format!("load-set {set}"))?;
            vec![format!("load parameter set {set}: {}", answer.show())]
        }
        AokAction::Reset => {
            s.run(Command::Reset, "reset")?;
            vec!["reset: unconfirmed (AOK defines no answer to 63 07; the device restarts)".into()]
        }
    };
    let mut out = Out::beside(&args.to);
    for line in &lines {
        out.line(line)?;
    }
    out.flush()
}

/// `debug on|off`: no answer is defined.
#[cfg(feature = "cli")]
fn debug(s: &mut Session, state: &str) -> Result<String> {
    let on = state == "on";
    let cmd = if on {
        Command::DebugOn
    } else {
        Command::DebugOff
    };
    s.run(cmd, "debug on/off")?;
    Ok(format!(
        "debug output {state}: unconfirmed (AOK defines no answer to 63 0{})",
        if on { 2 } else { 1 }
    ))
}

/// `get N`: the parameter's value.
#[cfg(feature = "cli")]
fn get(s: &mut Session, number: u8) -> Result<String> {
    let what = format!("the read of parameter {number}");
    match s.run(Command::ReadParameter(number), &what)? {
        Outcome::Parameter(p) => Ok(format!("parameter {} = {}", p.number, p.value)),
        other => Err(unexpected(&what, other)),
    }
}

/// `set N VALUE`: the client fails unless the device acks it.
#[cfg(feature = "cli")]
fn set(s: &mut Session, number: u8, value: i32) -> Result<String> {
    let cmd = Command::SetParameter(aok_proto::ParameterValue { number, value });
    s.run(cmd, &format!("setting parameter {number}"))?;
    Ok(format!(
        "parameter {number} = {value}: confirmed (acked 'O')"
    ))
}

/// `bulk FIRST`: sixteen parameters from `first` (firmware 0.35 and newer).
#[cfg(feature = "cli")]
fn bulk(s: &mut Session, firmware: FirmwareVersion, first: u8) -> Result<Vec<String>> {
    if !firmware.has_bulk_read() {
        return Err(Error::Usage(format!(
            "bulk read needs firmware 0.35 or newer, and --firmware says {}.{}",
            firmware.major, firmware.minor
        )));
    }
    let what = format!("the bulk read from parameter {first}");
    match s.run(Command::BulkRead(first), &what)? {
        Outcome::Bulk(b) => Ok(b
            .values
            .iter()
            .enumerate()
            .map(|(i, v)| {
                let n = b.first.wrapping_add(i as u8);
                format!("parameter {n} = {v}")
            })
            .collect()),
        other => Err(unexpected(&what, other)),
    }
}

/// `waypoint get SLOT`.
#[cfg(feature = "cli")]
fn waypoint_get(s: &mut Session, slot: WaypointSlot) -> Result<String> {
    let what = format!("the read of waypoint {}", slot_name(slot));
    match s.run(Command::ReadWaypoint(slot), &what)? {
        Outcome::Waypoint(w) => Ok(waypoint_line(&w)),
        other => Err(unexpected(&what, other)),
    }
}

/// `waypoint set SLOT ...`: the client fails unless the device acks it.
#[cfg(feature = "cli")]
fn waypoint_set(s: &mut Session, w: Waypoint) -> Result<String> {
    s.run(
        Command::SetWaypoint(w),
        &format!("setting waypoint {}", slot_name(w.slot)),
    )?;
    Ok(format!("{}: confirmed (acked 'O')", waypoint_line(&w)))
}

/// How soon `motor` sends its second frame: the box runs a motor at rest only from a second
/// frame for it, in a later burst within the 500 ms hold of the first (`sensor-box`'s AOK
/// link, "Motor test"; `docs/protocol-notes.md` PL41). This is the latency the rule adds.
#[cfg(feature = "cli")]
const MOTOR_SECOND_FRAME: Duration = Duration::from_millis(20);

/// `motor N VALUE`: sent twice, [`MOTOR_SECOND_FRAME`] apart, then every 200 ms for `hold`;
/// with `verify`, the debug values after the second frame say whether the box took it.
#[cfg(feature = "cli")]
fn motor_test(
    s: &mut Session,
    motor: Motor,
    value: u8,
    hold: Option<Duration>,
    verify: bool,
) -> Result<String> {
    let cmd = Command::MotorTest(MotorTest { motor, value });
    let hold = hold.unwrap_or(Duration::ZERO);
    let started = Instant::now();
    let mut sent = 0u32;
    let mut answer = Answer::Unconfirmed(
        "AOK defines no answer to a motor test; pass --verify to check the debug values".into(),
    );
    loop {
        s.run(cmd, "the motor test")?;
        sent += 1;
        if sent == 1 {
            std::thread::sleep(MOTOR_SECOND_FRAME);
            continue;
        }
        if verify && sent == 2 {
            answer = s.verify_motor(motor, value)?;
        }
        if started.elapsed() >= hold {
            break;
        }
        std::thread::sleep(Duration::from_millis(200).min(hold.saturating_sub(started.elapsed())));
    }
    Ok(format!(
        "motor {} test value {value} ({sent} frame(s)): {}",
        motor.get(),
        answer.show()
    ))
}

/// `extern ROLL NICK YAW PITCH`: no answer is defined.
#[cfg(feature = "cli")]
fn external_control(s: &mut Session, control: ExternalControl) -> Result<String> {
    s.run(Command::ExternalControl(control), "external control")?;
    Ok(format!(
        "external control roll={} nick={} yaw={} pitch={} expiry={} ms: \
         unconfirmed (AOK defines no answer to 53)",
        control.roll.get(),
        control.nick.get(),
        control.yaw.get(),
        control.pitch,
        control.expiry_ms
    ))
}

#[cfg(feature = "cli")]
fn unexpected(what: &str, outcome: Outcome) -> Error {
    Error::Device(format!("unexpected answer to {what}: {outcome:?}"))
}

/// The examples of this module's items, as tests (the items are crate-private, so rustdoc
/// does not run them).
#[cfg(feature = "cli")]
#[cfg(test)]
#[allow(unused_imports, clippy::unnecessary_wraps)]
mod examples {
    use super::*;

    #[test]
    fn show_example() -> Result<(), Box<dyn std::error::Error>> {
        assert_eq!(
            Answer::Confirmed("acked 'O'".into()).show(),
            "confirmed (acked 'O')"
        );
        Ok(())
    }
}
