//! The PC-side client: [`Client`], a non-blocking state machine over `embedded-hal-nb` serial
//! traits, and its async form `AsyncClient` over `embedded-io-async` (feature
//! `embedded-io-async`), the same state machine driven by an async port and a delay.
//!
//! For a request with a reply (`73`, `77`, `67`, `47`, `78`) while debug output is on, the client
//! sends debug-off, drains until the line has been quiet for [`Config::quiet_ms`] (the spec warns
//! that values keep coming for a while), sends the request, waits for its reply or ack for at most
//! [`Config::timeout_ms`], and sends debug-on again, also after a timeout or a refusal. Requests
//! without a reply (motor test, external control, `63` commands) are just sent.
//!
//! Drive it with [`Client::poll`], passing the time in milliseconds (any wrapping `u32` clock), or use
//! the blocking helpers ([`Client::run`] and friends) with a clock closure.

#[cfg(feature = "embedded-io-async")]
mod async_client;
mod io;
mod requests;

#[cfg(feature = "embedded-io-async")]
pub use async_client::{AsyncClient, Pipe, TICK_MS};

use embedded_hal_nb::serial::{Read, Write};

use crate::command::Expect;
use crate::command::{Command, MAX_COMMAND_LEN, MotorTest, ParameterValue, Waypoint};
use crate::command::{DEBUG_OFF, DEBUG_ON};
use crate::decoder::{MessageDecoder, Stats};
use crate::message::{DebugValue, Message};
use crate::values::{Ack, FirmwareVersion, WaypointSlot};
use crate::{ClientError, SerialError};

/// How many debug values the client keeps for [`Client::next_debug`]; older ones are dropped.
///
/// ```
/// # include!(concat!(env!("CARGO_MANIFEST_DIR"), "/src/client/doc_device.rs"));
/// # fn main() {
/// use aok_proto::client::DEBUG_QUEUE;
/// use aok_proto::{Client, Config, DebugValue, FirmwareVersion, Message};
/// // A fake device (hidden here) sends one debug value more than the queue holds.
/// let mut device = FakeDevice::new();
/// for value in 0..=DEBUG_QUEUE as i32 {
///     device.send(Message::Debug(DebugValue { number: 86, value }));
/// }
/// let mut client = Client::new(device, Config::new(FirmwareVersion::LATEST));
/// while !client.serial_mut().to_pc.is_empty() {
///     let _ = client.poll(0);
/// }
/// // The oldest (value 0) made room for the newest.
/// assert_eq!(client.stats().debug_dropped, 1);
/// assert_eq!(client.next_debug(), Some(DebugValue { number: 86, value: 1 }));
/// # }
/// ```
pub const DEBUG_QUEUE: usize = 16;
/// The most bytes one [`Client::poll`] reads, to bound its run time.
///
/// ```
/// # include!(concat!(env!("CARGO_MANIFEST_DIR"), "/src/client/doc_device.rs"));
/// # fn main() {
/// use aok_proto::client::MAX_READS_PER_POLL;
/// use aok_proto::{Client, Config, DebugValue, FirmwareVersion, Message};
/// // A fake device (hidden here) has sent ten 7-byte debug frames: 70 bytes.
/// let mut device = FakeDevice::new();
/// for value in 0..10 {
///     device.send(Message::Debug(DebugValue { number: 86, value }));
/// }
/// let mut client = Client::new(device, Config::new(FirmwareVersion::LATEST));
/// let _ = client.poll(0);
/// // One poll read 64 bytes: nine whole frames and the start of the tenth.
/// assert_eq!(MAX_READS_PER_POLL, 64);
/// assert_eq!(client.stats().debug_values, 9);
/// let _ = client.poll(1);
/// assert_eq!(client.stats().debug_values, 10);
/// # }
/// ```
pub const MAX_READS_PER_POLL: usize = 64;

/// Client settings.
///
/// ```
/// let c = aok_proto::Config::new(aok_proto::FirmwareVersion::LATEST);
/// assert_eq!((c.timeout_ms, c.quiet_ms, c.debug_on), (1000, 50, true));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Config {
    /// The device's firmware: picks the parameter-reply form and whether bulk read exists.
    pub firmware: FirmwareVersion,
    /// How long to wait for a reply (and the longest drain) in ms.
    pub timeout_ms: u32,
    /// How long the line must be silent before the drain after debug-off ends, in ms. Also the gap
    /// after which a partial frame is abandoned while waiting for a reply.
    pub quiet_ms: u32,
    /// Whether the device is sending debug values when the client starts (the AOK does by default).
    pub debug_on: bool,
}

