//! Every typed message's bytes, one table per message.
//!
//! Offsets are **data** offsets: byte 0 is the first byte after the message ID (the ICD
//! numbers the ID as byte 1, so ICD byte `n` is data offset `n - 2`). For the ForeFlight
//! messages the sub-ID is data byte 0. Each field is a [`Bits`]: a byte range read as one
//! unsigned integer (most significant byte first unless marked LSB first), and the bits of it
//! that the field occupies. Bits not listed are reserved: sent as zero, ignored on receipt.

use core::ops::Range;

/// Where a field sits: `width` bits, `shift` bits above the least significant bit of the
/// unsigned integer that `bytes` form.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Bits {
    /// The bytes holding the field (data offsets).
    pub bytes: Range<usize>,
    /// The bytes are sent least significant first (only the heartbeat time stamp).
    pub lsb_first: bool,
    /// Position of the field's least significant bit in that integer.
    pub shift: u32,
    /// Width of the field in bits.
    pub width: u32,
}

impl Bits {
    /// A field of `width` bits at `shift` in the big-endian integer of `bytes`.
    pub(crate) const fn msb_first(bytes: Range<usize>, shift: u32, width: u32) -> Self {
        Bits {
            bytes,
            lsb_first: false,
            shift,
            width,
        }
    }

    /// A whole big-endian integer.
    pub(crate) const fn whole(bytes: Range<usize>) -> Self {
        let width = (bytes.end - bytes.start) as u32 * 8;
        Self::msb_first(bytes, 0, width)
    }

    /// A single flag bit of data byte `byte`.
    pub(crate) const fn flag(byte: usize, bit: u32) -> Self {
        Self::msb_first(byte..byte + 1, bit, 1)
    }

    /// The largest value the field holds.
    pub(crate) const fn max(&self) -> u64 {
        if self.width >= 64 {
            u64::MAX
        } else {
            (1u64 << self.width) - 1
        }
    }

    /// Reads the field. Bytes beyond the end of `data` read as zero (callers check the
    /// length first; the fallback only keeps panics out).
    pub(crate) fn get(&self, data: &[u8]) -> u64 {
        let bytes = data.get(self.bytes.clone()).unwrap_or(&[]);
        let word = if self.lsb_first {
            bytes.iter().rev().fold(0u64, |w, &b| (w << 8) | b as u64)
        } else {
            bytes.iter().fold(0u64, |w, &b| (w << 8) | b as u64)
        };
        word.checked_shr(self.shift).unwrap_or(0) & self.max()
    }

    /// Reads the field as a two's-complement signed value of `width` bits.
    pub(crate) fn get_signed(&self, data: &[u8]) -> i64 {
        let v = self.get(data);
        let unused = 64u32.saturating_sub(self.width);
        (v.checked_shl(unused).unwrap_or(0) as i64)
            .checked_shr(unused)
            .unwrap_or(0)
    }

    /// Reads a one-bit field.
    pub(crate) fn get_flag(&self, data: &[u8]) -> bool {
        self.get(data) != 0
    }

    /// Writes the field, leaving the other bits of its bytes as they are. `value` is cut to
    /// `width` bits: callers clamp it first, so this only drops the sign extension of a
    /// negative two's-complement value.
    pub(crate) fn put(&self, out: &mut [u8], value: u64) {
        let Some(bytes) = out.get_mut(self.bytes.clone()) else {
            return;
        };
        let mask = self.max().checked_shl(self.shift).unwrap_or(0);
        let value = (value & self.max()).checked_shl(self.shift).unwrap_or(0);
        let n = bytes.len();
        for (i, b) in bytes.iter_mut().enumerate() {
            // Bit position of this byte's least significant bit in the integer.
            let at = if self.lsb_first { i } else { n - 1 - i } as u32 * 8;
            let m = (mask.checked_shr(at).unwrap_or(0) & 0xFF) as u8;
            let v = (value.checked_shr(at).unwrap_or(0) & 0xFF) as u8;
            *b = (*b & !m) | v;
        }
    }

    /// Writes a one-bit field.
    pub(crate) fn put_flag(&self, out: &mut [u8], on: bool) {
        self.put(out, on as u64);
    }
}

