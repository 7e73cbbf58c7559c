//! The measured functions of the benchmarks, shared by the x86-64 callgrind bench
//! (`bench/benches/codecs.rs`, through `protolink-bench`) and the Cortex-M3 harness
//! (`checks/cm3-bench`), so both count the instructions of the very same code.
//!
//! `no_std` and allocation-free, so it links on thumbv7m; the inputs are built elsewhere
//! (`protolink_bench::*_stream`). Every function is `#[inline(never)]`, so it stays one
//! measurable symbol. Each returns a value that depends on everything it decoded, so the
//! optimiser cannot drop the work.
#![no_std]
#![allow(clippy::collapsible_if)]

use aeolus_proto::{CrcMode, Decode, message::Message};
use aydp_proto::{Decoder, Encoder, Profile};

/// Deframes `stream` one byte a `feed` call (an interrupt handler's loop). Returns the frames
/// delivered.
#[inline(never)]
pub fn aeolus_deframe(stream: &[u8]) -> u32 {
    let mut d = aeolus_proto::Decoder::<{ aeolus_proto::MAX_FIXED_FRAME }>::new();
    let mut n = 0;
    for b in stream {
        d.feed(core::slice::from_ref(b), |ev| n += ev.is_ok() as u32);
    }
    n
}

/// Deframes `stream` with `feed` (runs copied in bulk). Returns the frames delivered.
#[inline(never)]
pub fn aeolus_deframe_slice(stream: &[u8]) -> u32 {
    let mut d = aeolus_proto::Decoder::<{ aeolus_proto::MAX_FIXED_FRAME }>::new();
    let mut n = 0;
    d.feed(stream, |ev| n += ev.is_ok() as u32);
    n
}

/// Deframes with `feed` and parses every frame into a typed message. Returns the XOR of
/// the GYRO timestamps' bit patterns: an integer fold, so that no soft-float addition (a
/// library call on Cortex-M3) is counted as decoding.
#[inline(never)]
pub fn aeolus_decode_slice(stream: &[u8]) -> u64 {
    let mut d = aeolus_proto::Decoder::<{ aeolus_proto::MAX_FIXED_FRAME }>::new();
    let mut acc = 0;
    d.feed(stream, |ev| {
        if let Ok(Ok(Message::Gyro(g))) = ev.map(|f| f.message()) {
            acc ^= g.timestamp_ms.to_bits();
        }
    });
    acc
}

/// Deframes one byte a `feed` call and parses every frame into a typed message. Returns the
/// XOR of the GYRO timestamps' bit patterns (see [`aeolus_decode_slice`]).
#[inline(never)]
pub fn aeolus_decode(stream: &[u8]) -> u64 {
    let mut d = aeolus_proto::Decoder::<{ aeolus_proto::MAX_FIXED_FRAME }>::new();
    let mut acc = 0;
    for b in stream {
        d.feed(core::slice::from_ref(b), |ev| {
            if let Ok(Ok(Message::Gyro(g))) = ev.map(|f| f.message()) {
                acc ^= g.timestamp_ms.to_bits();
            }
        });
    }
    acc
}

/// Encodes every message into one output buffer; returns the bytes written.
#[inline(never)]
pub fn aeolus_encode(msgs: &[Message<'_>], out: &mut [u8]) -> usize {
    let mut at = 0;
    for m in msgs {
        at += m.encode(&mut out[at..], CrcMode::Compute).unwrap();
    }
    at
}

/// Decodes `stream` one byte a `feed` call (every event of a rescan handed over) and parses
/// every frame.
#[inline(never)]
pub fn aydp_decode(stream: &[u8]) -> u32 {
    let mut d = Decoder::<128>::new(Profile::Spec);
    let mut n = 0;
    for &b in stream {
        d.feed(&[b], |e| {
            if let Ok(f) = e {
                if f.message().is_ok() {
                    n += 1;
                }
            }
        });
    }
    n
}

/// [`aydp_decode`] through `Decoder::feed`, the bulk path: every event handed over, every
/// frame parsed.
#[inline(never)]
pub fn aydp_decode_feed(stream: &[u8]) -> u32 {
    let mut d = Decoder::<128>::new(Profile::Spec);
    let mut n = 0;
    d.feed(stream, |e| {
        if let Ok(f) = e {
            if f.message().is_ok() {
                n += 1;
            }
        }
    });
    n
}

/// Encodes every message, expedited, into one buffer.
#[inline(never)]
pub fn aydp_encode(msgs: &[aydp_proto::Message<'_>], out: &mut [u8]) -> usize {
    let enc = Encoder::new(Profile::Spec);
    let mut at = 0;
    for m in msgs {
        at += enc.encode(m, None, &mut out[at..]).unwrap();
    }
    at
}

/// PC side: decodes the device's debug stream.
#[inline(never)]
pub fn aok_pc_decode(stream: &[u8]) -> i64 {
    let mut d = aok_proto::MessageDecoder::new(aok_proto::FirmwareVersion::LATEST);
    let mut acc = 0i64;
    for &b in stream {
        d.feed(&[b], |ev| {
            if let Ok(aok_proto::Message::Debug(v)) = ev {
                acc += v.value as i64;
            }
        });
    }
    acc
}

/// Device side: decodes the PC's commands.
#[inline(never)]
pub fn aok_device_decode(stream: &[u8]) -> u32 {
    let mut d = aok_proto::CommandDecoder::new();
    let mut n = 0;
    for &b in stream {
        d.feed(&[b], |ev| {
            n += ev.is_ok() as u32;
        });
    }
    n
}

/// [`aok_pc_decode`] through `MessageDecoder::feed`, the bulk path.
#[inline(never)]
pub fn aok_pc_decode_feed(stream: &[u8]) -> i64 {
    let mut d = aok_proto::MessageDecoder::new(aok_proto::FirmwareVersion::LATEST);
    let mut acc = 0i64;
    d.feed(stream, |m| {
        if let Ok(aok_proto::Message::Debug(v)) = m {
            acc += v.value as i64;
        }
    });
    acc
}

/// [`aok_device_decode`] through `CommandDecoder::feed`, the bulk path.
#[inline(never)]
pub fn aok_device_decode_feed(stream: &[u8]) -> u32 {
    let mut d = aok_proto::CommandDecoder::new();
    let mut n = 0;
    d.feed(stream, |c| n += c.is_ok() as u32);
    n
}

/// Encodes debug frames for every value; returns the bytes written.
#[inline(never)]
pub fn aok_encode(values: &[aok_proto::DebugValue], out: &mut [u8]) -> usize {
    let mut at = 0;
    for v in values {
        at += v.emit(&mut out[at..]).unwrap();
    }
    at
}

/// The section 4.3 CRC over `bytes`.
#[inline(never)]
pub fn aeolus_crc(bytes: &[u8]) -> u16 {
    aeolus_proto::crc::checksum(bytes)
}

/// The `crc` crate's table-driven CRC-16 (XMODEM: same polynomial, standard form).
#[inline(never)]
pub fn crc_crate_xmodem(bytes: &[u8]) -> u16 {
    const C: crc::Crc<u16> = crc::Crc::<u16>::new(&crc::CRC_16_XMODEM);
    C.checksum(bytes)
}
