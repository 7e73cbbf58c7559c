//! One datagram decoded in place: no panic; every frame it yields re-encodes to bytes that
//! decode to the same frame.
#![no_main]
use aeolus_proto::{CrcMode, decode_datagram, encode_frame};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let mut buf = data.to_vec();
    for frame in decode_datagram(&mut buf, false).flatten() {
        let mode = if frame.has_crc() { CrcMode::Compute } else { CrcMode::Omit };
        let mut out = vec![0u8; aeolus_proto::max_encoded_len(frame.data().len())];
        let n = encode_frame(frame.id(), frame.data(), &[], mode, &mut out).unwrap();
        let again: Vec<_> = decode_datagram(&mut out[..n], false).collect();
        assert_eq!(again.len(), 1);
        assert_eq!(again[0].unwrap().raw(), frame.raw());
    }
});
