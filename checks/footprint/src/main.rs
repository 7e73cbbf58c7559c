//! # footprint
//!
//! One protocol, one direction, nothing else: the flash a firmware pays for it is this binary's
//! size minus the empty baseline (no feature). Every entry point sits in its own
//! `#[inline(never)]` function so its stack frame can be read from `-Z emit-stack-sizes`.
#![no_std]
#![no_main]
#![allow(unused)]

use core::ptr::{addr_of, read_volatile, write_volatile, addr_of_mut};

#[panic_handler]
fn panic(_: &core::panic::PanicInfo<'_>) -> ! {
    loop {}
}

static mut INPUT: [u8; 256] = [0; 256];
static mut SINK: u32 = 0;

fn byte(i: usize) -> u8 {
    unsafe { read_volatile(addr_of!(INPUT).cast::<u8>().add(i % 256)) }
}
fn sink(v: u32) {
    unsafe { write_volatile(addr_of_mut!(SINK), v) }
}
/// A slice of the volatile input whose length is itself read at run time, so that `feed` keeps
/// both its paths (one byte, and a slice).
fn input() -> volatile_input::Input {
    volatile_input::Input::read()
}

mod volatile_input {
    /// Up to 8 input bytes and how many of them count.
    pub struct Input {
        bytes: [u8; 8],
        len: usize,
    }
    impl Input {
        pub fn read() -> Self {
            let mut bytes = [0u8; 8];
            for (i, b) in bytes.iter_mut().enumerate() {
                *b = super::byte(i);
            }
            Input { bytes, len: super::byte(8) as usize % 9 }
        }
    }
    impl core::ops::Deref for Input {
        type Target = [u8];
        fn deref(&self) -> &[u8] {
            self.bytes.get(..self.len).unwrap_or(&[])
        }
    }
}

fn f32_in(i: usize) -> f32 {
    f32::from_bits(u32::from_le_bytes([byte(i), byte(i + 1), byte(i + 2), byte(i + 3)]))
}

#[cfg(feature = "aeolus-decode")]
#[inline(never)]
#[unsafe(no_mangle)]
fn fp_aeolus_decode() {
    use aeolus_proto::{Decode, Decoder, MAX_FIXED_FRAME, message::Message};
    static mut D: Decoder<MAX_FIXED_FRAME> = Decoder::new();
    let d = unsafe { &mut *addr_of_mut!(D) };
    d.feed(&input(), |ev| {
        if let Ok(frame) = ev {
            if let Ok(Message::Gyro(g)) = frame.message() {
                sink(g.x.to_bits());
            }
        }
    });
}

#[cfg(feature = "aeolus-encode")]
#[inline(never)]
#[unsafe(no_mangle)]
fn fp_aeolus_encode() {
    use aeolus_proto::{CrcMode, max_encoded_len, message::{Gyro, Message}};
    let m = Message::Gyro(Gyro { valid: true, timestamp_ms: f32_in(0) as f64, x: f32_in(4), y: f32_in(8), z: f32_in(12) });
    let mut out = [0u8; max_encoded_len(Gyro::LEN)];
    if let Ok(n) = m.encode(&mut out, CrcMode::Compute) {
        for b in &out[..n] {
            sink(*b as u32);
        }
    }
}

#[cfg(feature = "aydp-decode")]
#[inline(never)]
#[unsafe(no_mangle)]
fn fp_aydp_decode() {
    use aydp_proto::{Decode, Decoder, Profile};
    static mut D: Decoder<128> = Decoder::new(Profile::Spec);
    let d = unsafe { &mut *addr_of_mut!(D) };
    d.feed(&input(), |e| {
        if let Ok(f) = e {
            if let Ok(m) = f.message() {
                sink(f.base_type() as u32);
            }
        }
    });
}

#[cfg(feature = "aydp-encode")]
#[inline(never)]
#[unsafe(no_mangle)]
fn fp_aydp_encode() {
    use aydp_proto::{Encoder, Position, Profile, Timestamp};
    let p = Position { latitude: f32_in(0) as f64, longitude: f32_in(4) as f64, altitude: f32_in(8) };
    let mut out = [0u8; 64];
    let ts = Timestamp { seconds: byte(12) as i64, subsec: byte(13) as i64 };
    if let Ok(n) = Encoder::new(Profile::Spec).encode(&p, Some(ts), &mut out) {
        for b in &out[..n] {
            sink(*b as u32);
        }
    }
}

