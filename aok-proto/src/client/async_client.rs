//! [`AsyncClient`]: the PC-side [`Client`] over an async serial port.
//!
//! It is the same state machine as the blocking client (debug off, drain until quiet, request,
//! wait for the reply with a timeout, debug on again), driven through a small in-memory port:
//! the async side moves the bytes the state machine writes to the transport and the bytes the
//! transport delivers to the state machine, and waits for input or a tick of [`TICK_MS`],
//! whichever comes first.

use core::future::{Future, poll_fn};
use core::pin::pin;
use core::task::Poll;

use ::embedded_io_async::{Read, Write};
use embedded_hal_async::delay::DelayNs;
use embedded_hal_nb::serial::{self, ErrorKind};

use super::{Client, Config, Outcome};
use crate::ClientError;
use crate::command::{Command, ParameterValue};

/// The longest the async client waits for input before it looks at the clock again, in ms.
/// Timeouts and quiet times are measured to within this.
///
/// ```
/// # include!(concat!(env!("CARGO_MANIFEST_DIR"), "/src/client/doc_device.rs"));
/// # fn main() {
/// use aok_proto::client::{AsyncClient, TICK_MS};
/// use aok_proto::{ClientError, Command, Config, FirmwareVersion};
/// // A fake device (hidden here) that has no waypoint to send, and a delay that moves a fake
/// // clock.
/// let delay = FakeDelay::new();
/// let mut config = Config::new(FirmwareVersion::LATEST);
/// config.debug_on = false;
/// let mut client = AsyncClient::new(FakeDevice::new(), delay.clone(), config);
/// let read = client.run(Command::ReadWaypoint(aok_proto::WaypointSlot::RamPoi), delay.clock());
/// assert_eq!(block_on(read), Err(ClientError::Timeout));
/// // The client waited in ticks of TICK_MS, and gave up at the first tick past 1000 ms.
/// assert_eq!(delay.now() % TICK_MS, 0);
/// assert!((1000..1000 + TICK_MS).contains(&delay.now()));
/// # }
/// ```
pub const TICK_MS: u32 = 5;

/// Bytes the in-memory port holds in each direction.
const PIPE: usize = 32;

/// The in-memory port between the state machine and the async transport: the serial port of
/// the [`Client`] inside an [`AsyncClient`] ([`AsyncClient::state`]). Only the async client
/// makes one.
///
/// ```
/// # include!(concat!(env!("CARGO_MANIFEST_DIR"), "/src/client/doc_device.rs"));
/// # fn main() {
/// use aok_proto::client::{AsyncClient, Pipe};
/// use aok_proto::{Client, Config, DebugValue, FirmwareVersion, Message};
/// /// Takes the debug values the state machine has received.
/// fn debug_values(state: &mut Client<Pipe>) -> Vec<DebugValue> {
///     core::iter::from_fn(|| state.next_debug()).collect()
/// }
/// // A fake device (hidden here) sends the flight status before the client turns debug off.
/// let mut device = FakeDevice::new();
/// device.send(Message::Debug(DebugValue { number: 86, value: 3 }));
/// let delay = FakeDelay::new();
/// let mut client = AsyncClient::new(device, delay.clone(), Config::new(FirmwareVersion::LATEST));
/// assert_eq!(block_on(client.read_parameter(12, delay.clock())), Ok(120));
/// assert_eq!(debug_values(client.state_mut()), [DebugValue { number: 86, value: 3 }]);
/// # }
/// ```
#[derive(Debug)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Pipe {
    rx: [u8; PIPE],
    rx_start: usize,
    rx_end: usize,
    tx: [u8; PIPE],
    tx_len: usize,
    /// A transport read failed: the state machine sees one read error (and counts it).
    read_failed: bool,
    /// A transport write failed: the state machine's next write or flush fails.
    write_failed: bool,
}

impl Pipe {
    const fn new() -> Self {
        Self {
            rx: [0; PIPE],
            rx_start: 0,
            rx_end: 0,
            tx: [0; PIPE],
            tx_len: 0,
            read_failed: false,
            write_failed: false,
        }
    }
}

impl serial::ErrorType for Pipe {
    type Error = ErrorKind;
}