impl Config {
    /// Defaults: 1000 ms timeout, 50 ms quiet time, debug output assumed on.
    ///
    /// ```
    /// let c = aok_proto::Config::new(aok_proto::FirmwareVersion::new(0, 30));
    /// assert_eq!(c.firmware.minor, 30);
    /// ```
    pub const fn new(firmware: FirmwareVersion) -> Self {
        Self {
            firmware,
            timeout_ms: 1000,
            quiet_ms: 50,
            debug_on: true,
        }
    }
}

/// The 16 values of a bulk read.
///
/// ```
/// # include!(concat!(env!("CARGO_MANIFEST_DIR"), "/src/client/doc_device.rs"));
/// # fn main() {
/// use aok_proto::client::BulkValues;
/// use aok_proto::{Client, Command, Config, FirmwareVersion, Outcome};
/// // A fake device (hidden here) where parameter n holds n * 10.
/// let mut client = Client::new(FakeDevice::new(), Config::new(FirmwareVersion::LATEST));
/// let Ok(Outcome::Bulk(bulk)) = client.run(Command::BulkRead(250), fake_clock()) else {
///     panic!("no bulk reply");
/// };
/// let BulkValues { first, values } = bulk;
/// assert_eq!(first, 250);
/// assert_eq!(values[..6], [2500, 2510, 2520, 2530, 2540, 2550]);
/// // The numbers wrap at 255: values[6] is parameter 0.
/// assert_eq!(values[6..9], [0, 10, 20]);
/// # }
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct BulkValues {
    /// The first parameter number.
    pub first: u8,
    /// Parameters `first..first+16` (numbers wrap at 255).
    pub values: [i32; 16],
}

/// How a finished operation went.
///
/// ```
/// # include!(concat!(env!("CARGO_MANIFEST_DIR"), "/src/client/doc_device.rs"));
/// # fn main() {
/// use aok_proto::{ActionWord, Client, Command, Config, FirmwareVersion, Outcome, ParameterValue,
///                 Waypoint, WaypointSlot};
/// // A fake device (hidden here) where parameter n holds n * 10.
/// let mut client = Client::new(FakeDevice::new(), Config::new(FirmwareVersion::LATEST));
/// // Saving a set has no reply: done once written.
/// assert_eq!(client.run(Command::SaveSet(1), fake_clock()), Ok(Outcome::Sent));
/// let set = ParameterValue { number: 12, value: 1500 };
/// assert_eq!(client.run(Command::SetParameter(set), fake_clock()), Ok(Outcome::Acked));
/// assert_eq!(client.run(Command::ReadParameter(12), fake_clock()), Ok(Outcome::Parameter(set)));
/// let poi = Waypoint { slot: WaypointSlot::RamPoi, longitude: 100, latitude: -100,
///                      action1: ActionWord::NONE, action2: ActionWord::NONE };
/// assert_eq!(client.run(Command::SetWaypoint(poi), fake_clock()), Ok(Outcome::Acked));
/// let read = client.run(Command::ReadWaypoint(WaypointSlot::RamPoi), fake_clock());
/// assert_eq!(read, Ok(Outcome::Waypoint(poi)));
/// # }
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Outcome {
    /// The command was sent; it has no reply.
    Sent,
    /// The device acked with 'O'.
    Acked,
    /// A parameter value.
    Parameter(ParameterValue),
    /// The 16 values of a bulk read.
    Bulk(BulkValues),
    /// A waypoint.
    Waypoint(Waypoint),
}

