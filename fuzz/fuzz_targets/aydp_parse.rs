//! Every AYDP typed parse on any type, form, profile and data: no panic; whatever parses
//! encodes to a frame of the length the encoder announces.
#![no_main]
use aydp_proto::{Encoder, Message, Profile, Timestamp};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Some((&head, rest)) = data.split_first() else { return };
    let profile = if head & 0x80 == 0 { Profile::Spec } else { Profile::Reference };
    let expedited = rest.first().is_some_and(|b| b & 1 == 1);
    if let Ok(msg) = Message::parse(head & 0x7F, expedited, rest, profile) {
        let enc = Encoder::new(profile);
        let mut out = vec![0u8; rest.len() + 64];
        let ts = Timestamp { seconds: 1, subsec: 2 };
        match enc.encode(&msg, if expedited { None } else { Some(ts) }, &mut out) {
            // The Reference profile has no expedited header: its encoder refuses one.
            Err(aydp_proto::EncodeError::ExpeditedInReference) => {
                assert!(expedited && !profile.has_expedited())
            }
            n => assert_eq!(n.unwrap(), enc.frame_len(&msg, expedited)),
        }
    }
});