impl serial::Read<u8> for Pipe {
    fn read(&mut self) -> nb::Result<u8, ErrorKind> {
        if core::mem::take(&mut self.read_failed) {
            return Err(nb::Error::Other(ErrorKind::Other));
        }
        if self.rx_start >= self.rx_end {
            return Err(nb::Error::WouldBlock);
        }
        let b = self.rx.get(self.rx_start).copied().unwrap_or(0);
        self.rx_start = self.rx_start.saturating_add(1);
        Ok(b)
    }
}

impl serial::Write<u8> for Pipe {
    fn write(&mut self, byte: u8) -> nb::Result<(), ErrorKind> {
        if core::mem::take(&mut self.write_failed) {
            return Err(nb::Error::Other(ErrorKind::Other));
        }
        let slot = self.tx.get_mut(self.tx_len).ok_or(nb::Error::WouldBlock)?;
        *slot = byte;
        self.tx_len = self.tx_len.saturating_add(1);
        Ok(())
    }

    fn flush(&mut self) -> nb::Result<(), ErrorKind> {
        if core::mem::take(&mut self.write_failed) {
            return Err(nb::Error::Other(ErrorKind::Other));
        }
        if self.tx_len == 0 {
            Ok(())
        } else {
            Err(nb::Error::WouldBlock)
        }
    }
}

/// The PC-side AOK client over an async serial port `S` (`embedded_io_async::Read + Write`,
/// both halves; see the crate README for split ports), waiting with a `DelayNs`.
///
/// The transport's `read` must be cancel-safe (embassy's buffered and ring-buffered UARTs
/// are): a read that waits longer than [`TICK_MS`] is dropped so the client can check its
/// timeouts. `now_ms` is any wrapping millisecond clock, as for [`Client::run`].
///
/// ```
/// use aok_proto::{client::AsyncClient, ClientError, Config, FirmwareVersion, Outcome, Command};
/// # fn block_on<F: core::future::Future>(f: F) -> F::Output {
/// #     let mut f = core::pin::pin!(f);
/// #     let mut cx = core::task::Context::from_waker(core::task::Waker::noop());
/// #     loop { if let core::task::Poll::Ready(v) = f.as_mut().poll(&mut cx) { return v; } }
/// # }
/// /// A port where nobody answers: reads wait forever, writes go nowhere.
/// struct Silent;
/// impl embedded_io_async::ErrorType for Silent { type Error = core::convert::Infallible; }
/// impl embedded_io_async::Read for Silent {
///     async fn read(&mut self, _: &mut [u8]) -> Result<usize, Self::Error> {
///         core::future::pending().await
///     }
/// }
/// impl embedded_io_async::Write for Silent {
///     async fn write(&mut self, buf: &[u8]) -> Result<usize, Self::Error> { Ok(buf.len()) }
///     async fn flush(&mut self) -> Result<(), Self::Error> { Ok(()) }
/// }
/// /// A delay that moves a fake clock.
/// struct Clock(std::rc::Rc<core::cell::Cell<u32>>);
/// impl embedded_hal_async::delay::DelayNs for Clock {
///     async fn delay_ns(&mut self, ns: u32) { self.0.set(self.0.get() + ns.div_ceil(1_000_000)); }
/// }
///
/// let t = std::rc::Rc::new(core::cell::Cell::new(0));
/// let mut config = Config::new(FirmwareVersion::LATEST);
/// config.debug_on = false;
/// let mut client = AsyncClient::new(Silent, Clock(t.clone()), config);
/// // No reply defined for a save-set: done once written.
/// assert_eq!(block_on(client.run(Command::SaveSet(1), || t.get())), Ok(Outcome::Sent));
/// // Nobody answers the read: a timeout after 1000 ms of the fake clock.
/// assert_eq!(block_on(client.read_parameter(12, || t.get())), Err(ClientError::Timeout));
/// assert!(t.get() >= 1000);
/// ```
#[derive(Debug)]
pub struct AsyncClient<S, D> {
    client: Client<Pipe>,
    serial: S,
    delay: D,
}

