//! Instruction counts of decode and encode per protocol, with peers on the same run.
//! `scripts/bench.py` divides each count by the input bytes.

use gungraun::{library_benchmark, library_benchmark_group, main};
use protolink_bench::*;
use std::hint::black_box;

#[library_benchmark]
#[bench::aeolus_crc(aeolus_stream())]
fn crc_section_4_3(input: Vec<u8>) -> u16 {
    black_box(aeolus_crc(black_box(&input)))
}

#[library_benchmark]
#[bench::crc_crate(aeolus_stream())]
fn crc_crate_table(input: Vec<u8>) -> u16 {
    black_box(crc_crate_xmodem(black_box(&input)))
}

#[library_benchmark]
#[bench::aeolus(aeolus_stream())]
fn deframe(input: Vec<u8>) -> u32 {
    black_box(aeolus_deframe(black_box(&input)))
}

#[library_benchmark]
#[bench::aeolus(aeolus_stream())]
fn decode_aeolus(input: Vec<u8>) -> u64 {
    black_box(aeolus_decode(black_box(&input)))
}

#[library_benchmark]
#[bench::aeolus(aeolus_stream())]
fn deframe_slice(input: Vec<u8>) -> u32 {
    black_box(aeolus_deframe_slice(black_box(&input)))
}

#[library_benchmark]
#[bench::aeolus(aeolus_stream())]
fn decode_aeolus_slice(input: Vec<u8>) -> u64 {
    black_box(aeolus_decode_slice(black_box(&input)))
}

#[library_benchmark]
#[bench::aeolus(aeolus_stream())]
fn naive_aeolus(input: Vec<u8>) -> usize {
    black_box(aeolus_naive(black_box(&input)))
}

// Every decoder twice: one byte a `feed` call (the `_push` rows, named after the per-byte call
// they measured first) and whole slices through `feed`.
#[library_benchmark]
#[bench::aydp(aydp_stream())]
fn decode_aydp_push(input: Vec<u8>) -> u32 {
    black_box(aydp_decode(black_box(&input)))
}

#[library_benchmark]
#[bench::aydp(aydp_stream())]
fn decode_aydp(input: Vec<u8>) -> u32 {
    black_box(aydp_decode_feed(black_box(&input)))
}

#[library_benchmark]
#[bench::aok(aok_debug_stream())]
fn decode_aok_pc_push(input: Vec<u8>) -> i64 {
    black_box(aok_pc_decode(black_box(&input)))
}

#[library_benchmark]
#[bench::aok(aok_debug_stream())]
fn decode_aok_pc(input: Vec<u8>) -> i64 {
    black_box(aok_pc_decode_feed(black_box(&input)))
}

#[library_benchmark]
#[bench::aok(aok_command_stream())]
fn decode_aok_device_push(input: Vec<u8>) -> u32 {
    black_box(aok_device_decode(black_box(&input)))
}

#[library_benchmark]
#[bench::aok(aok_command_stream())]
fn decode_aok_device(input: Vec<u8>) -> u32 {
    black_box(aok_device_decode_feed(black_box(&input)))
}

#[library_benchmark]
#[bench::mavlink(mavlink_stream())]
fn decode_mavlink(input: Vec<u8>) -> u32 {
    black_box(mavlink_decode(black_box(&input)))
}

fn aeolus_encode_setup() -> (Vec<aeolus_proto::message::Message<'static>>, Vec<u8>) {
    (aeolus_messages(), vec![0u8; 2 * STREAM])
}

#[library_benchmark]
#[bench::aeolus(setup = aeolus_encode_setup)]
fn encode_aeolus(input: (Vec<aeolus_proto::message::Message<'static>>, Vec<u8>)) -> usize {
    let (msgs, mut out) = input;
    black_box(aeolus_encode(black_box(&msgs), &mut out))
}

fn aydp_encode_setup() -> (Vec<aydp_proto::Message<'static>>, Vec<u8>) {
    (aydp_messages(), vec![0u8; 2 * STREAM])
}

#[library_benchmark]
#[bench::aydp(setup = aydp_encode_setup)]
fn encode_aydp(input: (Vec<aydp_proto::Message<'static>>, Vec<u8>)) -> usize {
    let (msgs, mut out) = input;
    black_box(aydp_encode(black_box(&msgs), &mut out))
}

fn aok_encode_setup() -> (Vec<aok_proto::DebugValue>, Vec<u8>) {
    let values = (0..STREAM / 7)
        .map(|i| aok_proto::DebugValue {
            number: i as u8,
            value: i as i32 * 7919,
        })
        .collect();
    (values, vec![0u8; 2 * STREAM])
}

#[library_benchmark]
#[bench::aok(setup = aok_encode_setup)]
fn encode_aok(input: (Vec<aok_proto::DebugValue>, Vec<u8>)) -> usize {
    let (values, mut out) = input;
    black_box(aok_encode(black_box(&values), &mut out))
}

library_benchmark_group!(
    name = codecs;
    benchmarks = crc_section_4_3, crc_crate_table, deframe, decode_aeolus, deframe_slice, decode_aeolus_slice, naive_aeolus,
        decode_aydp_push, decode_aydp, decode_aok_pc_push, decode_aok_pc, decode_aok_device_push, decode_aok_device,
        decode_mavlink, encode_aeolus, encode_aydp, encode_aok
);

main!(library_benchmark_groups = codecs);
