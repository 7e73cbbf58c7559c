//! Deterministic generators shared by the stream tests.

#![allow(dead_code)]

use aydp_proto::{
    DirectOutputBuilder, Encoder, FixDetailBuilder, FixQuality, OutputEntry, Position, Profile,
    Raw, Satellite, SystemControl, SystemValueUpdate, Timestamp, UpdateMode, VesselData,
    WindDirection, WindSpeed,
};

/// SplitMix64: small, fixed-seed, good enough for test data.
pub struct Rng(pub u64);

impl Rng {
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    pub fn below(&mut self, n: u64) -> u64 {
        self.next_u64() % n
    }
    pub fn byte(&mut self) -> u8 {
        self.next_u64() as u8
    }
    pub fn f32(&mut self, scale: f32) -> f32 {
        (self.below(2_000_001) as f32 / 1_000_000.0 - 1.0) * scale
    }
    pub fn chance(&mut self, num: u64, den: u64) -> bool {
        self.below(den) < num
    }
}

/// One random valid message (typed for `profile`), encoded normal or expedited.
///
/// The `Reference` encoder refuses expedited headers (its software has none), but a
/// `Reference` decoder still reads them, so the streams keep them: such a message is encoded
/// by the `Spec` encoder and its length field (data bytes only in `Reference`) and checksum
/// rewritten.
pub fn random_message(rng: &mut Rng, profile: Profile) -> Vec<u8> {
    let mut frame = random_message_in(rng, profile, Profile::Spec);
    if profile == Profile::Reference && frame[1] & 0x80 != 0 {
        let data_len = (frame.len() - 7) as u32;
        frame[2..6].copy_from_slice(&data_len.to_le_bytes());
        let last = frame.len() - 1;
        frame[last] = frame[..last].iter().fold(0, |x, b| x ^ b);
    }
    frame
}

/// [`random_message`]'s message, typed for `profile`, encoded in `profile` when normal and in
/// `expedited_in` when expedited.
fn random_message_in(rng: &mut Rng, profile: Profile, expedited_in: Profile) -> Vec<u8> {
    let normal = Encoder::new(profile);
    let expedited = Encoder::new(expedited_in);
    let ts = if rng.chance(1, 2) {
        Some(Timestamp::new(
            rng.next_u64() as i64 >> 20,
            rng.below(1_000_000) as i64,
        ))
    } else {
        None
    };
    let enc = if ts.is_some() { normal } else { expedited };
    let mut buf = [0u8; 512];
    let mut data = [0u8; 256];
    let n = match rng.below(11) {
        0 => enc.encode(
            &Raw {
                msg_type: 0,
                data: &[],
            },
            ts,
            &mut buf,
        ),
        1 => enc.encode(
            &Position {
                latitude: rng.f32(90.0) as f64,
                longitude: rng.f32(180.0) as f64,
                altitude: rng.f32(100.0),
            },
            ts,
            &mut buf,
        ),
        2 => enc.encode(
            &FixQuality {
                fix_type: rng.byte() % 4,
                mean_dop: rng.f32(5.0).abs(),
                hdop: rng.f32(5.0).abs(),
                vdop: rng.f32(5.0).abs(),
                satellites: rng.byte() % 24,
            },
            ts,
            &mut buf,
        ),
        3 => {
            let mut b = FixDetailBuilder::new(&mut data);
            for _ in 0..rng.below(10) {
                b.push(Satellite {
                    id: rng.byte(),
                    azimuth: rng.f32(360.0).abs(),
                    elevation: rng.f32(90.0).abs(),
                    snr: rng.f32(50.0).abs(),
                })
                .unwrap();
            }
            enc.encode(&b.finish(), ts, &mut buf)
        }
        4 => {
            let mut b = DirectOutputBuilder::new(&mut data);
            for _ in 0..rng.below(8) {
                b.push(OutputEntry {
                    device: rng.byte(),
                    channel: rng.byte(),
                    value: rng.f32(45.0),
                })
                .unwrap();
            }
            enc.encode(&b.finish(), ts, &mut buf)
        }
        5 => {
            let len = rng.below(41) as usize;
            let value: Vec<u8> = (0..len).map(|_| rng.byte()).collect();
            let mode = match rng.below(3) {
                0 => UpdateMode::Single,
                1 => UpdateMode::Array {
                    count: rng.below(10) as u32,
                },
                _ => UpdateMode::Element {
                    index: rng.below(10) as u32,
                },
            };
            enc.encode(
                &SystemValueUpdate {
                    address: rng.below(65536) as u16,
                    mode,
                    data: &value,
                },
                ts,
                &mut buf,
            )
        }
        6 => {
            let c = if rng.chance(1, 2) {
                SystemControl::StoreConfiguration
            } else {
                SystemControl::RequestData {
                    address: rng.below(65536) as u16,
                }
            };
            enc.encode(&c, ts, &mut buf)
        }
        7 => enc.encode(&WindSpeed(rng.f32(40.0).abs()), ts, &mut buf),
        8 => enc.encode(&WindDirection(rng.f32(360.0).abs()), ts, &mut buf),
        9 => enc.encode(
            &VesselData {
                roll: rng.f32(30.0),
                heading: rng.f32(360.0),
                latitude: rng.f32(90.0) as f64,
                longitude: rng.f32(180.0) as f64,
                satellites: rng.below(20) as i32,
                ..Default::default()
            },
            ts,
            &mut buf,
        ),
        _ => {
            let len = rng.below(30) as usize;
            let value: Vec<u8> = (0..len).map(|_| rng.byte()).collect();
            let t = 100 + rng.below(27) as u8;
            enc.encode(
                &Raw {
                    msg_type: t,
                    data: &value,
                },
                ts,
                &mut buf,
            )
        }
    }
    .unwrap();
    buf[..n].to_vec()
}

/// 0..=64 bytes of garbage, rich in 0xFF and in plausible length fields: a quarter of the
/// bytes are 0xFF, and after `header_num / header_den` of them the generator writes a type byte
/// and a length field that passes the profile minimum and a `capacity`-byte decoder's limit,
/// so the decoder must commit to a false candidate (random bytes would give such a length
/// about once in 2^24 starts).
pub fn garbage(
    rng: &mut Rng,
    profile: Profile,
    capacity: usize,
    (header_num, header_den): (u64, u64),
    out: &mut Vec<u8>,
) {
    let n = rng.below(65) as usize;
    let start = out.len();
    while out.len() - start < n {
        if rng.chance(1, 4) {
            out.push(0xFF);
            if rng.chance(header_num, header_den) {
                let t = rng.byte() & 0xFE; // never 0xFF
                let expedited = t & 0x80 != 0;
                let total = 7 + rng.below(capacity as u64 - 6) as usize; // 7..=capacity
                let total = if expedited { total } else { total.max(23) };
                let field = match profile {
                    Profile::Spec => total as u32,
                    Profile::Reference => (total - if expedited { 7 } else { 23 }) as u32,
                };
                out.push(t);
                out.extend_from_slice(&field.to_le_bytes());
            }
        } else {
            out.push(rng.byte());
        }
    }
    out.truncate(start + n);
}
