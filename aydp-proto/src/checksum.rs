//! The XOR checksum (DECISIONS.md Y4), and the word-at-a-time scans the bulk decoder uses.

/// Bytes in a machine word.
const WORD: usize = core::mem::size_of::<usize>();

/// XOR of every byte of `bytes`: over the start byte through the last data byte this is the
/// checksum a message ends with.
///
/// It works a machine word at a time (XOR is byte-wise, so the word's bytes are folded
/// together at the end), then takes the tail in one 4-, 2- and 1-byte step each at most.
///
/// ```
/// // "save config" from the document, checksum 0x7C per Y6.
/// assert_eq!(aydp_proto::checksum::xor(&[0xFF, 0x89, 0x08, 0, 0, 0, 0x02]), 0x7C);
/// // A whole message, checksum included, XORs to zero.
/// assert_eq!(aydp_proto::checksum::xor(&[0xFF, 0x89, 0x08, 0, 0, 0, 0x02, 0x7C]), 0);
/// ```
#[inline]
pub const fn xor(bytes: &[u8]) -> u8 {
    let mut acc: usize = 0;
    let mut rest = bytes;
    while let Some((pair, tail)) = rest.split_first_chunk::<{ 2 * WORD }>() {
        // Two words per step. Both halves of a `2 * WORD` array are exactly one word, so the
        // `if let` always matches; it only keeps indexing (and its panic path) out.
        // (Nested rather than a let chain: the crate's MSRV is 1.87.)
        if let Some((a, b)) = pair.split_first_chunk::<WORD>() {
            if let Some(b) = b.first_chunk::<WORD>() {
                acc ^= usize::from_ne_bytes(*a) ^ usize::from_ne_bytes(*b);
            }
        }
        rest = tail;
    }
    if let Some((w, tail)) = rest.split_first_chunk::<WORD>() {
        acc ^= usize::from_ne_bytes(*w);
        rest = tail;
    }
    if WORD > 4 {
        if let Some((w, tail)) = rest.split_first_chunk::<4>() {
            acc ^= u32::from_ne_bytes(*w) as usize;
            rest = tail;
        }
    }
    if let Some((w, tail)) = rest.split_first_chunk::<2>() {
        acc ^= u16::from_ne_bytes(*w) as usize;
        rest = tail;
    }
    if let [last, ..] = rest {
        acc ^= *last as usize;
    }
    // Fold the word's bytes onto its lowest byte (the first step is a no-op on 32 bits).
    acc ^= ((acc as u64) >> 32) as usize;
    acc ^= acc >> 16;
    acc ^= acc >> 8;
    acc as u8
}

/// 0x01 in every byte of a word.
const ONES: usize = usize::MAX / 0xFF;
/// 0x80 in every byte of a word.
const HIGHS: usize = ONES << 7;

/// The index of the first 0xFF in `bytes`, or `bytes.len()` if there is none.
#[inline]
pub(crate) fn find_ff(bytes: &[u8]) -> usize {
    let mut words = bytes.chunks_exact(WORD);
    let mut n = 0;
    for w in &mut words {
        // A byte of `x` is zero iff that byte of the word is 0xFF. The lowest marked byte of
        // `(x - ONES) & !x & HIGHS` is exactly the lowest zero byte (higher marks may be
        // spurious, and are ignored).
        let x = !usize::from_le_bytes(w.try_into().unwrap_or([0xFF; WORD]));
        let hits = x.wrapping_sub(ONES) & !x & HIGHS;
        if hits != 0 {
            return n + (hits.trailing_zeros() / 8) as usize;
        }
        n += WORD;
    }
    let tail = words.remainder();
    n + tail.iter().position(|&b| b == 0xFF).unwrap_or(tail.len())
}

/// The number of leading 0xFF bytes of `bytes`.
#[inline]
pub(crate) fn ff_run(bytes: &[u8]) -> usize {
    let mut words = bytes.chunks_exact(WORD);
    let mut n = 0;
    for w in &mut words {
        // Non-zero exactly in the bytes that are not 0xFF; the lowest one ends the run.
        let x = !usize::from_le_bytes(w.try_into().unwrap_or([0; WORD]));
        if x != 0 {
            return n + (x.trailing_zeros() / 8) as usize;
        }
        n += WORD;
    }
    let tail = words.remainder();
    n + tail.iter().position(|&b| b != 0xFF).unwrap_or(tail.len())
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use std::vec::Vec;

    fn bytes(x: &mut u64, len: usize) -> Vec<u8> {
        (0..len)
            .map(|_| {
                *x ^= *x << 13;
                *x ^= *x >> 7;
                *x ^= *x << 17;
                [
                    0xFF,
                    0xFF,
                    0xFE,
                    0x7F,
                    0x00,
                    0x01,
                    *x as u8,
                    (*x >> 8) as u8,
                ][(*x >> 40) as usize % 8]
            })
            .collect()
    }

    #[test]
    fn word_scans_and_xor_agree_with_plain_loops_everywhere() {
        let mut x = 0x9E37_79B9_7F4A_7C15u64;
        for len in 0..80 {
            for _ in 0..300 {
                let b = bytes(&mut x, len);
                let plain_xor = b.iter().fold(0, |a, &v| a ^ v);
                assert_eq!(xor(&b), plain_xor, "{b:02x?}");
                let plain_ff = b.iter().position(|&v| v == 0xFF).unwrap_or(len);
                assert_eq!(find_ff(&b), plain_ff, "{b:02x?}");
                let plain_run = b.iter().position(|&v| v != 0xFF).unwrap_or(len);
                assert_eq!(ff_run(&b), plain_run, "{b:02x?}");
            }
        }
    }
}
