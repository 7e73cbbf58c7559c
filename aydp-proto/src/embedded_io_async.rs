//! Async AYDP messages over [`embedded_io_async`] (feature `embedded-io-async`), for embassy
//! and other executors.
//!
//! - [`FrameReader`] owns a [`Decoder`] and a read buffer of `R` bytes; each
//!   [`FrameReader::read_frame`] returns the next message. Every read is decoded with the bulk
//!   path of [`Decoder::feed`] (messages checked in place in the read buffer), and the frames
//!   and errors are exactly those of [`Decoder::push`] and [`Decoder::poll`] byte by byte; at
//!   the end of the stream, those of [`Decoder::flush`].
//! - [`FrameWriter`] encodes messages straight into a [`Write`] with the [`Encoder`]'s byte
//!   iterator, a chunk of at most 32 bytes at a time.
//!
//! The blocking twins are in [`crate::embedded_io`] and behave the same. Errors are
//! [`IoError`]. Dropping a read future loses no decoded state; it loses the bytes of a read
//! in progress only if the transport's `read` is not cancel-safe.

use ::embedded_io_async::{Read, Write};

use crate::io::{CHUNK, ReaderCore, fill};
use crate::{Decoder, Encoder, Frame, IoError, Payload, Profile, Timestamp};

/// Reads AYDP messages from an async [`Read`]: a [`Decoder<N>`] plus an `R`-byte read buffer.
///
/// ```
/// # fn block_on<F: core::future::Future>(f: F) -> F::Output {
/// #     let mut f = core::pin::pin!(f);
/// #     let mut cx = core::task::Context::from_waker(core::task::Waker::noop());
/// #     loop { if let core::task::Poll::Ready(v) = f.as_mut().poll(&mut cx) { return v; } }
/// # }
/// use aydp_proto::{embedded_io_async::FrameReader, Error, IoError, Message, Profile};
///
/// // Noise, a heartbeat, then a message cut short by the end of the stream.
/// let wire: &[u8] = &[0x13, 0xFF, 0x80, 0x07, 0, 0, 0, 0x78, 0xFF, 0x89];
/// let mut reader = FrameReader::<_, 64>::new(wire, Profile::Spec);
/// assert_eq!(block_on(reader.read_frame()).unwrap().message(), Ok(Message::Heartbeat));
/// assert_eq!(block_on(reader.read_frame()).err(), Some(IoError::UnexpectedEof { pending: 2 }));
/// assert_eq!(block_on(reader.read_frame()).err(), Some(IoError::Eof));
/// ```
#[derive(Debug, Clone)]
pub struct FrameReader<T, const N: usize, const R: usize = 64> {
    inner: T,
    core: ReaderCore<N, R>,
}

impl<T: Read, const N: usize, const R: usize> FrameReader<T, N, R> {
    /// A reader with a fresh decoder for `profile`.
    ///
    /// ```
    /// use aydp_proto::{embedded_io_async::FrameReader, Profile};
    /// let reader = FrameReader::<_, 64, 16>::new(&[][..], Profile::Reference);
    /// assert_eq!(reader.decoder().profile(), Profile::Reference);
    /// ```
    pub const fn new(inner: T, profile: Profile) -> Self {
        Self::with_decoder(inner, Decoder::new(profile))
    }

    /// A reader around a decoder the caller already has.
    ///
    /// ```
    /// # fn block_on<F: core::future::Future>(f: F) -> F::Output {
    /// #     let mut f = core::pin::pin!(f);
    /// #     let mut cx = core::task::Context::from_waker(core::task::Waker::noop());
    /// #     loop { if let core::task::Poll::Ready(v) = f.as_mut().poll(&mut cx) { return v; } }
    /// # }
    /// use aydp_proto::{embedded_io_async::FrameReader, Decoder, Profile};
    /// let wire: &[u8] = &[0xFF, 0x80, 0x07, 0, 0, 0, 0x78];
    /// let mut reader = FrameReader::<_, 32>::with_decoder(wire, Decoder::new(Profile::Spec));
    /// assert_eq!(block_on(reader.read_frame()).map(|f| f.type_byte()), Ok(0x80));
    /// ```
    pub const fn with_decoder(inner: T, decoder: Decoder<N>) -> Self {
        Self {
            inner,
            core: ReaderCore::new(decoder),
        }
    }

