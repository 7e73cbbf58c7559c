//! The command line: `protolink <subcommand> ...`, every subcommand with an example in `--help`.
//! The top floor: each subcommand's arguments and `run` come from its module in
//! [`commands`](crate::commands).

use std::ffi::OsString;
use std::io::Write;

use clap::error::ErrorKind;
use clap::{Parser, Subcommand};

use crate::commands::aeolus::AeolusArgs;
use crate::commands::aok::AokArgs;
use crate::commands::aydp::AydpArgs;
use crate::commands::bridge::BridgeArgs;
use crate::commands::decode::DecodeArgs;
#[cfg(feature = "parquet")]
use crate::commands::decode::export::ExportArgs;
#[cfg(feature = "servers")]
use crate::commands::gdl90::Gdl90Args;
#[cfg(feature = "servers")]
use crate::commands::nmea::NmeaArgs;
use crate::commands::record::RecordArgs;
use crate::commands::replay::ReplayArgs;
#[cfg(feature = "sim")]
use crate::commands::sim::SimArgs;
use crate::commands::watch::WatchArgs;
#[cfg(feature = "servers")]
use crate::commands::web::WebArgs;
use crate::commands::wireshark::WiresharkArgs;
use crate::error::Result;

const ENDPOINTS: &str = "Endpoints (same syntax everywhere):
  serial:/dev/ttyUSB0@921600   a serial port at that baud rate (115200 if @BAUD is left out)
  tcp:127.0.0.1:7000           a TCP connection (the QEMU UART sockets: 7000 AEOLUS, 7001 AYDP, 7002 AOK)
  udp:5001                     a UDP socket bound to 127.0.0.1:5001 (udp:0.0.0.0:5001 for every interface)
  file:capture.bin             a file, read once
  -                            stdin (and stdout for writes)";

/// `protolink`: watch, drive and bridge AEOLUS, AYDP and AOK boxes from a desk.
#[derive(Debug, Parser)]
#[command(name = "protolink", version, about, after_help = ENDPOINTS)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub(crate) command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub(crate) enum Command {
    /// Decode a stream: one line per message, errors with their byte offset, counters at the end.
    #[command(after_help = "Examples:
  protolink decode --proto aeolus --from tcp:127.0.0.1:7000 --seconds 5
  protolink decode --proto aydp --profile spec --from file:capture.bin --json
  protolink decode --proto aok --side device --from serial:/dev/ttyUSB0@38400")]
    Decode(DecodeArgs),
    /// The AEOLUS box's WiFi side: UART frames out as UDP datagrams, datagrams in to the UART.
    #[command(after_help = "Examples:
  protolink bridge --uart tcp:127.0.0.1:7000 --udp-out 127.0.0.1:5001 --udp-in 5002
  protolink bridge --uart serial:/dev/ttyUSB0@921600 --pack 4 --seconds 60")]
    Bridge(BridgeArgs),
    /// A virtual AEOLUS-SENSE box on UDP: the firmware's telemetry, flight and command handling.
    #[command(after_help = "Examples:
  protolink sim --udp-out 127.0.0.1:5001 --udp-in 5002
  protolink sim --pack 8 --airspeed 35 --bank -15 --seconds 60
  protolink sim --climb 2.5 --bank 20
  protolink watch --from udp:5001      (in a second terminal: watch what it sends)")]
    #[cfg(feature = "sim")]
    Sim(SimArgs),
    /// Send an AEOLUS box a COMMAND or SETTIME, and report its TOAST answer.
    #[command(after_help = "Examples:
  protolink aeolus --to udp:127.0.0.1:5002 --from udp:5001 command \"a pause\"
  protolink aeolus --to tcp:127.0.0.1:7000 settime now")]
    Aeolus(AeolusArgs),
    /// Read and write an AYDP device's system values, store its configuration, set outputs.
    #[command(after_help = "Examples:
  protolink aydp --to tcp:127.0.0.1:7001 get 0x0001 --as char[40]
  protolink aydp --to tcp:127.0.0.1:7001 set 0x0110 64.5 --as f32
  protolink aydp --to tcp:127.0.0.1:7001 output 1:2=10.0 --enable --verify")]
    Aydp(AydpArgs),
    /// Drive an AOK flight controller: debug, parameters, waypoints, motors, external control.
    #[command(after_help = "Examples:
  protolink aok --to tcp:127.0.0.1:7002 get 12
  protolink aok --to serial:/dev/ttyUSB0@38400 --firmware 0.30 set 12 1500
  protolink aok --to tcp:127.0.0.1:7002 waypoint get 1")]
    Aok(AokArgs),
    /// The box's telemetry as GDL90 for EFB apps (ForeFlight, Garmin Pilot, SkyDemon) on UDP 4000.
    #[command(after_help = "Examples:
  protolink gdl90 --from udp:5001 --to 127.0.0.1:4000
  protolink gdl90 --from tcp:127.0.0.1:7000 --discover")]
    #[cfg(feature = "servers")]
    Gdl90(Gdl90Args),
    /// The box's telemetry as NMEA 0183 for gliding and moving-map apps (XCSoar, LK8000, gpsd) on TCP 4353.
    #[command(
        after_help = "Sentences: $GPRMC, $GPGGA (1 Hz); $LXWP0 (1 Hz) and $POV (5 Hz) for xcsoar and lk8000;