/// Client counters (wrapping).
///
/// ```
/// # include!(concat!(env!("CARGO_MANIFEST_DIR"), "/src/client/doc_device.rs"));
/// # fn main() {
/// use aok_proto::client::ClientStats;
/// use aok_proto::{Client, Config, DebugValue, FirmwareVersion, Message, ParameterValue};
/// use embedded_hal_nb::serial::ErrorKind;
/// // A fake device (hidden here): a debug value, a parameter reply nobody asked for, and an
/// // overrun in the port.
/// let mut device = FakeDevice::new();
/// device.send(Message::Debug(DebugValue { number: 86, value: 3 }));
/// device.send(Message::Parameter(ParameterValue { number: 12, value: 120 }));
/// device.read_error = Some(ErrorKind::Overrun);
/// let mut client = Client::new(device, Config::new(FirmwareVersion::LATEST));
/// // Idle, the client still reads the line.
/// assert_eq!(client.poll(0), Err(nb::Error::WouldBlock));
/// let expected = ClientStats { debug_values: 1, debug_dropped: 0, stray: 1, read_errors: 1 };
/// assert_eq!(client.stats(), expected);
/// # }
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ClientStats {
    /// Debug values received.
    pub debug_values: u32,
    /// Debug values pushed out of the full queue.
    pub debug_dropped: u32,
    /// Replies and acks that matched no pending request.
    pub stray: u32,
    /// Errors reported by the serial port's `read`.
    pub read_errors: u32,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
enum Phase {
    Idle,
    DebugOff,
    Drain,
    Send,
    Await,
    Restore,
}

/// The PC-side client. `S` is the serial port (both halves; see the crate README for split ports).
///
/// ```
/// use aok_proto::{Client, Command, Config, FirmwareVersion, Outcome};
/// # struct Loop(Option<u8>);
/// # impl embedded_hal_nb::serial::ErrorType for Loop { type Error = core::convert::Infallible; }
/// # impl embedded_hal_nb::serial::Read for Loop {
/// #     fn read(&mut self) -> nb::Result<u8, Self::Error> { self.0.take().ok_or(nb::Error::WouldBlock) }
/// # }
/// # impl embedded_hal_nb::serial::Write for Loop {
/// #     fn write(&mut self, _: u8) -> nb::Result<(), Self::Error> { Ok(()) }
/// #     fn flush(&mut self) -> nb::Result<(), Self::Error> { Ok(()) }
/// # }
/// let mut config = Config::new(FirmwareVersion::LATEST);
/// config.debug_on = false;
/// let mut client = Client::new(Loop(None), config);
/// let mut t = 0u32;
/// // No reply defined for a save-set: it completes when written.
/// assert_eq!(client.run(Command::SaveSet(1), || { t += 1; t }), Ok(Outcome::Sent));
/// // Nobody answers the read: a clean timeout after 1000 ms.
/// assert_eq!(client.read_parameter(12, || { t += 1; t }), Err(aok_proto::ClientError::Timeout));
/// ```
#[derive(Debug)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Client<S> {
    serial: S,
    decoder: MessageDecoder,
    config: Config,
    debug_on: bool,
    phase: Phase,
    command: Command,
    expect: Expect,
    restore: bool,
    tx: [u8; MAX_COMMAND_LEN],
    tx_len: usize,
    tx_pos: usize,
    flushed: bool,
    phase_since: u32,
    last_rx: u32,
    result: Option<Result<Outcome, ClientError>>,
    bulk: [i32; 16],
    bulk_seen: u16,
    debug: [DebugValue; DEBUG_QUEUE],
    debug_head: usize,
    debug_count: usize,
    stats: ClientStats,
}

impl<S: Read<u8> + Write<u8>> Client<S> {
    /// A client on this serial port.
    ///
    /// ```
    /// # include!(concat!(env!("CARGO_MANIFEST_DIR"), "/src/client/doc_device.rs"));
    /// # fn main() {
    /// use aok_proto::{Client, Config, FirmwareVersion};
    /// // A fake device (hidden here) stands for the port.
    /// let client = Client::new(FakeDevice::new(), Config::new(FirmwareVersion::LATEST));
    /// assert!(client.is_idle());
    /// // Nothing is written before the first request.
    /// assert!(client.release().sent.is_empty());
    /// # }
    /// ```
    pub fn new(serial: S, config: Config) -> Self {
        Self {
            serial,
            decoder: MessageDecoder::new(config.firmware),
            config,
            debug_on: config.debug_on,
            phase: Phase::Idle,
            command: Command::DebugOff,
            expect: Expect::Nothing,
            restore: false,
            tx: [0; MAX_COMMAND_LEN],
            tx_len: 0,
            tx_pos: 0,
            flushed: false,
            phase_since: 0,
            last_rx: 0,
            result: None,
            bulk: [0; 16],
            bulk_seen: 0,
            debug: [DebugValue {
                number: 0,
                value: 0,
            }; DEBUG_QUEUE],
            debug_head: 0,
            debug_count: 0,
            stats: ClientStats {
                debug_values: 0,
                debug_dropped: 0,
                stray: 0,
                read_errors: 0,
            },
        }
    }

