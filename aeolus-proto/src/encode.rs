//! Building frames: flag, ID, data and CRC, escaped, flag (spec section 4.1).

use crate::{
    ESCAPE, EncodeError, FLAG, crc,
    scan::{is_special, special_bytes},
};

/// Whether an encoded frame carries a real CRC.
///
/// ```
/// use aeolus_proto::{encode_frame, CrcMode};
/// let mut out = [0u8; 16];
/// let n = encode_frame(82, b"hi\0", &[], CrcMode::Omit, &mut out).unwrap();
/// assert_eq!(&out[..n], &[0x7E, 0x52, b'h', b'i', 0x00, 0x00, 0x00, 0x7E]); // `00 00`: no CRC
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum CrcMode {
    /// Compute the CRC and send it, least significant byte first (the default).
    #[default]
    Compute,
    /// Send `00 00`, which the spec defines as "no CRC" (section 4.1).
    Omit,
}

/// The worst-case length on the wire of a frame carrying `data_len` data bytes: two flags plus
/// the ID, the data and the CRC, every one of them escaped.
///
/// Use it to size buffers at compile time:
///
/// ```
/// use aeolus_proto::{max_encoded_len, message::Gyro};
/// let mut buf = [0u8; max_encoded_len(Gyro::LEN)];
/// assert_eq!(buf.len(), 72);
/// ```
pub const fn max_encoded_len(data_len: usize) -> usize {
    2 + 2 * (1 + data_len + 2)
}

/// Copies `head` and then `tail` into `out` at `at`, escaping 0x7D and 0x7E, and runs the
/// CRC `crc` over them: one pass. Four bytes a step while a word holds no byte to escape (one
/// load, one store, one test and two table steps of the CRC), the input and output words in
/// lockstep under one counter; the bytes of a word that holds one go one at a time. Returns
/// the new write position and the CRC. (One call for both slices, so it is inlined at its one
/// call site.)
#[inline]
fn put_escaped(
    out: &mut [u8],
    mut at: usize,
    head: &[u8],
    mut tail: &[u8],
    crc: u16,
) -> Option<(usize, u16)> {
    let mut c = (crc as u32) << 16;
    let mut src = head;
    loop {
        // The words that fit in both the input and the output: no bounds check per word.
        let mut words = 0;
        let dst = out.get_mut(at..).unwrap_or_default();
        for (s, d) in src.chunks_exact(4).zip(dst.chunks_exact_mut(4)) {
            let (Ok(s), Ok(d)) = (<[u8; 4]>::try_from(s), <&mut [u8; 4]>::try_from(d)) else {
                break;
            };
            // Stored before the test: a word with a byte to escape is written again below.
            *d = s;
            let w = u32::from_le_bytes(s);
            if special_bytes(w) != 0 {
                break;
            }
            c = crc::update_word(c, w.swap_bytes());
            words += 1;
        }
        at += 4 * words;
        src = src.get(4 * words..).unwrap_or_default();
        let Some((&byte, rest)) = src.split_first() else {
            if tail.is_empty() {
                return Some((at, (c >> 16) as u16));
            }
            src = core::mem::take(&mut tail);
            continue;
        };
        c = (crc::update((c >> 16) as u16, byte) as u32) << 16;
        at = put_escaped_byte(out, at, byte)?;
        src = rest;
    }
}

/// Writes one byte into `out` at `at`, escaped if it is 0x7D or 0x7E. Returns the new write
/// position. For the ID and the CRC bytes, where a run scan and a bulk copy cost more than
/// they save.
#[inline(always)]
fn put_escaped_byte(out: &mut [u8], at: usize, byte: u8) -> Option<usize> {
    if is_special(byte) {
        let pair = out.get_mut(at..).and_then(|o| o.get_mut(..2))?;
        pair.copy_from_slice(&[ESCAPE, byte ^ 0x20]);
        Some(at + 2)
    } else {
        *out.get_mut(at)? = byte;
        Some(at + 1)
    }
}

