//! Decoder counters (MAVLink style, wrapping), the same for both decoders.

/// What a decoder ([`crate::MessageDecoder`] or [`crate::CommandDecoder`]) has seen. Every counter
/// wraps. The names shared with the other protocol crates (`frames_ok`, `checksum_errors`,
/// `bytes_discarded`) mean the same there; see `docs/architecture.md`.
///
/// ```
/// use aok_proto::{CommandDecoder, Decode};
/// let mut dec = CommandDecoder::new();
/// dec.feed(&[0x00, 0x67, 0x0c], |_| {});
/// assert_eq!(dec.stats().frames_ok, 1);
/// assert_eq!(dec.stats().unknown_bytes, 1);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Stats {
    /// Frames decoded and accepted.
    pub frames_ok: u32,
    /// Candidate frames whose checksum did not match (each is rescanned from its second byte).
    pub checksum_errors: u32,
    /// Bytes that cannot start any frame in the current state.
    pub unknown_bytes: u32,
    /// Frames with a good checksum but an out-of-range field (slot, stick); only their first
    /// byte is dropped (and counted in `bytes_discarded`), the rest rescanned.
    pub invalid: u32,
    /// Partial frames given up by `finish` (the line went quiet mid-frame).
    pub abandoned: u32,
    /// Bytes thrown away: unknown bytes, false starts and abandoned starts.
    pub bytes_discarded: u32,
}

impl Stats {
    /// All counters at zero, in a `const` context.
    pub(crate) const ZERO: Stats = Stats {
        frames_ok: 0,
        checksum_errors: 0,
        unknown_bytes: 0,
        invalid: 0,
        abandoned: 0,
        bytes_discarded: 0,
    };
}
