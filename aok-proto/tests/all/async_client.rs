//! `AsyncClient` against a fake AOK device on an async port, with a fake clock moved by the
//! delay: the debug-off / drain / request / reply / debug-on sequence, acks, refusals,
//! timeouts and transport errors.

use crate::watchdog;

use crate::transport;

use std::cell::Cell;
use std::collections::VecDeque;
use std::rc::Rc;

use aok_proto::Decode;
use aok_proto::client::AsyncClient;
use aok_proto::{
    Ack, ClientError, Command, CommandDecoder, Config, DebugValue, FirmwareVersion, Message,
    ParameterValue, SerialError,
};
use embedded_io::ErrorKind;
use transport::block_on;

/// The device at the far end of the wire: decodes commands, answers them, and sends a debug
/// value on every read while its debug output is on.
struct Device {
    decoder: CommandDecoder,
    to_pc: VecDeque<u8>,
    params: [i32; 256],
    debug: bool,
    commands: Vec<Command>,
    answer: bool,
    refuse: bool,
    fail_writes: bool,
    /// The line is closed: a read with nothing to say returns 0 (end of stream) at once.
    eof: bool,
    reads: usize,
}

impl Device {
    fn new() -> Self {
        Device {
            decoder: CommandDecoder::new(),
            to_pc: VecDeque::new(),
            params: [0; 256],
            debug: true,
            commands: Vec::new(),
            answer: true,
            refuse: false,
            fail_writes: false,
            eof: false,
            reads: 0,
        }
    }

    fn send(&mut self, m: Message) {
        let mut buf = [0u8; 19];
        let n = m
            .emit(&mut buf, FirmwareVersion::LATEST.reply_form())
            .unwrap();
        self.to_pc.extend(&buf[..n]);
    }
}

impl embedded_io_async::ErrorType for Device {
    type Error = ErrorKind;
}

impl embedded_io_async::Read for Device {
    async fn read(&mut self, buf: &mut [u8]) -> Result<usize, ErrorKind> {
        if self.debug {
            self.send(Message::Debug(DebugValue {
                number: 7,
                value: 42,
            }));
        }
        self.reads += 1;
        assert!(
            self.reads < 100_000,
            "the client reads without letting the clock run"
        );
        if self.to_pc.is_empty() && self.eof {
            return Ok(0);
        }
        if self.to_pc.is_empty() {
            // Nothing to say: wait (the client's tick cancels this read).
            std::future::pending::<()>().await;
        }
        let n = buf.len().min(self.to_pc.len()).min(3);
        for b in buf.iter_mut().take(n) {
            *b = self.to_pc.pop_front().unwrap();
        }
        Ok(n)
    }
}

impl embedded_io_async::Write for Device {
    async fn write(&mut self, buf: &[u8]) -> Result<usize, ErrorKind> {
        if self.fail_writes {
            return Err(ErrorKind::BrokenPipe);
        }
        let mut items = Vec::new();
        for &b in buf {
            self.decoder.feed(&[b], |c| items.push(c));
        }
        for item in items {
            let cmd = item.unwrap();
            self.commands.push(cmd);
            match cmd {
                Command::DebugOff => self.debug = false,
                Command::DebugOn => self.debug = true,
                Command::ReadParameter(number) if self.answer => {
                    let value = self.params[usize::from(number)];
                    self.send(Message::Parameter(ParameterValue { number, value }));
                }
                Command::SetParameter(p) if self.answer => {
                    if self.refuse {
                        self.send(Message::Ack(Ack::InFlight));
                    } else {
                        self.params[usize::from(p.number)] = p.value;
                        self.send(Message::Ack(Ack::Ok));
                    }
                }
                _ => {}
            }
        }
        Ok(buf.len())
    }

    async fn flush(&mut self) -> Result<(), ErrorKind> {
        Ok(())
    }
}

/// A delay that moves the shared fake clock.
struct Clock(Rc<Cell<u32>>);

impl embedded_hal_async::delay::DelayNs for Clock {
    async fn delay_ns(&mut self, ns: u32) {
        self.0.set(self.0.get() + ns.div_ceil(1_000_000));
    }
}

fn client(device: Device) -> (AsyncClient<Device, Clock>, Rc<Cell<u32>>) {
    let t = Rc::new(Cell::new(0));
    let c = AsyncClient::new(
        device,
        Clock(t.clone()),
        Config::new(FirmwareVersion::LATEST),
    );
    (c, t)
}

