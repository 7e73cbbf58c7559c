//! GDL90 as an EFB app sees it, decoded by hand from the ICD's byte layout and from Stratux's
//! (not by `gdl90-proto` or `aeolus-proto`): the frame check computed bit by bit from the ICD's
//! polynomial, the unescaping, and the Stratux AHRS report's fields. Shared by the tests of
//! `protolink gdl90` on `sim` (host-tool) and on the firmware in QEMU.

/// The GDL90 frame check (ICD section 2.2.3), computed bit by bit: the ICD's table entry for a
/// byte is that byte shifted up 8 and divided by the polynomial 0x1021, and each data byte is
/// folded in as `table[crc >> 8] ^ (crc << 8) ^ byte`, from 0.
pub fn icd_crc(bytes: &[u8]) -> u16 {
    bytes.iter().fold(0u16, |crc, &b| {
        let mut entry = crc & 0xFF00;
        for _ in 0..8 {
            entry = if entry & 0x8000 != 0 {
                (entry << 1) ^ 0x1021
            } else {
                entry << 1
            };
        }
        entry ^ (crc << 8) ^ u16::from(b)
    })
}

/// One GDL90 frame's ID and data, unescaped, with its CRC checked by [`icd_crc`], or `None`
/// for a bad frame.
pub fn unframe(datagram: &[u8]) -> Option<(u8, Vec<u8>)> {
    let inner = datagram.strip_prefix(&[0x7E])?.strip_suffix(&[0x7E])?;
    let mut raw = Vec::new();
    let mut escaped = false;
    for &b in inner {
        if escaped {
            raw.push(b ^ 0x20);
            escaped = false;
        } else if b == 0x7D {
            escaped = true;
        } else {
            raw.push(b);
        }
    }
    let (body, crc) = raw.split_at(raw.len().checked_sub(2)?);
    let want = u16::from_le_bytes([crc[0], crc[1]]);
    (icd_crc(body) == want).then(|| (body[0], body[1..].to_vec()))
}

/// A Stratux AHRS report (0x4C) decoded here by hand from Stratux's layout
/// (`makeAHRSGDL90Report`): after `4C 45 01 01`, big-endian signed 16-bit roll, pitch,
/// heading, slip/skid, yaw rate, G (tenths), IAS (kt), then the pressure altitude unsigned as
/// feet + 5000, vertical speed (ft/min), and `7F FF` reserved. `0x7FFF` (the altitude:
/// `0xFFFF`) is invalid.
pub struct StratuxReport {
    /// Roll, pitch, heading, slip/skid, yaw rate, G, IAS, (pressure altitude), vertical speed:
    /// the nine signed words, in order (index 7 is the altitude's bytes read as signed).
    pub words: [i16; 9],
    /// The pressure altitude as sent: feet + 5000, `0xFFFF` when invalid.
    pub altitude_raw: u16,
}

/// The report in a 0x4C frame's data (after the ID); panics on a wrong length, header or
/// reserved word, as a test should.
pub fn stratux_report(data: &[u8]) -> StratuxReport {
    assert_eq!(data.len(), 23, "{data:02X?}");
    assert_eq!(&data[..3], &[0x45, 0x01, 0x01]);
    assert_eq!(&data[21..], &[0x7F, 0xFF]);
    let word = |at: usize| i16::from_be_bytes([data[at], data[at + 1]]);
    StratuxReport {
        words: [3, 5, 7, 9, 11, 13, 15, 17, 19].map(word),
        altitude_raw: u16::from_be_bytes([data[17], data[18]]),
    }
}
