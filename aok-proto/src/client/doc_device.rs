// The fake AOK device of the client's doc examples; not part of the library (no `mod` names
// this file). An example pulls it in with two hidden lines,
// `# include!(concat!(env!("CARGO_MANIFEST_DIR"), "/src/client/doc_device.rs"));` and
// `# fn main() {`, and ends with `# }`. The path is absolute so that the doctests still
// compile as one merged crate (a relative path is taken from rustdoc's generated file there,
// and the failed merge would compile every doctest of the crate on its own).
//
// `FakeDevice` is the serial port and the firmware at its far end: it decodes every byte the
// client writes, keeps them in `sent`, and answers as firmware 0.35 does (parameter `n` holds
// `n * 10` until a set changes it). It is both an `embedded_hal_nb` port (for `Client`) and an
// `embedded_io_async` one (for `AsyncClient`). `fake_clock` is the blocking helpers' clock;
// `FakeDelay` the async client's delay, which moves a clock that `FakeDelay::clock` reads;
// `block_on` runs a future on this thread. Paths are written out in full, so that an example
// imports whatever it names.

/// A fake AOK device at the far end of an in-memory serial port.
struct FakeDevice {
    /// Every byte the client wrote, in order.
    sent: Vec<u8>,
    /// What the device sent and the client has not read yet.
    to_pc: std::collections::VecDeque<u8>,
    decoder: aok_proto::CommandDecoder,
    /// Decides the parameter-reply form.
    firmware: aok_proto::FirmwareVersion,
    params: [i32; 256],
    waypoints: Vec<aok_proto::Waypoint>,
    /// The answer to a set (`73`, `77`, and `63 03..05` when `acks_sets`).
    ack: aok_proto::Ack,
    /// Whether the firmware also acks the flash-set commands (load, save, start set).
    acks_sets: bool,
    /// Whether the device is sending debug values (follows `63 01`, `63 02`).
    debug_on: bool,
    /// The error the next read gives, once.
    read_error: Option<embedded_hal_nb::serial::ErrorKind>,
    /// The error every write gives (the port is gone).
    write_error: Option<embedded_hal_nb::serial::ErrorKind>,
}

impl FakeDevice {
    /// Firmware 0.35, parameter `n` holding `n * 10`, every set acked with 'O'.
    fn new() -> Self {
        let mut params = [0; 256];
        for (n, p) in params.iter_mut().enumerate() {
            *p = n as i32 * 10;
        }
        FakeDevice {
            sent: Vec::new(),
            to_pc: std::collections::VecDeque::new(),
            decoder: aok_proto::CommandDecoder::new(),
            firmware: aok_proto::FirmwareVersion::LATEST,
            params,
            waypoints: Vec::new(),
            ack: aok_proto::Ack::Ok,
            acks_sets: false,
            debug_on: true,
            read_error: None,
            write_error: None,
        }
    }

    /// Puts a message on the line to the client.
    fn send(&mut self, message: aok_proto::Message) {
        let mut buf = [0; 19];
        let n = message.emit(&mut buf, self.firmware.reply_form()).unwrap();
        self.to_pc.extend(&buf[..n]);
    }

    /// Every write fails from now on, as on a port that is gone.
    fn unplug(&mut self) {
        self.write_error = Some(embedded_hal_nb::serial::ErrorKind::Other);
    }

    /// The bytes the client wrote since the last call.
    fn take_sent(&mut self) -> Vec<u8> {
        std::mem::take(&mut self.sent)
    }

    /// One byte from the client: decoded, and answered when it ends a command.
    fn from_pc(&mut self, byte: u8) {
        use aok_proto::{Command, Decode, Message, ParameterValue};
        self.sent.push(byte);
        let mut commands = Vec::new();
        self.decoder.feed(&[byte], |event| commands.push(event));
        for command in commands {
            match command.expect("the client wrote a bad frame") {
                Command::DebugOff => self.debug_on = false,
                Command::DebugOn | Command::Reset => self.debug_on = true,
                Command::ReadParameter(number) => {
                    let value = self.params[usize::from(number)];
                    self.send(Message::Parameter(ParameterValue { number, value }));
                }
                Command::BulkRead(first) => {
                    for i in 0..16 {
                        let number = first.wrapping_add(i);
                        let value = self.params[usize::from(number)];
                        self.send(Message::Parameter(ParameterValue { number, value }));
                    }
                }
                Command::SetParameter(p) => {
                    if self.ack == aok_proto::Ack::Ok {
                        self.params[usize::from(p.number)] = p.value;
                    }
                    self.send(Message::Ack(self.ack));
                }
                Command::SetWaypoint(w) => {
                    if self.ack == aok_proto::Ack::Ok {
                        self.waypoints.retain(|old| old.slot != w.slot);
                        self.waypoints.push(w);
                    }
                    self.send(Message::Ack(self.ack));
                }
                Command::ReadWaypoint(slot) => {
                    if let Some(&w) = self.waypoints.iter().find(|w| w.slot == slot) {
                        self.send(Message::Waypoint(w));
                    }
                }
                Command::LoadSet(_) | Command::SaveSet(_) | Command::StartSet(_)
                    if self.acks_sets =>
                {
                    self.send(Message::Ack(self.ack));
                }
                _ => {}
            }
        }
    }
}

