//! Each protocol's part in the corruption figures: random valid frames, garbage, and its real
//! and naive decoders reduced to the keys of the frames they deliver.

use crate::{
    aeolus_gen,
    channel::Channel,
    naive,
    rng::Rng,
    score::{Figures, score},
};
use aeolus_proto::{CrcMode, Decode, Decoder, max_encoded_len, message::Message};

/// A protocol under test.
pub trait Protocol {
    /// Name in the tables.
    fn name(&self) -> String;
    /// A random valid frame: its wire bytes and the key its decoded form is compared by.
    fn frame(&self, rng: &mut Rng) -> (Vec<u8>, Vec<u8>);
    /// `n` bytes of garbage that look like this protocol's bytes.
    fn garbage(&self, rng: &mut Rng, n: usize) -> Vec<u8>;
    /// The crate's decoder: what it reports, in order: the key of each frame it delivers,
    /// `None` for each error.
    fn decode_events(&self, stream: &[u8]) -> Vec<Option<Vec<u8>>>;
    /// The crate's decoder: keys of the frames it delivers.
    fn decode(&self, stream: &[u8]) -> Vec<Vec<u8>> {
        self.decode_events(stream).into_iter().flatten().collect()
    }
    /// The naive decoder: keys of the frames it delivers.
    fn decode_naive(&self, stream: &[u8]) -> Vec<Vec<u8>>;
}

/// Sends `n` random frames through `channel` and scores the crate's decoder and the naive one
/// on the same received stream.
pub fn run(p: &dyn Protocol, channel: Channel, n: usize, seed: u64) -> (Figures, Figures) {
    let mut rng = Rng::new(seed);
    let mut stream = Vec::new();
    let mut sent = Vec::with_capacity(n);
    let mut garbage = |r: &mut Rng, k: usize| p.garbage(r, k);
    for _ in 0..n {
        let (wire, key) = p.frame(&mut rng);
        let intact = channel.pass(&mut rng, &wire, &mut stream, &mut garbage);
        sent.push((key, intact));
    }
    // A last flush of garbage so a trailing frame is not left pending in either decoder.
    stream.extend(p.garbage(&mut rng, 8));
    let real = score(&sent, &p.decode(&stream), 256);
    let naive = score(&sent, &p.decode_naive(&stream), 256);
    (real, naive)
}

/// AEOLUS, in normal or strict mode.
pub struct Aeolus {
    /// Reject frames without CRC.
    pub strict: bool,
}

impl Aeolus {
    /// One of the nine types the generator builds, every field random.
    fn random_message(rng: &mut Rng) -> Message<'static> {
        use aeolus_gen::Kind::*;
        let t = rng.f64();
        let kind = [
            Gyro, Accel, Magnet, Pressure, Attitude, Compass, Gps, Toast, Wind,
        ][rng.below(9) as usize];
        aeolus_gen::message(rng, kind, t, aeolus_gen::Values::All)
    }
}

impl Protocol for Aeolus {
    fn name(&self) -> String {
        if self.strict {
            "AEOLUS (strict)".into()
        } else {
            "AEOLUS".into()
        }
    }

    fn frame(&self, rng: &mut Rng) -> (Vec<u8>, Vec<u8>) {
        let msg = Self::random_message(rng);
        let mut data = [0u8; 128];
        let n = msg.emit(&mut data).unwrap_or(0);
        let mut wire = [0u8; max_encoded_len(128)];
        let w = msg.encode(&mut wire, CrcMode::Compute).unwrap_or(0);
        let mut key = vec![msg.id()];
        key.extend_from_slice(&data[..n]);
        key.extend_from_slice(&aeolus_proto::crc::checksum(&key).to_le_bytes());
        (wire[..w].to_vec(), key)
    }

    fn garbage(&self, rng: &mut Rng, n: usize) -> Vec<u8> {
        (0..n)
            .map(|_| match rng.below(8) {
                0 => 0x7E,
                1 => 0x7D,
                _ => rng.byte(),
            })
            .collect()
    }

    fn decode_events(&self, stream: &[u8]) -> Vec<Option<Vec<u8>>> {
        let mut d = if self.strict {
            Decoder::<256>::strict()
        } else {
            Decoder::<256>::new()
        };
        let mut out = Vec::new();
        d.feed(stream, |ev| out.push(ev.ok().map(|f| f.raw().to_vec())));
        out
    }

    fn decode_naive(&self, stream: &[u8]) -> Vec<Vec<u8>> {
        let mut v = naive::aeolus(stream);
        if self.strict {
            v.retain(|k| k.len() >= 2 && k[k.len() - 2..] != [0, 0]);
        }
        v
    }
}

/// Every channel of the figures: (a), (b) at three BERs, (c).
pub fn channels() -> [Channel; 5] {
    [
        Channel::Garbage { max: 64 },
        Channel::BitFlips { ber: 1e-5 },
        Channel::BitFlips { ber: 1e-4 },
        Channel::BitFlips { ber: 1e-3 },
        Channel::Drops { rate: 1e-3 },
    ]
}

#[allow(dead_code, clippy::all)]
#[path = "../../aydp-proto/tests/support/naive.rs"]
mod aydp_naive;
/// The AYDP stream generators and naive decoder of `aydp-proto`'s own tests, shared here.
#[allow(dead_code, clippy::all)]
#[path = "../../aydp-proto/tests/support/streamgen.rs"]
mod aydp_streamgen;

/// AYDP in one profile. Garbage comes from `aydp-proto`'s stream generator: 0..=64 bytes, a
/// quarter of them 0xFF, one 0xFF in 64 followed by a plausible type and length.
pub struct Aydp {
    /// The profile.
    pub profile: aydp_proto::Profile,
}