    /// Reads until the next message and returns it; it borrows the reader until the next call.
    ///
    /// # Errors
    /// - [`IoError::Protocol`]: a candidate failed; call again (its bytes are rescanned).
    /// - [`IoError::Transport`]: the read failed; bytes already read are kept.
    /// - [`IoError::UnexpectedEof`]: the stream ended inside a message; messages the rescan
    ///   finds in its bytes follow, then [`IoError::Eof`].
    /// - [`IoError::Eof`]: the stream ended and nothing is left.
    ///
    /// ```
    /// # fn block_on<F: core::future::Future>(f: F) -> F::Output {
    /// #     let mut f = core::pin::pin!(f);
    /// #     let mut cx = core::task::Context::from_waker(core::task::Waker::noop());
    /// #     loop { if let core::task::Poll::Ready(v) = f.as_mut().poll(&mut cx) { return v; } }
    /// # }
    /// use aydp_proto::{embedded_io_async::FrameReader, Error, IoError, Profile};
    /// // A heartbeat with a bad checksum, then a good one, read 3 bytes at a time.
    /// let wire: &[u8] = &[0xFF, 0x80, 0x07, 0, 0, 0, 0x00, 0xFF, 0x80, 0x07, 0, 0, 0, 0x78];
    /// let mut reader = FrameReader::<_, 32, 3>::new(wire, Profile::Spec);
    /// assert_eq!(block_on(reader.read_frame()).err(), Some(IoError::Protocol(
    ///     Error::ChecksumMismatch { id: 0x80, computed: 0x78, received: 0 }
    /// )));
    /// assert_eq!(block_on(reader.read_frame()).map(|f| f.as_bytes().len()), Ok(7));
    /// ```
    pub async fn read_frame(&mut self) -> Result<Frame<'_>, IoError<T::Error>> {
        let token = loop {
            if let Some(token) = self.core.decode() {
                break token;
            }
            let n = self
                .inner
                .read(self.core.space())
                .await
                .map_err(IoError::Transport)?;
            if let Some(token) = self.core.filled(n) {
                break token;
            }
        };
        self.core.take(token)
    }

    /// The decoder, for its counters.
    ///
    /// ```
    /// # fn block_on<F: core::future::Future>(f: F) -> F::Output {
    /// #     let mut f = core::pin::pin!(f);
    /// #     let mut cx = core::task::Context::from_waker(core::task::Waker::noop());
    /// #     loop { if let core::task::Poll::Ready(v) = f.as_mut().poll(&mut cx) { return v; } }
    /// # }
    /// use aydp_proto::{embedded_io_async::FrameReader, Profile};
    /// let wire: &[u8] = &[0x00, 0xFF, 0x80, 0x07, 0, 0, 0, 0x78];
    /// let mut reader = FrameReader::<_, 32>::new(wire, Profile::Spec);
    /// block_on(reader.read_frame()).unwrap();
    /// assert_eq!(reader.decoder().stats().bytes_discarded, 1);
    /// ```
    pub const fn decoder(&self) -> &Decoder<N> {
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
    /// use aydp_proto::{embedded_io_async::FrameReader, Profile};
    /// let wire: &[u8] = &[0xFF, 0x80, 0x07, 0, 0, 0, 0x78, 0x00];
    /// let mut reader = FrameReader::<_, 32>::new(wire, Profile::Spec);
    /// block_on(reader.read_frame()).unwrap();
    /// assert_eq!(reader.unread(), 1);
    /// ```
    pub fn unread(&self) -> usize {
        self.core.unread()
    }

    /// The transport.
    ///
    /// ```
    /// use aydp_proto::{embedded_io_async::FrameReader, Profile};
    /// let reader = FrameReader::<_, 32>::new(&[1u8][..], Profile::Spec);
    /// assert_eq!(reader.get_ref().len(), 1);
    /// ```
    pub const fn get_ref(&self) -> &T {
        &self.inner
    }

    /// The transport, mutably (bytes read around the reader are not decoded).
    ///
    /// ```
    /// use aydp_proto::{embedded_io_async::FrameReader, Profile};
    /// let mut reader = FrameReader::<_, 32>::new(&[1u8][..], Profile::Spec);
    /// *reader.get_mut() = &[];
    /// ```
    pub fn get_mut(&mut self) -> &mut T {
        &mut self.inner
    }

    /// Gives the transport back; bytes read and not decoded are lost.
    ///
    /// ```
    /// use aydp_proto::{embedded_io_async::FrameReader, Profile};
    /// let reader = FrameReader::<_, 32>::new(&[1u8][..], Profile::Spec);
    /// assert_eq!(reader.into_inner(), &[1]);
    /// ```
    pub fn into_inner(self) -> T {
        self.inner
    }
}

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
    /// assert_eq!(FrameWriter::new(&mut buf[..], Profile::Spec).encoder().profile(), Profile::Spec);
    /// ```
    pub const fn encoder(&self) -> &Encoder {
        &self.encoder
    }

    /// Encodes a message, normal with `Some(timestamp)`, expedited with `None`, into the
    /// transport; returns the bytes written. It does not flush.
    ///
    /// # Errors
    /// [`IoError::Protocol`] if the payload cannot be encoded (nothing is written then);
    /// [`IoError::Transport`] or [`IoError::WriteZero`], and the message may be partly sent.
    ///
    /// ```
    /// # fn block_on<F: core::future::Future>(f: F) -> F::Output {
    /// #     let mut f = core::pin::pin!(f);
    /// #     let mut cx = core::task::Context::from_waker(core::task::Waker::noop());
    /// #     loop { if let core::task::Poll::Ready(v) = f.as_mut().poll(&mut cx) { return v; } }
    /// # }
    /// use aydp_proto::{embedded_io_async::{FrameReader, FrameWriter}, Message, Position, Profile, Timestamp};
    /// let pos = Position { latitude: 50.5, longitude: -1.25, altitude: 12.5 };
    /// let mut wire = [0u8; 64];
    /// let mut writer = FrameWriter::new(&mut wire[..], Profile::Spec);
    /// let n = block_on(writer.write_message(&pos, Some(Timestamp::new(1_700_000_000, 250)))).unwrap();
    /// let mut reader = FrameReader::<_, 64>::new(&wire[..n], Profile::Spec);
    /// assert_eq!(block_on(reader.read_frame()).unwrap().message(), Ok(Message::Position(pos)));
    /// ```
    pub async fn write_message<P: Payload + ?Sized>(
        &mut self,
        payload: &P,
        timestamp: Option<Timestamp>,
    ) -> Result<usize, IoError<W::Error>> {
        let mut bytes = self
            .encoder
            .iter(payload, timestamp)
            .map_err(IoError::Protocol)?;
        // One await, on the transport (no nested write_all): the state machine stays small
        // enough for LLVM to see through, which keeps checks/panic-never linking.
        let mut chunk = [0u8; CHUNK];
        let (mut at, mut end, mut total) = (0usize, 0usize, 0usize);
        loop {
            if at >= end {
                (at, end) = (0, fill(&mut chunk, &mut bytes));
                if end == 0 {
                    return Ok(total);
                }
            }
            let out = chunk.get(at..end).unwrap_or(&[]);
            match self.inner.write(out).await {
                Ok(0) => return Err(IoError::WriteZero),
                Ok(n) => {
                    let n = n.min(out.len());
                    at = at.saturating_add(n);
                    total = total.saturating_add(n);
                }
                Err(e) => return Err(IoError::Transport(e)),
            }
        }
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
    /// assert_eq!(block_on(writer.write_normal(&WindSpeed(3.5), Timestamp::new(42, 500_000))), Ok(27));
    /// ```
    pub async fn write_normal<P: Payload + ?Sized>(
        &mut self,
        payload: &P,
        timestamp: Timestamp,
    ) -> Result<usize, IoError<W::Error>> {
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
    ) -> Result<usize, IoError<W::Error>> {
        self.write_message(payload, None).await
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
    /// use aydp_proto::{embedded_io_async::FrameWriter, Profile};
    /// let mut buf = [0u8; 8];
    /// assert!(block_on(FrameWriter::new(&mut buf[..], Profile::Spec).flush()).is_ok());
    /// ```
    pub async fn flush(&mut self) -> Result<(), IoError<W::Error>> {
        self.inner.flush().await.map_err(IoError::Transport)
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