impl embedded_hal_nb::serial::ErrorType for FakeDevice {
    type Error = embedded_hal_nb::serial::ErrorKind;
}

impl embedded_hal_nb::serial::Read<u8> for FakeDevice {
    fn read(&mut self) -> nb::Result<u8, Self::Error> {
        if let Some(e) = self.read_error.take() {
            return Err(nb::Error::Other(e));
        }
        self.to_pc.pop_front().ok_or(nb::Error::WouldBlock)
    }
}

impl embedded_hal_nb::serial::Write<u8> for FakeDevice {
    fn write(&mut self, byte: u8) -> nb::Result<(), Self::Error> {
        if let Some(e) = self.write_error {
            return Err(nb::Error::Other(e));
        }
        self.from_pc(byte);
        Ok(())
    }

    fn flush(&mut self) -> nb::Result<(), Self::Error> {
        Ok(())
    }
}

impl embedded_io_async::ErrorType for FakeDevice {
    type Error = embedded_io_async::ErrorKind;
}

impl embedded_io_async::Read for FakeDevice {
    /// What the device has sent; waits (for ever: a cancel-safe read) while it has sent nothing.
    async fn read(&mut self, buf: &mut [u8]) -> Result<usize, Self::Error> {
        if self.read_error.take().is_some() {
            return Err(embedded_io_async::ErrorKind::Other);
        }
        if self.to_pc.is_empty() {
            core::future::pending::<()>().await;
        }
        let n = buf.len().min(self.to_pc.len());
        for (slot, byte) in buf.iter_mut().zip(self.to_pc.drain(..n)) {
            *slot = byte;
        }
        Ok(n)
    }
}

impl embedded_io_async::Write for FakeDevice {
    async fn write(&mut self, buf: &[u8]) -> Result<usize, Self::Error> {
        if self.write_error.is_some() {
            return Err(embedded_io_async::ErrorKind::Other);
        }
        for &byte in buf {
            self.from_pc(byte);
        }
        Ok(buf.len())
    }

    async fn flush(&mut self) -> Result<(), Self::Error> {
        Ok(())
    }
}

/// A fake millisecond clock for the blocking helpers: 1 ms later at every call.
fn fake_clock() -> impl FnMut() -> u32 {
    let mut now = 0;
    move || {
        now += 1;
        now
    }
}

/// The async client's delay: it returns at once and moves a fake clock on by the time asked.
#[derive(Clone, Default)]
struct FakeDelay(std::rc::Rc<core::cell::Cell<u32>>);

impl FakeDelay {
    fn new() -> Self {
        Self::default()
    }

    /// The fake time in ms: the sum of the delays so far.
    fn now(&self) -> u32 {
        self.0.get()
    }

    /// A clock closure reading the fake time, for the async client's `now_ms`.
    fn clock(&self) -> impl FnMut() -> u32 + use<> {
        let time = self.0.clone();
        move || time.get()
    }
}

impl embedded_hal_async::delay::DelayNs for FakeDelay {
    async fn delay_ns(&mut self, ns: u32) {
        self.0.set(self.0.get() + ns.div_ceil(1_000_000));
    }
}

/// Runs a future to its end on this thread (it must not wait on anything but `FakeDelay`).
fn block_on<F: core::future::Future>(future: F) -> F::Output {
    let mut future = core::pin::pin!(future);
    let mut cx = core::task::Context::from_waker(core::task::Waker::noop());
    loop {
        if let core::task::Poll::Ready(out) = future.as_mut().poll(&mut cx) {
            return out;
        }
    }
}
