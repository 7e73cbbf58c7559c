//! `Encoder::frame_len` is the length `encode` writes (normal and expedited), in both
//! profiles (the `Reference` encoder refuses the expedited form, and `frame_len` still says
//! how long it would be).

use aydp_proto::{Encoder, Profile, Raw, Timestamp};

#[test]
fn frame_len_is_what_the_encoder_writes() {
    let payload = Raw {
        msg_type: 9,
        data: &[1, 2, 3],
    };
    for profile in [Profile::Spec, Profile::Reference] {
        let e = Encoder::new(profile);
        let mut out = [0u8; 64];
        let normal = e.encode(&payload, Some(Timestamp::new(1, 2)), &mut out);
        let expedited = e.encode(&payload, None, &mut out);
        let lens = (e.frame_len(&payload, false), e.frame_len(&payload, true));
        let want_expedited = if profile.has_expedited() {
            Ok(10)
        } else {
            Err(aydp_proto::EncodeError::ExpeditedInReference)
        };
        assert_eq!((normal, expedited), (Ok(26), want_expedited), "{profile:?}");
        assert_eq!(lens, (26, 10), "{profile:?}");
    }
}
