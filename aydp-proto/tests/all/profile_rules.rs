//! The two profiles' arithmetic at its edges: header and overhead lengths, the length field
//! both ways (Spec counts the whole message, Reference the data only, Y1/Y2), and sub-seconds
//! in milliseconds (Spec, truncated) or microseconds (Reference).

use aydp_proto::{Profile, Timestamp};

#[test]
fn headers_are_22_or_6_bytes_and_a_checksum_byte_follows_the_data() {
    assert_eq!(
        (Profile::header_len(false), Profile::header_len(true)),
        (22, 6)
    );
    assert_eq!((Profile::overhead(false), Profile::overhead(true)), (23, 7));
}

#[test]
fn the_length_field_counts_the_whole_message_in_spec_and_the_data_in_reference() {
    use Profile::{Reference, Spec};
    assert_eq!(Spec.length_field(4, false), Some(27));
    assert_eq!(Spec.length_field(4, true), Some(11));
    assert_eq!(Reference.length_field(4, true), Some(4));
    assert_eq!(
        Spec.length_field(u32::MAX as usize - 7, true),
        Some(u32::MAX)
    );
    assert_eq!(Spec.length_field(u32::MAX as usize - 6, true), None);
    assert_eq!(
        Reference.length_field(u32::MAX as usize, false),
        Some(u32::MAX)
    );
    // Past u32 (only where usize is wider: on 32-bit targets no length gets there).
    if let Some(past) = (u32::MAX as usize).checked_add(1) {
        assert_eq!(Reference.length_field(past, false), None);
    }
    assert_eq!(Spec.length_field(usize::MAX, false), None);

    assert_eq!(Spec.frame_len(27, false), Some(27));
    assert_eq!(Spec.frame_len(23, false), Some(23));
    assert_eq!(Spec.frame_len(22, false), None);
    assert_eq!(Spec.frame_len(7, true), Some(7));
    assert_eq!(Spec.frame_len(6, true), None);
    assert_eq!(Reference.frame_len(0, true), Some(7));
    assert_eq!(Reference.frame_len(4, false), Some(27));
}

#[test]
fn sub_seconds_are_milliseconds_in_spec_and_microseconds_in_reference() {
    use Profile::{Reference, Spec};
    assert_eq!(
        (Spec.subsec_per_second(), Reference.subsec_per_second()),
        (1_000, 1_000_000)
    );
    assert_eq!(
        Timestamp::from_micros(42, 500_999, Spec),
        Timestamp::new(42, 500)
    );
    assert_eq!(Timestamp::from_micros(42, 999, Spec), Timestamp::new(42, 0));
    assert_eq!(
        Timestamp::from_micros(42, 500_999, Reference),
        Timestamp::new(42, 500_999)
    );
    let t = Timestamp::new(1, 250);
    assert_eq!(
        (t.subsec_micros(Spec), t.subsec_micros(Reference)),
        (250_000, 250)
    );
    assert_eq!(Timestamp::new(0, i64::MAX).subsec_micros(Spec), i64::MAX);
    assert_eq!(Timestamp::new(0, i64::MIN).subsec_micros(Spec), i64::MIN);
}