impl<S: Read + Write, D: DelayNs> AsyncClient<S, D> {
    /// A client on this port.
    ///
    /// ```
    /// # struct P;
    /// # impl embedded_io_async::ErrorType for P { type Error = core::convert::Infallible; }
    /// # impl embedded_io_async::Read for P {
    /// #     async fn read(&mut self, _: &mut [u8]) -> Result<usize, Self::Error> { Ok(0) } }
    /// # impl embedded_io_async::Write for P {
    /// #     async fn write(&mut self, b: &[u8]) -> Result<usize, Self::Error> { Ok(b.len()) }
    /// #     async fn flush(&mut self) -> Result<(), Self::Error> { Ok(()) } }
    /// # struct D;
    /// # impl embedded_hal_async::delay::DelayNs for D { async fn delay_ns(&mut self, _: u32) {} }
    /// use aok_proto::{client::AsyncClient, Config, FirmwareVersion};
    /// let client = AsyncClient::new(P, D, Config::new(FirmwareVersion::LATEST));
    /// assert!(client.state().debug_enabled());
    /// ```
    pub fn new(serial: S, delay: D, config: Config) -> Self {
        Self {
            client: Client::new(Pipe::new(), config),
            serial,
            delay,
        }
    }

    /// Runs `command` to its end (the reply [`Command::expected_reply`] defines, or a
    /// timeout), reading the time from `now_ms`. See the type's example.
    ///
    /// # Errors
    /// As [`Client::run`]: [`ClientError::Timeout`], [`ClientError::Rejected`], [`ClientError::Busy`],
    /// [`ClientError::Serial`] when the transport fails (its error reduced to a kind), ...
    ///
    /// ```
    /// # include!(concat!(env!("CARGO_MANIFEST_DIR"), "/src/client/doc_device.rs"));
    /// # fn main() {
    /// use aok_proto::client::AsyncClient;
    /// use aok_proto::{ClientError, Command, Config, FirmwareVersion, Outcome, ParameterValue,
    ///                 SerialError};
    /// // A fake device (hidden here) where parameter n holds n * 10, and a delay that moves a
    /// // fake clock, which `delay.clock()` reads.
    /// let delay = FakeDelay::new();
    /// let mut client = AsyncClient::new(FakeDevice::new(), delay.clone(),
    ///                                   Config::new(FirmwareVersion::LATEST));
    /// let outcome = block_on(client.run(Command::ReadParameter(12), delay.clock()));
    /// assert_eq!(outcome, Ok(Outcome::Parameter(ParameterValue { number: 12, value: 120 })));
    /// // The drain after debug-off waited for 50 quiet ms.
    /// assert!(delay.now() >= 50);
    /// let (mut device, delay) = client.release();
    /// assert_eq!(device.take_sent(), [0x63, 0x01, 0x67, 0x0C, 0x63, 0x02]);
    ///
    /// // The port fails: the transport's error, reduced to a kind.
    /// device.unplug();
    /// let mut client = AsyncClient::new(device, delay.clone(), Config::new(FirmwareVersion::LATEST));
    /// let failed = block_on(client.run(Command::SaveSet(1), delay.clock()));
    /// assert_eq!(failed, Err(ClientError::Serial(SerialError::Other)));
    /// # }
    /// ```
    pub async fn run(
        &mut self,
        command: Command,
        mut now_ms: impl FnMut() -> u32,
    ) -> Result<Outcome, ClientError> {
        self.client.start(command)?;
        loop {
            match self.client.poll(now_ms()) {
                Ok(outcome) => return Ok(outcome),
                Err(nb::Error::Other(e)) => return Err(e),
                Err(nb::Error::WouldBlock) => {}
            }
            self.pump().await;
        }
    }

