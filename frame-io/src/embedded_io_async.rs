//! Async frames over [`embedded_io_async`] (feature `embedded-io-async`), for embassy and other
//! executors.
//!
//! - [`Reader`] owns a [`Decode`]r and a read buffer of `R` bytes; each [`Reader::read`]
//!   returns the next item, decoding every read with the decoder's slice fast path, so the
//!   items and errors are exactly those of the decoder's `feed` over the same bytes.
//! - [`write_all`] writes a slice, [`write_iter`] the bytes of an iterator a chunk of at most
//!   32 bytes at a time (an encoder's byte iterator: no frame buffer); the protocol crates'
//!   writers are built on them.
//!
//! The blocking twins are in [`crate::embedded_io`] and behave the same. Errors are [`IoError`].
//! Dropping a read future loses no decoded state; it loses the bytes of a read in progress only
//! if the transport's `read` is not cancel-safe.
//!
//! **Blocking and async from one source.** Everything but the calls to `read` and `write` is in
//! one shared core (the read buffer and its bookkeeping, the decode step, the end-of-stream
//! state, turning an event into an item or an error, the chunking of the writers), plain
//! synchronous code tested once. Each feature module adds only the loops around it, a few
//! lines each, identical but for `.await`. This was chosen over one macro body expanded
//! twice: the public items keep ordinary source, documentation and compiler messages, and each
//! async loop keeps exactly one `.await` (on the transport), which keeps its state machine
//! small enough for LLVM to prove panic-free (`checks/panic-never`).

use ::embedded_io_async::{Read, Write};

use crate::shared::{Chunks, ReaderCore, advance};
use crate::{Decode, IoError};

/// Reads the items of a [`Decode`]r `D` from an async [`Read`], through an `R`-byte read
/// buffer.
///
/// ```
/// # fn block_on<F: core::future::Future>(f: F) -> F::Output {
/// #     let mut f = core::pin::pin!(f);
/// #     let mut cx = core::task::Context::from_waker(core::task::Waker::noop());
/// #     loop { if let core::task::Poll::Ready(v) = f.as_mut().poll(&mut cx) { return v; } }
/// # }
/// # struct Bytes; impl frame_io::Decode for Bytes { type Error = u8; type Found = u8; type Item<'a> = u8; const TRUNCATED: u8 = 0;
/// # fn decode(&mut self, b: &[u8]) -> (usize, Option<frame_io::Event<u8, u8>>) { match b.first() { Some(&0) => (1, Some(frame_io::Event::Error(0))), Some(&x) => (1, Some(frame_io::Event::Found(x))), None => (0, None) } }
/// # fn end(&mut self) -> Option<frame_io::Event<u8, u8>> { None }
/// # fn item(&self, _: &[u8], x: u8) -> u8 { x }
/// # fn span(&self) -> frame_io::Span { frame_io::Span { len: 1, after: 0 } } }
/// use frame_io::{embedded_io_async::Reader, IoError};
/// // `Bytes`: every non-zero byte is an item, a zero byte an error.
/// let mut reader = Reader::<_, _, 4>::new(&[7u8, 0, 8][..], Bytes);
/// assert_eq!(block_on(reader.read()), Ok(7));
/// assert_eq!(block_on(reader.read()), Err(IoError::Protocol(0)));
/// assert_eq!(block_on(reader.read()), Ok(8));
/// assert_eq!(block_on(reader.read()), Err(IoError::Eof));
/// ```
#[derive(Debug, Clone)]
pub struct Reader<T, D, const R: usize> {
    inner: T,
    core: ReaderCore<D, R>,
}

impl<T: Read, D: Decode, const R: usize> Reader<T, D, R> {
    /// A reader of `inner` through `decoder`.
    ///
    /// ```
    /// # struct Bytes; impl frame_io::Decode for Bytes { type Error = u8; type Found = u8; type Item<'a> = u8; const TRUNCATED: u8 = 0;
    /// # fn decode(&mut self, b: &[u8]) -> (usize, Option<frame_io::Event<u8, u8>>) { match b.first() { Some(&0) => (1, Some(frame_io::Event::Error(0))), Some(&x) => (1, Some(frame_io::Event::Found(x))), None => (0, None) } }
    /// # fn end(&mut self) -> Option<frame_io::Event<u8, u8>> { None }
    /// # fn item(&self, _: &[u8], x: u8) -> u8 { x }
    /// # fn span(&self) -> frame_io::Span { frame_io::Span { len: 1, after: 0 } } }
    /// let reader = frame_io::embedded_io_async::Reader::<_, _, 16>::new(&[][..], Bytes);
    /// assert_eq!(reader.unread(), 0);
    /// ```
    pub const fn new(inner: T, decoder: D) -> Self {
        Self {
            inner,
            core: ReaderCore::new(decoder),
        }
    }