    /// Start a command, waiting for the reply the spec defines for it ([`Command::expected_reply`]).
    ///
    /// Fails with [`ClientError::Busy`] while another operation runs, and with [`ClientError::Unsupported`] for a
    /// bulk read on firmware older than 0.35.
    ///
    /// ```
    /// # include!(concat!(env!("CARGO_MANIFEST_DIR"), "/src/client/doc_device.rs"));
    /// # fn main() {
    /// use aok_proto::{Client, ClientError, Command, Config, FirmwareVersion, Outcome,
    ///                 ParameterValue};
    /// // A fake device (hidden here) where parameter n holds n * 10.
    /// let mut client = Client::new(FakeDevice::new(), Config::new(FirmwareVersion::LATEST));
    /// assert_eq!(client.start(Command::ReadParameter(12)), Ok(()));
    /// // One operation at a time.
    /// assert_eq!(client.start(Command::ReadParameter(13)), Err(ClientError::Busy));
    /// // The main loop polls with the time until the outcome comes.
    /// let mut now_ms = 0;
    /// let outcome = loop {
    ///     now_ms += 1;
    ///     match client.poll(now_ms) {
    ///         Ok(outcome) => break outcome,
    ///         Err(nb::Error::WouldBlock) => { /* other work */ }
    ///         Err(nb::Error::Other(e)) => panic!("{e}"),
    ///     }
    /// };
    /// assert_eq!(outcome, Outcome::Parameter(ParameterValue { number: 12, value: 120 }));
    ///
    /// // Firmware 0.34 has no bulk read.
    /// let mut old = Client::new(FakeDevice::new(), Config::new(FirmwareVersion::new(0, 34)));
    /// assert_eq!(old.start(Command::BulkRead(0)), Err(ClientError::Unsupported));
    /// # }
    /// ```
    pub fn start(&mut self, command: Command) -> Result<(), ClientError> {
        self.start_expecting(command, command.expected_reply())
    }

    /// Start a command and wait for the given reply instead of the default one (for example an ack
    /// after a save-set, if a firmware sends one).
    ///
    /// ```
    /// # include!(concat!(env!("CARGO_MANIFEST_DIR"), "/src/client/doc_device.rs"));
    /// # fn main() {
    /// use aok_proto::{Client, Command, Config, Expect, FirmwareVersion, Outcome};
    /// // A fake device (hidden here) whose firmware acks a save-set.
    /// let mut device = FakeDevice::new();
    /// device.acks_sets = true;
    /// let mut client = Client::new(device, Config::new(FirmwareVersion::LATEST));
    /// assert_eq!(client.start_expecting(Command::SaveSet(1), Expect::Ack), Ok(()));
    /// assert_eq!(client.wait(fake_clock()), Ok(Outcome::Acked));
    /// // Waiting for a reply, the client turned debug output off around the request.
    /// assert_eq!(client.serial_mut().take_sent(), [0x63, 0x01, 0x63, 0x04, 0x01, 0x63, 0x02]);
    /// # }
    /// ```
    pub fn start_expecting(&mut self, command: Command, expect: Expect) -> Result<(), ClientError> {
        if self.phase != Phase::Idle {
            return Err(ClientError::Busy);
        }
        if matches!(command, Command::BulkRead(_)) && !self.config.firmware.has_bulk_read() {
            return Err(ClientError::Unsupported);
        }
        self.command = command;
        self.expect = expect;
        self.result = None;
        self.bulk_seen = 0;
        let quiet_first = expect != Expect::Nothing || matches!(command, Command::Reset);
        if quiet_first && self.debug_on {
            self.restore = !matches!(command, Command::Reset);
            self.load(&DEBUG_OFF);
            self.phase = Phase::DebugOff;
        } else {
            self.restore = false;
            self.load_command();
            self.phase = Phase::Send;
        }
        Ok(())
    }

