//! The AEOLUS frame check (DECISIONS.md A2).
//!
//! The algorithm is the one printed in section 4.3 of the spec:
//! `crc = lut[crc >> 8] ^ (crc << 8) ^ byte`, polynomial 0x1021, initial value 0, over the
//! message ID and the unescaped data. This is the GDL90 CRC; it is *not* CRC-16/XMODEM
//! (the data byte is added after the table step, not before). The table is built at compile
//! time.

/// The CRC polynomial (CRC-CCITT).
pub const POLY: u16 = 0x1021;

/// The 256-entry lookup table of section 4.3, computed at compile time.
pub const TABLE: [u16; 256] = build_table();

const fn build_table() -> [u16; 256] {
    let mut table = [0u16; 256];
    let mut i = 0;
    while i < 256 {
        let mut crc = (i as u16) << 8;
        let mut bit = 0;
        while bit < 8 {
            crc = (crc << 1) ^ if crc & 0x8000 != 0 { POLY } else { 0 };
            bit += 1;
        }
        table[i] = crc;
        i += 1;
    }
    table
}

/// Advances the CRC by one byte.
///
/// ```
/// use aeolus_proto::crc;
/// let c = b"123456789".iter().fold(0, |c, &b| crc::update(c, b));
/// assert_eq!(c, 0xBEEF);
/// ```
#[inline(always)]
pub const fn update(crc: u16, byte: u8) -> u16 {
    TABLE[(crc >> 8) as usize] ^ (crc << 8) ^ byte as u16
}

/// Two bytes at once: `PAIR[h]` is what the high byte `h` of the CRC contributes after two
/// [`update`] steps. The table step is linear (XOR) in its index, so two steps from `crc`
/// over `b0, b1` give `PAIR[crc >> 8] ^ TABLE[crc & 0xFF] ^ (b0 << 8 | b1)`.
const PAIR: [u16; 256] = build_pair_table();

const fn build_pair_table() -> [u16; 256] {
    let mut pair = [0u16; 256];
    let mut i = 0;
    while i < 256 {
        let t = TABLE[i];
        pair[i] = TABLE[(t >> 8) as usize] ^ (t << 8);
        i += 1;
    }
    pair
}

/// The table part of two [`update`] steps, for a CRC kept in the upper 16 bits of `c`; the
/// lower 16 bits of `c` are ignored and those of the result are zero. Both indices come out
/// of the upper half with a single shift or bit-field extract each, and the caller may XOR
/// a whole big-endian word in (its lower half lands in the ignored bits). The tables stay
/// `u16` (1 KiB for both): on Cortex-M the shift back up folds into the XOR for free.
#[inline(always)]
const fn step2(c: u32) -> u32 {
    ((PAIR[(c >> 24) as usize] ^ TABLE[((c >> 16) & 0xFF) as usize]) as u32) << 16
}

/// Advances the CRC over a whole byte slice: the same as [`update`] on every byte in turn,
/// four bytes per step.
///
/// ```
/// use aeolus_proto::crc;
/// let c = crc::update_slice(crc::update_slice(0, b"1234"), b"56789");
/// assert_eq!(c, 0xBEEF);
/// ```
#[inline]
pub const fn update_slice(crc: u16, bytes: &[u8]) -> u16 {
    let mut c = (crc as u32) << 16;
    let mut rest = bytes;
    while let [b0, b1, b2, b3, tail @ ..] = rest {
        // `b0 b1` land in the upper half; `b2 b3` in the ignored lower half.
        c = update_word(c, u32::from_be_bytes([*b0, *b1, *b2, *b3]));
        rest = tail;
    }
    if let [b0, b1, tail @ ..] = rest {
        c = step2(c) ^ ((u16::from_be_bytes([*b0, *b1]) as u32) << 16);
        rest = tail;
    }
    let crc = (c >> 16) as u16;
    if let [b, ..] = rest {
        update(crc, *b)
    } else {
        crc
    }
}

/// Advances a CRC kept in the upper 16 bits of `c` over four bytes, `word` holding them
/// big-endian (the first byte in the top bits): two [`step2`]s. The lower 16 bits of `c` are
/// ignored and those of the result are zero.
#[inline(always)]
pub(crate) const fn update_word(c: u32, word: u32) -> u32 {
    let c = step2(c) ^ word;
    step2(c) ^ (word << 16)
}

/// What the CRC run over a whole frame (ID, data **and** the two received CRC bytes) comes to
/// when the received CRC is right: the CRC of the body continued over its own two bytes, low
/// byte first. Two table steps are a linear, invertible map of the CRC (multiplication by
/// x^16 modulo the polynomial, which has a constant term), so for given received bytes the
/// running CRC equals this exactly when the body's CRC equals `received`. A decoder can then
/// keep one running CRC over every byte it stores, without knowing in advance which two bytes
/// are the CRC.
///
/// ```
/// use aeolus_proto::crc;
/// let body = b"123456789";
/// let sent = crc::checksum(body).to_le_bytes();
/// let all = crc::update_slice(crc::checksum(body), &sent);
/// assert_eq!(all, crc::residue(u16::from_le_bytes(sent)));
/// ```
#[inline]
pub const fn residue(received: u16) -> u16 {
    let [lo, hi] = received.to_le_bytes();
    update(update(received, lo), hi)
}

/// The CRC of a whole byte slice (the message ID followed by the data).
///
/// ```
/// assert_eq!(aeolus_proto::crc::checksum(b"123456789"), 0xBEEF);
/// assert_eq!(aeolus_proto::crc::checksum(&[]), 0);
/// ```
#[inline]
pub const fn checksum(bytes: &[u8]) -> u16 {
    update_slice(0, bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn update_slice_agrees_with_update_at_every_length_and_seed() {
        let mut x = 0x9E37_79B9u32;
        let mut bytes = [0u8; 40];
        for b in bytes.iter_mut() {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            *b = x as u8;
        }
        for seed in [0u16, 1, 0x8000, 0xBEEF, 0xFFFF] {
            for len in 0..=bytes.len() {
                let part = &bytes[..len];
                let plain = part.iter().fold(seed, |c, &b| update(c, b));
                assert_eq!(update_slice(seed, part), plain, "seed {seed:#x} len {len}");
            }
        }
    }
}
