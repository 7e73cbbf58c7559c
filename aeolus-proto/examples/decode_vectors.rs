//! Decodes the AEOLUS known-answer vectors and prints every message.
//!
//! `cargo run -p aeolus-proto --example decode_vectors -- testdata/aeolus-frames.json`

use aeolus_proto::{Decode, Decoder, MAX_FIXED_FRAME};
use std::process::ExitCode;

fn hex(s: &str) -> Option<Vec<u8>> {
    (0..s.len())
        .step_by(2)
        .map(|i| s.get(i..i + 2).and_then(|h| u8::from_str_radix(h, 16).ok()))
        .collect()
}

fn main() -> ExitCode {
    let path = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "testdata/aeolus-frames.json".into());
    let text = match std::fs::read_to_string(&path) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("cannot read {path}: {e}");
            return ExitCode::FAILURE;
        }
    };
    let doc: serde_json::Value = match serde_json::from_str(&text) {
        Ok(d) => d,
        Err(e) => {
            eprintln!("{path} is not JSON: {e}");
            return ExitCode::FAILURE;
        }
    };
    let mut decoder = Decoder::<MAX_FIXED_FRAME>::new();
    for v in doc["vectors"].as_array().into_iter().flatten() {
        let name = v["name"].as_str().unwrap_or("?");
        let wire = v["frame"]
            .as_str()
            .or(v["bytes"].as_str())
            .and_then(hex)
            .unwrap_or_default();
        println!("{name} ({} bytes on the wire)", wire.len());
        decoder.feed(&wire, |event| match event {
            Ok(frame) => {
                let crc = if frame.has_crc() { "CRC ok" } else { "no CRC" };
                match frame.message() {
                    Ok(msg) => println!("  {} [{crc}] {msg:?}", msg.name()),
                    Err(e) => println!("  id {} [{crc}] {e}", frame.id()),
                }
            }
            Err(e) => println!("  error: {e}"),
        });
    }
    let s = decoder.stats();
    println!(
        "frames ok {}, without CRC {}, CRC errors {}, overflows {}, bytes discarded {}",
        s.frames_ok, s.frames_no_crc, s.checksum_errors, s.overflows, s.bytes_discarded
    );
    ExitCode::SUCCESS
}