    /// Reads until the next item and returns it; it may borrow the reader until the next call.
    ///
    /// # Errors
    /// - [`IoError::Protocol`]: a frame was dropped (its error); call again for the next one.
    /// - [`IoError::Transport`]: the read failed; bytes already read are kept.
    /// - [`IoError::UnexpectedEof`]: the stream ended inside a frame; what follows is the
    ///   protocol's (items rescanned from the held bytes, if it rescans), then
    ///   [`IoError::Eof`].
    /// - [`IoError::Eof`]: the stream ended and nothing is held. The next call reads again.
    ///
    /// ```
    /// # fn block_on<F: core::future::Future>(f: F) -> F::Output {
    /// #     let mut f = core::pin::pin!(f);
    /// #     let mut cx = core::task::Context::from_waker(core::task::Waker::noop());
    /// #     loop { if let core::task::Poll::Ready(v) = f.as_mut().poll(&mut cx) { return v; } }
    /// # }
    /// # struct Bytes; impl frame_io::Decode for Bytes { type Error = u8; type Found = u8; type Item<'a> = u8; const TRUNCATED: u8 = 0;
    /// # fn decode(&mut self, b: &[u8]) -> (usize, Option<frame_io::Event<u8, u8>>) { match b.first() { Some(&0) => (1, Some(frame_io::Event::Error(0))), Some(&x) => (1, Some(frame_io::Event::Found(x))), None => (0, None) } }
    /// # fn end(&mut self) -> Option<frame_io::Event<u8, u8>> { None }
    /// # fn item(&self, _: &[u8], x: u8) -> u8 { x }
    /// # fn span(&self) -> frame_io::Span { frame_io::Span { len: 1, after: 0 } } }
    /// use frame_io::{embedded_io_async::Reader, IoError};
    /// let mut reader = Reader::<_, _, 1>::new(&[5u8][..], Bytes);
    /// assert_eq!(block_on(reader.read()), Ok(5));
    /// assert_eq!(block_on(reader.read()), Err(IoError::Eof));
    /// ```
    pub async fn read(&mut self) -> Result<D::Item<'_>, IoError<T::Error, D::Error>> {
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
    /// # struct Bytes; impl frame_io::Decode for Bytes { type Error = u8; type Found = u8; type Item<'a> = u8; const TRUNCATED: u8 = 0;
    /// # fn decode(&mut self, b: &[u8]) -> (usize, Option<frame_io::Event<u8, u8>>) { match b.first() { Some(&0) => (1, Some(frame_io::Event::Error(0))), Some(&x) => (1, Some(frame_io::Event::Found(x))), None => (0, None) } }
    /// # fn end(&mut self) -> Option<frame_io::Event<u8, u8>> { None }
    /// # fn item(&self, _: &[u8], x: u8) -> u8 { x }
    /// # fn span(&self) -> frame_io::Span { frame_io::Span { len: 1, after: 0 } } }
    /// let reader = frame_io::embedded_io_async::Reader::<_, _, 16>::new(&[][..], Bytes);
    /// let _: &Bytes = reader.decoder();
    /// ```
    pub const fn decoder(&self) -> &D {
        &self.core.decoder
    }

