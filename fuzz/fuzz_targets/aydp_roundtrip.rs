//! emit(parse(x)) == x wherever parse succeeds: a frame that the decoder accepts and whose
//! data parses re-encodes to exactly the bytes received.
#![no_main]
use aeolus_proto::Decode as _;
use aydp_proto::{Decoder, Encoder, Profile};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    for profile in [Profile::Spec, Profile::Reference] {
        let mut d = Decoder::<512>::new(profile);
        let enc = Encoder::new(profile);
        let check = |frame: aydp_proto::Frame<'_>, raw: &[u8]| {
            // A Reference decoder reads an expedited frame its encoder refuses to write.
            let writable = frame.timestamp().is_some() || profile.has_expedited();
            if let (true, Ok(msg)) = (writable, frame.message()) {
                let mut out = vec![0u8; raw.len() + 64];
                let n = enc.encode(&msg, frame.timestamp(), &mut out).unwrap();
                assert_eq!(&out[..n], raw, "re-encoding changed the frame");
            }
        };
        for &b in data {
            d.feed(&[b], |e| {
                if let Ok(frame) = e {
                    let raw = frame.as_bytes().to_vec();
                    check(frame, &raw);
                }
            });
        }
    }
});