    /// Advance the running operation. Reads what the port has (at most [`MAX_READS_PER_POLL`] bytes),
    /// writes what it can, and checks the timeouts against `now_ms`.
    ///
    /// Returns the outcome once, when the operation is over; `WouldBlock` while it runs and while the
    /// client is idle (it still collects debug values then).
    ///
    /// ```
    /// # include!(concat!(env!("CARGO_MANIFEST_DIR"), "/src/client/doc_device.rs"));
    /// # fn main() {
    /// use aok_proto::{Client, Command, Config, DebugValue, FirmwareVersion, Message, Outcome,
    ///                 ParameterValue};
    /// // A fake device (hidden here), with debug output off.
    /// let mut device = FakeDevice::new();
    /// device.send(Message::Debug(DebugValue { number: 86, value: 3 }));
    /// let mut config = Config::new(FirmwareVersion::LATEST);
    /// config.debug_on = false;
    /// let mut client = Client::new(device, config);
    /// // Idle: nothing to return, but the debug value is taken in.
    /// assert_eq!(client.poll(0), Err(nb::Error::WouldBlock));
    /// assert_eq!(client.next_debug(), Some(DebugValue { number: 86, value: 3 }));
    ///
    /// let set = ParameterValue { number: 12, value: 1500 };
    /// client.start(Command::SetParameter(set)).unwrap();
    /// // This poll sends the request; the fake device acks it at once.
    /// assert_eq!(client.poll(1), Err(nb::Error::WouldBlock));
    /// assert_eq!(client.poll(2), Ok(Outcome::Acked));
    /// // The outcome comes once.
    /// assert_eq!(client.poll(3), Err(nb::Error::WouldBlock));
    /// assert_eq!(client.release().params[12], 1500);
    /// # }
    /// ```
    pub fn poll(&mut self, now_ms: u32) -> nb::Result<Outcome, ClientError> {
        self.receive(now_ms);
        loop {
            match self.phase {
                Phase::Idle => return Err(nb::Error::WouldBlock),
                Phase::DebugOff => match self.transmit() {
                    Ok(true) => {
                        self.debug_on = false;
                        self.phase = Phase::Drain;
                        self.phase_since = now_ms;
                        self.last_rx = now_ms;
                    }
                    Ok(false) => return Err(nb::Error::WouldBlock),
                    Err(e) => self.conclude(Err(e)),
                },
                Phase::Drain => {
                    let quiet = now_ms.wrapping_sub(self.last_rx) >= self.config.quiet_ms;
                    let too_long = now_ms.wrapping_sub(self.phase_since) >= self.config.timeout_ms;
                    if !quiet && !too_long {
                        return Err(nb::Error::WouldBlock);
                    }
                    // Anything still buffered is stale: let it go before the request.
                    self.flush_decoder(now_ms);
                    self.load_command();
                    self.phase = Phase::Send;
                }
                Phase::Send => {
                    self.decoder.expect(self.expect);
                    match self.transmit() {
                        Ok(true) => {
                            match self.command {
                                Command::DebugOff => self.debug_on = false,
                                Command::DebugOn | Command::Reset => self.debug_on = true,
                                _ => {}
                            }
                            if self.expect == Expect::Nothing {
                                self.conclude(Ok(Outcome::Sent));
                            } else {
                                self.phase = Phase::Await;
                                self.phase_since = now_ms;
                                self.last_rx = now_ms;
                            }
                        }
                        Ok(false) => return Err(nb::Error::WouldBlock),
                        Err(e) => self.conclude(Err(e)),
                    }
                }
                Phase::Await => {
                    if self.result.is_some() {
                        self.conclude_pending();
                    } else if now_ms.wrapping_sub(self.phase_since) >= self.config.timeout_ms {
                        self.conclude(Err(ClientError::Timeout));
                    } else if self.decoder.held_bytes() > 0
                        && now_ms.wrapping_sub(self.last_rx) >= self.config.quiet_ms
                    {
                        // A partial frame with nothing after it: rescan what it hides.
                        self.flush_decoder(now_ms);
                        if self.result.is_none() {
                            return Err(nb::Error::WouldBlock);
                        }
                    } else {
                        return Err(nb::Error::WouldBlock);
                    }
                }
                Phase::Restore => match self.transmit() {
                    Ok(true) => {
                        self.debug_on = true;
                        return self.finish(None);
                    }
                    Ok(false) => return Err(nb::Error::WouldBlock),
                    Err(e) => return self.finish(Some(e)),
                },
            }
            if self.phase == Phase::Idle {
                return self.finish(None);
            }
        }
    }

