//! Async AEOLUS frames over [`embedded_io_async`] (feature `embedded-io-async`), for embassy
//! and other executors.
//!
//! - [`FrameReader`] owns a [`Decoder`] and a read buffer of `R` bytes; each
//!   [`FrameReader::read_frame`]`.await` returns the next frame. Every read is decoded with
//!   the slice fast path of [`Decoder::feed`], and the frames and errors are exactly
//!   those of [`Decoder::push`] byte by byte.
//! - [`FrameWriter`] encodes frames straight into a [`Write`], a chunk of at most 32 bytes at
//!   a time, with no frame buffer.
//!
//! The blocking twins are in [`crate::embedded_io`] and behave the same. Errors are
//! [`IoError`]. Cancelling `read_frame` loses no decoded state; it loses the bytes of a read in
//! progress only if the transport's `read` is not cancel-safe.

use ::embedded_io_async::{Read, Write};

use crate::io::{CHUNK, ReaderCore, fill, frame_bytes, message_data, scratch};
use crate::message::Message;
use crate::{CrcMode, Decoder, Frame, IoError};

/// Reads AEOLUS frames from an async [`Read`]: a [`Decoder<N>`] plus an `R`-byte read
/// buffer.
///
/// ```
/// # fn block_on<F: core::future::Future>(f: F) -> F::Output {
/// #     let mut f = core::pin::pin!(f);
/// #     let mut cx = core::task::Context::from_waker(core::task::Waker::noop());
/// #     loop { if let core::task::Poll::Ready(v) = f.as_mut().poll(&mut cx) { return v; } }
/// # }
/// use aeolus_proto::{embedded_io_async::FrameReader, IoError, message::Message};
///
/// // TOAST "hi", then half a frame and the end of the stream.
/// let wire: &[u8] = &[0x7E, 0x52, b'h', b'i', 0x00, 0x73, 0xEC, 0x7E, 0x52, b'h'];
/// let mut reader = FrameReader::<_, 64>::new(wire);
/// let frame = block_on(reader.read_frame()).unwrap();
/// assert!(matches!(frame.message(), Ok(Message::Toast(t)) if t.as_str() == Some("hi")));
/// assert_eq!(block_on(reader.read_frame()).err(), Some(IoError::UnexpectedEof { pending: 2 }));
/// assert_eq!(block_on(reader.read_frame()).err(), Some(IoError::Eof));
/// ```
#[derive(Debug, Clone)]
pub struct FrameReader<T, const N: usize, const R: usize = 64> {
    inner: T,
    core: ReaderCore<N, R>,
}

impl<T: Read, const N: usize, const R: usize> FrameReader<T, N, R> {
    /// A reader with a fresh, non-strict [`Decoder`].
    ///
    /// ```
    /// let reader = aeolus_proto::embedded_io_async::FrameReader::<_, 64, 16>::new(&[][..]);
    /// assert_eq!(reader.decoder().stats().frames_ok, 0);
    /// ```
    pub const fn new(inner: T) -> Self {
        Self::with_decoder(inner, Decoder::new())
    }

    /// A reader around a decoder set up by the caller (strict mode, say).
    ///
    /// ```
    /// # fn block_on<F: core::future::Future>(f: F) -> F::Output {
    /// #     let mut f = core::pin::pin!(f);
    /// #     let mut cx = core::task::Context::from_waker(core::task::Waker::noop());
    /// #     loop { if let core::task::Poll::Ready(v) = f.as_mut().poll(&mut cx) { return v; } }
    /// # }
    /// use aeolus_proto::{embedded_io_async::FrameReader, Decoder, Error, IoError};
    /// let wire: &[u8] = &[0x7E, 0x52, b'x', 0x00, 0x00, 0x00, 0x7E];
    /// let mut reader = FrameReader::<_, 16>::with_decoder(wire, Decoder::strict());
    /// assert_eq!(block_on(reader.read_frame()).err(), Some(IoError::Protocol(Error::MissingCrc { id: 82 })));
    /// ```
    pub const fn with_decoder(inner: T, decoder: Decoder<N>) -> Self {
        Self {
            inner,
            core: ReaderCore::new(decoder),
        }
    }

