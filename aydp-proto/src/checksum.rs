//! The XOR checksum (DECISIONS.md Y4).

/// XOR of every byte of `bytes`: over the start byte through the last data byte this is the
/// checksum a message ends with.
///
/// ```
/// // "save config" from the document, checksum 0x7C per Y6.
/// assert_eq!(aydp_proto::checksum::xor(&[0xFF, 0x89, 0x08, 0, 0, 0, 0x02]), 0x7C);
/// ```
#[inline]
pub const fn xor(bytes: &[u8]) -> u8 {
    let mut acc = 0u8;
    let mut rest = bytes;
    while let [first, tail @ ..] = rest {
        acc ^= *first;
        rest = tail;
    }
    acc
}