#[test]
fn read_parameter_turns_debug_off_drains_asks_and_turns_it_on_again() {
    let _watchdog = watchdog::arm();
    let mut device = Device::new();
    device.params[12] = 1500;
    // Debug values still on the line when the client starts: the drain takes them.
    for _ in 0..3 {
        device.send(Message::Debug(DebugValue {
            number: 7,
            value: 42,
        }));
    }
    let (mut c, t) = client(device);
    let value = block_on(c.read_parameter(12, || t.get()));
    assert_eq!(value, Ok(1500));
    assert!(c.state().debug_enabled());
    // The drain waited for the quiet time (50 ms) after debug-off.
    assert!(t.get() >= 50, "clock {}", t.get());
    assert_eq!(c.state().stats().debug_values, 3);
    assert_eq!(
        c.state_mut().next_debug(),
        Some(DebugValue {
            number: 7,
            value: 42
        })
    );
    let (device, _) = c.release();
    assert_eq!(
        device.commands,
        [
            Command::DebugOff,
            Command::ReadParameter(12),
            Command::DebugOn
        ]
    );
}

#[test]
fn set_parameter_is_acked_or_refused() {
    let _watchdog = watchdog::arm();
    let (mut c, t) = client(Device::new());
    assert_eq!(block_on(c.set_parameter(3, -7, || t.get())), Ok(()));
    let (mut device, delay) = c.release();
    assert_eq!(device.params[3], -7);
    device.refuse = true;
    device.commands.clear();
    let mut c = AsyncClient::new(device, delay, Config::new(FirmwareVersion::LATEST));
    assert_eq!(
        block_on(c.set_parameter(3, 9, || t.get())),
        Err(ClientError::RefusedInFlight)
    );
    let (device, _) = c.release();
    // Debug output is restored after a refusal too.
    assert_eq!(device.commands.last(), Some(&Command::DebugOn));
    assert_eq!(device.params[3], -7);
}

#[test]
fn a_silent_device_times_out_and_debug_is_restored() {
    let _watchdog = watchdog::arm();
    let mut device = Device::new();
    device.answer = false;
    let (mut c, t) = client(device);
    let start = t.get();
    assert_eq!(
        block_on(c.read_parameter(1, || t.get())),
        Err(ClientError::Timeout)
    );
    let waited = t.get() - start;
    // The drain (>= 50 ms) and the reply timeout (1000 ms), measured to a tick.
    assert!((1050..1100).contains(&waited), "waited {waited} ms");
    let (device, _) = c.release();
    assert_eq!(
        device.commands,
        [
            Command::DebugOff,
            Command::ReadParameter(1),
            Command::DebugOn
        ]
    );
}

#[test]
fn at_the_end_of_the_stream_the_clock_runs_and_the_request_times_out() {
    let _watchdog = watchdog::arm();
    let mut device = Device::new();
    device.answer = false;
    device.debug = false;
    device.eof = true;
    let (mut c, t) = client(device);
    c.state_mut().assume_debug(false);
    assert_eq!(
        block_on(c.read_parameter(1, || t.get())),
        Err(ClientError::Timeout)
    );
    // Each read of 0 bytes waits one tick: the reply timeout (1000 ms), to a tick.
    let waited = t.get();
    assert!((1000..1050).contains(&waited), "waited {waited} ms");
    let (device, _) = c.release();
    assert_eq!(device.commands, [Command::ReadParameter(1)]);
}

#[test]
fn a_failing_transport_is_a_serial_error() {
    let _watchdog = watchdog::arm();
    let mut device = Device::new();
    device.fail_writes = true;
    let (mut c, t) = client(device);
    assert_eq!(
        block_on(c.read_parameter(1, || t.get())),
        Err(ClientError::Serial(SerialError::Other))
    );
    assert!(c.state().is_idle());
}

#[test]
fn commands_without_a_reply_are_just_sent() {
    let _watchdog = watchdog::arm();
    let mut device = Device::new();
    device.debug = false;
    let (mut c, t) = client(device);
    c.state_mut().assume_debug(false);
    assert_eq!(
        block_on(c.run(Command::SaveSet(2), || t.get())),
        Ok(aok_proto::Outcome::Sent)
    );
    let (device, _) = c.release();
    assert_eq!(device.commands, [Command::SaveSet(2)]);
}