    /// Reads until the next frame and returns it; it borrows the reader until the next call.
    ///
    /// # Errors
    /// - [`IoError::Protocol`]: a frame was dropped (its error); call again for the next one.
    /// - [`IoError::Transport`]: the read failed; bytes already read are kept.
    /// - [`IoError::UnexpectedEof`]: the stream ended inside a frame (then [`IoError::Eof`]).
    /// - [`IoError::Eof`]: the stream ended between frames.
    ///
    /// ```
    /// # fn block_on<F: core::future::Future>(f: F) -> F::Output {
    /// #     let mut f = core::pin::pin!(f);
    /// #     let mut cx = core::task::Context::from_waker(core::task::Waker::noop());
    /// #     loop { if let core::task::Poll::Ready(v) = f.as_mut().poll(&mut cx) { return v; } }
    /// # }
    /// use aeolus_proto::{embedded_io_async::FrameReader, Error, IoError};
    /// // A frame with a bad CRC, then a good one: the error comes first, then the frame.
    /// let wire: &[u8] = &[0x7E, 0x52, b'h', b'i', 0, 0x00, 0xEC, 0x7E,
    ///                     0x52, b'h', b'i', 0, 0x73, 0xEC, 0x7E];
    /// let mut reader = FrameReader::<_, 32, 4>::new(wire);
    /// assert!(matches!(block_on(reader.read_frame()), Err(IoError::Protocol(Error::ChecksumMismatch { .. }))));
    /// assert_eq!(block_on(reader.read_frame()).map(|f| f.id()), Ok(82));
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
    /// let wire: &[u8] = &[0x00, 0x7E, 0x52, b'h', b'i', 0, 0x73, 0xEC, 0x7E];
    /// let mut reader = aeolus_proto::embedded_io_async::FrameReader::<_, 64>::new(wire);
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
    /// let wire: &[u8] = &[0x7E, 0x52, b'h', b'i', 0, 0x73, 0xEC, 0x7E, 0x7E];
    /// let mut reader = aeolus_proto::embedded_io_async::FrameReader::<_, 64>::new(wire);
    /// block_on(reader.read_frame()).unwrap();
    /// assert_eq!(reader.unread(), 1);
    /// ```
    pub fn unread(&self) -> usize {
        self.core.unread()
    }

    /// The transport.
    ///
    /// ```
    /// let reader = aeolus_proto::embedded_io_async::FrameReader::<_, 64>::new(&[1u8][..]);
    /// assert_eq!(reader.get_ref().len(), 1);
    /// ```
    pub const fn get_ref(&self) -> &T {
        &self.inner
    }

    /// The transport, mutably (bytes read around the reader are not decoded).
    ///
    /// ```
    /// let mut reader = aeolus_proto::embedded_io_async::FrameReader::<_, 64>::new(&[1u8][..]);
    /// *reader.get_mut() = &[];
    /// ```
    pub fn get_mut(&mut self) -> &mut T {
        &mut self.inner
    }

    /// Gives the transport back; bytes read and not decoded are lost.
    ///
    /// ```
    /// let reader = aeolus_proto::embedded_io_async::FrameReader::<_, 64>::new(&[1u8][..]);
    /// assert_eq!(reader.into_inner(), &[1]);
    /// ```
    pub fn into_inner(self) -> T {
        self.inner
    }
}

/// Writes AEOLUS frames into an async [`Write`], encoding on the fly (no frame buffer).
///
/// ```
/// # fn block_on<F: core::future::Future>(f: F) -> F::Output {
/// #     let mut f = core::pin::pin!(f);
/// #     let mut cx = core::task::Context::from_waker(core::task::Waker::noop());
/// #     loop { if let core::task::Poll::Ready(v) = f.as_mut().poll(&mut cx) { return v; } }
/// # }
/// use aeolus_proto::{embedded_io_async::FrameWriter, CrcMode};
/// let mut wire = [0u8; 16];
/// let mut writer = FrameWriter::new(&mut wire[..]);
/// let n = block_on(writer.write_frame(82, b"hi\0", CrcMode::Compute)).unwrap();
/// assert_eq!(&wire[..n], &[0x7E, 0x52, b'h', b'i', 0x00, 0x73, 0xEC, 0x7E]);
/// ```
#[derive(Debug, Clone)]
pub struct FrameWriter<W> {
    inner: W,
}

