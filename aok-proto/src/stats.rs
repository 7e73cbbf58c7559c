//! Decoder counters (MAVLink style, wrapping).

/// What a decoder has seen. Every counter wraps.
///
/// ```
/// let mut dec = aok_proto::DeviceDecoder::new();
/// for b in [0x00, 0x67, 0x0c] {
///     for _ in dec.push(b) {}
/// }
/// assert_eq!(dec.stats().ok, 1);
/// assert_eq!(dec.stats().unknown_bytes, 1);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct DecoderStats {
    /// Frames decoded and accepted.
    pub ok: u32,
    /// Candidate frames whose checksum did not match (each is rescanned from its second byte).
    pub checksum_errors: u32,
    /// Bytes that cannot start any frame in the current state.
    pub unknown_bytes: u32,
    /// Frames with a good checksum but an out-of-range field (slot, stick); consumed whole.
    pub invalid: u32,
    /// Partial frames abandoned by `idle()` (the line went quiet mid-frame).
    pub abandoned: u32,
    /// Bytes thrown away: unknown bytes, false starts and abandoned starts.
    pub discarded: u32,
}
