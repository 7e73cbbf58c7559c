//! A deliberately naive AYDP decoder, for comparison only: it trusts the claimed length.
//!
//! It applies the same start rule (0xFF, with the Y5 "FF FF" resync) and the same length
//! checks (profile minimum, capacity), but after a checksum failure it throws away every byte
//! the false start claimed, and after a length failure the whole header: it never rescans.
//! Declared once in `tests/all/main.rs` (`#[path = "../support/naive.rs"] mod naive;`).

#![allow(dead_code)]

use aydp_proto::Profile;

/// The naive decoder. Frames are returned as owned byte vectors.
pub struct NaiveDecoder {
    profile: Profile,
    capacity: usize,
    buf: Vec<u8>,
    need: usize,
}

impl NaiveDecoder {
    /// A naive decoder with the given profile and capacity.
    pub fn new(profile: Profile, capacity: usize) -> Self {
        Self {
            profile,
            capacity,
            buf: Vec::new(),
            need: 0,
        }
    }

    /// Feed one byte; returns a frame when one completes with a good checksum.
    pub fn push(&mut self, byte: u8) -> Option<Vec<u8>> {
        match self.buf.len() {
            0 => {
                if byte == 0xFF {
                    self.buf.push(byte);
                }
                None
            }
            1 if byte == 0xFF => None,
            n if n < 6 => {
                self.buf.push(byte);
                if self.buf.len() == 6 {
                    let field =
                        u32::from_le_bytes([self.buf[2], self.buf[3], self.buf[4], self.buf[5]]);
                    let expedited = self.buf[1] & 0x80 != 0;
                    match self.profile.frame_len(field, expedited) {
                        Some(total) if total <= self.capacity => self.need = total,
                        _ => self.buf.clear(),
                    }
                }
                None
            }
            _ => {
                self.buf.push(byte);
                if self.buf.len() < self.need {
                    return None;
                }
                let frame = std::mem::take(&mut self.buf);
                if frame.iter().fold(0u8, |a, b| a ^ b) == 0 {
                    Some(frame)
                } else {
                    None
                }
            }
        }
    }
}
