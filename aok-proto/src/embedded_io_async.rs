//! Async AOK over [`embedded_io_async`] (feature `embedded-io-async`), for embassy
//! and other executors.
//!
//! - [`MessageReader`] (PC side) owns a [`PcDecoder`] and [`CommandReader`] (device side) a
//!   [`DeviceDecoder`], each with a read buffer of `R` bytes; [`MessageReader::read_message`]
//!   and [`CommandReader::read_command`] return the next item. Every read is decoded with the
//!   bulk path of `feed` (frames parsed in place in the read buffer), and the items are
//!   exactly those of `push` and `poll` byte by byte; at the end of the stream, those of `idle`.
//! - [`Writer`] writes commands (PC side) and messages (device side) into a [`Write`].
//! - [`AsyncClient`] is the PC-side [`Client`](crate::Client) over an async port.
//!
//! The blocking twins are in [`crate::embedded_io`] and behave the same. Errors are
//! [`IoError`]. Dropping a read future loses no decoded state; it loses the bytes of a read
//! in progress only if the transport's `read` is not cancel-safe.

use ::embedded_io_async::{Read, Write};

mod client;
pub use client::{AsyncClient, Pipe, TICK_MS};

use crate::io::{ReaderCore, Stream, command_bytes, message_bytes};
use crate::{Command, DeviceDecoder, FirmwareVersion, IoError, Message, PcDecoder, ReplyForm};

/// Reads what the device sends (debug frames, replies, acks) from an async [`Read`]: a
/// [`PcDecoder`] plus an `R`-byte read buffer.
///
/// ```
/// # fn block_on<F: core::future::Future>(f: F) -> F::Output {
/// #     let mut f = core::pin::pin!(f);
/// #     let mut cx = core::task::Context::from_waker(core::task::Waker::noop());
/// #     loop { if let core::task::Poll::Ready(v) = f.as_mut().poll(&mut cx) { return v; } }
/// # }
/// use aok_proto::{embedded_io_async::MessageReader, pc::Expect, Ack, DebugValue, FirmwareVersion,
///                 IoError, Message};
///
/// // A debug frame and an ack.
/// let wire: &[u8] = &[0x1c, 0x56, 0xff, 0xff, 0xff, 0xfe, 0x57, b'O'];
/// let mut reader = MessageReader::<_>::new(wire, FirmwareVersion::LATEST);
/// reader.decoder_mut().expect(Expect::Ack);
/// assert_eq!(block_on(reader.read_message()), Ok(Message::Debug(DebugValue { number: 86, value: -2 })));
/// assert_eq!(block_on(reader.read_message()), Ok(Message::Ack(Ack::Ok)));
/// assert_eq!(block_on(reader.read_message()), Err(IoError::Eof));
/// ```
#[derive(Debug, Clone)]
pub struct MessageReader<T, const R: usize = 32> {
    inner: T,
    core: ReaderCore<PcDecoder, R>,
}

impl<T: Read, const R: usize> MessageReader<T, R> {
    /// A reader with a fresh decoder for a device with this firmware.
    ///
    /// ```
    /// use aok_proto::{embedded_io_async::MessageReader, FirmwareVersion, ReplyForm};
    /// let reader = MessageReader::<_, 16>::new(&[][..], FirmwareVersion::new(0, 30));
    /// assert_eq!(reader.decoder().reply_form(), ReplyForm::Headerless);
    /// ```
    pub const fn new(inner: T, firmware: FirmwareVersion) -> Self {
        Self::with_decoder(inner, PcDecoder::new(firmware))
    }

    /// A reader around a decoder the caller already has.
    ///
    /// ```
    /// use aok_proto::{embedded_io_async::MessageReader, FirmwareVersion, PcDecoder};
    /// let reader = MessageReader::<_>::with_decoder(&[][..], PcDecoder::new(FirmwareVersion::LATEST));
    /// assert_eq!(reader.unread(), 0);
    /// ```
    pub const fn with_decoder(inner: T, decoder: PcDecoder) -> Self {
        Self {
            inner,
            core: ReaderCore::new(decoder),
        }
    }

