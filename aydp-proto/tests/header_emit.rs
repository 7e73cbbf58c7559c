//! `HeaderRepr::emit` writes 6 (expedited) or 22 (normal) bytes into a buffer of at least that
//! size and refuses a shorter one, naming the size it needs, with nothing written.

use aydp_proto::{Error, HeaderRepr, Profile, Timestamp};

#[test]
fn emit_needs_exactly_the_header_length() {
    let expedited = HeaderRepr {
        base_type: 9,
        timestamp: None,
        data_len: 1,
    };
    let normal = HeaderRepr {
        timestamp: Some(Timestamp::new(1, 2)),
        ..expedited
    };
    for (h, n) in [(expedited, 6), (normal, 22)] {
        let mut short = vec![0xAA; n - 1];
        assert_eq!(
            h.emit(&mut short, Profile::Spec),
            Err(Error::BufferTooSmall { needed: n })
        );
        assert!(short.iter().all(|&b| b == 0xAA));
        let mut exact = vec![0xAA; n];
        assert_eq!(h.emit(&mut exact, Profile::Spec), Ok(n));
        let mut long = vec![0xAA; n + 3];
        assert_eq!(h.emit(&mut long, Profile::Spec), Ok(n));
        assert_eq!(long[..n], exact[..]);
        assert_eq!(long[n..], [0xAA; 3]);
    }
    let mut exact = [0u8; 6];
    expedited.emit(&mut exact, Profile::Spec).unwrap();
    // FF, type 9 with the expedited bit, length 8 (whole message, Spec) little-endian.
    assert_eq!(exact, [0xFF, 0x89, 0x08, 0, 0, 0]);
}
