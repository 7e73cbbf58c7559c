//! Prints the byte count each benchmark processes (input for decoders, output for encoders),
//! one `name bytes` pair a line, so instruction counts can be divided per byte.

use protolink_bench::*;

fn main() {
    let a = aeolus_stream().len();
    for name in [
        "crc_section_4_3",
        "crc_crate_table",
        "deframe",
        "decode_aeolus",
        "deframe_slice",
        "decode_aeolus_slice",
        "naive_aeolus",
    ] {
        println!("{name} {a}");
    }
    for (names, len) in [
        (["decode_aydp", "decode_aydp_push"], aydp_stream().len()),
        (
            ["decode_aok_pc", "decode_aok_pc_push"],
            aok_debug_stream().len(),
        ),
        (
            ["decode_aok_device", "decode_aok_device_push"],
            aok_command_stream().len(),
        ),
    ] {
        for name in names {
            println!("{name} {len}");
        }
    }
    println!("decode_mavlink {}", mavlink_stream().len());
    let msgs = aeolus_messages();
    let mut out = vec![0u8; 2 * STREAM];
    println!("encode_aeolus {}", aeolus_encode(&msgs, &mut out));
    println!("encode_aydp {}", aydp_encode(&aydp_messages(), &mut out));
    let values: Vec<_> = (0..STREAM / 7)
        .map(|i| aok_proto::DebugValue {
            number: i as u8,
            value: i as i32 * 7919,
        })
        .collect();
    println!("encode_aok {}", aok_encode(&values, &mut out));
}