    /// Reads until the next message and returns it.
    ///
    /// # Errors
    /// - [`IoError::Protocol`]: a frame failed its checksum or held an out-of-range field;
    ///   call again.
    /// - [`IoError::Transport`]: the read failed; bytes already read are kept.
    /// - [`IoError::UnexpectedEof`]: the stream ended inside a frame; what the rescan of its
    ///   bytes finds follows, then [`IoError::Eof`].
    /// - [`IoError::Eof`]: the stream ended and nothing is buffered.
    ///
    /// ```
    /// # fn block_on<F: core::future::Future>(f: F) -> F::Output {
    /// #     let mut f = core::pin::pin!(f);
    /// #     let mut cx = core::task::Context::from_waker(core::task::Waker::noop());
    /// #     loop { if let core::task::Poll::Ready(v) = f.as_mut().poll(&mut cx) { return v; } }
    /// # }
    /// use aok_proto::{embedded_io_async::MessageReader, pc::Expect, FirmwareVersion, IoError, Message,
    ///                 ParameterValue};
    /// // A headerless (<= 0.30) reply to "read 12", read one byte at a time.
    /// let wire: &[u8] = &[0x00, 0x00, 0x05, 0xdc, 0xd9];
    /// let mut reader = MessageReader::<_, 1>::new(wire, FirmwareVersion::new(0, 30));
    /// reader.decoder_mut().expect(Expect::Parameter(12));
    /// assert_eq!(block_on(reader.read_message()),
    ///            Ok(Message::Parameter(ParameterValue { number: 12, value: 1500 })));
    /// ```
    pub async fn read_message(&mut self) -> Result<Message, IoError<T::Error>> {
        next_item(&mut self.inner, &mut self.core).await
    }

    /// The decoder (counters, pending request).
    ///
    /// ```
    /// # fn block_on<F: core::future::Future>(f: F) -> F::Output {
    /// #     let mut f = core::pin::pin!(f);
    /// #     let mut cx = core::task::Context::from_waker(core::task::Waker::noop());
    /// #     loop { if let core::task::Poll::Ready(v) = f.as_mut().poll(&mut cx) { return v; } }
    /// # }
    /// use aok_proto::{embedded_io_async::MessageReader, FirmwareVersion};
    /// let mut reader = MessageReader::<_>::new(&[0x00][..], FirmwareVersion::LATEST);
    /// let _ = block_on(reader.read_message());
    /// assert_eq!(reader.decoder().stats().unknown_bytes, 1);
    /// ```
    pub const fn decoder(&self) -> &PcDecoder {
        &self.core.decoder
    }

    /// The decoder, mutably: tell it what the PC waits for ([`PcDecoder::expect`]) right
    /// before sending a request. See the type's example.
    ///
    /// ```
    /// use aok_proto::{embedded_io_async::MessageReader, pc::Expect, FirmwareVersion};
    /// let mut reader = MessageReader::<_>::new(&[][..], FirmwareVersion::LATEST);
    /// reader.decoder_mut().expect(Expect::Ack);
    /// assert_eq!(reader.decoder().expecting(), Expect::Ack);
    /// ```
    pub fn decoder_mut(&mut self) -> &mut PcDecoder {
        &mut self.core.decoder
    }

    /// Bytes read from the transport and not decoded yet.
    ///
    /// ```
    /// # fn block_on<F: core::future::Future>(f: F) -> F::Output {
    /// #     let mut f = core::pin::pin!(f);
    /// #     let mut cx = core::task::Context::from_waker(core::task::Waker::noop());
    /// #     loop { if let core::task::Poll::Ready(v) = f.as_mut().poll(&mut cx) { return v; } }
    /// # }
    /// use aok_proto::{embedded_io_async::MessageReader, FirmwareVersion};
    /// let wire: &[u8] = &[0x1c, 0x56, 0xff, 0xff, 0xff, 0xfe, 0x57, 0x00];
    /// let mut reader = MessageReader::<_>::new(wire, FirmwareVersion::LATEST);
    /// block_on(reader.read_message()).unwrap();
    /// assert_eq!(reader.unread(), 1);
    /// ```
    pub fn unread(&self) -> usize {
        self.core.unread()
    }

    /// The transport.
    ///
    /// ```
    /// use aok_proto::{embedded_io_async::MessageReader, FirmwareVersion};
    /// let reader = MessageReader::<_>::new(&[1u8][..], FirmwareVersion::LATEST);
    /// assert_eq!(reader.get_ref().len(), 1);
    /// ```
    pub const fn get_ref(&self) -> &T {
        &self.inner
    }