impl<W: Write> FrameWriter<W> {
    /// A writer into `inner`.
    ///
    /// ```
    /// let mut buf = [0u8; 8];
    /// let writer = aeolus_proto::embedded_io_async::FrameWriter::new(&mut buf[..]);
    /// assert_eq!(writer.into_inner().len(), 8);
    /// ```
    pub const fn new(inner: W) -> Self {
        Self { inner }
    }

    /// Encodes one frame (ID + data + CRC) into the transport; returns the wire bytes written.
    /// It does not flush.
    ///
    /// # Errors
    /// [`IoError::Transport`] or [`IoError::WriteZero`]; the frame may then be partly sent.
    ///
    /// ```
    /// # fn block_on<F: core::future::Future>(f: F) -> F::Output {
    /// #     let mut f = core::pin::pin!(f);
    /// #     let mut cx = core::task::Context::from_waker(core::task::Waker::noop());
    /// #     loop { if let core::task::Poll::Ready(v) = f.as_mut().poll(&mut cx) { return v; } }
    /// # }
    /// use aeolus_proto::{embedded_io_async::FrameWriter, CrcMode};
    /// let mut wire = [0u8; 16];
    /// // `00 00` instead of a CRC; 0x7E in the data is escaped.
    /// let n = block_on(FrameWriter::new(&mut wire[..]).write_frame(99, &[0x7E], CrcMode::Omit)).unwrap();
    /// assert_eq!(&wire[..n], &[0x7E, 99, 0x7D, 0x5E, 0, 0, 0x7E]);
    /// ```
    pub async fn write_frame(
        &mut self,
        id: u8,
        data: &[u8],
        crc: CrcMode,
    ) -> Result<usize, IoError<W::Error>> {
        let mut bytes = frame_bytes(id, data, crc);
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

    /// Encodes a typed message; returns the wire bytes written. It does not flush.
    ///
    /// # Errors
    /// As [`FrameWriter::write_frame`].
    ///
    /// ```
    /// # fn block_on<F: core::future::Future>(f: F) -> F::Output {
    /// #     let mut f = core::pin::pin!(f);
    /// #     let mut cx = core::task::Context::from_waker(core::task::Waker::noop());
    /// #     loop { if let core::task::Poll::Ready(v) = f.as_mut().poll(&mut cx) { return v; } }
    /// # }
    /// use aeolus_proto::{embedded_io_async::{FrameReader, FrameWriter}, CrcMode, message::{Gyro, Message}};
    /// let gyro = Message::Gyro(Gyro { valid: true, timestamp_ms: 7.0, x: 0.1, y: 0.0, z: -0.2 });
    /// let mut wire = [0u8; 80];
    /// let n = block_on(FrameWriter::new(&mut wire[..]).write_message(&gyro, CrcMode::Compute)).unwrap();
    /// let mut reader = FrameReader::<_, 64>::new(&wire[..n]);
    /// assert_eq!(block_on(reader.read_frame()).unwrap().message(), Ok(gyro));
    /// ```
    pub async fn write_message(
        &mut self,
        message: &Message<'_>,
        crc: CrcMode,
    ) -> Result<usize, IoError<W::Error>> {
        let mut scratch = scratch();
        let data = message_data(message, &mut scratch).map_err(IoError::Protocol)?;
        self.write_frame(message.id(), data, crc).await
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
    /// let mut writer = aeolus_proto::embedded_io_async::FrameWriter::new(&mut buf[..]);
    /// assert!(block_on(writer.flush()).is_ok());
    /// ```
    pub async fn flush(&mut self) -> Result<(), IoError<W::Error>> {
        self.inner.flush().await.map_err(IoError::Transport)
    }

    /// The transport, mutably.
    ///
    /// ```
    /// let mut buf = [0u8; 8];
    /// let mut writer = aeolus_proto::embedded_io_async::FrameWriter::new(&mut buf[..]);
    /// assert_eq!(writer.get_mut().len(), 8);
    /// ```
    pub fn get_mut(&mut self) -> &mut W {
        &mut self.inner
    }

    /// Gives the transport back.
    ///
    /// ```
    /// let mut buf = [0u8; 8];
    /// let writer = aeolus_proto::embedded_io_async::FrameWriter::new(&mut buf[..]);
    /// assert_eq!(writer.into_inner().len(), 8);
    /// ```
    pub fn into_inner(self) -> W {
        self.inner
    }
}