/// Heartbeat, ID 0 (ICD 3.1): 6 data bytes.
pub(crate) mod heartbeat {
    use super::Bits;

    /// Data length.
    pub(crate) const LEN: usize = 6;
    /// Status byte 1, bit 7: GPS position valid.
    pub(crate) const GPS_POSITION_VALID: Bits = Bits::flag(0, 7);
    /// Status byte 1, bit 6: maintenance required.
    pub(crate) const MAINTENANCE_REQUIRED: Bits = Bits::flag(0, 6);
    /// Status byte 1, bit 5: IDENT talkback.
    pub(crate) const IDENT: Bits = Bits::flag(0, 5);
    /// Status byte 1, bit 4: address type talkback.
    pub(crate) const ADDRESS_TALKBACK: Bits = Bits::flag(0, 4);
    /// Status byte 1, bit 3: GPS battery low.
    pub(crate) const GPS_BATTERY_LOW: Bits = Bits::flag(0, 3);
    /// Status byte 1, bit 2: ATC services talkback (RATCS).
    pub(crate) const ATC_SERVICES: Bits = Bits::flag(0, 2);
    /// Status byte 1, bit 0: UAT initialised.
    pub(crate) const UAT_INITIALIZED: Bits = Bits::flag(0, 0);
    /// Status byte 2, bit 7: bit 16 of the time stamp.
    pub(crate) const TIMESTAMP_BIT16: Bits = Bits::flag(1, 7);
    /// Status byte 2, bit 6: CSA requested.
    pub(crate) const CSA_REQUESTED: Bits = Bits::flag(1, 6);
    /// Status byte 2, bit 5: CSA not available.
    pub(crate) const CSA_NOT_AVAILABLE: Bits = Bits::flag(1, 5);
    /// Status byte 2, bit 0: UTC OK.
    pub(crate) const UTC_OK: Bits = Bits::flag(1, 0);
    /// Seconds since 0000Z, bits 15-0, **least significant byte first**.
    pub(crate) const TIMESTAMP: Bits = Bits {
        bytes: 2..4,
        lsb_first: true,
        shift: 0,
        width: 16,
    };
    /// Message counts, bits 15-11: uplink messages received in the last second.
    pub(crate) const UPLINK_COUNT: Bits = Bits::msb_first(4..6, 11, 5);
    /// Message counts, bits 9-0: basic and long messages received in the last second.
    pub(crate) const BASIC_LONG_COUNT: Bits = Bits::msb_first(4..6, 0, 10);
}

/// Ownship Report, ID 10, and Traffic Report, ID 20 (ICD 3.4, 3.5): 27 data bytes, most
/// significant byte first.
pub(crate) mod report {
    use super::Bits;