    /// The transport, mutably (bytes read around the reader are not decoded).
    ///
    /// ```
    /// use aok_proto::{embedded_io_async::MessageReader, FirmwareVersion};
    /// let mut reader = MessageReader::<_>::new(&[1u8][..], FirmwareVersion::LATEST);
    /// *reader.get_mut() = &[];
    /// ```
    pub fn get_mut(&mut self) -> &mut T {
        &mut self.inner
    }

    /// Gives the transport back; bytes read and not decoded are lost.
    ///
    /// ```
    /// use aok_proto::{embedded_io_async::MessageReader, FirmwareVersion};
    /// let reader = MessageReader::<_>::new(&[1u8][..], FirmwareVersion::LATEST);
    /// assert_eq!(reader.into_inner(), &[1]);
    /// ```
    pub fn into_inner(self) -> T {
        self.inner
    }
}

/// Reads the PC's commands (device side) from an async [`Read`]: a [`DeviceDecoder`] plus
/// an `R`-byte read buffer.
///
/// ```
/// # fn block_on<F: core::future::Future>(f: F) -> F::Output {
/// #     let mut f = core::pin::pin!(f);
/// #     let mut cx = core::task::Context::from_waker(core::task::Waker::noop());
/// #     loop { if let core::task::Poll::Ready(v) = f.as_mut().poll(&mut cx) { return v; } }
/// # }
/// use aok_proto::{embedded_io_async::CommandReader, Command, Error, IoError};
/// // A motor-test start whose checksum fails, then "read parameter 12".
/// let wire: &[u8] = &[0x31, 0x67, 0x0c];
/// let mut reader = CommandReader::<_>::new(wire);
/// let mismatch = Error::ChecksumMismatch { id: 0x31, computed: 0x56, received: 0x0c };
/// assert_eq!(block_on(reader.read_command()), Err(IoError::Protocol(mismatch)));
/// assert_eq!(block_on(reader.read_command()), Ok(Command::ReadParameter(12)));
/// assert_eq!(block_on(reader.read_command()), Err(IoError::Eof));
/// ```
#[derive(Debug, Clone)]
pub struct CommandReader<T, const R: usize = 32> {
    inner: T,
    core: ReaderCore<DeviceDecoder, R>,
}

impl<T: Read, const R: usize> CommandReader<T, R> {
    /// A reader with a fresh decoder.
    ///
    /// ```
    /// let reader = aok_proto::embedded_io_async::CommandReader::<_, 8>::new(&[][..]);
    /// assert_eq!(reader.decoder().held_bytes(), 0);
    /// ```
    pub const fn new(inner: T) -> Self {
        Self {
            inner,
            core: ReaderCore::new(DeviceDecoder::new()),
        }
    }

    /// Reads until the next command and returns it.
    ///
    /// # Errors
    /// - [`IoError::Protocol`]: a frame failed its checksum (answer 'E' if you like) or held
    ///   an out-of-range field; call again.
    /// - [`IoError::Transport`]: the read failed; bytes already read are kept.
    /// - [`IoError::UnexpectedEof`]: the stream ended inside a command; what the rescan of
    ///   its bytes finds follows, then [`IoError::Eof`].
    /// - [`IoError::Eof`]: the stream ended and nothing is buffered.
    ///
    /// ```
    /// # fn block_on<F: core::future::Future>(f: F) -> F::Output {
    /// #     let mut f = core::pin::pin!(f);
    /// #     let mut cx = core::task::Context::from_waker(core::task::Waker::noop());
    /// #     loop { if let core::task::Poll::Ready(v) = f.as_mut().poll(&mut cx) { return v; } }
    /// # }
    /// use aok_proto::{embedded_io_async::CommandReader, Command, IoError};
    /// // "set parameter" cut short by the end of the stream, with "debug on" inside it.
    /// let mut reader = CommandReader::<_>::new(&[0x73, 0x63, 0x02][..]);
    /// assert_eq!(block_on(reader.read_command()), Err(IoError::UnexpectedEof { pending: 3 }));
    /// assert_eq!(block_on(reader.read_command()), Ok(Command::DebugOn));
    /// assert_eq!(block_on(reader.read_command()), Err(IoError::Eof));
    /// ```
    pub async fn read_command(&mut self) -> Result<Command, IoError<T::Error>> {
        next_item(&mut self.inner, &mut self.core).await
    }

