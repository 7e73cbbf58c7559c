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
pub const TICK_MS: u32 = 5;

/// Bytes the in-memory port holds in each direction.
const PIPE: usize = 32;

/// The in-memory port between the state machine and the async transport.
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
    /// See the type's example.
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

    /// The state machine, mutably (take debug values, [`Client::assume_debug`]). See
    /// [`AsyncClient::state`].
    pub fn state_mut(&mut self) -> &mut Client<Pipe> {
        &mut self.client
    }

    /// Gives the port and the delay back.
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
    /// let (_port, _delay) = client.release();
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
