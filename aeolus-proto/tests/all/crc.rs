//! The CRC against every line of the vectors made by compiling the spec's own C code.

use crate::common;
use aeolus_proto::crc;
use common::hex;
use proptest::prelude::*;

/// CRC-16/XMODEM from the `crc` crate, an independent implementation.
fn xmodem(bytes: &[u8]) -> u16 {
    ::crc::Crc::<u16>::new(&::crc::CRC_16_XMODEM).checksum(bytes)
}

const VECTORS: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../testdata/aeolus-crc.txt"
));

#[test]
fn every_vector_line_matches() {
    let mut checked = 0;
    for line in VECTORS
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
    {
        let (input, expected) = line.split_once(' ').expect("two columns");
        let input = if input == "-" { Vec::new() } else { hex(input) };
        let expected = u16::from_str_radix(expected.trim(), 16).unwrap();
        assert_eq!(crc::checksum(&input), expected, "input {line}");
        assert_eq!(
            input.iter().fold(0, |c, &b| crc::update(c, b)),
            expected,
            "incremental, {line}"
        );
        checked += 1;
    }
    assert_eq!(checked, 19, "every vector line was read");
}

#[test]
fn not_xmodem() {
    assert_eq!(crc::checksum(b"123456789"), 0xBEEF);
    assert_eq!(xmodem(b"123456789"), 0x31C3);
}

proptest! {
    /// DECISIONS.md A2: seed(m) == XMODEM(m[..n-2]) ^ be16(m[n-2..]), checked against the
    /// `crc` crate's independent implementation.
    #[test]
    fn identity_with_xmodem(m in prop::collection::vec(any::<u8>(), 2..300)) {
        let n = m.len();
        let xmodem = xmodem(&m[..n - 2]);
        let tail = u16::from_be_bytes([m[n - 2], m[n - 1]]);
        prop_assert_eq!(crc::checksum(&m), xmodem ^ tail);
    }
}