    /// The decoder, for its counters.
    ///
    /// ```
    /// # fn block_on<F: core::future::Future>(f: F) -> F::Output {
    /// #     let mut f = core::pin::pin!(f);
    /// #     let mut cx = core::task::Context::from_waker(core::task::Waker::noop());
    /// #     loop { if let core::task::Poll::Ready(v) = f.as_mut().poll(&mut cx) { return v; } }
    /// # }
    /// let mut reader = aok_proto::embedded_io_async::CommandReader::<_>::new(&[0x63, 0x01][..]);
    /// block_on(reader.read_command()).unwrap();
    /// assert_eq!(reader.decoder().stats().frames_ok, 1);
    /// ```
    pub const fn decoder(&self) -> &DeviceDecoder {
        &self.core.decoder
    }

    /// Bytes read from the transport and not decoded yet.
    ///
    /// ```
    /// # fn block_on<F: core::future::Future>(f: F) -> F::Output {
    /// #     let mut f = core::pin::pin!(f);
    /// #     let mut cx = core::task::Context::from_waker(core::task::Waker::noop());
    /// #     loop { if let core::task::Poll::Ready(v) = f.as_mut().poll(&mut cx) { return v; } }
    /// # }
    /// let mut reader = aok_proto::embedded_io_async::CommandReader::<_>::new(&[0x63, 0x01, 0x63][..]);
    /// block_on(reader.read_command()).unwrap();
    /// assert_eq!(reader.unread(), 1);
    /// ```
    pub fn unread(&self) -> usize {
        self.core.unread()
    }

    /// The transport, mutably (bytes read around the reader are not decoded).
    ///
    /// ```
    /// let mut reader = aok_proto::embedded_io_async::CommandReader::<_>::new(&[1u8][..]);
    /// *reader.get_mut() = &[];
    /// ```
    pub fn get_mut(&mut self) -> &mut T {
        &mut self.inner
    }

    /// Gives the transport back; bytes read and not decoded are lost.
    ///
    /// ```
    /// let reader = aok_proto::embedded_io_async::CommandReader::<_>::new(&[1u8][..]);
    /// assert_eq!(reader.into_inner(), &[1]);
    /// ```
    pub fn into_inner(self) -> T {
        self.inner
    }
}

async fn next_item<T: Read, D: Stream, const R: usize>(
    inner: &mut T,
    core: &mut ReaderCore<D, R>,
) -> Result<D::Item, IoError<T::Error>> {
    loop {
        if let Some(step) = core.decode() {
            return step;
        }
        let n = inner.read(core.space()).await.map_err(IoError::Transport)?;
        if let Some(step) = core.filled(n) {
            return step;
        }
    }
}

/// Writes AOK frames into an async [`Write`]: commands on the PC side, messages (debug
/// values, acks, replies) on the device side.
///
/// ```
/// # fn block_on<F: core::future::Future>(f: F) -> F::Output {
/// #     let mut f = core::pin::pin!(f);
/// #     let mut cx = core::task::Context::from_waker(core::task::Waker::noop());
/// #     loop { if let core::task::Poll::Ready(v) = f.as_mut().poll(&mut cx) { return v; } }
/// # }
/// use aok_proto::{embedded_io_async::Writer, Command, ParameterValue};
/// let mut wire = [0u8; 19];
/// let mut writer = Writer::new(&mut wire[..]);
/// let n = block_on(writer.write_command(&Command::SetParameter(ParameterValue { number: 12, value: 1500 })))?;
/// assert_eq!(&wire[..n], &[0x73, 0x0c, 0x00, 0x00, 0x05, 0xdc, 0xd5]);
/// # Ok::<(), aok_proto::IoError<embedded_io::SliceWriteError>>(())
/// ```
#[derive(Debug, Clone)]
pub struct Writer<W> {
    inner: W,
}

impl<W: Write> Writer<W> {
    /// A writer into `inner`.
    ///
    /// ```
    /// let mut buf = [0u8; 8];
    /// let writer = aok_proto::embedded_io_async::Writer::new(&mut buf[..]);
    /// assert_eq!(writer.into_inner().len(), 8);
    /// ```
    pub const fn new(inner: W) -> Self {
        Self { inner }
    }