    /// Data length.
    pub(crate) const LEN: usize = 27;
    /// `s`: traffic alert status (0 no alert, 1 alert).
    pub(crate) const ALERT_STATUS: Bits = Bits::msb_first(0..1, 4, 4);
    /// `t`: address type.
    pub(crate) const ADDRESS_TYPE: Bits = Bits::msb_first(0..1, 0, 4);
    /// `aa aa aa`: 24-bit participant address.
    pub(crate) const ADDRESS: Bits = Bits::whole(1..4);
    /// `ll ll ll`: latitude, 24-bit two's complement, LSB = 180/2^23 degrees.
    pub(crate) const LATITUDE: Bits = Bits::whole(4..7);
    /// `nn nn nn`: longitude, 24-bit two's complement, LSB = 180/2^23 degrees.
    pub(crate) const LONGITUDE: Bits = Bits::whole(7..10);
    /// `ddd`: pressure altitude, 25 ft steps from -1000 ft; `0xFFF` invalid.
    pub(crate) const ALTITUDE: Bits = Bits::msb_first(10..12, 4, 12);
    /// `m` bit 3: airborne (0 on ground).
    pub(crate) const AIRBORNE: Bits = Bits::msb_first(10..12, 3, 1);
    /// `m` bit 2: report extrapolated (0 updated).
    pub(crate) const EXTRAPOLATED: Bits = Bits::msb_first(10..12, 2, 1);
    /// `m` bits 1-0: track type (0 invalid, 1 true track, 2 magnetic heading, 3 true heading).
    pub(crate) const TRACK_TYPE: Bits = Bits::msb_first(10..12, 0, 2);
    /// `i`: navigation integrity category (NIC).
    pub(crate) const NIC: Bits = Bits::msb_first(12..13, 4, 4);
    /// `a`: navigation accuracy category for position (NACp).
    pub(crate) const NACP: Bits = Bits::msb_first(12..13, 0, 4);
    /// `hhh`: horizontal velocity, knots; `0xFFF` not available.
    pub(crate) const GROUND_SPEED: Bits = Bits::msb_first(13..16, 12, 12);
    /// `vvv`: vertical velocity, 12-bit two's complement, 64 fpm; `0x800` not available.
    pub(crate) const VERTICAL_RATE: Bits = Bits::msb_first(13..16, 0, 12);
    /// `tt`: track or heading, 360/256 degrees.
    pub(crate) const TRACK: Bits = Bits::whole(16..17);
    /// `ee`: emitter category.
    pub(crate) const EMITTER: Bits = Bits::whole(17..18);
    /// `cc` x 8: call sign, ASCII, space padded.
    pub(crate) const CALL_SIGN: core::ops::Range<usize> = 18..26;
    /// `p`: emergency / priority code (the low nibble `x` is spare).
    pub(crate) const EMERGENCY: Bits = Bits::msb_first(26..27, 4, 4);
}

/// Ownship Geometric Altitude, ID 11 (ICD 3.8): 4 data bytes, most significant byte first.
pub(crate) mod geo_altitude {
    use super::Bits;

    /// Data length.
    pub(crate) const LEN: usize = 4;
    /// Geometric altitude, signed 16 bits, 5 ft steps.
    pub(crate) const ALTITUDE: Bits = Bits::whole(0..2);
    /// Vertical metrics bit 15: vertical warning.
    pub(crate) const VERTICAL_WARNING: Bits = Bits::msb_first(2..4, 15, 1);
    /// Vertical metrics bits 14-0: vertical figure of merit, metres; `0x7FFF` not available.
    pub(crate) const VFOM: Bits = Bits::msb_first(2..4, 0, 15);
}

/// ForeFlight ID, ID 0x65 sub-ID 0 (ForeFlight GDL 90 Extended Specification): 38 data
/// bytes, big-endian.
pub(crate) mod foreflight_id {
    use super::Bits;

    /// Data length (sub-ID included).
    pub(crate) const LEN: usize = 38;
    /// Sub-ID, 0.
    pub(crate) const SUB_ID: Bits = Bits::whole(0..1);
    /// Version, 1.
    pub(crate) const VERSION: Bits = Bits::whole(1..2);
    /// Device serial number; all ones is invalid.
    pub(crate) const SERIAL: Bits = Bits::whole(2..10);
    /// Device name, UTF-8, NUL padded.
    pub(crate) const NAME: core::ops::Range<usize> = 10..18;
    /// Device long name, UTF-8, NUL padded.
    pub(crate) const LONG_NAME: core::ops::Range<usize> = 18..34;
    /// Capabilities mask.
    pub(crate) const CAPABILITIES: Bits = Bits::whole(34..38);
    /// Capabilities bit 0: geometric altitude datum (0 WGS-84 ellipsoid, 1 MSL).
    pub(crate) const ALTITUDE_DATUM: Bits = Bits::msb_first(34..38, 0, 1);
}

/// ForeFlight AHRS, ID 0x65 sub-ID 1: 11 data bytes, big-endian.
pub(crate) mod ahrs {
    use super::Bits;

