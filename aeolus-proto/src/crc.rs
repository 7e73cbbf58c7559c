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

/// The CRC of a whole byte slice (the message ID followed by the data).
///
/// ```
/// assert_eq!(aeolus_proto::crc::checksum(b"123456789"), 0xBEEF);
/// assert_eq!(aeolus_proto::crc::checksum(&[]), 0);
/// ```
#[inline]
pub const fn checksum(bytes: &[u8]) -> u16 {
    let mut crc = 0;
    let mut i = 0;
    while i < bytes.len() {
        crc = update(crc, bytes[i]);
        i += 1;
    }
    crc
}