    /// Writes a command (PC side); returns the bytes written. It does not flush.
    ///
    /// # Errors
    /// [`IoError::Transport`] or [`IoError::WriteZero`]; the command may be partly sent.
    ///
    /// ```
    /// # fn block_on<F: core::future::Future>(f: F) -> F::Output {
    /// #     let mut f = core::pin::pin!(f);
    /// #     let mut cx = core::task::Context::from_waker(core::task::Waker::noop());
    /// #     loop { if let core::task::Poll::Ready(v) = f.as_mut().poll(&mut cx) { return v; } }
    /// # }
    /// use aok_proto::{embedded_io_async::Writer, Command};
    /// let mut wire = [0u8; 4];
    /// assert_eq!(block_on(Writer::new(&mut wire[..]).write_command(&Command::DebugOff)), Ok(2));
    /// assert_eq!(&wire[..2], &[0x63, 0x01]);
    /// ```
    pub async fn write_command(&mut self, command: &Command) -> Result<usize, IoError<W::Error>> {
        let (frame, n) = command_bytes(command);
        write_all(&mut self.inner, frame.get(..n).unwrap_or(&[])).await?;
        Ok(n)
    }

    /// Writes a device message in the firmware's reply `form` (device side); returns the
    /// bytes written. It does not flush.
    ///
    /// # Errors
    /// [`IoError::Protocol`] if the message cannot be encoded (nothing is written);
    /// [`IoError::Transport`] or [`IoError::WriteZero`].
    ///
    /// ```
    /// # fn block_on<F: core::future::Future>(f: F) -> F::Output {
    /// #     let mut f = core::pin::pin!(f);
    /// #     let mut cx = core::task::Context::from_waker(core::task::Waker::noop());
    /// #     loop { if let core::task::Poll::Ready(v) = f.as_mut().poll(&mut cx) { return v; } }
    /// # }
    /// use aok_proto::{embedded_io_async::Writer, Ack, Message, ReplyForm};
    /// let mut wire = [0u8; 4];
    /// assert_eq!(block_on(Writer::new(&mut wire[..]).write_message(&Message::Ack(Ack::Ok), ReplyForm::Headed)), Ok(1));
    /// assert_eq!(wire[0], b'O');
    /// ```
    pub async fn write_message(
        &mut self,
        message: &Message,
        form: ReplyForm,
    ) -> Result<usize, IoError<W::Error>> {
        let (frame, n) = message_bytes(message, form).map_err(IoError::Protocol)?;
        write_all(&mut self.inner, frame.get(..n).unwrap_or(&[])).await?;
        Ok(n)
    }

    /// Flushes the transport.
    ///
    /// # Errors
    /// [`IoError::Transport`].
    ///
    /// ```
    /// # fn block_on<F: core::future::Future>(f: F) -> F::Output {
    /// #     let mut f = core::pin::pin!(f);
    /// #     let mut cx = core::task::Context::from_waker(core::task::Waker::noop());
    /// #     loop { if let core::task::Poll::Ready(v) = f.as_mut().poll(&mut cx) { return v; } }
    /// # }
    /// let mut buf = [0u8; 8];
    /// assert!(block_on(aok_proto::embedded_io_async::Writer::new(&mut buf[..]).flush()).is_ok());
    /// ```
    pub async fn flush(&mut self) -> Result<(), IoError<W::Error>> {
        self.inner.flush().await.map_err(IoError::Transport)
    }

    /// The transport, mutably.
    ///
    /// ```
    /// let mut buf = [0u8; 8];
    /// let mut writer = aok_proto::embedded_io_async::Writer::new(&mut buf[..]);
    /// assert_eq!(writer.get_mut().len(), 8);
    /// ```
    pub fn get_mut(&mut self) -> &mut W {
        &mut self.inner
    }

    /// Gives the transport back.
    ///
    /// ```
    /// let mut buf = [0u8; 8];
    /// assert_eq!(aok_proto::embedded_io_async::Writer::new(&mut buf[..]).into_inner().len(), 8);
    /// ```
    pub fn into_inner(self) -> W {
        self.inner
    }
}

/// `Write::write_all`, but `Ok(0)` is [`IoError::WriteZero`] instead of a panic.
async fn write_all<W: Write>(w: &mut W, mut buf: &[u8]) -> Result<(), IoError<W::Error>> {
    while !buf.is_empty() {
        match w.write(buf).await {
            Ok(0) => return Err(IoError::WriteZero),
            Ok(n) => buf = buf.get(n..).unwrap_or(&[]),
            Err(e) => return Err(IoError::Transport(e)),
        }
    }
    Ok(())
}