    /// Reads one parameter.
    ///
    /// # Errors
    /// As [`AsyncClient::run`].
    ///
    /// ```
    /// # include!(concat!(env!("CARGO_MANIFEST_DIR"), "/src/client/doc_device.rs"));
    /// # fn main() {
    /// use aok_proto::client::AsyncClient;
    /// use aok_proto::{Config, FirmwareVersion};
    /// // A fake device (hidden here) and a delay that moves a fake clock.
    /// let mut device = FakeDevice::new();
    /// device.params[12] = 1500;
    /// let delay = FakeDelay::new();
    /// let mut client = AsyncClient::new(device, delay.clone(), Config::new(FirmwareVersion::LATEST));
    /// assert_eq!(block_on(client.read_parameter(12, delay.clock())), Ok(1500));
    /// assert_eq!(block_on(client.read_parameter(13, delay.clock())), Ok(130));
    /// // Debug output is on again after each read.
    /// assert!(client.state().debug_enabled());
    /// # }
    /// ```
    pub async fn read_parameter(
        &mut self,
        number: u8,
        now_ms: impl FnMut() -> u32,
    ) -> Result<i32, ClientError> {
        match self.run(Command::ReadParameter(number), now_ms).await? {
            Outcome::Parameter(p) => Ok(p.value),
            _ => Err(ClientError::Timeout),
        }
    }

    /// Sets a parameter and waits for the ack ('E' and 'I' come back as [`ClientError::Rejected`]
    /// and [`ClientError::RefusedInFlight`]).
    ///
    /// # Errors
    /// As [`AsyncClient::run`].
    ///
    /// ```
    /// # struct P;
    /// # impl embedded_io_async::ErrorType for P { type Error = core::convert::Infallible; }
    /// # impl embedded_io_async::Read for P {
    /// #     async fn read(&mut self, b: &mut [u8]) -> Result<usize, Self::Error> { b[0] = b'E'; Ok(1) } }
    /// # impl embedded_io_async::Write for P {
    /// #     async fn write(&mut self, b: &[u8]) -> Result<usize, Self::Error> { Ok(b.len()) }
    /// #     async fn flush(&mut self) -> Result<(), Self::Error> { Ok(()) } }
    /// # struct D;
    /// # impl embedded_hal_async::delay::DelayNs for D { async fn delay_ns(&mut self, _: u32) {} }
    /// # fn block_on<F: core::future::Future>(f: F) -> F::Output {
    /// #     let mut f = core::pin::pin!(f);
    /// #     let mut cx = core::task::Context::from_waker(core::task::Waker::noop());
    /// #     loop { if let core::task::Poll::Ready(v) = f.as_mut().poll(&mut cx) { return v; } }
    /// # }
    /// use aok_proto::{client::AsyncClient, ClientError, Config, FirmwareVersion};
    /// // A device that answers every byte with 'E'.
    /// let mut config = Config::new(FirmwareVersion::LATEST);
    /// config.debug_on = false;
    /// let mut client = AsyncClient::new(P, D, config);
    /// assert_eq!(block_on(client.set_parameter(12, 1500, || 0)), Err(ClientError::Rejected));
    /// ```
    pub async fn set_parameter(
        &mut self,
        number: u8,
        value: i32,
        now_ms: impl FnMut() -> u32,
    ) -> Result<(), ClientError> {
        let command = Command::SetParameter(ParameterValue { number, value });
        self.run(command, now_ms).await.map(|_| ())
    }

    /// The state machine: debug values received ([`Client::next_debug`]), counters, the
    /// debug-output flag.
    ///
    /// ```
    /// # struct P;
    /// # impl embedded_io_async::ErrorType for P { type Error = core::convert::Infallible; }
    /// # impl embedded_io_async::Read for P {
    /// #     async fn read(&mut self, _: &mut [u8]) -> Result<usize, Self::Error> { Ok(0) } }
    /// # impl embedded_io_async::Write for P {
    /// #     async fn write(&mut self, b: &[u8]) -> Result<usize, Self::Error> { Ok(b.len()) }
    /// #     async fn flush(&mut self) -> Result<(), Self::Error> { Ok(()) } }
    /// # struct D;
    /// # impl embedded_hal_async::delay::DelayNs for D { async fn delay_ns(&mut self, _: u32) {} }
    /// use aok_proto::{client::AsyncClient, Config, FirmwareVersion};
    /// let mut client = AsyncClient::new(P, D, Config::new(FirmwareVersion::LATEST));
    /// assert_eq!(client.state().stats().read_errors, 0);
    /// assert_eq!(client.state_mut().next_debug(), None);
    /// ```
    pub const fn state(&self) -> &Client<Pipe> {
        &self.client
    }