$PGRMZ (1 Hz) for lk8000 only.

Examples:
  protolink nmea --from udp:5001                       (XCSoar: TCP client to 127.0.0.1:4353)
  protolink nmea --from udp:5001 --for lk8000 --listen 0.0.0.0:4353
  protolink nmea --from udp:5001 --for gpsd            (then: gpsd -N tcp://127.0.0.1:4353)
  protolink nmea --from udp:5001 --to 127.0.0.1:10110  (UDP datagrams instead)"
    )]
    #[cfg(feature = "servers")]
    Nmea(NmeaArgs),
    /// A live view of AEOLUS telemetry: attitude, airspeed, altitude, heading, GPS, wind, rates.
    #[command(after_help = "Examples:
  protolink watch --from tcp:127.0.0.1:7000
  protolink watch --from udp:5001 --seconds 10
  protolink watch --from udp:5001 --units aviation")]
    Watch(WatchArgs),
    /// A glass cockpit in the browser: horizon, tapes, heading, ground track, rates, errors.
    #[command(
        after_help = "The page is built in (no network needed); GET /api/state returns its state as JSON.

Examples:
  protolink web --from tcp:127.0.0.1:7000      (then open http://127.0.0.1:8080/)
  protolink web --from udp:5001 --listen 127.0.0.1:8081 --seconds 600
  protolink web --from udp:5001 --units aviation"
    )]
    #[cfg(feature = "servers")]
    Web(WebArgs),
    /// Record an endpoint into a pcapng file: UDP as Ethernet/IPv4/UDP, byte streams by link type.
    #[command(after_help = "Examples:
  protolink record --from udp:5001 --out flight.pcapng --seconds 60
  protolink record --from tcp:127.0.0.1:7000 --proto aeolus --out uart.pcapng
  protolink record --from tcp:127.0.0.1:7002 --proto aok --side device --out aok.pcapng")]
    Record(RecordArgs),
    /// Send a capture's payloads to an endpoint with their original timing (or faster).
    #[command(after_help = "Examples:
  protolink replay flight.pcapng --to udp:127.0.0.1:5001
  protolink replay flight.pcapng --to udp:127.0.0.1:5001 --speed 4 --loop --seconds 60")]
    Replay(ReplayArgs),
    /// Write captures and byte files as Parquet or Arrow IPC tables, one per protocol and message type.
    #[command(after_help = "Examples:
  protolink export --out tables flight1.pcapng flight2.pcapng
  protolink export --format arrow --out tables --proto aeolus uart.bin
  duckdb -c \"SELECT source, count(*) FROM read_parquet('tables/proto=aeolus/type=GYRO/*.parquet') GROUP BY source\"")]
    #[cfg(feature = "parquet")]
    Export(ExportArgs),
    /// Print the Wireshark Lua dissector for AEOLUS, generated from the protocol crates' layouts.
    #[command(after_help = "Examples:
  protolink wireshark    (save it as ~/.local/lib/wireshark/plugins/protolink.lua)
  tshark -X lua_script:tools/wireshark/protolink.lua -r capture.pcapng")]
    Wireshark(WiresharkArgs),
}

