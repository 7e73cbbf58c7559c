//! Blocking AEOLUS frames over [`embedded_io`] (feature `embedded-io`).
//!
//! - [`FrameReader`] is `frame-io`'s reader around a [`Decoder`] and a read buffer of `R`
//!   bytes; each [`FrameReader::read`] returns the next frame. Every read is decoded
//!   with the slice fast path of [`crate::Decode::feed`], and the frames and errors are exactly
//!   those of `feed` over the same bytes in any pieces.
//! - [`FrameWriter`] encodes frames straight into a [`Write`], a chunk of at most 32 bytes at
//!   a time, with no frame buffer.
//!
//! The async twins are in [`crate::embedded_io_async`]. A reader fails with [`IoError`](crate::IoError), a writer with [`WriteError`].

use ::embedded_io::Write;

use crate::io::{frame_bytes, message_data, scratch};
use crate::message::Message;
use crate::{CrcMode, Decoder, WriteError};

/// Reads AEOLUS frames from a blocking [`Read`](::embedded_io::Read): a [`Decoder<N>`] plus an
/// `R`-byte read buffer ([`frame_io::embedded_io::Reader`] over a [`Decoder<N>`]: its methods are
/// there).
///
/// ```
/// use aeolus_proto::{embedded_io::FrameReader, Decoder, IoError, message::Message};
///
/// // TOAST "hi", then half a frame and the end of the stream.
/// let wire: &[u8] = &[0x7E, 0x52, b'h', b'i', 0x00, 0x73, 0xEC, 0x7E, 0x52, b'h'];
/// let mut reader = FrameReader::<_, 64>::new(wire, Decoder::new());
/// let frame = reader.read().unwrap();
/// assert!(matches!(frame.message(), Ok(Message::Toast(t)) if t.as_str() == Some("hi")));
/// assert_eq!(reader.read().err(), Some(IoError::UnexpectedEof { pending: 2 }));
/// assert_eq!(reader.read().err(), Some(IoError::Eof));
/// ```
pub type FrameReader<T, const N: usize, const R: usize = 64> =
    frame_io::embedded_io::Reader<T, Decoder<N>, R>;

/// Writes AEOLUS frames into a blocking [`Write`], encoding on the fly (no frame buffer).
///
/// ```
/// use aeolus_proto::{embedded_io::FrameWriter, CrcMode};
/// let mut wire = [0u8; 16];
/// let mut writer = FrameWriter::new(&mut wire[..]);
/// let n = writer.write_frame(82, b"hi\0", CrcMode::Compute).unwrap();
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
    /// let writer = aeolus_proto::embedded_io::FrameWriter::new(&mut buf[..]);
    /// assert_eq!(writer.into_inner().len(), 8);
    /// ```
    pub const fn new(inner: W) -> Self {
        Self { inner }
    }

    /// Encodes one frame (ID + data + CRC) into the transport; returns the wire bytes written.
    /// It does not flush.
    ///
    /// # Errors
    /// [`WriteError::Transport`] or [`WriteError::WriteZero`]; the frame may then be partly sent.
    ///
    /// ```
    /// use aeolus_proto::{embedded_io::FrameWriter, CrcMode};
    /// let mut wire = [0u8; 16];
    /// // `00 00` instead of a CRC; 0x7E in the data is escaped.
    /// let n = FrameWriter::new(&mut wire[..]).write_frame(99, &[0x7E], CrcMode::Omit).unwrap();
    /// assert_eq!(&wire[..n], &[0x7E, 99, 0x7D, 0x5E, 0, 0, 0x7E]);
    /// ```
    pub fn write_frame(
        &mut self,
        id: u8,
        data: &[u8],
        crc: CrcMode,
    ) -> Result<usize, WriteError<W::Error>> {
        frame_io::embedded_io::write_iter(&mut self.inner, frame_bytes(id, data, crc))
    }

    /// Encodes a typed message; returns the wire bytes written. It does not flush.
    ///
    /// # Errors
    /// As [`FrameWriter::write_frame`].
    ///
    /// ```
    /// use aeolus_proto::embedded_io::{FrameReader, FrameWriter};
    /// use aeolus_proto::{CrcMode, Decoder, message::{Gyro, Message}};
    /// let gyro = Message::Gyro(Gyro { valid: true, timestamp_ms: 7.0, x: 0.1, y: 0.0, z: -0.2 });
    /// let mut wire = [0u8; 80];
    /// let n = FrameWriter::new(&mut wire[..]).write_message(&gyro, CrcMode::Compute).unwrap();
    /// let mut reader = FrameReader::<_, 64>::new(&wire[..n], Decoder::new());
    /// assert_eq!(reader.read().unwrap().message(), Ok(gyro));
    /// ```
    pub fn write_message(
        &mut self,
        message: &Message<'_>,
        crc: CrcMode,
    ) -> Result<usize, WriteError<W::Error>> {
        let mut scratch = scratch();
        let data = message_data(message, &mut scratch);
        self.write_frame(message.id(), data, crc)
    }

    /// Flushes the transport.
    ///
    /// # Errors
    /// [`WriteError::Transport`].
    ///
    /// ```
    /// let mut buf = [0u8; 8];
    /// let mut writer = aeolus_proto::embedded_io::FrameWriter::new(&mut buf[..]);
    /// assert!(writer.flush().is_ok());
    /// ```
    pub fn flush(&mut self) -> Result<(), WriteError<W::Error>> {
        self.inner.flush().map_err(WriteError::Transport)
    }

    /// The transport, mutably.
    ///
    /// ```
    /// let mut buf = [0u8; 8];
    /// let mut writer = aeolus_proto::embedded_io::FrameWriter::new(&mut buf[..]);
    /// assert_eq!(writer.get_mut().len(), 8);
    /// ```
    pub fn get_mut(&mut self) -> &mut W {
        &mut self.inner
    }

    /// Gives the transport back.
    ///
    /// ```
    /// let mut buf = [0u8; 8];
    /// let writer = aeolus_proto::embedded_io::FrameWriter::new(&mut buf[..]);
    /// assert_eq!(writer.into_inner().len(), 8);
    /// ```
    pub fn into_inner(self) -> W {
        self.inner
    }
}
