//! Finding the next byte that needs escaping (0x7D or 0x7E), a machine word at a time.

use crate::ESCAPE;

const WORD: usize = core::mem::size_of::<usize>();
/// 0x01 in every byte of a word.
const ONES: usize = usize::MAX / 0xFF;
/// 0x80 in every byte of a word.
const HIGHS: usize = ONES << 7;

/// Whether `byte` is the flag or the escape byte.
#[inline(always)]
pub(crate) const fn is_special(byte: u8) -> bool {
    // In 32 bits, so no zero extension is needed after the subtraction.
    (byte as u32).wrapping_sub(ESCAPE as u32) < 2
}

/// A word with the high bit set in (at least) the lowest byte of `x` that is zero. The lowest
/// set bit is exact; bits above it may be spurious, which is all [`run_len`] needs.
#[inline(always)]
const fn zero_bytes(x: usize) -> usize {
    x.wrapping_sub(ONES) & !x & HIGHS
}

/// The high bit set in the lowest byte of the little-endian word `x` that is 0x7D or 0x7E
/// (bits above it may be spurious); zero if no byte of `x` is. Four bytes whatever the
/// machine word, for the decoder's fused copy-and-CRC loop.
#[inline(always)]
pub(crate) const fn special_bytes(x: u32) -> u32 {
    const ONES32: u32 = 0x0101_0101;
    let a = x ^ 0x7D7D_7D7D;
    let b = x ^ 0x7E7E_7E7E;
    (a.wrapping_sub(ONES32) & !a | b.wrapping_sub(ONES32) & !b) & 0x8080_8080
}

/// The number of leading bytes of `bytes` that are neither 0x7D nor 0x7E.
#[inline(always)]
pub(crate) fn run_len(bytes: &[u8]) -> usize {
    let mut words = bytes.chunks_exact(WORD);
    let mut n = 0;
    for w in &mut words {
        // `chunks_exact` guarantees the length; the fallback only keeps panics out.
        let x = usize::from_le_bytes(<[u8; WORD]>::try_from(w).unwrap_or([0x7E; WORD]));
        let hits = zero_bytes(x ^ (ONES * 0x7D)) | zero_bytes(x ^ (ONES * 0x7E));
        if hits != 0 {
            return n + (hits.trailing_zeros() / 8) as usize;
        }
        n += WORD;
    }
    let tail = words.remainder();
    n + tail
        .iter()
        .position(|&b| is_special(b))
        .unwrap_or(tail.len())
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;

    #[test]
    fn run_len_agrees_with_a_plain_scan_everywhere() {
        let mut x = 0x1234_5678_9ABC_DEF1u64;
        for len in 0..70 {
            for _ in 0..300 {
                let bytes: std::vec::Vec<u8> = (0..len)
                    .map(|_| {
                        x ^= x << 13;
                        x ^= x >> 7;
                        x ^= x << 17;
                        [0x7D, 0x7E, 0x7C, 0x7F, 0xFD, 0xFE, 0x00, x as u8][(x >> 40) as usize % 8]
                    })
                    .collect();
                let plain = bytes.iter().position(|&b| is_special(b)).unwrap_or(len);
                assert_eq!(run_len(&bytes), plain, "{bytes:02x?}");
            }
        }
    }
}
