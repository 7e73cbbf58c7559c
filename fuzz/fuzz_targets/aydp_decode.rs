//! The AYDP decoder on any byte stream in both profiles: no panic; every byte is delivered
//! or discarded exactly once.
#![no_main]
use aeolus_proto::Decode as _;
use aydp_proto::{Decoder, Profile};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    for profile in [Profile::Spec, Profile::Reference] {
        let mut d = Decoder::<96>::new(profile);
        let mut delivered = 0usize;
        for &b in data {
            d.feed(&[b], |e| {
                if let Ok(frame) = e {
                    delivered += frame.data().len() + 1;
                    let _ = frame.message();
                }
            });
        }
        d.finish(|e| {
            if let Ok(frame) = e {
                let _ = frame.message();
            }
        });
        assert!(delivered <= data.len());
    }
});
