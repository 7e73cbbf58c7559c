//! Async AOK over [`embedded_io_async`] (feature `embedded-io-async`), for embassy
//! and other executors.
//!
//! - [`MessageReader`] (PC side) around a [`MessageDecoder`] and [`CommandReader`] (device
//!   side) around a [`CommandDecoder`] are `frame-io`'s reader, each with a read buffer of `R`
//!   bytes; [`MessageReader::read`] and [`CommandReader::read`] return the next item. Every
//!   read is decoded with the pull form of the decoder's contract (`decode`, on the bulk path
//!   of `feed`), and the items are exactly those of `feed` byte by byte; at the end of the
//!   stream, those of `finish`.
//! - [`Writer`] writes commands (PC side) and messages (device side) into a [`Write`].
//! - The PC-side client over an async port is [`crate::client::AsyncClient`].
//!
//! The blocking twins are in [`crate::embedded_io`] and behave the same. A reader fails with
//! [`IoError`](crate::IoError), a writer with [`WriteError`]. Dropping a read future loses no
//! decoded state; it loses the bytes of a read in progress only if the transport's `read` is
//! not cancel-safe.

use ::embedded_io_async::Write;

use crate::io::{command_bytes, message_bytes};
use crate::{Command, CommandDecoder, Message, MessageDecoder, ReplyForm, WriteError};

/// Reads what the device sends (debug frames, replies, acks) from an async
/// [`Read`](::embedded_io_async::Read): a [`MessageDecoder`] plus an `R`-byte read buffer.
///
/// ```
/// # fn block_on<F: core::future::Future>(f: F) -> F::Output {
/// #     let mut f = core::pin::pin!(f);
/// #     let mut cx = core::task::Context::from_waker(core::task::Waker::noop());
/// #     loop { if let core::task::Poll::Ready(v) = f.as_mut().poll(&mut cx) { return v; } }
/// # }
/// use aok_proto::{embedded_io_async::MessageReader, Ack, DebugValue, Expect,
///                 FirmwareVersion, IoError, Message, MessageDecoder};
///
/// // A debug frame and an ack.
/// let wire: &[u8] = &[0x1c, 0x56, 0xff, 0xff, 0xff, 0xfe, 0x57, b'O'];
/// let mut reader = MessageReader::<_>::new(wire, MessageDecoder::new(FirmwareVersion::LATEST));
/// reader.decoder_mut().expect(Expect::Ack);
/// assert_eq!(block_on(reader.read()), Ok(Message::Debug(DebugValue { number: 86, value: -2 })));
/// assert_eq!(block_on(reader.read()), Ok(Message::Ack(Ack::Ok)));
/// assert_eq!(block_on(reader.read()), Err(IoError::Eof));
/// ```
pub type MessageReader<T, const R: usize = 32> =
    frame_io::embedded_io_async::Reader<T, MessageDecoder, R>;

/// Reads the PC's commands (device side) from an async [`Read`](::embedded_io_async::Read): a
/// [`CommandDecoder`] plus an `R`-byte read buffer.
///
/// ```
/// # fn block_on<F: core::future::Future>(f: F) -> F::Output {
/// #     let mut f = core::pin::pin!(f);
/// #     let mut cx = core::task::Context::from_waker(core::task::Waker::noop());
/// #     loop { if let core::task::Poll::Ready(v) = f.as_mut().poll(&mut cx) { return v; } }
/// # }
/// use aok_proto::{embedded_io_async::CommandReader, Command, CommandDecoder, Error, IoError};
/// // A motor-test start whose checksum fails, then "read parameter 12".
/// let wire: &[u8] = &[0x31, 0x67, 0x0c];
/// let mut reader = CommandReader::<_>::new(wire, CommandDecoder::new());
/// let mismatch = Error::ChecksumMismatch { id: 0x31, computed: 0x56, received: 0x0c };
/// assert_eq!(block_on(reader.read()), Err(IoError::Protocol(mismatch)));
/// assert_eq!(block_on(reader.read()), Ok(Command::ReadParameter(12)));
/// assert_eq!(block_on(reader.read()), Err(IoError::Eof));
/// ```
pub type CommandReader<T, const R: usize = 32> =
    frame_io::embedded_io_async::Reader<T, CommandDecoder, R>;

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
/// let n = block_on(writer.write_command(&Command::SetParameter(ParameterValue { number: 12, value:
///     1500 })))?;
/// assert_eq!(&wire[..n], &[0x73, 0x0c, 0x00, 0x00, 0x05, 0xdc, 0xd5]);
/// # Ok::<(), aok_proto::WriteError<embedded_io::SliceWriteError>>(())
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
    /// [`WriteError::Transport`] or [`WriteError::WriteZero`]; the command may be partly sent.
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
    pub async fn write_command(
        &mut self,
        command: &Command,
    ) -> Result<usize, WriteError<W::Error>> {
        let (frame, n) = command_bytes(command);
        let bytes = frame.get(..n).unwrap_or(&[]);
        frame_io::embedded_io_async::write_all(&mut self.inner, bytes)
            .await
            .map(|()| n)
    }

    /// Writes a device message in the firmware's reply `form` (device side); returns the
    /// bytes written. It does not flush.
    ///
    /// # Errors
    /// [`WriteError::Transport`] or [`WriteError::WriteZero`].
    ///
    /// ```
    /// # fn block_on<F: core::future::Future>(f: F) -> F::Output {
    /// #     let mut f = core::pin::pin!(f);
    /// #     let mut cx = core::task::Context::from_waker(core::task::Waker::noop());
    /// #     loop { if let core::task::Poll::Ready(v) = f.as_mut().poll(&mut cx) { return v; } }
    /// # }
    /// use aok_proto::{embedded_io_async::Writer, Ack, Message, ReplyForm};
    /// let mut wire = [0u8; 4];
    /// assert_eq!(block_on(Writer::new(&mut wire[..]).write_message(&Message::Ack(Ack::Ok),
    ///     ReplyForm::Headed)), Ok(1));
    /// assert_eq!(wire[0], b'O');
    /// ```
    pub async fn write_message(
        &mut self,
        message: &Message,
        form: ReplyForm,
    ) -> Result<usize, WriteError<W::Error>> {
        let (frame, n) = message_bytes(message, form);
        let bytes = frame.get(..n).unwrap_or(&[]);
        frame_io::embedded_io_async::write_all(&mut self.inner, bytes)
            .await
            .map(|()| n)
    }

    /// Flushes the transport.
    ///
    /// # Errors
    /// [`WriteError::Transport`].
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
    pub async fn flush(&mut self) -> Result<(), WriteError<W::Error>> {
        self.inner.flush().await.map_err(WriteError::Transport)
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