    /// Whether no operation is running.
    ///
    /// ```
    /// # include!(concat!(env!("CARGO_MANIFEST_DIR"), "/src/client/doc_device.rs"));
    /// # fn main() {
    /// use aok_proto::{Client, Command, Config, FirmwareVersion};
    /// // A fake device (hidden here).
    /// let mut client = Client::new(FakeDevice::new(), Config::new(FirmwareVersion::LATEST));
    /// assert!(client.is_idle());
    /// client.start(Command::ReadParameter(12)).unwrap();
    /// assert!(!client.is_idle());
    /// assert!(client.wait(fake_clock()).is_ok());
    /// assert!(client.is_idle());
    /// # }
    /// ```
    pub fn is_idle(&self) -> bool {
        self.phase == Phase::Idle
    }

    /// Whether the client believes the device is sending debug values.
    ///
    /// ```
    /// # include!(concat!(env!("CARGO_MANIFEST_DIR"), "/src/client/doc_device.rs"));
    /// # fn main() {
    /// use aok_proto::{Client, Command, Config, FirmwareVersion};
    /// // A fake device (hidden here); the AOK sends debug values from power-on.
    /// let mut client = Client::new(FakeDevice::new(), Config::new(FirmwareVersion::LATEST));
    /// assert!(client.debug_enabled());
    /// client.run(Command::DebugOff, fake_clock()).unwrap();
    /// assert!(!client.debug_enabled());
    /// // A read with debug output off leaves it off.
    /// client.read_parameter(12, fake_clock()).unwrap();
    /// assert!(!client.debug_enabled());
    /// assert!(!client.release().debug_on);
    /// # }
    /// ```
    pub const fn debug_enabled(&self) -> bool {
        self.debug_on
    }

    /// Tell the client whether the device is sending debug values (for example after a reconnect).
    ///
    /// ```
    /// # include!(concat!(env!("CARGO_MANIFEST_DIR"), "/src/client/doc_device.rs"));
    /// # fn main() {
    /// use aok_proto::{Client, Config, FirmwareVersion};
    /// // A fake device (hidden here).
    /// let mut config = Config::new(FirmwareVersion::LATEST);
    /// config.debug_on = false;
    /// let mut client = Client::new(FakeDevice::new(), config);
    /// assert_eq!(client.read_parameter(12, fake_clock()), Ok(120));
    /// assert_eq!(client.serial_mut().take_sent(), [0x67, 0x0C]);
    /// // The device was reset and sends debug values again: the next read turns them off first
    /// // and back on after.
    /// client.assume_debug(true);
    /// assert_eq!(client.read_parameter(12, fake_clock()), Ok(120));
    /// assert_eq!(client.serial_mut().take_sent(), [0x63, 0x01, 0x67, 0x0C, 0x63, 0x02]);
    /// # }
    /// ```
    pub fn assume_debug(&mut self, on: bool) {
        self.debug_on = on;
    }

    /// The oldest debug value received and not yet taken.
    ///
    /// ```
    /// # include!(concat!(env!("CARGO_MANIFEST_DIR"), "/src/client/doc_device.rs"));
    /// # fn main() {
    /// use aok_proto::{Client, Config, DebugValue, FirmwareVersion, Message};
    /// // A fake device (hidden here) sends the flight status, then debug value 7.
    /// let mut device = FakeDevice::new();
    /// device.send(Message::Debug(DebugValue { number: DebugValue::FLIGHT_STATUS, value: 3 }));
    /// device.send(Message::Debug(DebugValue { number: 7, value: -42 }));
    /// let mut client = Client::new(device, Config::new(FirmwareVersion::LATEST));
    /// let _ = client.poll(0);
    /// assert_eq!(client.next_debug(), Some(DebugValue { number: 86, value: 3 }));
    /// assert_eq!(client.next_debug(), Some(DebugValue { number: 7, value: -42 }));
    /// assert_eq!(client.next_debug(), None);
    /// # }
    /// ```
    pub fn next_debug(&mut self) -> Option<DebugValue> {
        if self.debug_count == 0 {
            return None;
        }
        let v = self.debug.get(self.debug_head).copied();
        self.debug_head = (self.debug_head.wrapping_add(1)) % DEBUG_QUEUE;
        self.debug_count = self.debug_count.saturating_sub(1);
        v
    }