/// Encodes one frame into `out` and returns the number of bytes written.
///
/// The data is `head` followed by `tail` (pass `&[]` as `tail` for a single slice; the text
/// messages use it for their NUL terminator, so no copy is needed).
///
/// ```
/// use aeolus_proto::{encode_frame, CrcMode};
/// let mut out = [0u8; 16];
/// let n = encode_frame(82, b"hi\0", &[], CrcMode::Compute, &mut out).unwrap();
/// assert_eq!(&out[..n], &[0x7E, 0x52, b'h', b'i', 0x00, 0x73, 0xEC, 0x7E]);
/// ```
///
/// # Errors
/// [`EncodeError::BufferTooSmall`] if `out` cannot hold the escaped frame; `out` then holds a
/// partial frame that must not be sent. Its `needed` is [`max_encoded_len`] of the data: a
/// buffer that long always holds the frame. (The exact length depends on how many bytes the
/// escapes double, the CRC's included; counting them on this path cost the firmware 150 B of
/// flash, more than its budget had left.)
///
/// ```
/// use aeolus_proto::{encode_frame, max_encoded_len, CrcMode, EncodeError};
/// let mut out = [0u8; 7];
/// let e = encode_frame(82, &[0x7E, 0], &[], CrcMode::Compute, &mut out);
/// assert_eq!(e, Err(EncodeError::BufferTooSmall { needed: max_encoded_len(2) }));
/// let mut out = [0u8; max_encoded_len(2)];
/// assert_eq!(encode_frame(82, &[0x7E, 0], &[], CrcMode::Compute, &mut out), Ok(8));
/// ```
pub fn encode_frame(
    id: u8,
    head: &[u8],
    tail: &[u8],
    crc_mode: CrcMode,
    out: &mut [u8],
) -> Result<usize, EncodeError> {
    write_frame(id, head, tail, crc_mode, out).ok_or(EncodeError::BufferTooSmall {
        needed: max_encoded_len(head.len().saturating_add(tail.len())),
    })
}

/// [`encode_frame`]'s writing; `None` when `out` is too short.
fn write_frame(
    id: u8,
    head: &[u8],
    tail: &[u8],
    crc_mode: CrcMode,
    out: &mut [u8],
) -> Option<usize> {
    *out.first_mut()? = FLAG;
    let at = put_escaped_byte(out, 1, id)?;
    let (mut at, crc) = put_escaped(out, at, head, tail, crc::update(0, id))?;
    let crc = match crc_mode {
        CrcMode::Compute => crc,
        CrcMode::Omit => 0,
    };
    let [lo, hi] = crc.to_le_bytes();
    at = put_escaped_byte(out, at, lo)?;
    at = put_escaped_byte(out, at, hi)?;
    *out.get_mut(at)? = FLAG;
    Some(at + 1)
}

/// An iterator over the bytes of one escaped frame, for a UART TX path with no buffer.
///
/// The CRC is computed on the fly as the data goes out.
///
/// ```
/// use aeolus_proto::{FrameBytes, CrcMode};
/// let wire: Vec<u8> = FrameBytes::new(82, b"hi\0", CrcMode::Compute).collect();
/// assert_eq!(wire, [0x7E, 0x52, b'h', b'i', 0x00, 0x73, 0xEC, 0x7E]);
/// ```
#[derive(Debug, Clone)]
pub struct FrameBytes<'a> {
    id: u8,
    data: &'a [u8],
    crc: u16,
    mode: CrcMode,
    /// 0: start flag; 1: ID; 2..2+n: data; then CRC low, CRC high, end flag.
    pos: usize,
    /// The second byte of an escape pair, waiting to go out.
    pending: Option<u8>,
}

impl<'a> FrameBytes<'a> {
    /// Prepares the frame `id` + `data` (+ CRC).
    ///
    /// ```
    /// use aeolus_proto::{CrcMode, FrameBytes};
    /// let bytes: Vec<u8> = FrameBytes::new(82, b"hi\0", CrcMode::Compute).collect();
    /// assert_eq!(bytes, [0x7E, 0x52, b'h', b'i', 0x00, 0x73, 0xEC, 0x7E]);
    /// ```
    pub const fn new(id: u8, data: &'a [u8], mode: CrcMode) -> Self {
        FrameBytes {
            id,
            data,
            crc: 0,
            mode,
            pos: 0,
            pending: None,
        }
    }

    fn logical(&mut self, pos: usize) -> Option<u8> {
        let n = self.data.len();
        let byte = match pos {
            1 => self.id,
            p if p >= 2 && p - 2 < n => *self.data.get(p - 2)?,
            p if p == n + 2 || p == n + 3 => {
                let crc = if self.mode == CrcMode::Omit {
                    0
                } else {
                    self.crc
                };
                return Some(if p == n + 2 {
                    crc as u8
                } else {
                    (crc >> 8) as u8
                });
            }
            _ => return None,
        };
        self.crc = crc::update(self.crc, byte);
        Some(byte)
    }
}

impl Iterator for FrameBytes<'_> {
    type Item = u8;

    fn next(&mut self) -> Option<u8> {
        if let Some(b) = self.pending.take() {
            return Some(b);
        }
        let pos = self.pos;
        let end = self.data.len().saturating_add(4);
        if pos > end {
            return None;
        }
        self.pos = pos.saturating_add(1);
        if pos == 0 || pos == end {
            return Some(FLAG);
        }
        let byte = self.logical(pos)?;
        if is_special(byte) {
            self.pending = Some(byte ^ 0x20);
            Some(ESCAPE)
        } else {
            Some(byte)
        }
    }
}