#[cfg(feature = "aok-decode")]
#[inline(never)]
#[unsafe(no_mangle)]
fn fp_aok_decode() {
    use aok_proto::{CommandDecoder, Decode};
    static mut D: CommandDecoder = CommandDecoder::new();
    let d = unsafe { &mut *addr_of_mut!(D) };
    d.feed(&input(), |ev| {
        if let Ok(c) = ev {
            sink(c.buffer_len() as u32);
        }
    });
}

#[cfg(feature = "aok-encode")]
#[inline(never)]
#[unsafe(no_mangle)]
fn fp_aok_encode() {
    use aok_proto::{DebugValue, Message, ReplyForm};
    let mut out = [0u8; 8];
    let v = DebugValue { number: byte(0), value: f32_in(1).to_bits() as i32 };
    if let Ok(n) = Message::Debug(v).emit(&mut out, ReplyForm::Headed) {
        for b in &out[..n] {
            sink(*b as u32);
        }
    }
}

/// A transport that hands over an opaque number of opaque bytes per read.
#[cfg(any(feature = "aeolus-read", feature = "aydp-read", feature = "aok-read"))]
struct Volatile;

#[cfg(any(feature = "aeolus-read", feature = "aydp-read", feature = "aok-read"))]
impl embedded_io::ErrorType for Volatile {
    type Error = embedded_io::ErrorKind;
}

#[cfg(any(feature = "aeolus-read", feature = "aydp-read", feature = "aok-read"))]
impl embedded_io::Read for Volatile {
    fn read(&mut self, buf: &mut [u8]) -> Result<usize, Self::Error> {
        let n = (byte(1) as usize).min(buf.len());
        for (i, b) in buf.iter_mut().take(n).enumerate() {
            *b = byte(i + 2);
        }
        Ok(n)
    }
}

#[cfg(feature = "aeolus-read")]
#[inline(never)]
#[unsafe(no_mangle)]
fn fp_aeolus_read() {
    use aeolus_proto::{Decoder, MAX_FIXED_FRAME, embedded_io::FrameReader, message::Message};
    static mut R: FrameReader<Volatile, MAX_FIXED_FRAME, 64> =
        FrameReader::new(Volatile, Decoder::new());
    let r = unsafe { &mut *addr_of_mut!(R) };
    if let Ok(frame) = r.read() {
        if let Ok(Message::Gyro(g)) = frame.message() {
            sink(g.x.to_bits());
        }
    }
}

#[cfg(feature = "aydp-read")]
#[inline(never)]
#[unsafe(no_mangle)]
fn fp_aydp_read() {
    use aydp_proto::{Decoder, Profile, embedded_io::FrameReader};
    static mut R: FrameReader<Volatile, 128, 64> =
        FrameReader::new(Volatile, Decoder::new(Profile::Spec));
    let r = unsafe { &mut *addr_of_mut!(R) };
    if let Ok(f) = r.read() {
        if let Ok(m) = f.message() {
            sink(f.base_type() as u32);
        }
    }
}

#[cfg(feature = "aok-read")]
#[inline(never)]
#[unsafe(no_mangle)]
fn fp_aok_read() {
    use aok_proto::{CommandDecoder, embedded_io::CommandReader};
    static mut R: CommandReader<Volatile, 64> = CommandReader::new(Volatile, CommandDecoder::new());
    let r = unsafe { &mut *addr_of_mut!(R) };
    if let Ok(c) = r.read() {
        sink(c.buffer_len() as u32);
    }
}

#[unsafe(no_mangle)]
pub extern "C" fn entry() -> ! {
    loop {
        #[cfg(feature = "aeolus-decode")]
        fp_aeolus_decode();
        #[cfg(feature = "aeolus-encode")]
        fp_aeolus_encode();
        #[cfg(feature = "aydp-decode")]
        fp_aydp_decode();
        #[cfg(feature = "aydp-encode")]
        fp_aydp_encode();
        #[cfg(feature = "aok-decode")]
        fp_aok_decode();
        #[cfg(feature = "aok-encode")]
        fp_aok_encode();
        #[cfg(feature = "aeolus-read")]
        fp_aeolus_read();
        #[cfg(feature = "aydp-read")]
        fp_aydp_read();
        #[cfg(feature = "aok-read")]
        fp_aok_read();
        sink(byte(255) as u32);
    }
}
