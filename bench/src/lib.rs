//! Inputs of the benchmarks: 64 KiB streams of valid frames per protocol, built outside the
//! measured code. The measured functions are in `bench-kernels` (re-exported here), shared with
//! the Cortex-M3 harness; the two that need `std` (the `mavlink` peer and the naive decoder)
//! stay here.

pub use bench_kernels::*;

use aeolus_proto::{CrcMode, Decode, Decoder, max_encoded_len, message::Message};
use aydp_proto::{Encoder, Profile, Timestamp};
use protolink_tests::aeolus_gen::{self, Kind::*, Values};
use protolink_tests::rng::Rng;

/// Size of every input stream.
pub const STREAM: usize = 64 * 1024;

/// AEOLUS telemetry as the box sends it: the figure-1c mix (IMU types dominate), 64 KiB.
pub fn aeolus_stream() -> Vec<u8> {
    let mut rng = Rng::new(1);
    let mut out = Vec::with_capacity(STREAM + 128);
    let mut t = 0.0;
    while out.len() < STREAM {
        t += 1.0;
        let kind = [
            Gyro, Accel, Magnet, Pressure, Attitude, Attitude, Compass, Gps,
        ][rng.below(8) as usize];
        let msg = aeolus_gen::message(&mut rng, kind, t, Values::Telemetry);
        let mut buf = [0u8; max_encoded_len(80)];
        let n = msg.encode(&mut buf, CrcMode::Compute).unwrap();
        out.extend_from_slice(&buf[..n]);
    }
    out
}

/// The AEOLUS messages of [`aeolus_stream`], for the encoder benchmarks.
pub fn aeolus_messages() -> Vec<Message<'static>> {
    let stream = aeolus_stream();
    let mut d = Decoder::<256>::new();
    let mut msgs = Vec::new();
    d.feed(&stream, |ev| {
        let f = ev.unwrap();
        let data: &'static [u8] = Box::leak(f.raw().to_vec().into_boxed_slice());
        msgs.push(Message::parse(data[0], &data[1..data.len() - 2]).unwrap());
    });
    msgs
}

/// AYDP in the `Spec` profile: a mix of expedited and timed messages, 64 KiB.
pub fn aydp_stream() -> Vec<u8> {
    let mut rng = Rng::new(2);
    let enc = Encoder::new(Profile::Spec);
    let mut out = Vec::with_capacity(STREAM + 128);
    let mut buf = [0u8; 128];
    while out.len() < STREAM {
        let msg = aydp_message(&mut rng);
        let n = if rng.below(2) == 0 {
            enc.encode(&msg, None, &mut buf).unwrap()
        } else {
            enc.encode(
                &msg,
                Some(Timestamp {
                    seconds: 1_700_000_000,
                    subsec: 250,
                }),
                &mut buf,
            )
            .unwrap()
        };
        out.extend_from_slice(&buf[..n]);
    }
    out
}

fn aydp_message(rng: &mut Rng) -> aydp_proto::Message<'static> {
    use aydp_proto::Message as M;
    let data: &'static [u8] = Box::leak(rng.bytes(20).into_boxed_slice());
    match rng.below(3) {
        0 => M::parse(3, false, data, Profile::Spec).unwrap(),
        1 => M::parse(4, false, &data[..8], Profile::Spec).unwrap_or(M::Heartbeat),
        _ => M::Heartbeat,
    }
}

/// The AYDP messages of [`aydp_stream`].
pub fn aydp_messages() -> Vec<aydp_proto::Message<'static>> {
    let mut rng = Rng::new(2);
    (0..3000).map(|_| aydp_message(&mut rng)).collect()
}

/// AOK debug frames as the device streams them, 64 KiB.
pub fn aok_debug_stream() -> Vec<u8> {
    let mut rng = Rng::new(3);
    let mut out = Vec::with_capacity(STREAM + 16);
    let mut buf = [0u8; 8];
    while out.len() < STREAM {
        let v = aok_proto::DebugValue {
            number: rng.byte(),
            value: rng.next_u64() as i32,
        };
        let n = v.emit(&mut buf).unwrap();
        out.extend_from_slice(&buf[..n]);
    }
    out
}

/// AOK commands as the PC sends them (parameter sets, waypoint sets, motor tests), 64 KiB.
pub fn aok_command_stream() -> Vec<u8> {
    use aok_proto::{Command, Motor, MotorTest, ParameterValue};
    let mut rng = Rng::new(4);
    let mut out = Vec::with_capacity(STREAM + 32);
    let mut buf = [0u8; 32];
    while out.len() < STREAM {
        let cmd = match rng.below(2) {
            0 => Command::SetParameter(ParameterValue {
                number: rng.byte(),
                value: rng.next_u64() as i32,
            }),
            _ => Command::MotorTest(MotorTest {
                motor: Motor::new(1 + rng.byte() % 12).unwrap(),
                value: rng.byte(),
            }),
        };
        let n = cmd.emit(&mut buf).unwrap();
        out.extend_from_slice(&buf[..n]);
    }
    out
}

/// MAVLink v2 ATTITUDE frames (28-byte payload, 40 bytes on the wire: the size of an AEOLUS
/// GYRO frame), 64 KiB.
pub fn mavlink_stream() -> Vec<u8> {
    use mavlink::{
        MavHeader,
        dialects::common::{ATTITUDE_DATA, MavMessage},
    };
    let mut rng = Rng::new(5);
    let mut out = Vec::with_capacity(STREAM + 64);
    let mut seq = 0u8;
    while out.len() < STREAM {
        let msg = MavMessage::ATTITUDE(ATTITUDE_DATA {
            time_boot_ms: rng.next_u64() as u32,
            roll: rng.f32(),
            pitch: rng.f32(),
            yaw: rng.f32(),
            rollspeed: rng.f32(),
            pitchspeed: rng.f32(),
            yawspeed: rng.f32(),
        });
        let header = MavHeader {
            system_id: 1,
            component_id: 1,
            sequence: seq,
        };
        seq = seq.wrapping_add(1);
        mavlink::write_v2_msg(&mut out, header, &msg).unwrap();
    }
    out
}

/// The `mavlink` crate's v2 frame parser over `stream`; returns the messages parsed.
#[inline(never)]
pub fn mavlink_decode(stream: &[u8]) -> u32 {
    let mut reader = mavlink::MavlinkReader::new(stream);
    let mut n = 0;
    while let Ok((_, _msg)) =
        reader.read_message::<mavlink::dialects::common::MavMessage>(mavlink::MavlinkVersion::V2)
    {
        n += 1;
    }
    n
}

/// The naive AEOLUS decoder of the corruption figures (allocates per frame).
#[inline(never)]
pub fn aeolus_naive(stream: &[u8]) -> usize {
    protolink_tests::naive::aeolus(stream).len()
}