    /// Data length (sub-ID included).
    pub(crate) const LEN: usize = 11;
    /// Sub-ID, 1.
    pub(crate) const SUB_ID: Bits = Bits::whole(0..1);
    /// Roll, signed 0.1 degree, right wing down positive; `0x7FFF` invalid.
    pub(crate) const ROLL: Bits = Bits::whole(1..3);
    /// Pitch, signed 0.1 degree, nose up positive; `0x7FFF` invalid.
    pub(crate) const PITCH: Bits = Bits::whole(3..5);
    /// Heading, the whole word: `0xFFFF` invalid.
    pub(crate) const HEADING_WORD: Bits = Bits::whole(5..7);
    /// Heading bit 15: magnetic (0 true).
    pub(crate) const HEADING_MAGNETIC: Bits = Bits::msb_first(5..7, 15, 1);
    /// Heading bits 14-0: signed 0.1 degree.
    pub(crate) const HEADING: Bits = Bits::msb_first(5..7, 0, 15);
    /// Indicated airspeed, knots; `0xFFFF` invalid.
    pub(crate) const IAS: Bits = Bits::whole(7..9);
    /// True airspeed, knots; `0xFFFF` invalid.
    pub(crate) const TAS: Bits = Bits::whole(9..11);
}

/// Stratux AHRS report, ID 0x4C (the Levil "LE" format Stratux writes in
/// `makeAHRSGDL90Report`): 23 data bytes after the ID, big-endian. Every field but the
/// pressure altitude is a signed 16-bit integer whose `0x7FFF` means invalid.
pub(crate) mod stratux_ahrs {
    use super::Bits;

    /// Data length (the `0x45 0x01 0x01` header included).
    pub(crate) const LEN: usize = 23;
    /// The header after the ID: `0x45` ('E'), then `0x01 0x01`.
    pub(crate) const HEADER: core::ops::Range<usize> = 0..3;
    /// Roll, signed 0.1 degree, right wing down positive.
    pub(crate) const ROLL: Bits = Bits::whole(3..5);
    /// Pitch, signed 0.1 degree, nose up positive.
    pub(crate) const PITCH: Bits = Bits::whole(5..7);
    /// Heading, signed 0.1 degree.
    pub(crate) const HEADING: Bits = Bits::whole(7..9);
    /// Slip/skid, signed 0.1 degree.
    pub(crate) const SLIP_SKID: Bits = Bits::whole(9..11);
    /// Yaw (turn) rate, signed 0.1 degree per second.
    pub(crate) const YAW_RATE: Bits = Bits::whole(11..13);
    /// Load factor, signed 0.1 G.
    pub(crate) const G: Bits = Bits::whole(13..15);
    /// Indicated airspeed, signed, knots.
    pub(crate) const IAS: Bits = Bits::whole(15..17);
    /// Pressure altitude, **unsigned**, feet plus 5000; `0xFFFF` invalid.
    pub(crate) const PRESSURE_ALTITUDE: Bits = Bits::whole(17..19);
    /// Vertical speed, signed, feet per minute.
    pub(crate) const VERTICAL_SPEED: Bits = Bits::whole(19..21);
    /// Reserved: Stratux sends `0x7F 0xFF`; ignored on receipt.
    pub(crate) const RESERVED: Bits = Bits::whole(21..23);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn put_then_get_every_field_shape() {
        let mut buf = [0xA5u8; 8];
        let f = Bits::msb_first(1..3, 4, 12);
        f.put(&mut buf, 0xABC);
        assert_eq!(buf[..4], [0xA5, 0xAB, 0xC5, 0xA5]);
        assert_eq!(f.get(&buf), 0xABC);
        let le = heartbeat::TIMESTAMP;
        let mut hb = [0u8; 6];
        le.put(&mut hb, 0xD0DB);
        assert_eq!(hb[2..4], [0xDB, 0xD0]);
        assert_eq!(le.get(&hb), 0xD0DB);
        let s = report::VERTICAL_RATE;
        let mut r = [0u8; 27];
        s.put(&mut r, (-1i64) as u64);
        assert_eq!(s.get_signed(&r), -1);
        assert_eq!(report::GROUND_SPEED.get(&r), 0);
        let w = foreflight_id::SERIAL;
        let mut id = [0u8; 38];
        w.put(&mut id, u64::MAX);
        assert_eq!(w.get(&id), u64::MAX);
        assert_eq!(
            id[1..11],
            [0, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0]
        );
    }
}