    /// The state machine, mutably (take debug values, [`Client::assume_debug`]).
    ///
    /// ```
    /// # include!(concat!(env!("CARGO_MANIFEST_DIR"), "/src/client/doc_device.rs"));
    /// # fn main() {
    /// use aok_proto::client::AsyncClient;
    /// use aok_proto::{Config, FirmwareVersion};
    /// // A fake device (hidden here) reconnected with debug output off, and a fake delay.
    /// let delay = FakeDelay::new();
    /// let mut client = AsyncClient::new(FakeDevice::new(), delay.clone(),
    ///                                   Config::new(FirmwareVersion::LATEST));
    /// client.state_mut().assume_debug(false);
    /// assert_eq!(block_on(client.read_parameter(12, delay.clock())), Ok(120));
    /// // Only the request went out: no debug off and on, no drain.
    /// assert_eq!(client.release().0.take_sent(), [0x67, 0x0C]);
    /// assert!(delay.now() < 50);
    /// # }
    /// ```
    pub fn state_mut(&mut self) -> &mut Client<Pipe> {
        &mut self.client
    }

    /// Gives the port and the delay back.
    ///
    /// ```
    /// # include!(concat!(env!("CARGO_MANIFEST_DIR"), "/src/client/doc_device.rs"));
    /// # fn main() {
    /// use aok_proto::client::AsyncClient;
    /// use aok_proto::{Config, FirmwareVersion};
    /// // A fake device (hidden here) and a delay that moves a fake clock.
    /// let delay = FakeDelay::new();
    /// let mut client = AsyncClient::new(FakeDevice::new(), delay.clone(),
    ///                                   Config::new(FirmwareVersion::LATEST));
    /// assert_eq!(block_on(client.set_parameter(12, 1500, delay.clock())), Ok(()));
    /// let (device, _delay) = client.release();
    /// assert_eq!(device.params[12], 1500);
    /// assert!(device.debug_on);
    /// # }
    /// ```
    pub fn release(self) -> (S, D) {
        (self.serial, self.delay)
    }

    /// Moves what the state machine wrote out to the transport; otherwise waits for input (or
    /// a tick) and hands it over.
    async fn pump(&mut self) {
        let pipe = self.client.serial_mut();
        if pipe.tx_len > 0 {
            let out = pipe.tx.get(..pipe.tx_len).unwrap_or(&[]);
            let sent = write_all(&mut self.serial, out).await;
            let sent = match sent {
                Ok(()) => self.serial.flush().await.is_ok(),
                Err(()) => false,
            };
            pipe.tx_len = 0;
            pipe.write_failed = !sent;
            return;
        }
        if pipe.rx_start < pipe.rx_end {
            return;
        }
        let read = self.serial.read(&mut pipe.rx);
        let tick = self.delay.delay_ms(TICK_MS);
        match select(read, tick).await {
            Some(Ok(n)) => {
                pipe.rx_start = 0;
                pipe.rx_end = n.min(PIPE);
                if n == 0 {
                    // End of stream: nothing more will come; let the clock run.
                    self.delay.delay_ms(TICK_MS).await;
                }
            }
            Some(Err(_)) => pipe.read_failed = true,
            None => {}
        }
    }
}

/// Writes all of `buf`; `Err` on a transport error or a write of 0 bytes.
async fn write_all<S: Write>(serial: &mut S, mut buf: &[u8]) -> Result<(), ()> {
    while !buf.is_empty() {
        match serial.write(buf).await {
            Ok(0) | Err(_) => return Err(()),
            Ok(n) => buf = buf.get(n..).unwrap_or(&[]),
        }
    }
    Ok(())
}

/// The output of `first` if it finishes first, else `None` when `second` does.
async fn select<A: Future, B: Future>(first: A, second: B) -> Option<A::Output> {
    let mut first = pin!(first);
    let mut second = pin!(second);
    poll_fn(|cx| {
        if let Poll::Ready(out) = first.as_mut().poll(cx) {
            return Poll::Ready(Some(out));
        }
        if second.as_mut().poll(cx).is_ready() {
            return Poll::Ready(None);
        }
        Poll::Pending
    })
    .await
}