    /// The decoder, mutably (to change what it expects, say).
    ///
    /// ```
    /// # struct Bytes; impl frame_io::Decode for Bytes { type Error = u8; type Found = u8; type Item<'a> = u8; const TRUNCATED: u8 = 0;
    /// # fn decode(&mut self, b: &[u8]) -> (usize, Option<frame_io::Event<u8, u8>>) { match b.first() { Some(&0) => (1, Some(frame_io::Event::Error(0))), Some(&x) => (1, Some(frame_io::Event::Found(x))), None => (0, None) } }
    /// # fn end(&mut self) -> Option<frame_io::Event<u8, u8>> { None }
    /// # fn item(&self, _: &[u8], x: u8) -> u8 { x }
    /// # fn span(&self) -> frame_io::Span { frame_io::Span { len: 1, after: 0 } } }
    /// let mut reader = frame_io::embedded_io_async::Reader::<_, _, 16>::new(&[][..], Bytes);
    /// *reader.decoder_mut() = Bytes;
    /// ```
    pub fn decoder_mut(&mut self) -> &mut D {
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
    /// # struct Bytes; impl frame_io::Decode for Bytes { type Error = u8; type Found = u8; type Item<'a> = u8; const TRUNCATED: u8 = 0;
    /// # fn decode(&mut self, b: &[u8]) -> (usize, Option<frame_io::Event<u8, u8>>) { match b.first() { Some(&0) => (1, Some(frame_io::Event::Error(0))), Some(&x) => (1, Some(frame_io::Event::Found(x))), None => (0, None) } }
    /// # fn end(&mut self) -> Option<frame_io::Event<u8, u8>> { None }
    /// # fn item(&self, _: &[u8], x: u8) -> u8 { x }
    /// # fn span(&self) -> frame_io::Span { frame_io::Span { len: 1, after: 0 } } }
    /// let mut reader = frame_io::embedded_io_async::Reader::<_, _, 16>::new(&[1u8, 2, 3][..],
    ///     Bytes);
    /// assert_eq!(block_on(reader.read()), Ok(1));
    /// assert_eq!(reader.unread(), 2);
    /// ```
    pub fn unread(&self) -> usize {
        self.core.unread()
    }

    /// The transport.
    ///
    /// ```
    /// # struct Bytes; impl frame_io::Decode for Bytes { type Error = u8; type Found = u8; type Item<'a> = u8; const TRUNCATED: u8 = 0;
    /// # fn decode(&mut self, b: &[u8]) -> (usize, Option<frame_io::Event<u8, u8>>) { match b.first() { Some(&0) => (1, Some(frame_io::Event::Error(0))), Some(&x) => (1, Some(frame_io::Event::Found(x))), None => (0, None) } }
    /// # fn end(&mut self) -> Option<frame_io::Event<u8, u8>> { None }
    /// # fn item(&self, _: &[u8], x: u8) -> u8 { x }
    /// # fn span(&self) -> frame_io::Span { frame_io::Span { len: 1, after: 0 } } }
    /// let reader = frame_io::embedded_io_async::Reader::<_, _, 16>::new(&[1u8][..], Bytes);
    /// assert_eq!(reader.get_ref().len(), 1);
    /// ```
    pub const fn get_ref(&self) -> &T {
        &self.inner
    }

    /// The transport, mutably (bytes read around the reader are not decoded).
    ///
    /// ```
    /// # fn block_on<F: core::future::Future>(f: F) -> F::Output {
    /// #     let mut f = core::pin::pin!(f);
    /// #     let mut cx = core::task::Context::from_waker(core::task::Waker::noop());
    /// #     loop { if let core::task::Poll::Ready(v) = f.as_mut().poll(&mut cx) { return v; } }
    /// # }
    /// # struct Bytes; impl frame_io::Decode for Bytes { type Error = u8; type Found = u8; type Item<'a> = u8; const TRUNCATED: u8 = 0;
    /// # fn decode(&mut self, b: &[u8]) -> (usize, Option<frame_io::Event<u8, u8>>) { match b.first() { Some(&0) => (1, Some(frame_io::Event::Error(0))), Some(&x) => (1, Some(frame_io::Event::Found(x))), None => (0, None) } }
    /// # fn end(&mut self) -> Option<frame_io::Event<u8, u8>> { None }
    /// # fn item(&self, _: &[u8], x: u8) -> u8 { x }
    /// # fn span(&self) -> frame_io::Span { frame_io::Span { len: 1, after: 0 } } }
    /// let mut reader = frame_io::embedded_io_async::Reader::<_, _, 16>::new(&[1u8][..], Bytes);
    /// *reader.get_mut() = &[];
    /// assert_eq!(block_on(reader.read()), Err(frame_io::IoError::Eof));
    /// ```
    pub fn get_mut(&mut self) -> &mut T {
        &mut self.inner
    }

    /// Gives the transport back; bytes read and not decoded are lost.
    ///
    /// ```
    /// # struct Bytes; impl frame_io::Decode for Bytes { type Error = u8; type Found = u8; type Item<'a> = u8; const TRUNCATED: u8 = 0;
    /// # fn decode(&mut self, b: &[u8]) -> (usize, Option<frame_io::Event<u8, u8>>) { match b.first() { Some(&0) => (1, Some(frame_io::Event::Error(0))), Some(&x) => (1, Some(frame_io::Event::Found(x))), None => (0, None) } }
    /// # fn end(&mut self) -> Option<frame_io::Event<u8, u8>> { None }
    /// # fn item(&self, _: &[u8], x: u8) -> u8 { x }
    /// # fn span(&self) -> frame_io::Span { frame_io::Span { len: 1, after: 0 } } }
    /// let reader = frame_io::embedded_io_async::Reader::<_, _, 16>::new(&[1u8][..], Bytes);
    /// assert_eq!(reader.into_inner(), &[1]);
    /// ```
    pub fn into_inner(self) -> T {
        self.inner
    }
}

/// `Write::write_all`, but `Ok(0)` is [`IoError::WriteZero`] instead of a panic. `P` is the
/// protocol's error, which this never returns.
///
/// # Errors
/// [`IoError::Transport`] or [`IoError::WriteZero`]; `bytes` may then be partly written.
///
/// ```
/// # fn block_on<F: core::future::Future>(f: F) -> F::Output {
/// #     let mut f = core::pin::pin!(f);
/// #     let mut cx = core::task::Context::from_waker(core::task::Waker::noop());
/// #     loop { if let core::task::Poll::Ready(v) = f.as_mut().poll(&mut cx) { return v; } }
/// # }
/// use embedded_io::SliceWriteError;
/// use frame_io::{embedded_io_async::write_all, IoError};
/// let mut out = [0u8; 4];
/// let mut w = &mut out[..];
/// assert_eq!(block_on(write_all::<_, ()>(&mut w, &[1, 2])), Ok(()));
/// assert_eq!(block_on(write_all::<_, ()>(&mut w, &[3, 4, 5])),
///     Err(IoError::Transport(SliceWriteError::Full)));
/// assert_eq!(out, [1, 2, 3, 4]);
/// ```
pub async fn write_all<W: Write, P>(
    w: &mut W,
    mut bytes: &[u8],
) -> Result<(), IoError<W::Error, P>> {
    while !bytes.is_empty() {
        let n = w.write(bytes).await.map_err(IoError::Transport)?;
        bytes = advance(bytes, n)?;
    }
    Ok(())
}

/// Writes the bytes of `bytes`, a chunk of at most 32 at a time; returns how many were
/// written. `P` is the protocol's error, which this never returns.
///
/// # Errors
/// [`IoError::Transport`] or [`IoError::WriteZero`]; the bytes may then be partly written.
///
/// ```
/// # fn block_on<F: core::future::Future>(f: F) -> F::Output {
/// #     let mut f = core::pin::pin!(f);
/// #     let mut cx = core::task::Context::from_waker(core::task::Waker::noop());
/// #     loop { if let core::task::Poll::Ready(v) = f.as_mut().poll(&mut cx) { return v; } }
/// # }
/// use frame_io::embedded_io_async::write_iter;
/// let mut out = [0u8; 40];
/// let n = block_on(write_iter::<_, ()>(&mut &mut out[..], (1..=40).map(|b: u8| b))).unwrap();
/// assert_eq!(n, 40);
/// assert_eq!(out[39], 40);
/// ```
pub async fn write_iter<W: Write, P>(
    w: &mut W,
    bytes: impl IntoIterator<Item = u8>,
) -> Result<usize, IoError<W::Error, P>> {
    let mut chunks = Chunks::new(bytes.into_iter());
    while let Some(out) = chunks.pending() {
        let n = w.write(out).await.map_err(IoError::Transport)?;
        chunks.wrote(n)?;
    }
    Ok(chunks.total())
}
