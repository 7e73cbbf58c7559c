//! Async AYDP messages over [`embedded_io_async`] (feature `embedded-io-async`), for embassy
//! and other executors.
//!
//! - [`FrameReader`] is `frame-io`'s reader around a [`Decoder`] and a read buffer of `R`
//!   bytes; each [`FrameReader::read`]`.await` returns the next message. Every read is decoded
//!   with the pull form of [`Decode`](crate::Decode) (the slice fast path: messages checked
//!   in place in the read buffer), and the frames and errors are exactly those of
//!   [`Decode::feed`](crate::Decode::feed) on the same bytes; at the end of the stream,
//!   those of [`Decode::finish`](crate::Decode::finish).
//! - [`FrameWriter`] encodes messages straight into a [`Write`] with the [`Encoder`]'s byte
//!   iterator, a chunk of at most 32 bytes at a time.
//!
//! The blocking twins are in [`crate::embedded_io`] and behave the same. A reader fails with
//! [`IoError`](crate::IoError), a writer with [`WriteError`]. Dropping a read future loses no decoded state; it loses the bytes of a read
//! in progress only if the transport's `read` is not cancel-safe.

use ::embedded_io_async::Write;

use crate::{Decoder, Encoder, Payload, Profile, Timestamp, WriteError};

/// Reads AYDP messages from an async [`Read`](::embedded_io_async::Read): a [`Decoder<N>`] plus an
/// `R`-byte read buffer.
///
/// ```
/// # fn block_on<F: core::future::Future>(f: F) -> F::Output {
/// #     let mut f = core::pin::pin!(f);
/// #     let mut cx = core::task::Context::from_waker(core::task::Waker::noop());
/// #     loop { if let core::task::Poll::Ready(v) = f.as_mut().poll(&mut cx) { return v; } }
/// # }
/// use aydp_proto::{Decoder, embedded_io_async::FrameReader, Error, IoError, Message, Profile};
///
/// // Noise, a heartbeat, then a message cut short by the end of the stream.
/// let wire: &[u8] = &[0x13, 0xFF, 0x80, 0x07, 0, 0, 0, 0x78, 0xFF, 0x89];
/// let mut reader = FrameReader::<_, 64>::new(wire, Decoder::new(Profile::Spec));
/// assert_eq!(block_on(reader.read()).unwrap().message(), Ok(Message::Heartbeat));
/// assert_eq!(block_on(reader.read()).err(), Some(IoError::UnexpectedEof { pending: 2 }));
/// assert_eq!(block_on(reader.read()).err(), Some(IoError::Eof));
/// ```
pub type FrameReader<T, const N: usize, const R: usize = 64> =
    frame_io::embedded_io_async::Reader<T, Decoder<N>, R>;

/// Writes AYDP messages into an async [`Write`], encoding on the fly (no message buffer).
///
/// ```
/// # fn block_on<F: core::future::Future>(f: F) -> F::Output {
/// #     let mut f = core::pin::pin!(f);
/// #     let mut cx = core::task::Context::from_waker(core::task::Waker::noop());
/// #     loop { if let core::task::Poll::Ready(v) = f.as_mut().poll(&mut cx) { return v; } }
/// # }
/// use aydp_proto::{embedded_io_async::FrameWriter, Profile, SystemControl};
/// let mut wire = [0u8; 16];
/// let mut writer = FrameWriter::new(&mut wire[..], Profile::Spec);
/// let n = block_on(writer.write_expedited(&SystemControl::StoreConfiguration)).unwrap();
/// assert_eq!(&wire[..n], &[0xFF, 0x89, 0x08, 0, 0, 0, 0x02, 0x7C]);
/// ```
#[derive(Debug, Clone)]
pub struct FrameWriter<W> {
    inner: W,
    encoder: Encoder,
}

impl<W: Write> FrameWriter<W> {
    /// A writer into `inner` in `profile`.
    ///
    /// ```
    /// use aydp_proto::{embedded_io_async::FrameWriter, Profile};
    /// let mut buf = [0u8; 8];
    /// let writer = FrameWriter::new(&mut buf[..], Profile::Reference);
    /// assert_eq!(writer.encoder().profile(), Profile::Reference);
    /// ```
    pub const fn new(inner: W, profile: Profile) -> Self {
        Self {
            inner,
            encoder: Encoder::new(profile),
        }
    }

    /// The encoder (its profile).
    ///
    /// ```
    /// use aydp_proto::{embedded_io_async::FrameWriter, Profile};
    /// let mut buf = [0u8; 8];
    /// assert_eq!(FrameWriter::new(&mut buf[..], Profile::Spec).encoder().profile(),
    /// Profile::Spec);
    /// ```
    pub const fn encoder(&self) -> &Encoder {
        &self.encoder
    }