    /// The client's counters.
    ///
    /// ```
    /// # include!(concat!(env!("CARGO_MANIFEST_DIR"), "/src/client/doc_device.rs"));
    /// # fn main() {
    /// use aok_proto::{Client, Config, FirmwareVersion, Message, ParameterValue};
    /// // A fake device (hidden here): a parameter reply arrives while nothing was asked.
    /// let mut device = FakeDevice::new();
    /// device.send(Message::Parameter(ParameterValue { number: 12, value: 120 }));
    /// let mut client = Client::new(device, Config::new(FirmwareVersion::LATEST));
    /// assert_eq!(client.stats().stray, 0);
    /// let _ = client.poll(0);
    /// assert_eq!(client.stats().stray, 1);
    /// // A reply that was asked for is not stray.
    /// assert_eq!(client.read_parameter(12, fake_clock()), Ok(120));
    /// assert_eq!(client.stats().stray, 1);
    /// # }
    /// ```
    pub const fn stats(&self) -> ClientStats {
        self.stats
    }

    /// The stream decoder's counters.
    ///
    /// ```
    /// # include!(concat!(env!("CARGO_MANIFEST_DIR"), "/src/client/doc_device.rs"));
    /// # fn main() {
    /// use aok_proto::{Client, Config, FirmwareVersion};
    /// // A fake device (hidden here) sends flight status 3 twice, the first time with a bad
    /// // checksum (00 instead of 55).
    /// let mut device = FakeDevice::new();
    /// device.to_pc.extend([0x1C, 0x56, 0x00, 0x00, 0x00, 0x03, 0x00]);
    /// device.to_pc.extend([0x1C, 0x56, 0x00, 0x00, 0x00, 0x03, 0x55]);
    /// let mut client = Client::new(device, Config::new(FirmwareVersion::LATEST));
    /// let _ = client.poll(0);
    /// assert_eq!(client.decoder_stats().checksum_errors, 1);
    /// assert_eq!(client.decoder_stats().frames_ok, 1);
    /// assert_eq!(client.stats().debug_values, 1);
    /// # }
    /// ```
    pub const fn decoder_stats(&self) -> Stats {
        self.decoder.stats()
    }

    /// The serial port.
    ///
    /// ```
    /// # include!(concat!(env!("CARGO_MANIFEST_DIR"), "/src/client/doc_device.rs"));
    /// # fn main() {
    /// use aok_proto::{Client, Command, Config, FirmwareVersion, Outcome};
    /// // A fake device (hidden here), which keeps what the client wrote.
    /// let mut config = Config::new(FirmwareVersion::LATEST);
    /// config.debug_on = false;
    /// let mut client = Client::new(FakeDevice::new(), config);
    /// assert_eq!(client.run(Command::SaveSet(1), fake_clock()), Ok(Outcome::Sent));
    /// let port = client.serial_mut();
    /// assert_eq!(port.take_sent(), [0x63, 0x04, 0x01]);
    /// # }
    /// ```
    pub fn serial_mut(&mut self) -> &mut S {
        &mut self.serial
    }

    /// Give the serial port back.
    ///
    /// ```
    /// # include!(concat!(env!("CARGO_MANIFEST_DIR"), "/src/client/doc_device.rs"));
    /// # fn main() {
    /// use aok_proto::{Client, Config, FirmwareVersion};
    /// // A fake device (hidden here).
    /// let mut client = Client::new(FakeDevice::new(), Config::new(FirmwareVersion::LATEST));
    /// assert_eq!(client.set_parameter(12, 1500, fake_clock()), Ok(()));
    /// let device = client.release();
    /// assert_eq!(device.params[12], 1500);
    /// // Debug output is on again after the set.
    /// assert!(device.debug_on);
    /// # }
    /// ```
    pub fn release(self) -> S {
        self.serial
    }
}
