//! Framing: flag, ID, data, CRC (LSB first), escaped, flag. A message goes on the wire with
//! [`Message::encode`](crate::message::Message::encode); [`encode_frame`] frames any ID with
//! raw data.
//!
//! The framing is AEOLUS's ([`aeolus_proto::encode_frame`]), which is GDL90's: the same
//! flags, escapes and CRC. GDL90 frames always carry a computed CRC.

use crate::EncodeError;
use crate::message::MAX_TYPED_DATA;

/// The worst-case length on the wire of a frame carrying `data_len` data bytes: two flags
/// plus the ID, the data and the CRC, every one of them escaped.
///
/// ```
/// use gdl90_proto::{max_encoded_len, message::Heartbeat};
/// let buf = [0u8; max_encoded_len(Heartbeat::LEN)];
/// assert_eq!(buf.len(), 20);
/// ```
pub const fn max_encoded_len(data_len: usize) -> usize {
    aeolus_proto::max_encoded_len(data_len)
}

/// A buffer of this many bytes holds any typed message this crate encodes (the longest is
/// the ForeFlight ID, 38 data bytes).
pub const MAX_ENCODED_LEN: usize = max_encoded_len(MAX_TYPED_DATA);

/// Encodes one frame with message ID `id` and data `data` into `out`; returns the number of
/// bytes written.
///
/// ```
/// use gdl90_proto::encode_frame;
/// // The ICD's heartbeat example (section 2.2.4).
/// let mut out = [0u8; 20];
/// let n = encode_frame(0, &[0x81, 0x41, 0xDB, 0xD0, 0x08, 0x02], &mut out).unwrap();
/// assert_eq!(&out[..n], &[0x7E, 0x00, 0x81, 0x41, 0xDB, 0xD0, 0x08, 0x02, 0xB3, 0x8B, 0x7E]);
/// ```
///
/// # Errors
/// [`EncodeError::BufferTooSmall`] if `out` cannot hold the escaped frame; `out` then holds a
/// partial frame that must not be sent.
pub fn encode_frame(id: u8, data: &[u8], out: &mut [u8]) -> Result<usize, EncodeError> {
    aeolus_proto::encode_frame(id, data, &[], aeolus_proto::CrcMode::Compute, out)
        .map_err(EncodeError::from_framing)
}