const AYDP_CAPACITY: usize = 256;

impl Protocol for Aydp {
    fn name(&self) -> String {
        format!("AYDP ({:?})", self.profile)
    }

    fn frame(&self, rng: &mut Rng) -> (Vec<u8>, Vec<u8>) {
        let mut r = aydp_streamgen::Rng(rng.next_u64());
        let wire = aydp_streamgen::random_message(&mut r, self.profile);
        (wire.clone(), wire)
    }

    fn garbage(&self, rng: &mut Rng, _n: usize) -> Vec<u8> {
        let mut r = aydp_streamgen::Rng(rng.next_u64());
        let mut out = Vec::new();
        aydp_streamgen::garbage(&mut r, self.profile, AYDP_CAPACITY, (1, 64), &mut out);
        out
    }

    fn decode_events(&self, stream: &[u8]) -> Vec<Option<Vec<u8>>> {
        let mut d = aydp_proto::Decoder::<AYDP_CAPACITY>::new(self.profile);
        let mut out = Vec::new();
        d.feed(stream, |ev| {
            out.push(ev.ok().map(|f| f.as_bytes().to_vec()))
        });
        d.finish(|ev| out.push(ev.ok().map(|f| f.as_bytes().to_vec())));
        out
    }

    fn decode_naive(&self, stream: &[u8]) -> Vec<Vec<u8>> {
        let mut d = aydp_naive::NaiveDecoder::new(self.profile, AYDP_CAPACITY);
        stream.iter().filter_map(|&b| d.push(b)).collect()
    }
}

/// AOK, device side: the PC's checksummed commands (parameter set, waypoint set, motor test,
/// external control). Garbage is rich in command bytes.
pub struct Aok;

impl Aok {
    fn command(rng: &mut Rng) -> aok_proto::Command {
        use aok_proto::*;
        let stick = |rng: &mut Rng| Stick::saturating(rng.below(401) as i16 - 200);
        match rng.below(4) {
            0 => Command::SetParameter(ParameterValue {
                number: rng.byte(),
                value: rng.next_u64() as i32,
            }),
            1 => Command::MotorTest(MotorTest {
                motor: Motor::new(1 + rng.byte() % 12).unwrap_or(Motor::new(1).unwrap()),
                value: rng.byte(),
            }),
            2 => Command::SetWaypoint(Waypoint {
                slot: WaypointSlot::from_wire(rng.byte() % 32).unwrap_or(WaypointSlot::FbcTarget),
                longitude: rng.next_u64() as i32,
                latitude: rng.next_u64() as i32,
                action1: ActionWord(rng.next_u64() as u32),
                action2: ActionWord(rng.next_u64() as u32),
            }),
            _ => Command::ExternalControl(ExternalControl {
                roll: stick(rng),
                nick: stick(rng),
                yaw: stick(rng),
                pitch: rng.next_u64() as i16,
                expiry_ms: rng.next_u64() as u16,
            }),
        }
    }
}

/// Length of the AOK command that starts with `first` (and `second` for `63`), if any.
fn aok_len(first: u8, second: Option<u8>) -> Option<usize> {
    Some(match first {
        0x63 => match second? {
            0x03..=0x05 => 3,
            _ => 2,
        },
        0x67 | 0x47 | 0x78 => 2,
        0x73 => 7,
        0x31..=0x39 | 0x41..=0x43 => 3,
        0x77 => 19,
        0x53 => 12,
        _ => return None,
    })
}

impl Protocol for Aok {
    fn name(&self) -> String {
        "AOK (device side)".into()
    }

    fn frame(&self, rng: &mut Rng) -> (Vec<u8>, Vec<u8>) {
        let mut bytes = [0u8; aok_proto::command::MAX_COMMAND_LEN];
        let n = Self::command(rng).emit(&mut bytes).unwrap();
        (bytes[..n].to_vec(), bytes[..n].to_vec())
    }

    fn garbage(&self, rng: &mut Rng, n: usize) -> Vec<u8> {
        const STARTS: [u8; 6] = [0x73, 0x77, 0x53, 0x33, 0x63, 0x67];
        (0..n)
            .map(|_| {
                if rng.below(4) == 0 {
                    STARTS[rng.below(6) as usize]
                } else {
                    rng.byte()
                }
            })
            .collect()
    }

    fn decode_events(&self, stream: &[u8]) -> Vec<Option<Vec<u8>>> {
        let mut d = aok_proto::CommandDecoder::new();
        let mut out = Vec::new();
        let mut keep = |ev: Result<aok_proto::Command, aok_proto::Error>| {
            out.push(ev.ok().map(|c| {
                let mut bytes = [0u8; aok_proto::command::MAX_COMMAND_LEN];
                let n = c.emit(&mut bytes).unwrap();
                bytes[..n].to_vec()
            }));
        };
        for b in stream {
            d.feed(core::slice::from_ref(b), &mut keep);
        }
        d.finish(keep);
        out
    }

    /// Trusts the length the command byte implies: on a bad checksum it skips all of it.
    fn decode_naive(&self, stream: &[u8]) -> Vec<Vec<u8>> {
        let mut out = Vec::new();
        let mut i = 0;
        while i < stream.len() {
            match aok_len(stream[i], stream.get(i + 1).copied()) {
                Some(len) if i + len <= stream.len() => {
                    if let Ok((c, _)) = aok_proto::Command::parse(&stream[i..i + len]) {
                        let mut bytes = [0u8; aok_proto::command::MAX_COMMAND_LEN];
                        let n = c.emit(&mut bytes).unwrap();
                        out.push(bytes[..n].to_vec());
                    }
                    i += len;
                }
                _ => i += 1,
            }
        }
        out
    }
}
