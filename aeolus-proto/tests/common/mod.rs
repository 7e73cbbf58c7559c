//! Shared test helpers: hex, proptest strategies for every message type, a seeded RNG.
#![allow(dead_code)]

use aeolus_proto::Decode;
use aeolus_proto::message::*;
use proptest::prelude::*;

pub fn hex(s: &str) -> Vec<u8> {
    assert!(s.len().is_multiple_of(2), "odd hex length");
    (0..s.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(&s[i..i + 2], 16).unwrap())
        .collect()
}

/// Feeds `bytes` and collects every event as `Ok((id, raw))` or `Err(error)`.
pub fn events<const N: usize>(
    d: &mut aeolus_proto::Decoder<N>,
    bytes: &[u8],
) -> Vec<Result<(u8, Vec<u8>), aeolus_proto::Error>> {
    let mut out = Vec::new();
    d.feed(bytes, |ev| out.push(ev.map(|f| (f.id(), f.raw().to_vec()))));
    out
}

/// A tiny deterministic xorshift RNG so stream tests are reproducible.
pub struct Rng(pub u64);
impl Rng {
    pub fn next_u64(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        self.0 = x;
        x
    }
    pub fn below(&mut self, n: u64) -> u64 {
        self.next_u64() % n
    }
    pub fn byte(&mut self) -> u8 {
        self.next_u64() as u8
    }
    pub fn f32(&mut self) -> f32 {
        f32::from_bits(self.next_u64() as u32)
    }
    pub fn f64(&mut self) -> f64 {
        f64::from_bits(self.next_u64())
    }
    pub fn bytes(&mut self, n: usize) -> Vec<u8> {
        (0..n).map(|_| self.byte()).collect()
    }
}

/// Any f32, NaN payloads included.
pub fn f32_bits() -> impl Strategy<Value = f32> + Clone {
    any::<u32>().prop_map(f32::from_bits)
}
fn f3() -> impl Strategy<Value = (f32, f32, f32)> {
    (f32_bits(), f32_bits(), f32_bits())
}

pub fn f64_bits() -> impl Strategy<Value = f64> {
    any::<u64>().prop_map(f64::from_bits)
}

fn leak(v: Vec<u8>) -> &'static [u8] {
    Box::leak(v.into_boxed_slice())
}

/// Every message type, with arbitrary field values.
pub fn arb_message() -> impl Strategy<Value = Message<'static>> {
    let text = prop::collection::vec(1u8..=255, 0..=aeolus_proto::TEXT_CAPACITY)
        .prop_map(|v| Text::from_bytes(&v).unwrap());
    prop_oneof![
        (any::<u8>(), any::<[u8; 3]>(), any::<[u8; 6]>()).prop_map(|(model, firmware, mac)| {
            Message::AeolusInfo(AeolusInfo {
                model,
                firmware,
                mac,
            })
        }),
        (any::<bool>(), f64_bits(), f3()).prop_map(|(valid, timestamp_ms, (a, b, c))| {
            Message::Pressure(Pressure {
                valid,
                timestamp_ms,
                static_mbar: a,
                pitot_mbar: b,
                airspeed_mps: c,
            })
        }),
        (any::<bool>(), f64_bits(), f3()).prop_map(|(valid, timestamp_ms, (x, y, z))| {
            Message::Gyro(Gyro {
                valid,
                timestamp_ms,
                x,
                y,
                z,
            })
        }),
        (any::<bool>(), f64_bits(), f3()).prop_map(|(valid, timestamp_ms, (x, y, z))| {
            Message::Accel(Accel {
                valid,
                timestamp_ms,
                x,
                y,
                z,
            })
        }),
        (any::<bool>(), f64_bits(), f3()).prop_map(|(valid, timestamp_ms, (x, y, z))| {
            Message::Magnet(Magnet {
                valid,
                timestamp_ms,
                x,
                y,
                z,
            })
        }),
        (any::<bool>(), f64_bits(), f32_bits()).prop_map(|(valid, timestamp_ms, celsius)| {
            Message::Temp(Temp {
                valid,
                timestamp_ms,
                celsius,
            })
        }),
        (any::<(bool, bool, u8)>(), f64_bits(), f3(), f32_bits()).prop_map(
            |((valid, has_fix, satellites), timestamp_ms, (a, b, c), d)| {
                Message::Gps(Gps {
                    valid,
                    has_fix,
                    satellites,
                    timestamp_ms,
                    latitude_deg: a,
                    longitude_deg: b,
                    altitude_m: c,
                    ground_speed_mps: d,
                })
            }
        ),
        (any::<bool>(), f64_bits(), prop::array::uniform9(f32_bits())).prop_map(
            |(valid, timestamp_ms, f)| {
                Message::Attitude(Attitude {
                    valid,
                    timestamp_ms,
                    roll_rad: f[0],
                    pitch_rad: f[1],
                    yaw_rad: f[2],
                    slip_ball: f[3],
                    turn_coordinator: f[4],
                    qx: f[5],
                    qy: f[6],
                    qz: f[7],
                    qw: f[8],
                })
            }
        ),
        (
            (
                any::<bool>(),
                any::<i8>(),
                any::<bool>(),
                any::<u8>(),
                any::<u8>()
            ),
            f64_bits(),
            f32_bits(),
            prop::array::uniform3(f32_bits()),
            prop::array::uniform9(f32_bits())
        )
            .prop_map(
                |(
                    (valid, cal, has_value, pct, rem),
                    timestamp_ms,
                    heading_deg,
                    soft_iron,
                    hard_iron,
                )| {
                    Message::Compass(Compass {
                        valid,
                        calibration: CalibrationStatus::from_i8(cal),
                        has_value,
                        calibration_percent: pct,
                        calibration_remaining: rem,
                        timestamp_ms,
                        heading_deg,
                        soft_iron,
                        hard_iron,
                    })
                }
            ),
        (any::<bool>(), f64_bits(), f32_bits(), f32_bits()).prop_map(
            |(valid, timestamp_ms, s, d)| {
                Message::Wind(Wind {
                    valid,
                    timestamp_ms,
                    speed_mps: s,
                    direction_deg: d,
                })
            }
        ),
        any::<[u8; 6]>().prop_map(|t| Message::SetTime(SetTime {
            year_since_1900: t[0],
            month0: t[1],
            day: t[2],
            hour: t[3],
            minute: t[4],
            second: t[5],
        })),
        any::<[u8; 32]>().prop_map(|d| Message::CalibInfo(leak(d.to_vec()))),
        prop::collection::vec(any::<u8>(), 208).prop_map(|d| Message::DebugInfo(leak(d))),
        prop::collection::vec(any::<u8>(), 0..200).prop_map(|d| Message::Log(leak(d))),
        text.clone().prop_map(Message::Toast),
        text.prop_map(Message::Command),
        (any::<u8>(), prop::collection::vec(any::<u8>(), 0..200))
            .prop_filter("an undefined ID", |(id, _)| {
                !matches!(id, 11 | 12 | 51 | 61..=66 | 71..=73 | 75 | 76 | 81 | 82)
            })
            .prop_map(|(id, d)| Message::Unknown { id, data: leak(d) }),
    ]
}

/// Compares messages bit for bit (so NaN == NaN when the payloads agree).
pub fn same_bits(a: &Message<'_>, b: &Message<'_>) -> bool {
    let mut x = [0u8; 256];
    let mut y = [0u8; 256];
    match (a.emit(&mut x), b.emit(&mut y)) {
        (Ok(n), Ok(m)) => a.id() == b.id() && x[..n] == y[..m],
        _ => false,
    }
}