    /// Encodes a message, normal with `Some(timestamp)`, expedited with `None`, into the
    /// transport; returns the bytes written. It does not flush.
    ///
    /// # Errors
    /// [`WriteError::Protocol`] if the payload cannot be encoded (nothing is written then);
    /// [`WriteError::Transport`] or [`WriteError::WriteZero`], and the message may be partly sent.
    ///
    /// ```
    /// # fn block_on<F: core::future::Future>(f: F) -> F::Output {
    /// #     let mut f = core::pin::pin!(f);
    /// #     let mut cx = core::task::Context::from_waker(core::task::Waker::noop());
    /// #     loop { if let core::task::Poll::Ready(v) = f.as_mut().poll(&mut cx) { return v; } }
    /// # }
    /// use aydp_proto::embedded_io_async::{FrameReader, FrameWriter};
    /// use aydp_proto::{Decoder, Message, Position, Profile, Timestamp};
    /// let pos = Position { latitude: 50.5, longitude: -1.25, altitude: 12.5 };
    /// let mut wire = [0u8; 64];
    /// let mut writer = FrameWriter::new(&mut wire[..], Profile::Spec);
    /// let stamp = Some(Timestamp::new(1_700_000_000, 250));
    /// let n = block_on(writer.write_message(&pos, stamp)).unwrap();
    /// let mut reader = FrameReader::<_, 64>::new(&wire[..n], Decoder::new(Profile::Spec));
    /// assert_eq!(block_on(reader.read()).unwrap().message(), Ok(Message::Position(pos)));
    /// ```
    pub async fn write_message<P: Payload + ?Sized>(
        &mut self,
        payload: &P,
        timestamp: Option<Timestamp>,
    ) -> Result<usize, WriteError<W::Error>> {
        let bytes = self
            .encoder
            .iter(payload, timestamp)
            .map_err(WriteError::Protocol)?;
        frame_io::embedded_io_async::write_iter(&mut self.inner, bytes).await
    }

    /// Encodes a normal message (22-byte header with `timestamp`).
    ///
    /// # Errors
    /// As [`FrameWriter::write_message`].
    ///
    /// ```
    /// # fn block_on<F: core::future::Future>(f: F) -> F::Output {
    /// #     let mut f = core::pin::pin!(f);
    /// #     let mut cx = core::task::Context::from_waker(core::task::Waker::noop());
    /// #     loop { if let core::task::Poll::Ready(v) = f.as_mut().poll(&mut cx) { return v; } }
    /// # }
    /// use aydp_proto::{embedded_io_async::FrameWriter, Profile, Timestamp, WindSpeed};
    /// let mut wire = [0u8; 64];
    /// let mut writer = FrameWriter::new(&mut wire[..], Profile::Reference);
    /// assert_eq!(block_on(writer.write_normal(&WindSpeed(3.5), Timestamp::new(42, 500_000))),
    /// Ok(27));
    /// ```
    pub async fn write_normal<P: Payload + ?Sized>(
        &mut self,
        payload: &P,
        timestamp: Timestamp,
    ) -> Result<usize, WriteError<W::Error>> {
        self.write_message(payload, Some(timestamp)).await
    }

    /// Encodes an expedited message (6-byte header). See the type's example.
    ///
    /// # Errors
    /// As [`FrameWriter::write_message`].
    ///
    /// ```
    /// # fn block_on<F: core::future::Future>(f: F) -> F::Output {
    /// #     let mut f = core::pin::pin!(f);
    /// #     let mut cx = core::task::Context::from_waker(core::task::Waker::noop());
    /// #     loop { if let core::task::Poll::Ready(v) = f.as_mut().poll(&mut cx) { return v; } }
    /// # }
    /// use aydp_proto::{embedded_io_async::FrameWriter, Profile, Raw};
    /// let mut wire = [0u8; 16];
    /// let mut writer = FrameWriter::new(&mut wire[..], Profile::Spec);
    /// assert_eq!(block_on(writer.write_expedited(&Raw { msg_type: 9, data: &[2] })), Ok(8));
    /// ```
    pub async fn write_expedited<P: Payload + ?Sized>(
        &mut self,
        payload: &P,
    ) -> Result<usize, WriteError<W::Error>> {
        self.write_message(payload, None).await
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
    /// use aydp_proto::{embedded_io_async::FrameWriter, Profile};
    /// let mut buf = [0u8; 8];
    /// assert!(block_on(FrameWriter::new(&mut buf[..], Profile::Spec).flush()).is_ok());
    /// ```
    pub async fn flush(&mut self) -> Result<(), WriteError<W::Error>> {
        self.inner.flush().await.map_err(WriteError::Transport)
    }

    /// The transport, mutably.
    ///
    /// ```
    /// use aydp_proto::{embedded_io_async::FrameWriter, Profile};
    /// let mut buf = [0u8; 8];
    /// let mut writer = FrameWriter::new(&mut buf[..], Profile::Spec);
    /// assert_eq!(writer.get_mut().len(), 8);
    /// ```
    pub fn get_mut(&mut self) -> &mut W {
        &mut self.inner
    }

    /// Gives the transport back.
    ///
    /// ```
    /// use aydp_proto::{embedded_io_async::FrameWriter, Profile};
    /// let mut buf = [0u8; 8];
    /// assert_eq!(FrameWriter::new(&mut buf[..], Profile::Spec).into_inner().len(), 8);
    /// ```
    pub fn into_inner(self) -> W {
        self.inner
    }
}
