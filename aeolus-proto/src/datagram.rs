//! Decoding one UDP datagram, which may hold several messages (DECISIONS.md A9).

use crate::{ESCAPE, Error, FLAG, Frame};

/// An iterator over the frames of one datagram, unescaped in place (no copy, no buffer).
///
/// Created by [`decode_datagram`].
///
/// ```
/// use aeolus_proto::{Error, decode_datagram};
/// // TOAST "hi", then the start of another frame.
/// let mut datagram = [0x7E, 0x52, b'h', b'i', 0, 0x73, 0xEC, 0x7E, 0x7E, 0x52, b'h'];
/// let mut frames = decode_datagram(&mut datagram, true);
/// assert_eq!(frames.next().map(|f| f.map(|f| f.id())), Some(Ok(82)));
/// assert_eq!(frames.next().map(|f| f.map(|f| f.id())), Some(Err(Error::Truncated)));
/// assert_eq!(frames.next().map(|f| f.map(|f| f.id())), None);
/// ```
#[derive(Debug)]
pub struct DatagramFrames<'a> {
    rest: &'a mut [u8],
    strict: bool,
}

/// Decodes one UDP datagram into an iterator of frames (or errors, one per bad frame).
///
/// The datagram buffer is unescaped in place, which is why it is borrowed mutably. A frame never
/// spans two datagrams, so bytes after the last flag are reported as [`Error::Truncated`].
///
/// ```
/// use aeolus_proto::decode_datagram;
/// // GYRO and TOAST "hi" in one datagram, 7E 7E between them (from the vectors).
/// let mut datagram = [
///     0x7e, 0x3e, 0x01, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0xf0, 0x3f, 0, 0, 0, 0, 0, 0,
///     0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0xe5, 0xe5, 0x7e, 0x7e, 0x52, 0x68, 0x69, 0x00, 0x73,
///     0xec, 0x7e,
/// ];
/// let ids: Vec<_> = decode_datagram(&mut datagram, true).map(|f| f.map(|f| f.id())).collect();
/// assert_eq!(ids, [Ok(62), Ok(82)]);
/// ```
pub fn decode_datagram(datagram: &mut [u8], strict: bool) -> DatagramFrames<'_> {
    DatagramFrames {
        rest: datagram,
        strict,
    }
}

/// Removes the escapes of a frame body in place; returns the unescaped length.
fn unescape_in_place(body: &mut [u8]) -> Result<usize, Error> {
    let mut read = 0;
    let mut write = 0;
    while let Some(&b) = body.get(read) {
        read += 1;
        let out = if b == ESCAPE {
            let next = *body.get(read).ok_or(Error::EscapedFlag)?;
            read += 1;
            match next {
                0x5D | 0x5E => next ^ 0x20,
                _ => return Err(Error::InvalidEscape),
            }
        } else {
            b
        };
        if let Some(slot) = body.get_mut(write) {
            *slot = out;
        }
        write += 1;
    }
    Ok(write)
}

impl<'a> Iterator for DatagramFrames<'a> {
    type Item = Result<Frame<'a>, Error>;

    fn next(&mut self) -> Option<Self::Item> {
        loop {
            let rest = core::mem::take(&mut self.rest);
            let start = rest.iter().position(|&b| b == FLAG)?;
            let rest = rest.get_mut(start + 1..)?;
            let Some(end) = rest.iter().position(|&b| b == FLAG) else {
                return if rest.is_empty() {
                    None
                } else {
                    Some(Err(Error::Truncated))
                };
            };
            let (body, after) = rest.split_at_mut(end);
            // The closing flag may open the next frame: keep it.
            self.rest = after;
            if body.is_empty() {
                continue;
            }
            let result = unescape_in_place(body).and_then(|n| {
                let body: &'a [u8] = body;
                Frame::new_checked(body.get(..n).unwrap_or(&[]), self.strict)
            });
            return Some(result);
        }
    }
}
