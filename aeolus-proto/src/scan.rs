//! Finding the bytes that need escaping (0x7D or 0x7E) four bytes at a time, and the next flag a machine word at a time.

use crate::ESCAPE;

/// Whether `byte` is the flag or the escape byte.
#[inline(always)]
pub(crate) const fn is_special(byte: u8) -> bool {
    // In 32 bits, so no zero extension is needed after the subtraction.
    (byte as u32).wrapping_sub(ESCAPE as u32) < 2
}

/// `SPECIAL[b]` is whether `b` is the flag or the escape byte: the test of [`is_special`] as
/// one load. The decoder's per-byte path uses it: at opt-level "s" the arithmetic test compiles to three
/// instructions (the subtraction is narrowed to a byte and zero-extended again) where the
/// table takes one load, two instructions a byte fewer for 256 bytes of flash.
pub(crate) static SPECIAL: [bool; 256] = {
    let mut t = [false; 256];
    t[ESCAPE as usize] = true;
    t[crate::FLAG as usize] = true;
    t
};

/// The high bit set in the lowest byte of the little-endian word `x` that is 0x7D or 0x7E
/// (bits above it may be spurious); zero if no byte of `x` is one. `(v - 0x01..) & !v & 0x80..`
/// marks the lowest zero byte of `v` exactly, so the lowest mark of the two tests is the first
/// special byte. Four bytes whatever the machine word: the decoder's and the encoder's loops
/// copy and run the CRC a 32-bit word at a time.
#[inline(always)]
pub(crate) const fn special_bytes(x: u32) -> u32 {
    const ONES: u32 = 0x0101_0101;
    let a = x ^ 0x7D7D_7D7D;
    let b = x ^ 0x7E7E_7E7E;
    (a.wrapping_sub(ONES) & !a | b.wrapping_sub(ONES) & !b) & 0x8080_8080
}

/// Bytes in a machine word: the decoder's loop takes one a step on 64-bit hosts, and
/// [`find_flag`] on every target.
pub(crate) const WORD: usize = core::mem::size_of::<usize>();

/// `0x01` in every byte of a machine word.
const ONES: usize = usize::MAX / 0xFF;

/// The high bit set in the lowest zero byte of the machine word `x` (bits above it may be
/// spurious); zero if no byte of `x` is zero. XOR a word with a byte repeated first, and its
/// lowest mark is the first byte equal to that byte.
#[inline(always)]
const fn zero_bytes(x: usize) -> usize {
    x.wrapping_sub(ONES) & !x & (ONES << 7)
}

/// [`special_bytes`] over a whole machine word: the same four-byte test on 32-bit targets,
/// eight bytes at once on 64-bit hosts.
#[cfg(target_pointer_width = "64")]
#[inline(always)]
pub(crate) const fn special_in_word(x: usize) -> usize {
    zero_bytes(x ^ (ONES * 0x7D)) | zero_bytes(x ^ (ONES * 0x7E))
}

/// Where the first flag (0x7E) of `bytes` is, if it has one: where the frame in progress ends
/// and the next begins. A machine word is tested a step, so a decoder that is hunting for a
/// frame (after garbage or an error) passes over the garbage a word at a time, and a reader
/// that must act before each frame ends can cut a slice at its flags cheaply.
///
/// ```
/// assert_eq!(aeolus_proto::find_flag(&[0x01, 0x7D, 0x5E, 0x7E, 0x7E]), Some(3));
/// assert_eq!(aeolus_proto::find_flag(&[0x01, 0x02, 0x7D]), None);
/// ```
#[inline(always)]
pub fn find_flag(bytes: &[u8]) -> Option<usize> {
    let mut at = 0;
    let mut rest = bytes;
    while let Some((w, tail)) = rest.split_first_chunk::<WORD>() {
        let hits = zero_bytes(usize::from_le_bytes(*w) ^ (ONES * crate::FLAG as usize));
        if hits != 0 {
            return Some(at + (hits.trailing_zeros() / 8) as usize);
        }
        at += WORD;
        rest = tail;
    }
    rest.iter().position(|&b| b == crate::FLAG).map(|i| at + i)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn find_flag_finds_the_first_flag_at_every_place_and_alignment() {
        // Fillers next to the flag (0x7D, 0x7F) and the word trick's borrow cases (0x00, 0xFF).
        for filler in [0x00, 0x7D, 0x7F, 0xFE, 0xFF] {
            for v in 0..=255u8 {
                for at in 0..19 {
                    let mut bytes = [filler; 19];
                    bytes[at] = v;
                    // A second flag later must not hide the first.
                    bytes[18] = 0x7E;
                    for start in 0..bytes.len() {
                        let s = &bytes[start..];
                        let want = s.iter().position(|&b| b == 0x7E);
                        assert_eq!(
                            find_flag(s),
                            want,
                            "{filler:02x} {v:02x} at {at} from {start}"
                        );
                        let cut = &s[..s.len() - 1];
                        let want = cut.iter().position(|&b| b == 0x7E);
                        assert_eq!(
                            find_flag(cut),
                            want,
                            "{filler:02x} {v:02x} at {at} from {start}, cut"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn the_word_test_finds_the_first_special_byte() {
        let mut x = 0x2545_F491u32;
        for _ in 0..200_000 {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            // Bias the bytes towards 0x7C..=0x7F.
            let w = x & !(((x >> 3) & 0x0303_0303) * 0x20);
            let b = w.to_le_bytes();
            let first = b.iter().position(|&v| is_special(v));
            let hits = special_bytes(w);
            let got = if hits == 0 {
                None
            } else {
                Some((hits.trailing_zeros() / 8) as usize)
            };
            assert_eq!(first, got, "{w:08x}");
            // The machine-word test on the same bytes, repeated to fill a word.
            #[cfg(target_pointer_width = "64")]
            {
                let mut word = [0u8; WORD];
                for (i, v) in word.iter_mut().enumerate() {
                    *v = b[i % 4];
                }
                let hits = special_in_word(usize::from_le_bytes(word));
                let got = if hits == 0 {
                    None
                } else {
                    Some((hits.trailing_zeros() / 8) as usize)
                };
                assert_eq!(first, got, "{w:08x}");
            }
        }
        for v in 0..=255u8 {
            assert_eq!(special_bytes(u32::from(v)) != 0, is_special(v));
            #[cfg(target_pointer_width = "64")]
            assert_eq!(special_in_word(usize::from(v)) != 0, is_special(v));
            assert_eq!(SPECIAL[usize::from(v)], is_special(v));
        }
    }
}