impl Cli {
    /// Runs the chosen subcommand.
    ///
    /// # Errors
    /// Whatever the subcommand reports.
    pub(crate) fn run(&self) -> Result<()> {
        match &self.command {
            Command::Decode(a) => crate::commands::decode::run(a),
            #[cfg(feature = "parquet")]
            Command::Export(a) => crate::commands::decode::export::run(a),
            Command::Bridge(a) => crate::commands::bridge::run(a),
            Command::Aeolus(a) => crate::commands::aeolus::run(a),
            Command::Aydp(a) => crate::commands::aydp::run(a),
            Command::Aok(a) => crate::commands::aok::run(a),
            #[cfg(feature = "sim")]
            Command::Sim(a) => crate::commands::sim::run(a),
            Command::Watch(a) => crate::commands::watch::run(a),
            #[cfg(feature = "servers")]
            Command::Web(a) => crate::commands::web::run(a),
            #[cfg(feature = "servers")]
            Command::Gdl90(a) => crate::commands::gdl90::run(a),
            #[cfg(feature = "servers")]
            Command::Nmea(a) => crate::commands::nmea::run(a),
            Command::Record(a) => crate::commands::record::run(a),
            Command::Replay(a) => crate::commands::replay::run(a),
            Command::Wireshark(a) => crate::commands::wireshark::run(a),
        }
    }
}

/// Runs a command line as the `protolink` binary does, `args` starting with the program's
/// name: clap's help and version go to stdout, a command-line mistake to stderr as one
/// sentence, a failure as `error: <sentence>`. Returns the exit status: 0 done (confirmed, or
/// unconfirmed where the protocol gives no answer), 1 a failure or a refusal by the box, 2 a
/// command-line mistake. The Python package's `python -m protolink decode` runs it too.
pub fn main_with<I, T>(args: I) -> u8
where
    I: IntoIterator<Item = T>,
    T: Into<OsString> + Clone,
{
    let cli = match Cli::try_parse_from(args) {
        Ok(cli) => cli,
        Err(e) if matches!(e.kind(), ErrorKind::DisplayHelp | ErrorKind::DisplayVersion) => {
            let _ = e.print();
            return 0;
        }
        Err(e) => {
            let _ = writeln!(
                std::io::stderr(),
                "{}",
                one_sentence(&e.render().to_string())
            );
            return 2;
        }
    };
    match cli.run() {
        Ok(()) => 0,
        // The reader went away (`protolink decode ... | head`): not an error of ours.
        Err(crate::Error::Output(e)) if e.kind() == std::io::ErrorKind::BrokenPipe => 0,
        Err(e) => {
            let _ = writeln!(std::io::stderr(), "error: {e}");
            e.exit_code()
        }
    }
}

/// Clap's message up to its usage block, on one line: `error: invalid value 'inf' for ...`.
fn one_sentence(rendered: &str) -> String {
    let head = rendered
        .split("\n\nUsage:")
        .next()
        .unwrap_or(rendered)
        .split("\n\nFor more information")
        .next()
        .unwrap_or(rendered);
    let mut line = head.split_whitespace().collect::<Vec<_>>().join(" ");
    if !line.starts_with("error:") {
        line.insert_str(0, "error: ");
    }
    line
}
